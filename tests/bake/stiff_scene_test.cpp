// Stiff scenes (issue #39): geometry and light that strain the lookup and the bake. The first is a Cornell
// box whose light is a closed, double-sided emissive box 0.13 mm under the ceiling: its inside is a sealed
// cavity of emitting walls, and the probes placed there hold ~180 W/m^2 where the room's hold ~1. SVO voxels
// that the box's walls cut used to list those probes for lookups on the room's side: 150x the reference on
// the ceiling beside the box. Each voxel now serves one group of mutually visible probes.
#include <algorithm>
#include <cmath>
#include <utility>

#include <gtest/gtest.h>

#include "bake_test_util.h"
#include "probebake/probe_index/lookup.h"
#include "probebake/eval/eval.h"
#include "probebake/samples/scenes.h"

namespace probebake::test {
namespace {

struct LookupComparison {
  double mean_all = 0.0;     // mean of the all-probe loop over receivers and channels
  double worst_excess = 0.0; // max over receivers of (SVO - all-probe loop), per channel
  float brightest_probe = 0; // the largest probe DC irradiance
  std::size_t misses = 0;
};

// The SVO lookup against the all-probe loop (visibility rays to every probe) with the same probes, at the
// visible receivers `eval` uses.
LookupComparison compare_lookups(const scene::Scene& scene, const bake::BakeSettings& settings) {
  const scene::RayScene rays(scene);
  bake::ReceiverSettings receivers;
  receivers.count = 200;
  const std::vector<bake::SamplePoint> points = bake::make_receivers(scene, rays, receivers).points;
  const bake::BakeResult baked = bake::bake(scene, settings);
  LookupComparison out;
  for (const gpu::Probe& p : baked.volume.probes)
    if (p.link != 0) out.brightest_probe = std::max(out.brightest_probe, p.irradiance_sh[0] * probe_index::kShY0);
  probe_index::SamplerStats stats;
  for (const bake::SamplePoint& point : points) {
    const glm::vec3 svo = probe_index::sample_irradiance(baked.volume, point.position, point.normal, &stats);
    const glm::vec3 all = probe_index::sample_irradiance_all_probes(baked.volume, rays, point.position, point.normal);
    for (int c = 0; c < 3; ++c) {
      out.mean_all += all[c] / (3.0 * double(points.size()));
      out.worst_excess = std::max(out.worst_excess, double(svo[c] - all[c]));
    }
  }
  out.misses = stats.misses;
  return out;
}

TEST(StiffScenes, ASealedEmissiveBoxUnderTheCeilingDoesNotLightTheRoomThroughTheIndex) {
  samples::CornellOptions options;
  options.light_box_gap = 0.00013f;
  const scene::Scene scene = load_generated(samples::cornell(options), "stiff-light-box");
  // (octree depth, SVO depth): the defaults' blow-up needs the default SVO depth and surfels; at SVO depth 4 a
  // voxel is taller than the box, and its nine sample points can all fall inside it (135 W/m^2 on the ceiling
  // beside the box until a minor group's voxel asked its octants).
  for (const auto& [depth, svo_depth] : {std::pair{3, 5}, std::pair{4, 5}, std::pair{4, 4}}) {
    bake::BakeSettings settings;
    settings.max_depth = depth;
    settings.svo_depth = svo_depth;
    const LookupComparison c = compare_lookups(scene, settings);
    std::printf("[stiff] light box, octree depth %d, SVO depth %d: brightest probe %.1f W/m^2, mean all-probe %.3f, "
                "worst SVO excess %.3f, misses %zu\n",
                depth, svo_depth, c.brightest_probe, c.mean_all, c.worst_excess, c.misses);
    // The cavity's probes are there and bright: the test would see them leak.
    EXPECT_GT(c.brightest_probe, 50.0f * float(c.mean_all));
    // The bound (no receiver off by more than 10x the mean). Before the group rule: 270x the mean
    // above the all-probe loop at depth 4 (118 W/m^2); after, 3.2x, what interpolation alone differs by.
    EXPECT_LT(c.worst_excess, 10.0 * c.mean_all);
    EXPECT_EQ(c.misses, 0u);
  }
}

// No holes (issue #39): every visible receiver's lookup finds a probe. The octree at depth 5 left 2 % of the
// light-box scene's receivers (under the box and on the ceiling beside it) in voxels whose 12 nearest
// probes all lay behind the box; such a voxel now looks among the 48 nearest.
TEST(StiffScenes, EveryVisibleReceiverFindsAProbe) {
  samples::CornellOptions options;
  options.light_box_gap = 0.00013f;
  const scene::Scene light_box = load_generated(samples::cornell(options), "coverage-light-box");
  const scene::Scene cornell = load_generated(samples::cornell(), "coverage-cornell");
  for (const scene::Scene* scene : {&light_box, &cornell})
    for (const int depth : {2, 5}) {
      bake::BakeSettings settings;
      settings.max_depth = depth;
      const LookupComparison c = compare_lookups(*scene, settings);
      EXPECT_EQ(c.misses, 0u) << "depth " << depth;
    }
}

// Probe irradiance stays physically bounded and the bounce iteration converges quickly on every stiff
// scene. The bounds are energy arguments: no radiance anywhere exceeds the brightest source over (1 - the
// largest albedo), and the probes hold reflected light only (emitters and the sun are added per pixel).
struct StiffCase {
  const char* name;
  samples::SceneBuilder builder;
  float bound; // W/m^2, on any probe's mean irradiance (its DC term) in any channel
};

std::vector<StiffCase> stiff_cases() {
  samples::CornellOptions light_box;
  light_box.light_box_gap = 0.00013f;
  return {
      // Inside the sealed double-sided light box (radiance 17 at most, albedo 0.78): pi 17 / (1 - 0.78).
      {"light box", samples::cornell(light_box), 3.14159f * 17.0f / (1.0f - 0.78f)},
      // A surface gets at most the sun's 10 lux directly; reflected light: 0.7 * 10 / (1 - 0.7).
      {"window room", samples::window_room(), 0.7f * 10.0f / (1.0f - 0.7f)},
      // The 1 cm emitter (radiance 1e5) seen from any surface facing it, 1.99 m away at least: E_direct
      // <= 1e5 * 1e-4 / 1.99^2 = 2.53; reflected light: 0.7 * 2.53 / (1 - 0.7).
      {"tiny emitter", samples::tiny_emitter(), 0.7f * 2.53f / (1.0f - 0.7f)},
      // The 10 cm emitter (radiance 10) seen from any surface facing it, 0.45 m away at least (the walls):
      // E_direct <= 10 * 0.01 / 0.45^2 = 0.494; reflected light in a box of albedo 0.95: 0.95 * 0.494 / 0.05.
      {"cavity", samples::cavity(), 0.95f * 0.494f / (1.0f - 0.95f)},
  };
}

TEST(StiffScenes, ProbeIrradianceIsBoundedAndTheIterationConverges) {
  for (const StiffCase& c : stiff_cases()) {
    const scene::Scene scene = load_generated(c.builder, std::string("stiff-") + c.name);
    for (const bool grid : {false, true}) {
      bake::BakeSettings settings;
      settings.max_depth = 3;
      settings.placement = grid ? bake::Placement::grid : bake::Placement::octree;
      settings.grid_resolution = 8;
      const bake::BakeResult r = bake::bake(scene, settings);
      float brightest = 0.0f;
      for (const gpu::Probe& p : r.volume.probes) {
        if (p.link == 0) continue;
        for (float v : p.irradiance_sh) ASSERT_TRUE(std::isfinite(v)) << c.name;
        for (int channel = 0; channel < 3; ++channel)
          brightest = std::max(brightest, p.irradiance_sh[channel] * probe_index::kShY0);
      }
      std::printf("[stiff] %s, %s: %d probes, brightest mean irradiance %.3g W/m^2 (bound %.3g), %d sweeps\n", c.name,
                  grid ? "grid 8" : "octree depth 3", r.report.probes, brightest, c.bound,
                  r.report.lighting.iterations);
      EXPECT_LE(brightest, c.bound) << c.name;
      EXPECT_TRUE(r.report.lighting.converged) << c.name;
      EXPECT_LE(r.report.lighting.iterations, 500) << c.name;
    }
  }
}

// The window room's probes are noisy (a sun patch seen by few of 256 rays): that noise, not the lookup,
// kept its error from falling as probes were added. The estimate falls as 1 / sqrt(rays), and a furnace,
// where every ray sees the same radiance, has none.
TEST(StiffScenes, ProbeNoiseFallsAsOneOverTheRootOfTheRays) {
  const scene::Scene room = load_generated(samples::window_room(), "stiff-noise-room");
  float noise[2] = {};
  for (int i = 0; i < 2; ++i) {
    bake::BakeSettings settings;
    settings.placement = bake::Placement::grid;
    settings.grid_resolution = 6;
    settings.lighting.rays = i == 0 ? 256 : 1024;
    noise[i] = bake::bake(room, settings).report.lighting.noise_median;
  }
  std::printf("[stiff] window room, grid 6: probe noise %.4f at 256 rays, %.4f at 1024\n", noise[0], noise[1]);
  EXPECT_GT(noise[0], 0.08f); // the level at which the blotches show (cmd_bake.cpp)
  EXPECT_NEAR(noise[0] / noise[1], 2.0f, 0.3f);
  bake::BakeSettings furnace;
  furnace.max_depth = 2;
  const bake::BakeResult f =
      bake::bake(load_generated(samples::furnace({.albedo = 0.5f}), "stiff-noise-furnace"), furnace);
  EXPECT_GT(f.report.lighting.probes, 0);
  EXPECT_LT(f.report.lighting.noise_p95, 1e-3f);
}

} // namespace
} // namespace probebake::test
