// libFuzzer target for the glTF loader: any bytes either load into a scene whose every position is
// finite and every index in range, or give probebake::Error. Seeds: ../shared/scenes (.glb files) and
// generated scenes. Run: fuzz_scene_loader CORPUS_DIR ../shared/scenes/*/ -max_len=200000
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "probebake/bake/scene.h"
#include "probebake/formats/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace probebake;
  try {
    // No base directory: external URIs cannot resolve, so the fuzzer stays inside its input.
    const scene::Scene s = scene::load_scene_from_memory(std::vector<unsigned char>(data, data + size), "fuzz",
                                                         "/nonexistent-probebake-fuzz-dir");
    for (const auto& t : s.triangles)
      if (t.x >= s.positions.size() || t.y >= s.positions.size() || t.z >= s.positions.size()) std::abort();
    for (const auto& p : s.positions)
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) std::abort();
    if (s.triangle_albedo.size() != s.triangles.size()) std::abort();
  } catch (const Error&) {
  }
  return 0;
}
