// Cost of the blended lookup (probe_index::sample_irradiance) next to one leaf's stencil (svo_stencil), the lookup
// the blend replaced, on the CPU twin of the shader: same volume, same points, one thread, side by side.
// Usage: probebake-bench-lookup [--points N]
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <glm/geometric.hpp>

#include "probebake/bake/bake.h"
#include "probebake/probe_index/lookup.h"
#include "probebake/samples/scenes.h"
#include "probebake/scene/scene.h"

namespace {

using namespace probebake;

struct Points {
  std::vector<glm::vec3> positions, normals;
};

// Uniform in the scene's bounds, random unit normals: most lie in open space inside the box.
Points random_points(const scene::Bounds& b, int count) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::normal_distribution<float> g(0.0f, 1.0f);
  Points p;
  while (int(p.positions.size()) < count) {
    const glm::vec3 n(g(rng), g(rng), g(rng));
    if (glm::dot(n, n) < 1e-6f) continue;
    p.positions.push_back(b.min + glm::vec3(u(rng), u(rng), u(rng)) * (b.max - b.min));
    p.normals.push_back(glm::normalize(n));
  }
  return p;
}

template <class Lookup>
double nanoseconds_per_lookup(const Points& points, const Lookup& lookup, float* checksum) {
  const auto t0 = std::chrono::steady_clock::now();
  glm::vec3 sum(0.0f);
  for (std::size_t i = 0; i < points.positions.size(); ++i) sum += lookup(points.positions[i], points.normals[i]);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  *checksum += sum.x + sum.y + sum.z; // keeps the loop
  return 1e9 * s / double(points.positions.size());
}

void row(const std::string& label, const scene::Scene& scene, const bake::BakeSettings& settings, int count) {
  const bake::BakeResult baked = bake::bake(scene, settings);
  const formats::ProbeVolume& v = baked.volume;
  const Points points = random_points(scene.bounds, count);
  float checksum = 0.0f;
  const double leaf = nanoseconds_per_lookup(
      points,
      [&](glm::vec3 p, glm::vec3 n) { return probe_index::apply_stencil(v, probe_index::svo_stencil(v, p, n), n); },
      &checksum);
  const double blend = nanoseconds_per_lookup(
      points, [&](glm::vec3 p, glm::vec3 n) { return probe_index::sample_irradiance(v, p, n); }, &checksum);
  int one_leaf = 0, leaves = 0, probes = 0;
  for (std::size_t i = 0; i < points.positions.size(); ++i) {
    const probe_index::BlendedLookup b = probe_index::blended_lookup(v, points.positions[i], points.normals[i]);
    one_leaf += b.count == 1 ? 1 : 0;
    leaves += b.count;
    probes += probe_index::probe_blend(v, b, points.positions[i], points.normals[i]).count;
  }
  fmt::print("| {} | {} | {} | {:.0f} | {:.0f} | {:.2f}x | {:.1f} % | {:.2f} | {:.2f} |\n", label, v.probes.size(),
             v.svo_leaves.size(), leaf, blend, blend / leaf, 100.0 * one_leaf / count, double(leaves) / count,
             double(probes) / count);
  if (!(checksum == checksum)) fmt::print("(non-finite checksum)\n");
}

} // namespace

int main(int argc, char** argv) {
  int count = 200000;
  for (int i = 1; i + 1 < argc; ++i)
    if (std::string(argv[i]) == "--points") count = std::max(1, std::atoi(argv[++i]));
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "probebake-bench-lookup";
  std::filesystem::create_directories(dir);
  const std::filesystem::path path = dir / "cornell.glb";
  samples::cornell().write_glb(path);
  const scene::Scene scene = scene::load_scene(path, {.require_triangles = true});
  fmt::print("| volume | probes | SVO leaves | one leaf ns/lookup | blend ns/lookup | ratio | lookups reading one leaf "
             "| leaves per lookup | probes per lookup |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (int depth : {3, 5}) {
    bake::BakeSettings s;
    s.max_depth = depth;
    row(fmt::format("Cornell octree d{}", depth), scene, s, count);
  }
  bake::BakeSettings grid;
  grid.placement = formats::PlacementKind::grid;
  grid.grid_resolution = 16;
  row("Cornell grid 16^3", scene, grid, count);
  return 0;
}
