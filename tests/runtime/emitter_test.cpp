// Emitters at run time (FrameInputs::emitters, issue #43): the host switches and dims emissive materials, and the
// GPU's probes converge to the CPU bake of the scene with those emissions (bound 2e-3 of the brightest DC, the
// bake's own stopping error, as the sky and moved-light tests); switched off and on again, they return to where
// they were within 1e-4 of the brightest DC.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "probebake/lighting/lighting.h"
#include "probebake/samples/geometry.h"
#include "probebake/samples/scene_builder.h"
#include "runtime_test_util.h"

namespace probebake::test {
namespace {

using EmitterTest = RuntimeTest;

constexpr int kLampA = 1, kLampB = 2; // glTF material indices (white is 0)

// A shut 4 x 2.5 x 4 m room (albedo 0.7) lit by two 40 cm ceiling lamps of their own materials, each 8 triangles.
samples::SceneBuilder two_lamps() {
  using samples::Facing;
  samples::SceneBuilder scene("two-lamps");
  const samples::MaterialId white = scene.add_material({"white", glm::vec3(0.7f), {}});
  const samples::MaterialId a = scene.add_material({"lamp_a", glm::vec3(0.0f), glm::vec3(20.0f, 18.0f, 15.0f)});
  const samples::MaterialId b = scene.add_material({"lamp_b", glm::vec3(0.0f), glm::vec3(5.0f, 8.0f, 12.0f)});
  scene.add_mesh_node("room", scene.add_mesh("room", samples::box({-2, 0, -2}, {2, 2.5f, 2}, Facing::inward), white));
  // Edges +X then +Z: the lamps face down.
  const glm::vec3 u(0.4f, 0, 0), v(0, 0, 0.4f);
  scene.add_mesh_node("lamp_a", scene.add_mesh("lamp_a", samples::quad({-1.2f, 2.49f, -0.2f}, u, v, 2), a));
  scene.add_mesh_node("lamp_b", scene.add_mesh("lamp_b", samples::quad({0.8f, 2.49f, -0.2f}, u, v, 2), b));
  return scene;
}

// One patch per emissive triangle (k = 1 whatever the power), so that a bake with one lamp dimmed has the other
// lamp's patches unchanged: the CPU references then differ from the GPU only by what the runtime changes.
Baked bake_two_lamps() {
  bake::BakeSettings settings = small_bake_settings();
  settings.lighting.emitter_samples = 1;
  return bake_generated(two_lamps(), "two-lamps", settings);
}

// The CPU bake with each lamp's emission times its scale.
formats::ProbeVolume cpu_bake_with(Baked& b, glm::vec3 scale_a, glm::vec3 scale_b) {
  scene::Scene& scene = *b.scene;
  const std::vector<glm::vec3> emission = scene.triangle_emission;
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
    const int material = int(scene.triangle_material[t]);
    if (material == kLampA) scene.triangle_emission[t] *= scale_a;
    if (material == kLampB) scene.triangle_emission[t] *= scale_b;
  }
  formats::ProbeVolume cpu = b.volume;
  lighting::bake_lighting(scene, *b.rays, cpu, b.settings.lighting);
  scene.triangle_emission = emission;
  return cpu;
}

bool relit(const runtime::FrameStats& stats) {
  return std::any_of(stats.passes.begin(), stats.passes.end(), [](const auto& p) { return p.name == "light_relight"; });
}

// `frames` frames, `change` in the first: a change of strengths relights there, and the next frame changes nothing.
void run_with(runtime::Volume& volume, const runtime::FrameInputs& change, int frames) {
  for (int f = 0; f < frames; ++f) {
    auto stats = volume.run_frame(f == 0 ? change : runtime::FrameInputs{});
    ASSERT_TRUE(stats.ok()) << stats.status().message;
    if (f == 0 && !change.emitters.empty()) {
      EXPECT_TRUE(relit(stats.value()));
    }
    if (f == 1) {
      EXPECT_FALSE(relit(stats.value()));
    }
  }
}

runtime::FrameInputs strengths(glm::vec3 a, glm::vec3 b) {
  runtime::FrameInputs in;
  in.emitters = {{kLampA, a}, {kLampB, b}};
  return in;
}

TEST_F(EmitterTest, ALampSwitchedOffMatchesTheBakeWithoutItAndReturnsWhenOn) {
  Baked b = bake_two_lamps();
  ASSERT_EQ(b.volume.emitter_patches.size(), 16u);
  runtime::Volume gpu = upload_sweeping(context(), b.volume);
  ASSERT_EQ(std::vector<int>(gpu.emitter_materials().begin(), gpu.emitter_materials().end()),
            (std::vector<int>{kLampA, kLampB}));
  run_with(gpu, {}, 40);
  const formats::ProbeVolume before = read_back(gpu);

  const formats::ProbeVolume without_a = cpu_bake_with(b, glm::vec3(0.0f), glm::vec3(1.0f));
  run_with(gpu, strengths(glm::vec3(0.0f), glm::vec3(1.0f)), 60);
  const float off = max_sh_difference(read_back(gpu), without_a);
  run_with(gpu, strengths(glm::vec3(1.0f), glm::vec3(1.0f)), 60);
  const formats::ProbeVolume after = read_back(gpu);
  const float back = max_sh_difference(after, before), file = max_sh_difference(after, b.volume);
  std::printf("[emitters] lamp A off: the bakes differ by %.3g of the brightest DC, GPU vs CPU %.2e; on again: "
              "%.2e from before, %.2e from the file\n",
              double(max_sh_difference(without_a, b.volume)), double(off), double(back), double(file));
  EXPECT_GT(max_sh_difference(without_a, b.volume), 0.1f); // lamp A matters
  EXPECT_LT(off, 2e-3f);
  EXPECT_LT(back, 1e-4f);
  EXPECT_TRUE(gpu.validate_live().ok());
}

// Per channel, both lamps at once; relit at once or a quarter of the probes a frame (FrameLimits::relight_frames),
// and probes the load trace reaches after the change trace with the new strengths.
TEST_F(EmitterTest, DimmedLampsMatchTheCpuBakeAlsoForProbesTracedAfterTheChange) {
  Baked b = bake_two_lamps();
  const glm::vec3 a(0.25f, 0.5f, 1.0f), lamp_b(2.0f, 0.0f, 0.5f);
  const formats::ProbeVolume cpu = cpu_bake_with(b, a, lamp_b);
  runtime::Volume relit_later = upload_sweeping(context(), b.volume),
                  traced_later = upload_sweeping(context(), b.volume),
                  by_quarter = upload_sweeping(context(), b.volume);
  run_with(relit_later, {}, 2);
  run_with(relit_later, strengths(a, lamp_b), 60);
  runtime::FrameInputs quarter = strengths(a, lamp_b);
  quarter.limits.relight_frames = 4;
  for (int f = 0; f < 62; ++f) {
    if (f == 3) quarter.emitters.clear(); // changed in frame 2, after the load trace
    ASSERT_TRUE(by_quarter.run_frame(f < 2 ? runtime::FrameInputs{} : quarter).ok());
  }
  runtime::FrameInputs windowed = strengths(a, lamp_b);
  windowed.limits.max_traced_probes = 4; // the load trace after the change, 4 slots a frame
  runtime::FrameInputs later;
  later.limits = windowed.limits;
  for (int f = 0; f < 80; ++f) {
    auto stats = traced_later.run_frame(f == 0 ? windowed : later);
    ASSERT_TRUE(stats.ok()) << stats.status().message;
  }
  const float relit_error = max_sh_difference(read_back(relit_later), cpu);
  const float traced_error = max_sh_difference(read_back(traced_later), cpu);
  const float quarter_error = max_sh_difference(read_back(by_quarter), cpu);
  std::printf("[emitters] lamps dimmed per channel: GPU vs CPU %.2e relit, %.2e a quarter a frame, %.2e traced after "
              "the change\n",
              double(relit_error), double(quarter_error), double(traced_error));
  EXPECT_LT(relit_error, 2e-3f);
  EXPECT_LT(quarter_error, 2e-3f);
  EXPECT_LT(traced_error, 2e-3f);
}

TEST_F(EmitterTest, BadStrengthsAreInvalidArguments) {
  Baked b = bake_two_lamps();
  runtime::Volume gpu = upload_sweeping(context(), b.volume);
  const auto refused = [&](runtime::FrameInputs in, const char* says) {
    const auto stats = gpu.run_frame(in);
    ASSERT_FALSE(stats.ok());
    EXPECT_EQ(stats.status().code, runtime::StatusCode::invalid_argument);
    EXPECT_NE(stats.status().message.find(says), std::string::npos) << stats.status().message;
  };
  refused(strengths(glm::vec3(-1.0f), glm::vec3(1.0f)), "emitters[0]: scale");
  refused(strengths(glm::vec3(1.0f), glm::vec3(std::nanf(""))), "emitters[1]: scale");
  runtime::FrameInputs white;
  white.emitters = {{0, glm::vec3(1.0f)}};
  refused(white, "material 0 is no emitter");

  // Emitters in the probes: no patches, so nothing to switch.
  bake::BakeSettings settings = small_bake_settings();
  settings.lighting.emissive_as_lights = false;
  const Baked in_probes = bake_generated(two_lamps(), "two-lamps-in-probes", settings);
  runtime::Volume carried = upload_sweeping(context(), in_probes.volume);
  EXPECT_TRUE(carried.emitter_materials().empty());
  const auto stats = carried.run_frame(strengths(glm::vec3(0.0f), glm::vec3(0.0f)));
  ASSERT_FALSE(stats.ok());
  EXPECT_NE(stats.status().message.find("--emitters-in-probes"), std::string::npos) << stats.status().message;
}

} // namespace
} // namespace probebake::test
