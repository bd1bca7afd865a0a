// The sky at run time (FrameInputs::sky, issue #43): the host changes the sky map, its radiance and the sun, and
// the GPU's probes converge to the CPU bake of the scene under the new sky (bound 2e-3 of the brightest DC, the
// bake's own stopping error, as the moved-light tests); the sky alone lighting a scene scales its probes exactly.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <vector>

#include "probebake/lighting/lighting.h"
#include "probebake/samples/scenes.h"
#include "probebake/scene/scene.h"
#include "probebake/sky/sky.h"
#include "runtime_test_util.h"

namespace probebake::test {
namespace {

using SkyTest = RuntimeTest;

formats::ProbeVolume cpu_converged(const Baked& b) {
  formats::ProbeVolume cpu = b.volume;
  lighting::bake_lighting(*b.scene, *b.rays, cpu, b.settings.lighting);
  return cpu;
}

// The probes above the courtyard's ground (y > 0) only. The grid also puts probes under its single-sided ground,
// where they see the blocks' bottom faces: the CPU bake lights them with the sealed faces culled
// (placement::without_sealed), the GPU traces every face, and they differ there with or without a sky (the test
// prints by how much); no receiver is there.
formats::ProbeVolume above_ground(formats::ProbeVolume v) {
  for (gpu::Probe& p : v.probes)
    if (p.position.y <= 0.0f) p.link = 0;
  return v;
}

// `frames` frames, `change` in frame 5: after the load trace, so that light_sky relights the kept records.
void run_with(runtime::Volume& volume, const runtime::FrameInputs& change, int frames) {
  for (int f = 0; f < frames; ++f) {
    auto stats = volume.run_frame(f == 5 ? change : runtime::FrameInputs{});
    ASSERT_TRUE(stats.ok()) << stats.status().message;
    // The change relights in frame 5 (light_sky, and light_relight's sun), and the frame after changes nothing.
    const auto& passes = stats->passes;
    const bool relit =
        std::any_of(passes.begin(), passes.end(), [](const auto& p) { return p.name == "light_relight"; });
    if (f == 5 && change.sky) {
      EXPECT_TRUE(relit);
    }
    if (f == 6) {
      EXPECT_FALSE(relit);
    }
  }
}

TEST_F(SkyTest, SunAndSkyMovedMatchTheCpuBakeOfTheNewHour) {
  bake::BakeSettings settings = small_bake_settings();
  settings.lighting.rays = 96;
  const sky::PhysicalSky morning{sky::direction_from_angles(20.0f, 80.0f), 2.5f};
  const sky::PhysicalSky noon{sky::direction_from_angles(60.0f, 170.0f), 2.5f};
  Baked b = bake_generated(samples::courtyard(), "courtyard-sky", settings, sky::physical_sky(morning));
  ASSERT_FALSE(b.volume.sky.empty());
  ASSERT_EQ(b.scene->sun_light, 0);

  runtime::Volume gpu = upload_sweeping(context(), b.volume);
  ASSERT_TRUE(gpu.sky().has_value());
  EXPECT_EQ(gpu.sky()->kind, gpu::SKY_KIND_PHYSICAL);
  runtime::FrameInputs in;
  const sky::Sky noon_sky = sky::physical_sky(noon);
  in.sky = runtime::SkyInput{glm::vec3(1.0f), noon_sky.map.texels};
  in.lights.emplace(gpu.lights().begin(), gpu.lights().end());
  (*in.lights)[0].direction = -noon.sun_direction;
  (*in.lights)[0].intensity = sky::sun_irradiance(noon);
  scene::set_sky(*b.scene, noon_sky);
  const formats::ProbeVolume cpu = cpu_converged(b);
  run_with(gpu, in, 60);
  const formats::ProbeVolume all = read_back(gpu), live = above_ground(all), target = above_ground(cpu);
  const float moved_by = max_sh_difference(above_ground(b.volume), target), after = max_sh_difference(live, target);
  std::printf("[sky] courtyard 8:00 -> 12:00: the bakes differ by %.3g of the brightest DC; GPU vs CPU after 60 "
              "frames %.2e above the ground, %.3g with the probes under it\n",
              double(moved_by), double(after), double(max_sh_difference(all, cpu)));
  EXPECT_GT(moved_by, 0.05f); // the new hour matters
  EXPECT_LT(after, 2e-3f);
  EXPECT_TRUE(gpu.validate_live().ok());
}

// Light is linear in the sky: 60 frames with the sky's radiance doubled give twice the probes of 60 frames
// without the change, to rounding, under-ground probes included (the GPU against itself).
TEST_F(SkyTest, SkyRadianceScalesASkyLitSceneExactly) {
  bake::BakeSettings settings = small_bake_settings();
  settings.placement = bake::Placement::grid;
  settings.grid_resolution = 5;
  const Baked b = bake_generated(samples::courtyard(), "courtyard-constant-sky", settings,
                                 sky::constant_sky(glm::vec3(1.0f, 0.5f, 0.25f))); // the sky is the only light
  EXPECT_TRUE(b.volume.sky.empty());                                               // a constant sky needs no map
  runtime::Volume same = upload_sweeping(context(), b.volume), brighter = upload_sweeping(context(), b.volume);
  run_with(same, {}, 60);
  runtime::FrameInputs in;
  in.sky = runtime::SkyInput{glm::vec3(2.0f, 1.0f, 0.5f)};
  run_with(brighter, in, 60);
  formats::ProbeVolume doubled = read_back(same);
  for (gpu::Probe& p : doubled.probes)
    for (float& c : p.irradiance_sh) c *= 2.0f;
  const float after = max_sh_difference(read_back(brighter), doubled);
  std::printf("[sky] courtyard, constant sky doubled: twice the unchanged run within %.2e\n", double(after));
  EXPECT_LT(after, 1e-5f);
}

// FrameLimits::relight_frames 4: the sun and the sky moving every frame relight a quarter of the probes each frame.
// Three frames after they stop, or at once when another light changes, every record is that of a run relit every
// frame: after the bounces settle the probes agree to rounding.
TEST_F(SkyTest, SunAndSkyRelitOverFramesSettleToTheRunRelitEveryFrame) {
  bake::BakeSettings settings = small_bake_settings();
  settings.lighting.rays = 96;
  const Baked b = bake_generated(samples::courtyard(), "courtyard-spread", settings,
                                 sky::physical_sky({sky::direction_from_angles(20.0f, 80.0f), 2.5f}));
  runtime::Volume exact = upload_sweeping(context(), b.volume, 1), spread = upload_sweeping(context(), b.volume, 1);
  const auto both = [&](runtime::FrameInputs in) {
    ASSERT_TRUE(exact.run_frame(in).ok());
    in.limits.relight_frames = 4;
    const auto stats = spread.run_frame(in);
    ASSERT_TRUE(stats.ok()) << stats.status().message;
  };
  const auto sun_at = [&](float elevation) {
    runtime::FrameInputs in;
    in.lights.emplace(exact.lights().begin(), exact.lights().end());
    const sky::PhysicalSky sun{sky::direction_from_angles(elevation, 80.0f + elevation), 2.5f};
    (*in.lights)[0].direction = -sun.sun_direction;
    (*in.lights)[0].intensity = sky::sun_irradiance(sun);
    in.sky = runtime::SkyInput{glm::vec3(elevation / 20.0f)}; // the map scaled: light_sky runs as for a new map
    return in;
  };
  for (int f = 0; f < 3; ++f) both({});
  for (int f = 0; f < 30; ++f) both(sun_at(20.0f + 1.5f * float(f))); // 1.5 degrees a frame
  const float moving = max_sh_difference(read_back(spread), read_back(exact));
  for (int f = 0; f < 40; ++f) both({});
  const float stopped = max_sh_difference(read_back(spread), read_back(exact));
  for (int f = 0; f < 5; ++f) both(sun_at(70.0f - 1.5f * float(f)));
  runtime::FrameInputs lamp = sun_at(62.5f); // the sun and a new light in one frame: every whole sum
  gpu::PunctualLight point{};
  point.position = glm::vec3(0.0f, 3.0f, 0.0f);
  point.type = gpu::LIGHT_POINT;
  point.intensity = glm::vec3(50.0f);
  lamp.lights->push_back(point);
  both(lamp);
  for (int f = 0; f < 40; ++f) both({});
  const float interrupted = max_sh_difference(read_back(spread), read_back(exact));
  std::printf("[sky] sun and sky relit over 4 frames against every frame: %.2e of the brightest DC while the sun "
              "moves 1.5 degrees a frame, %.2e after it stopped, %.2e after another light interrupted it\n",
              double(moving), double(stopped), double(interrupted));
  EXPECT_GT(moving, stopped); // the windows lag while it moves
  EXPECT_LT(moving, 0.08f);
  EXPECT_LT(stopped, 1e-5f);
  EXPECT_LT(interrupted, 1e-5f);
}

TEST_F(SkyTest, BadSkiesAreInvalidArguments) {
  bake::BakeSettings settings = small_bake_settings();
  settings.lighting.rays = 16;
  settings.placement = bake::Placement::grid;
  settings.grid_resolution = 3;
  const Baked b = bake_generated(samples::plane_light(), "plane-bad-sky", settings, sky::constant_sky(glm::vec3(1.0f)));
  runtime::Volume gpu = upload_sweeping(context(), b.volume);
  runtime::FrameInputs in;
  in.sky = runtime::SkyInput{glm::vec3(-1.0f, 0.0f, 0.0f)};
  EXPECT_EQ(gpu.run_frame(in).status().code, runtime::StatusCode::invalid_argument);
  in.sky = runtime::SkyInput{glm::vec3(1.0f), std::vector<glm::vec3>(8, glm::vec3(1.0f))}; // the file has no map
  const auto refused = gpu.run_frame(in);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.status().message.find("no sky section"), std::string::npos) << refused.status().message;
}

} // namespace
} // namespace probebake::test
