// The blended lookup (lookup.h, step 3) on probes that hold an analytic field: a linear field comes
// back to a stated bound, and the lookup has no steps along lines that cross leaf and level borders.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "bake_test_util.h"
#include "probebake/probe_index/lookup.h"
#include "probebake/formats/octree.h"
#include "probebake/scene/scene.h"
#include "probebake/samples/scenes.h"

namespace probebake::test {
namespace {

glm::vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<float> g(0.0f, 1.0f);
  for (;;) {
    const glm::vec3 d(g(rng), g(rng), g(rng));
    if (glm::dot(d, d) > 1e-6f) return glm::normalize(d);
  }
}

// E(x) = 1 + dot(kSlope, x) W/m^2 in every direction: the probes hold it in their constant SH term.
const glm::vec3 kSlope(0.2f, -0.1f, 0.05f);
float linear_field(glm::vec3 x) { return 1.0f + glm::dot(kSlope, x); }

struct FieldBake {
  scene::Scene scene;
  bake::BakeResult baked;
};

FieldBake bake_field(bake::Placement placement, int grid_resolution, int max_depth) {
  FieldBake f{load_generated(samples::cornell(), "lookup-cornell"), {}};
  bake::BakeSettings settings = test_settings();
  settings.placement = placement;
  settings.grid_resolution = grid_resolution;
  settings.max_depth = max_depth;
  f.baked = bake::bake(f.scene, settings);
  for (gpu::Probe& p : f.baked.volume.probes) {
    std::fill(std::begin(p.irradiance_sh), std::end(p.irradiance_sh), 0.0f);
    for (int c = 0; c < 3; ++c) p.irradiance_sh[c] = linear_field(p.position) / probe_index::kShY0;
  }
  return f;
}

// The scene's bounds less a tenth of its extent on every side (the box is open at the front).
struct Inner {
  glm::vec3 lo, hi;
  float margin;
  explicit Inner(const scene::Scene& scene)
      : lo(scene.bounds.min + 0.1f * scene.bounds.largest_extent()),
        hi(scene.bounds.max - 0.1f * scene.bounds.largest_extent()),
        margin(0.1f * scene.bounds.largest_extent()) {}
  bool contains(glm::vec3 p) const { return glm::all(glm::greaterThan(p, lo)) && glm::all(glm::lessThan(p, hi)); }
};

// Points of open space inside Inner, at least its margin from every surface, with random normals.
std::vector<std::pair<glm::vec3, glm::vec3>> open_points(const scene::Scene& scene, int count) {
  const scene::RayScene rays(scene);
  const Inner inner(scene);
  const glm::vec3 lo = inner.lo, extent = inner.hi - inner.lo;
  const float margin = inner.margin;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<std::pair<glm::vec3, glm::vec3>> points;
  while (int(points.size()) < count) {
    const glm::vec3 p = lo + glm::vec3(u(rng), u(rng), u(rng)) * extent;
    if (!inside_geometry(rays, p) && nearest_surface(rays, p) > margin) points.push_back({p, random_unit(rng)});
  }
  return points;
}

// Largest error of the lookup against the field, in units of the field's change over the local probe
// spacing: the grid's spacing, or the edge of the placement octree's leaf holding the point.
float worst_linear_error(const FieldBake& f) {
  const formats::ProbeVolume& v = f.baked.volume;
  float worst = 0.0f;
  int misses = 0;
  for (const auto& [p, n] : open_points(f.scene, 400)) {
    const auto leaf = formats::find_leaf(v, p);
    const float spacing = v.info.placement == gpu::PLACEMENT_GRID ? v.info.root_size / float(v.info.grid_resolution - 1)
                                                                  : (leaf ? leaf->size : v.info.root_size);
    probe_index::SamplerStats stats;
    const glm::vec3 e = probe_index::sample_irradiance(f.baked.volume, p, n, &stats);
    misses += int(stats.misses);
    worst = std::max(worst, std::abs(e.x - linear_field(p)) / (glm::length(kSlope) * spacing));
  }
  EXPECT_EQ(misses, 0);
  return worst;
}

// The probes' weights come from visibility over squared distance from the voxel's centre (probe_index/src/build.cpp),
// not from interpolation coordinates, so a linear field is not reproduced exactly (issue #39 asks for
// exact on the grid; open, see docs/results/lookup.md). Measured: 0.59 of the change over one grid
// spacing (8^3), 2.37 over one placement leaf (octree depth 4, where relocated probes and the nearest-probe
// bias of 1/d^2 pull the value towards one probe).
TEST(BlendedLookup, LinearFieldWithinStatedBounds) {
  const FieldBake grid = bake_field(bake::Placement::grid, 8, 4);
  const float grid_error = worst_linear_error(grid);
  const FieldBake octree = bake_field(bake::Placement::octree, 16, 4);
  const float octree_error = worst_linear_error(octree);
  std::printf("[lookup] linear field: worst error %.3f (grid 8^3) and %.3f (octree depth 4) of the change over "
              "one probe spacing\n",
              double(grid_error), double(octree_error));
  EXPECT_LT(grid_error, 0.75f);
  EXPECT_LT(octree_error, 3.0f);
}

// Lines through open space in steps of a thousandth of a finest voxel: the lookup never jumps. One leaf's
// stencil alone (what the blend replaced) jumps at its borders; lines cross leaves of several depths.
TEST(BlendedLookup, ContinuousAcrossLeafAndLevelBorders) {
  const scene::Scene scene = load_generated(samples::cornell(), "lookup-lines");
  bake::BakeSettings settings = test_settings();
  settings.max_depth = 3;
  const bake::BakeResult baked = bake::bake(scene, settings);
  const formats::ProbeVolume& v = baked.volume;
  const scene::RayScene rays(scene);
  const Inner inner(scene);
  const float voxel = v.info.root_size / float(1 << v.info.svo_depth);
  const float step = voxel / 1000.0f;
  std::mt19937 rng(5);
  float worst_blend = 0.0f, worst_leaf = 0.0f;
  int level_borders = 0, steps = 0;
  for (const auto& [start, n] : open_points(scene, 40)) {
    const glm::vec3 d = random_unit(rng);
    glm::vec3 x = start;
    glm::vec3 previous = probe_index::sample_irradiance(v, x, n);
    glm::vec3 previous_leaf = probe_index::apply_stencil(v, probe_index::svo_stencil(v, x, n), n);
    int depth = -1;
    probe_index::find_svo_leaf(v, x + n * probe_index::normal_bias(v.info), &depth);
    for (int k = 0; k < 4000; ++k) {
      const glm::vec3 next = x + step * d;
      if (!inner.contains(next) || rays.occluded(x, d, 0.0f, 2.0f * voxel)) break; // lines stay in open space
      const glm::vec3 e = probe_index::sample_irradiance(v, next, n);
      const glm::vec3 e_leaf = probe_index::apply_stencil(v, probe_index::svo_stencil(v, next, n), n);
      const float local = std::max(0.5f * (e.x + previous.x), 1e-3f);
      worst_blend = std::max(worst_blend, std::abs(e.x - previous.x) / local);
      worst_leaf = std::max(worst_leaf, std::abs(e_leaf.x - previous_leaf.x) / local);
      int next_depth = -1;
      probe_index::find_svo_leaf(v, next + n * probe_index::normal_bias(v.info), &next_depth);
      level_borders += next_depth != depth ? 1 : 0;
      depth = next_depth;
      previous = e;
      previous_leaf = e_leaf;
      x = next;
      ++steps;
    }
  }
  std::printf("[lookup] lines: %d steps of %.2e m, %d level borders; largest step: blend %.2e, one leaf %.2e of the "
              "local irradiance\n",
              steps, double(step), level_borders, double(worst_blend), double(worst_leaf));
  EXPECT_GT(level_borders, 10);
  EXPECT_GT(worst_leaf, 0.05f); // the steps the blend removed
  EXPECT_LT(worst_blend, 2e-3f);
}

// Coverage: every surface point of CornellBox.glb whose lookup point lies in the room finds probes. Its short
// block is closed and double-sided: the probes inside it were the 48 nearest to the voxels just above its top,
// none visible, and those voxels were left empty (receivers on the top missed: coverage 0.993 in two of eval's
// rows; 119 of these 11,182 lookups missed). Empty voxels now rank their neighbours' probes, outwards from the
// served ones.
TEST(BlendedLookup, EverySurfacePointInTheRoomFindsProbes) {
  const std::filesystem::path path = std::filesystem::path(PROBEBAKE_SHARED_SCENES) / "cornell_box" / "CornellBox.glb";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "no " << path;
  const scene::Scene scene = scene::load_scene(path.string());
  const scene::RayScene rays(scene);
  bake::BakeSettings settings; // eval's row octree-d4-s256: the default SVO depth
  settings.max_depth = 4;
  settings.surfels_per_probe = 256;
  const bake::BakeResult baked = bake::bake(scene, settings);
  const formats::ProbeVolume& v = baked.volume;
  const float bias = probe_index::normal_bias(v.info);
  const auto in_room = [&](glm::vec3 p) {
    return glm::all(glm::greaterThan(p, scene.bounds.min)) && glm::all(glm::lessThan(p, scene.bounds.max));
  };
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  int lookups = 0;
  probe_index::SamplerStats stats;
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
    const glm::vec3 normal = scene::triangle_normal(scene, t);
    if (normal == glm::vec3(0.0f)) continue;
    const glm::uvec3 tri = scene.triangles[t];
    for (int i = 0; i < 200; ++i) {
      float a = unit(rng), b = unit(rng);
      if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
      const glm::vec3 p0 = scene.positions[tri.x];
      const glm::vec3 p = p0 + a * (scene.positions[tri.y] - p0) + b * (scene.positions[tri.z] - p0);
      for (const glm::vec3 n : {glm::normalize(normal), -glm::normalize(normal)}) {
        if (!in_room(p + n * bias) || rays.occluded(p, n, 1e-3f * bias, bias)) continue;
        ++lookups;
        probe_index::sample_irradiance(v, p, n, &stats);
      }
    }
  }
  std::printf("[lookup] CornellBox.glb octree-d4, 256 surfels: %zu of %d surface lookups in the room missed\n",
              stats.misses, lookups);
  EXPECT_GT(lookups, 3000);
  EXPECT_EQ(stats.misses, 0u);
}

} // namespace
} // namespace probebake::test
