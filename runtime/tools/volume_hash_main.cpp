// probebake-volume-hash FILE.probes [FRAMES]: runs FRAMES light-update frames (default 12) with the first
// punctual light moving a little every third frame, then prints the xxh64 of the read-back probes, octree
// and SVO leaves and of the irradiance sampled at 4,096 seeded points of the root cube. Two builds that print
// the same line gave the same bits: how a refactor shows that it changed no result (docs/RESULTS.md).
// The memory update is left off (it is not deterministic).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#define XXH_INLINE_ALL
#include <xxhash.h>

#include <glm/geometric.hpp>

#include "probebake/runtime/runtime.h"

namespace {

template <class T>
unsigned long long hash_of(const std::vector<T>& values) {
  return XXH64(values.data(), values.size() * sizeof(T), 0);
}

int fail(const char* what, const probebake::runtime::Status& status) {
  std::fprintf(stderr, "probebake-volume-hash: %s: %s\n", what, status.message.c_str());
  return 4;
}

} // namespace

int main(int argc, char** argv) {
  using namespace probebake;
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: probebake-volume-hash FILE.probes [FRAMES]\n");
    return 1;
  }
  const int frames = argc == 3 ? std::atoi(argv[2]) : 12;
  auto context = runtime::Context::create();
  if (!context.ok()) return fail("context", context.status());
  runtime::UploadOptions options;
  options.memory_update = false;
  auto loaded = runtime::Volume::load(context.value(), argv[1], options);
  if (!loaded.ok()) return fail(argv[1], loaded.status());
  runtime::Volume& volume = loaded.value();
  std::vector<gpu::PunctualLight> lights(volume.lights().begin(), volume.lights().end());
  for (int f = 0; f < frames; ++f) {
    runtime::FrameInputs inputs;
    if (!lights.empty() && f % 3 == 1) {
      lights[0].position.x += 0.01f * std::sin(0.3f * float(f));
      inputs.lights = lights;
    }
    if (auto stats = volume.run_frame(inputs); !stats.ok()) return fail("frame", stats.status());
  }
  auto back = volume.read_back();
  if (!back.ok()) return fail("read-back", back.status());
  const formats::ProbeVolume& v = back.value();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<glm::vec3> points(4096), normals(4096);
  for (std::size_t i = 0; i < points.size(); ++i) {
    points[i] = v.info.root_min + v.info.root_size * glm::vec3(u(rng), u(rng), u(rng));
    normals[i] = glm::normalize(glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f) + glm::vec3(1e-3f));
  }
  auto irradiance = volume.sample_irradiance(points, normals);
  if (!irradiance.ok()) return fail("sampling", irradiance.status());
  std::printf("probes %zu %016llx octree %016llx svo %016llx samples %016llx\n", v.probes.size(), hash_of(v.probes),
              hash_of(v.octree), hash_of(v.svo_leaves), hash_of(irradiance.value()));
  return 0;
}
