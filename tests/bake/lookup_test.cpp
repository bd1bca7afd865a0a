// The blended lookup (lookup.h, step 3) on probes that hold an analytic field: a linear field comes
// back to a stated bound, and the lookup has no steps along lines that cross leaf and level borders. The grid
// engine's lookup (grid_lookup.h): a linear field exactly, weights, hostile inputs, a baked grid.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <random>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "bake_test_util.h"
#include "probebake/formats/grid_lattice.h"
#include "probebake/formats/validate.h"
#include "probebake/probe_index/grid_lookup.h"
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

// ---- The grid engine's lookup (grid_lookup.h, issue #41) ---------------------------------------------------

// An n^3 lattice over [0, 1]^3 with a probe at every point holding linear_field there, each serving every
// cell around it: the interpolation alone, without a scene.
formats::ProbeVolume field_lattice(int n) {
  gpu::VolumeInfo info{};
  info.root_size = 1.0f;
  info.placement = gpu::PLACEMENT_GRID;
  info.grid_resolution = n;
  formats::ProbeVolume v = formats::make_empty_volume(info);
  const gpu::GridLatticeHeader frame = formats::grid_lattice_frame(glm::vec3(0.0f), glm::vec3(1.0f), n);
  std::vector<gpu::GridPoint> points;
  const std::uint32_t no_surface = formats::grid_reach_word({2.0f, 2.0f, 2.0f, 2.0f, 2.0f, 2.0f});
  for (int z = 0; z < n; ++z) // (bits of cells outside the lattice are never read)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        gpu::Probe p{};
        p.position = formats::grid_point_position(frame, x, y, z);
        p.link = ~gpu::PROBE_NO_SURFELS;
        p.node = -1;
        for (int c = 0; c < 3; ++c) p.irradiance_sh[c] = linear_field(p.position) / probe_index::kShY0;
        points.push_back({formats::grid_probe_cells(int(v.probes.size()), 0xFFu), no_surface});
        v.probes.push_back(p);
      }
  v.grid_lattice = formats::grid_lattice_words(frame, points);
  return v;
}

// Volume lookups (zero normal) anywhere inside the lattice, and surface lookups whose biased point lies on a
// lattice plane facing the normal (the corners of non-zero weight lie a bias in front): the linear field
// comes back to float rounding.
TEST(GridLookup, ReproducesALinearFieldExactly) {
  const formats::ProbeVolume v = field_lattice(5);
  const gpu::GridLatticeHeader h = formats::grid_lattice_view(v)->header;
  const float bias = probe_index::grid_normal_bias(h);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  float worst_volume = 0.0f, worst_surface = 0.0f;
  for (int i = 0; i < 2000; ++i) {
    const glm::vec3 p = h.origin + 0.5f * h.spacing + glm::vec3(u(rng), u(rng), u(rng)) * 4.0f * h.spacing;
    worst_volume = std::max(worst_volume,
                            std::abs(probe_index::sample_irradiance_grid(v, p, glm::vec3(0.0f)).x - linear_field(p)));
    const int axis = i % 3;
    glm::vec3 n(0.0f), q = p;
    n[axis] = 1.0f;
    q[axis] = formats::grid_point_position(h, i % 4, i % 4, i % 4)[axis]; // a lattice plane
    const glm::vec3 e = probe_index::sample_irradiance_grid(v, q - n * bias, n);
    worst_surface = std::max(worst_surface, std::abs(e.x - linear_field(q)));
  }
  std::printf("[lookup] grid engine, linear field: worst error %.2e (volume), %.2e (surface) W/m^2\n",
              double(worst_volume), double(worst_surface));
  EXPECT_LT(worst_volume, 2e-6f);
  EXPECT_LT(worst_surface, 2e-6f);
}

// A probe that does not serve the cell (its cell bit clear) and a probe behind the surface's plane add
// nothing, however bright; the others' weights renormalise.
TEST(GridLookup, ProbesThatDoNotServeOrLieBehindAddNothing) {
  formats::ProbeVolume v = field_lattice(2);
  const glm::vec3 centre(0.5f);
  const float all = probe_index::sample_irradiance_grid(v, centre, glm::vec3(0.0f)).x;
  EXPECT_NEAR(all, linear_field(centre), 1e-5f);
  v.probes[7].irradiance_sh[0] = 1e6f; // corner (+x, +y, +z)
  std::uint32_t& probe_7 = v.grid_lattice[gpu::GRID_LATTICE_HEADER_WORDS + 7 * gpu::GRID_POINT_WORDS];
  probe_7 = formats::grid_probe_cells(7, 0xFEu); // its cell: bit 0
  const float without = probe_index::sample_irradiance_grid(v, centre, glm::vec3(0.0f)).x;
  float others = 0.0f;
  for (int k = 0; k < 7; ++k) others += linear_field(v.probes[std::size_t(k)].position) / 7.0f;
  EXPECT_NEAR(without, others, 1e-5f);
  // Facing -z from just above the cell's middle: the four corners at z = 0.75 lie behind; probe 7 serves again.
  probe_7 = formats::grid_probe_cells(7, 0xFFu);
  const glm::vec3 down(0.0f, 0.0f, -1.0f);
  const float below = probe_index::sample_irradiance_grid(v, glm::vec3(0.5f, 0.5f, 0.74f), down).x;
  EXPECT_LT(below, 2.0f); // probe 7's 1e6 stays out
  EXPECT_NEAR(below,
              0.25f * (linear_field(v.probes[0].position) + linear_field(v.probes[1].position) +
                       linear_field(v.probes[2].position) + linear_field(v.probes[3].position)),
              1e-4f);
}

// Non-finite points and normals, points far outside, and a damaged lattice: finite results, misses where
// nothing can be read.
TEST(GridLookup, HostileInputsGiveFiniteResults) {
  formats::ProbeVolume v = field_lattice(3);
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  probe_index::SamplerStats stats;
  EXPECT_EQ(probe_index::sample_irradiance_grid(v, glm::vec3(nan, 0.5f, 0.5f), glm::vec3(0, 1, 0), &stats),
            glm::vec3(0));
  EXPECT_EQ(probe_index::sample_irradiance_grid(v, glm::vec3(0.5f), glm::vec3(inf, 0, 0), &stats), glm::vec3(0));
  EXPECT_EQ(stats.misses, 2u);
  for (const glm::vec3 p : {glm::vec3(1e30f), glm::vec3(-1e30f), glm::vec3(3e38f, -3e38f, 0.0f)}) {
    const glm::vec3 e = probe_index::sample_irradiance_grid(v, p, glm::vec3(0, 0, 1), &stats);
    EXPECT_TRUE(std::isfinite(e.x) && std::isfinite(e.y) && std::isfinite(e.z)) << p.x;
  }
  EXPECT_EQ(stats.misses, 2u); // outside the lattice the border cell's value extends
  v.grid_lattice.pop_back();
  EXPECT_EQ(probe_index::sample_irradiance_grid(v, glm::vec3(0.5f), glm::vec3(0, 1, 0), &stats), glm::vec3(0));
  EXPECT_EQ(stats.misses, 3u);
}

// A baked grid (generated Cornell box, 8^3, its lattice built from the scene): every surface point whose lookup
// point lies in open space finds probes, and lines through open space at least a twentieth of the box from every surface show no step.
TEST(GridLookup, BakedGridCoversTheBoxAndIsContinuousInOpenSpace) {
  const FieldBake f = bake_field(bake::Placement::grid, 8, 4);
  const formats::ProbeVolume& v = f.baked.volume;
  ASSERT_TRUE(formats::grid_lattice_view(v));
  EXPECT_TRUE(formats::validate(v).valid());
  const gpu::GridLatticeHeader h = formats::grid_lattice_view(v)->header;
  const float spacing = h.spacing.x, step = spacing / 1000.0f, bias = probe_index::grid_normal_bias(h);
  const scene::RayScene rays(f.scene);
  const Inner inner(f.scene);
  std::mt19937 rng(8);
  float worst = 0.0f;
  int steps = 0;
  for (const auto& [start, n] : open_points(f.scene, 40)) {
    const glm::vec3 d = random_unit(rng);
    glm::vec3 x = start, previous = probe_index::sample_irradiance_grid(v, x, n);
    const int length = int((nearest_surface(rays, start) - 0.5f * inner.margin) / step); // stays half a margin clear
    for (int k = 0; k < std::min(length, 3000) && inner.contains(x + step * d); ++k, ++steps) {
      const glm::vec3 e = probe_index::sample_irradiance_grid(v, x + step * d, n);
      worst = std::max(worst, std::abs(e.x - previous.x) / std::max(0.5f * (e.x + previous.x), 1e-3f));
      previous = e;
      x += step * d;
    }
  }
  probe_index::SamplerStats stats;
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (std::size_t t = 0; t < f.scene.triangles.size(); ++t) {
    const glm::uvec3 tri = f.scene.triangles[t];
    const glm::vec3 n = glm::normalize(scene::triangle_normal(f.scene, t));
    for (int i = 0; i < 50; ++i) {
      float a = u(rng), b = u(rng);
      if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
      const glm::vec3 p0 = f.scene.positions[tri.x];
      const glm::vec3 p = p0 + a * (f.scene.positions[tri.y] - p0) + b * (f.scene.positions[tri.z] - p0);
      if (inside_geometry(rays, p + n * bias) || rays.occluded(p, n, 1e-3f * bias, bias)) continue; // under a block
      probe_index::sample_irradiance_grid(v, p, n, &stats);
    }
  }
  std::printf("[lookup] grid engine 8^3: %d steps, largest %.2e of the local irradiance; %zu of %zu surface "
              "lookups missed\n",
              steps, double(worst), stats.misses, stats.samples);
  EXPECT_GT(steps, 10000);
  EXPECT_LT(worst, 2e-3f);
  EXPECT_GT(stats.samples, 1000u);
  EXPECT_EQ(stats.misses, 0u);
}

} // namespace
} // namespace probebake::test
