// The GPU light update (thesis §3.2.2: runtime/light_update/light_trace.comp, light_gather.comp, light_resolve.comp)
// against the CPU lighting (lighting::bake_lighting): with hysteresis 0 one frame is one Jacobi sweep of the
// bake's iteration, so N frames from zero irradiance must equal N sweeps without extrapolation. Also the
// L1 hit fractions against the bake's placement, the same on double-sided scenes (glTF doubleSided, #19),
// the white furnace converging to pi L / (1 - R) on the
// GPU alone, determinism, and overflow that must not leak NaN/Inf into the probes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <glm/common.hpp>

#include "probebake/bake/bake.h"
#include "probebake/lighting/lighting.h"
#include "probebake/probe_index/lookup.h"
#include "probebake/scene/scene.h"
#include "probebake/formats/probes_file.h"
#include "probebake/formats/validate.h"
#include "probebake/samples/scenes.h"
#include "runtime_test_util.h"

namespace probebake::test {
namespace {

using LightUpdateTest = RuntimeTest;
constexpr float kPi = 3.14159265f;

// Runs `frames` frames; returns the read-back volume and the last frame's statistics.
struct FrameRun {
  formats::ProbeVolume volume;
  std::vector<runtime::FrameStats> frames;
};

FrameRun run_frames(runtime::Context& context, const formats::ProbeVolume& volume, int frames, float hysteresis) {
  auto gpu =
      runtime::Volume::upload(context, volume, {.validate = true, .light_update = true, .hysteresis = hysteresis});
  EXPECT_TRUE(gpu.ok()) << gpu.status().message;
  FrameRun run;
  if (!gpu.ok()) return run;
  for (int f = 0; f < frames; ++f) {
    auto stats = gpu.value().run_frame();
    EXPECT_TRUE(stats.ok()) << stats.status().message;
    if (!stats.ok()) return run;
    run.frames.push_back(stats.value());
  }
  auto back = gpu.value().read_back();
  EXPECT_TRUE(back.ok()) << back.status().message;
  if (back.ok()) run.volume = std::move(back).value();
  return run;
}

// Largest (GPU - CPU) / CPU of a DC term over the live probes lit to at least 1 % of the brightest DC, and
// that probe's height (docs/RUNTIME_INTERNALS.md quotes it for the flipped Cornell box).
struct DcExcess {
  float relative = 0.0f;
  float y = 0.0f;
};
DcExcess largest_dc_excess(const formats::ProbeVolume& gpu, const formats::ProbeVolume& cpu) {
  const float floor = 0.01f * brightest_dc(cpu);
  DcExcess excess;
  for (std::size_t i = 0; i < cpu.probes.size(); ++i) {
    if (cpu.probes[i].link == 0) continue;
    for (int c = 0; c < 3; ++c) {
      const float reference = cpu.probes[i].irradiance_sh[c];
      if (!(reference > floor)) continue;
      const float relative = (gpu.probes[i].irradiance_sh[c] - reference) / reference;
      if (relative > excess.relative) excess = {relative, cpu.probes[i].position.y};
    }
  }
  return excess;
}

bool all_finite(const formats::ProbeVolume& volume) {
  for (const gpu::Probe& p : volume.probes)
    for (float v : p.irradiance_sh)
      if (!std::isfinite(v)) return false;
  return true;
}

// N GPU frames at hysteresis 0 from zero irradiance == N CPU sweeps without extrapolation. Returns the CPU's
// brightest DC term (a test that all is dark would prove nothing).
float expect_gpu_equals_cpu(runtime::Context& context, const Baked& b, const char* name, int sweeps) {
  const formats::ProbeVolume start = with_zero_irradiance(b.volume);
  formats::ProbeVolume cpu = start;
  lighting::LightingSettings lighting = b.settings.lighting;
  lighting.max_iterations = sweeps;
  lighting.accelerate = false;
  lighting.tolerance = 1e-30f; // run exactly `sweeps` sweeps
  const lighting::LightingReport report = lighting::bake_lighting(*b.scene, *b.rays, cpu, lighting);
  EXPECT_EQ(report.iterations, sweeps);
  const FrameRun gpu = run_frames(context, start, sweeps, 0.0f);
  EXPECT_EQ(gpu.frames.size(), std::size_t(sweeps));
  if (gpu.frames.size() != std::size_t(sweeps)) return 0.0f;
  const runtime::LightStats& first = gpu.frames.front().light;
  const float difference = max_sh_difference(gpu.volume, cpu);
  std::printf("[light] %s: %d probes x %d rays, %d sweeps: max |GPU - CPU| / brightest DC (%.3g) = %.2e; front %d "
              "back %d miss %d (CPU back %zu miss %zu), indirect misses GPU %d CPU %zu\n",
              name, report.probes, lighting.rays, sweeps, double(brightest_dc(cpu)), double(difference),
              first.front_hits, first.backface_hits, first.misses, report.backface_hits, report.misses,
              gpu.frames.back().light.indirect_misses, report.indirect_misses);
  const DcExcess excess = largest_dc_excess(gpu.volume, cpu);
  std::printf("[light] %s: largest (GPU - CPU) / CPU of a DC term %.2e, probe at y = %.3g\n", name,
              double(excess.relative), double(excess.y));
  EXPECT_TRUE(first.active);
  EXPECT_EQ(first.traced_probes, report.probes);
  EXPECT_EQ(gpu.frames.back().light.traced_probes, sweeps > 1 ? 0 : report.probes); // L1 runs once
  EXPECT_EQ(first.lit_probes, report.probes);
  EXPECT_EQ(std::size_t(first.front_hits + first.backface_hits + first.misses), report.rays);
  EXPECT_EQ(std::size_t(first.backface_hits), report.backface_hits);
  EXPECT_EQ(std::size_t(first.misses), report.misses);
  EXPECT_EQ(std::size_t(gpu.frames.back().light.indirect_misses), report.indirect_misses);
  EXPECT_EQ(gpu.frames.back().light.non_finite, 0);
  EXPECT_LT(difference, 1e-4f);
  EXPECT_TRUE(all_finite(gpu.volume));
  return brightest_dc(cpu);
}

TEST_F(LightUpdateTest, CornellOctreeFramesEqualCpuSweeps) {
  const Baked b = bake_generated(samples::cornell(), "cornell", small_bake_settings());
  expect_gpu_equals_cpu(context(), b, "cornell octree", 4);
}

TEST_F(LightUpdateTest, CornellGridFramesEqualCpuSweeps) {
  bake::BakeSettings s = small_bake_settings();
  s.placement = bake::Placement::grid;
  s.grid_resolution = 5;
  const Baked b = bake_generated(samples::cornell(), "cornell-grid", s);
  expect_gpu_equals_cpu(context(), b, "cornell grid", 3);
}

TEST_F(LightUpdateTest, PointLightAndLeakFramesEqualCpuSweeps) {
  // Punctual light relit every frame (shadow rays through the BVH), two rooms behind a 2 cm wall.
  const Baked b = bake_generated(samples::leak(), "leak", small_bake_settings());
  expect_gpu_equals_cpu(context(), b, "leak (point light)", 3);
}

TEST_F(LightUpdateTest, EmittersAsProbeContentFramesEqualCpuSweeps) {
  bake::BakeSettings s = small_bake_settings();
  s.lighting.emissive_as_lights = false;
  const Baked b = bake_generated(samples::cornell(), "cornell-emission-in-probes", s);
  expect_gpu_equals_cpu(context(), b, "cornell, emitters in probes", 3);
}

// L1 recomputes every octree probe's hit and back-face fractions; they must match the bake's placement
// up to rays that graze an edge (different BVHs round differently). Returns the probes compared.
int expect_hit_fractions_equal_the_bakes(runtime::Context& context, const Baked& b) {
  formats::ProbeVolume scrambled = b.volume;
  for (gpu::Probe& p : scrambled.probes)
    if (p.link != 0) p.hit_fraction = p.backface_fraction = 0.25f; // the GPU must recompute them
  const FrameRun gpu = run_frames(context, scrambled, 1, 0.5f);
  int compared = 0, different_rays = 0;
  const float ray = 1.0f / float(b.volume.info.surfels_per_probe);
  for (std::size_t i = 0; i < b.volume.probes.size(); ++i) {
    const gpu::Probe& cpu = b.volume.probes[i];
    if (cpu.link == 0 || cpu.node < 0) continue;
    ++compared;
    const float d = std::abs(gpu.volume.probes[i].hit_fraction - cpu.hit_fraction);
    different_rays += int(std::lround(d / ray));
    EXPECT_LE(d, ray * 1.01f) << "probe " << i;
    EXPECT_NEAR(gpu.volume.probes[i].backface_fraction, cpu.backface_fraction, 0.05f) << "probe " << i;
  }
  std::printf("[light] hit fractions: %d octree probes, %d lattice rays judged differently in all\n", compared,
              different_rays);
  EXPECT_GT(compared, 10);
  EXPECT_LE(different_rays, compared / 10);
  return compared;
}

TEST_F(LightUpdateTest, HitFractionsEqualTheBakesPlacement) {
  expect_hit_fractions_equal_the_bakes(context(), bake_generated(samples::cornell(), "cornell", small_bake_settings()));
}

// ---- glTF doubleSided (#19) -------------------------------------------------------------------------------
// The GPU's rule must be the CPU's (docs/LIGHTING.md): the back of a double-sided triangle is a front hit
// with the reversed normal (shaded, emitting), only the back of a single-sided one is inside a solid, and
// a double-sided emitter patch lights both sides.

// The Cornell box as the glTF spec sees it with every triangle's winding reversed and every material
// double-sided: the same scene, so the same light (issue #19's measurement: today 0 irradiance).
samples::SceneBuilder flipped_double_sided(const samples::SceneBuilder& source) {
  samples::SceneBuilder out(source.scene_name() + "-flipped");
  for (samples::Material m : source.materials()) {
    m.double_sided = true;
    out.add_material(m);
  }
  std::vector<samples::MeshId> meshes;
  for (const samples::SceneBuilder::MeshEntry& mesh : source.meshes()) {
    std::vector<samples::Primitive> primitives = mesh.primitives;
    for (samples::Primitive& p : primitives) p.geometry = samples::flipped(p.geometry);
    meshes.push_back(out.add_mesh(mesh.name, primitives));
  }
  for (int root : source.roots()) {
    const samples::SceneBuilder::NodeEntry& node = source.nodes()[std::size_t(root)];
    EXPECT_TRUE(node.mesh && node.children.empty() && !node.light) << node.name; // all the Cornell box has
    if (node.mesh) out.add_mesh_node(node.name, meshes[std::size_t(node.mesh->index)], node.transform);
  }
  return out;
}

// A 2 m room (single-sided walls facing in), a single-sided solid block on the floor, a single-sided
// screen facing the back wall (most of the room sees its back: back-face records), and a double-sided
// emissive panel hanging at 1.4 m whose front faces the ceiling: everything below sees only its back.
samples::SceneBuilder room_with_panel_seen_from_behind() {
  samples::SceneBuilder scene("panel-from-behind");
  const samples::MaterialId wall = scene.add_material({"wall", glm::vec3(0.6f), {}});
  const samples::MaterialId block = scene.add_material({"block", {0.3f, 0.5f, 0.7f}, {}});
  const samples::MaterialId panel = scene.add_material({"panel", glm::vec3(0.5f), {6.0f, 5.0f, 4.0f}, true});
  const auto add = [&](const char* name, const samples::MeshData& mesh, samples::MaterialId material) {
    scene.add_mesh_node(name, scene.add_mesh(name, mesh, material));
  };
  add("room", samples::box({-1, 0, -1}, {1, 2, 1}, samples::Facing::inward), wall);
  // Lifted off the floor: a bottom face in the floor's plane would be sealed (left out of placement but not
  // of the runtime's triangles), and probes inside the block would then judge its back faces differently.
  add("block", samples::box({0.2f, 0.05f, 0.2f}, {0.7f, 0.6f, 0.7f}, samples::Facing::outward), block);
  add("screen", samples::quad({-0.8f, 0.2f, -0.3f}, {0, 0.8f, 0}, {0.6f, 0, 0}), wall); // front: -z
  add("panel", samples::quad({-0.4f, 1.4f, 0.3f}, {0.7f, 0, 0}, {0, 0, -0.6f}), panel); // front: +y
  return scene;
}

// With back faces black (the bug of #19) these scenes are dark: the flipped Cornell box's probes hold 0.
constexpr float kLitDc = 0.1f;

TEST_F(LightUpdateTest, DoubleSidedCornellFramesEqualCpuSweeps) {
  const Baked b = bake_generated(flipped_double_sided(samples::cornell()), "cornell-flipped", small_bake_settings());
  ASSERT_FALSE(b.volume.trace_faces.empty());
  for (const gpu::TraceFace& f : b.volume.trace_faces) ASSERT_NE(f.material & gpu::TRACE_FACE_DOUBLE_SIDED, 0u);
  EXPECT_GT(expect_gpu_equals_cpu(context(), b, "cornell flipped, double-sided", 4), kLitDc);
}

TEST_F(LightUpdateTest, DoubleSidedCornellEmittersInProbesFramesEqualCpuSweeps) {
  bake::BakeSettings s = small_bake_settings();
  s.lighting.emissive_as_lights = false;
  const Baked b = bake_generated(flipped_double_sided(samples::cornell()), "cornell-flipped-emission", s);
  EXPECT_GT(expect_gpu_equals_cpu(context(), b, "cornell flipped, emitters in probes", 3), kLitDc);
}

TEST_F(LightUpdateTest, DoubleSidedEmitterSeenFromBehindFramesEqualCpuSweeps) {
  const Baked b = bake_generated(room_with_panel_seen_from_behind(), "panel", small_bake_settings());
  int flagged_patches = 0;
  for (const gpu::EmitterPatch& p : b.volume.emitter_patches)
    flagged_patches += p.flags == gpu::EMITTER_DOUBLE_SIDED ? 1 : 0;
  EXPECT_GT(flagged_patches, 0);
  EXPECT_EQ(std::size_t(flagged_patches), b.volume.emitter_patches.size());
  EXPECT_GT(expect_gpu_equals_cpu(context(), b, "panel seen from behind", 3), kLitDc);
  bake::BakeSettings s = small_bake_settings();
  s.lighting.emissive_as_lights = false;
  EXPECT_GT(expect_gpu_equals_cpu(context(), bake_generated(room_with_panel_seen_from_behind(), "panel-emission", s),
                                  "panel seen from behind, emitters in probes", 3),
            kLitDc);
}

TEST_F(LightUpdateTest, DoubleSidedHitFractionsEqualTheBakesPlacement) {
  expect_hit_fractions_equal_the_bakes(
      context(), bake_generated(flipped_double_sided(samples::cornell()), "cornell-flipped", small_bake_settings()));
  expect_hit_fractions_equal_the_bakes(
      context(), bake_generated(room_with_panel_seen_from_behind(), "panel", small_bake_settings()));
}

// The white furnace on the GPU alone: from zero, frames at hysteresis 0 converge to pi L / (1 - R) (the
// probes hold all but the walls' own pi L, which shading points add as area lights).
void expect_gpu_furnace(runtime::Context& context, float albedo, int frames) {
  bake::BakeSettings s = small_bake_settings();
  s.placement = bake::Placement::grid;
  s.grid_resolution = 2;
  s.svo_depth = 3;
  s.lighting.rays = 128;
  const Baked b = bake_generated(samples::furnace({.albedo = albedo, .emission = 1.0f}), "furnace", s);
  const FrameRun gpu = run_frames(context, with_zero_irradiance(b.volume), frames, 0.0f);
  const float expected = kPi / (1.0f - albedo);
  float worst = 0.0f;
  int probes = 0;
  for (const gpu::Probe& p : gpu.volume.probes) {
    if (p.link == 0) continue;
    ++probes;
    for (const glm::vec3 n :
         {glm::vec3(1, 0, 0), glm::vec3(0, -1, 0), glm::vec3(0, 0, 1), glm::vec3(0.6f, 0.0f, -0.8f)}) {
      const glm::vec3 e = kPi + probe_index::evaluate_sh(p.irradiance_sh, n);
      worst = std::max(
          worst,
          glm::max(glm::max(std::abs(e.x - expected), std::abs(e.y - expected)), std::abs(e.z - expected)) / expected);
    }
  }
  std::printf("[light] GPU furnace R = %.2f: %d probes, %d frames, max relative error %.2e (pi L / (1 - R) = %.3f)\n",
              double(albedo), probes, frames, double(worst), double(expected));
  EXPECT_GT(probes, 0);
  EXPECT_LT(worst, 0.01f);
}

TEST_F(LightUpdateTest, FurnaceConvergesOnTheGpuHalf) { expect_gpu_furnace(context(), 0.5f, 30); }
TEST_F(LightUpdateTest, FurnaceConvergesOnTheGpuStiff) { expect_gpu_furnace(context(), 0.99f, 700); }

TEST_F(LightUpdateTest, SameInputSameBits) {
  const Baked b = bake_generated(samples::cornell(), "cornell", small_bake_settings());
  const FrameRun one = run_frames(context(), b.volume, 5, 0.9f);
  const FrameRun two = run_frames(context(), b.volume, 5, 0.9f);
  ASSERT_EQ(one.volume.probes.size(), two.volume.probes.size());
  for (std::size_t i = 0; i < one.volume.probes.size(); ++i)
    for (int v = 0; v < gpu::PROBE_SH_FLOATS; ++v)
      ASSERT_EQ(one.volume.probes[i].irradiance_sh[v], two.volume.probes[i].irradiance_sh[v]);
}

TEST_F(LightUpdateTest, LiveStateValidAfterEveryFrameOfAHundred) {
  const Baked b = bake_generated(samples::cornell(), "cornell", small_bake_settings());
  auto gpu = runtime::Volume::upload(context(), b.volume);
  ASSERT_TRUE(gpu.ok()) << gpu.status().message;
  for (int f = 0; f < 100; ++f) {
    auto stats = gpu.value().run_frame();
    ASSERT_TRUE(stats.ok()) << stats.status().message;
    ASSERT_TRUE(stats.value().light.active);
    const runtime::Status valid = gpu.value().validate_live();
    ASSERT_TRUE(valid.ok()) << "frame " << f << ": " << valid.message;
  }
  // The light update writes the probes' irradiance and hit fractions and nothing else.
  auto back = gpu.value().read_back();
  ASSERT_TRUE(back.ok());
  formats::ProbeVolume expected = b.volume;
  for (std::size_t i = 0; i < expected.probes.size(); ++i) {
    const gpu::Probe& live = back.value().probes[i];
    std::copy(std::begin(live.irradiance_sh), std::end(live.irradiance_sh), expected.probes[i].irradiance_sh);
    expected.probes[i].hit_fraction = live.hit_fraction;
    expected.probes[i].backface_fraction = live.backface_fraction;
  }
  EXPECT_EQ(formats::write_probes(back.value()), formats::write_probes(expected));
}

TEST_F(LightUpdateTest, StartingFromTheBakeStaysAtTheBake) {
  // The bake's probes are the converged fixed point: GPU frames may move them by rounding only.
  const Baked b = bake_generated(samples::cornell(), "cornell", small_bake_settings());
  const FrameRun gpu = run_frames(context(), b.volume, 20, 0.0f);
  const float difference = max_sh_difference(gpu.volume, b.volume);
  std::printf("[light] cornell: 20 GPU frames from the bake's converged probes: max change %.2e of the brightest DC\n",
              double(difference));
  EXPECT_LT(difference, 2e-3f); // the bake stops at an estimated relative error of 1e-4 per probe
}

TEST_F(LightUpdateTest, VolumesWithoutLightingSectionsRunNoLightPasses) {
  bake::BakeSettings s = small_bake_settings();
  s.runtime_lighting = false;
  const Baked b = bake_generated(samples::cornell(), "cornell", s);
  ASSERT_FALSE(b.volume.lighting.has_value());
  auto gpu = runtime::Volume::upload(context(), b.volume);
  ASSERT_TRUE(gpu.ok()) << gpu.status().message;
  auto stats = gpu.value().run_frame();
  ASSERT_TRUE(stats.ok());
  EXPECT_FALSE(stats.value().light.active);
  ASSERT_EQ(stats.value().passes.size(), 1u);
  EXPECT_EQ(stats.value().passes[0].name, "probe_index");
  // light_update = false leaves out the passes and their buffers (records in one page here, next irradiance,
  // trace flags, light list, relight changes, tracked punctual, counters on the device, and on the host once
  // per frame in flight) for a volume that has the sections.
  const Baked lit = bake_generated(samples::cornell(), "cornell", small_bake_settings());
  const auto buffers_for = [&](bool light_update) {
    const std::size_t before = context().memory_stats().live_buffers;
    auto v = runtime::Volume::upload(context(), lit.volume, {.light_update = light_update});
    EXPECT_TRUE(v.ok());
    if (!v.ok()) return std::size_t(0);
    auto frame = v.value().run_frame();
    EXPECT_TRUE(frame.ok());
    EXPECT_EQ(frame.ok() && frame.value().light.active, light_update);
    return context().memory_stats().live_buffers - before;
  };
  const std::size_t off = buffers_for(false), on = buffers_for(true);
  EXPECT_EQ(on, off + 7 + std::size_t(runtime::UploadOptions{}.frames_in_flight));
}

TEST_F(LightUpdateTest, BadHysteresisIsInvalidArgument) {
  const Baked b = bake_generated(samples::cornell(), "cornell", small_bake_settings());
  for (float h : {-0.1f, 1.0f, std::nanf("")}) {
    auto gpu = runtime::Volume::upload(context(), b.volume, {.hysteresis = h});
    ASSERT_FALSE(gpu.ok());
    EXPECT_EQ(gpu.status().code, runtime::StatusCode::invalid_argument);
  }
}

TEST_F(LightUpdateTest, OverflowingEmissionNeverLeavesNonFiniteProbes) {
  // Emission near float max: the CPU bake refuses it (Error(input)); baked without lighting, the GPU
  // overflows to Inf while gathering and must keep the probes' old, finite values and count them.
  bake::BakeSettings s = small_bake_settings();
  s.lighting.enabled = false;
  const Baked b = bake_generated(samples::furnace({.albedo = 0.9f, .emission = 3.0e38f}), "furnace-overflow", s);
  const FrameRun gpu = run_frames(context(), b.volume, 3, 0.0f);
  ASSERT_FALSE(gpu.frames.empty());
  int non_finite = 0;
  for (const auto& f : gpu.frames) non_finite += f.light.non_finite;
  std::printf("[light] overflow furnace: %d probe updates refused as non-finite over 3 frames\n", non_finite);
  EXPECT_GT(non_finite, 0);
  EXPECT_TRUE(all_finite(gpu.volume));
}

} // namespace
} // namespace probebake::test
