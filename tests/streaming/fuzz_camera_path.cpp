// libFuzzer target for the camera path reader (probebake run --path; untrusted text). Properties beyond "no
// crash, no sanitizer report": the parser either refuses with Error(input) or returns at least one row, frames
// strictly increasing and every coordinate finite. Seeds: tests/data/fuzz/camera_path (scripts/fuzz.sh).
#include <cmath>
#include <cstdint>
#include <string_view>

#include "fuzz_check.h"
#include "probebake/formats/error.h"
#include "probebake/streaming/camera_path.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace probebake;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const auto path = streaming::parse_camera_path(text, "fuzz.csv");
    fuzz::check(!path.empty(), "a parsed path has rows");
    for (std::size_t i = 0; i < path.size(); ++i) {
      fuzz::check(i == 0 || path[i].frame > path[i - 1].frame, "frames increase");
      for (int a = 0; a < 3; ++a) fuzz::check(std::isfinite(path[i].position[a]), "coordinates are finite");
    }
  } catch (const Error& e) {
    fuzz::check(e.kind() == ErrorKind::input, "refusals are input errors");
  }
  return 0;
}
