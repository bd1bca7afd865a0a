// Atomic file output: readers never see a half-written .glb (write a temporary file next to the target,
// then rename it over the target, which POSIX makes atomic within one file system).
#include "probebake/samples/scene_builder.h"

#include <unistd.h>

#include <fstream>
#include <system_error>

namespace probebake::samples {
namespace {

[[noreturn]] void unwritable(const std::filesystem::path& path, const std::string& why) {
  throw Error(ErrorKind::output, "cannot write '" + path.string() + "': " + why);
}

std::filesystem::path temporary_path_for(const std::filesystem::path& path) {
  std::filesystem::path temporary = path;
  temporary += ".tmp-" + std::to_string(::getpid());
  return temporary;
}

}  // namespace

void write_file_atomically(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes) {
  if (path.empty()) unwritable(path, "empty path");
  const std::filesystem::path temporary = temporary_path_for(path);
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) unwritable(path, "cannot create a file in its folder");
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) {
      std::error_code ignored;
      std::filesystem::remove(temporary, ignored);
      unwritable(path, "write failed");
    }
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    unwritable(path, error.message());
  }
}

}  // namespace probebake::samples
