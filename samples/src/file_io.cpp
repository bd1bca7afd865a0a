// Atomic file output (formats/atomic_file.h): readers never see a half-written .glb.
#include "probebake/samples/scene_builder.h"

#include "probebake/formats/atomic_file.h"

namespace probebake::samples {
namespace {

[[noreturn]] void unwritable(const std::filesystem::path& path, const std::string& why) {
  throw Error(ErrorKind::output, "cannot write '" + path.string() + "': " + why);
}

} // namespace

void write_file_atomically(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes) {
  if (path.empty()) unwritable(path, "empty path");
  probebake::write_file_atomically(path, std::span<const std::uint8_t>(bytes));
}

} // namespace probebake::samples
