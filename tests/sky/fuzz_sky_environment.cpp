// libFuzzer target for the sky's environment reader (probebake --sky FILE.exr; an untrusted OpenEXR file). The
// input is written to a scratch file and read with sky::environment_sky. Properties beyond "no crash, no
// sanitizer report": it either refuses with Error(input) or returns a 2:1 map of at most 128 x 64 texels, every
// value finite and >= 0. Seeds: tests/data/fuzz/sky_environment (scripts/fuzz.sh).
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "fuzz_check.h"
#include "probebake/formats/error.h"
#include "probebake/sky/sky.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace probebake;
  const char* scratch = std::getenv("PROBEBAKE_FUZZ_SCRATCH");
  const std::filesystem::path file =
      std::filesystem::path(scratch ? scratch : std::filesystem::temp_directory_path().string()) / "input.exr";
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  }
  try {
    const sky::Sky s = sky::environment_sky(file);
    fuzz::check(s.map.width == 2 * s.map.height && s.map.width <= sky::kEnvironmentWidth, "a 2:1 map, small");
    fuzz::check(s.map.texels.size() == std::size_t(s.map.width) * std::size_t(s.map.height), "its texels");
    for (const glm::vec3& t : s.map.texels)
      for (int c = 0; c < 3; ++c) fuzz::check(std::isfinite(t[c]) && t[c] >= 0.0f, "finite radiance >= 0");
  } catch (const Error& e) {
    fuzz::check(e.kind() == ErrorKind::input, "refusals are input errors");
  }
  return 0;
}
