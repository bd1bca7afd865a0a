// The load trace spread over frames (FrameLimits::max_traced_probes, issue #42): each probe slot is traced
// exactly once, in windows of the budget; a probe the window has not reached keeps the bake's irradiance bit
// for bit; and a volume loaded that way converges to the same irradiance as one traced at once, also when a
// light moves while it loads.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "probebake/lighting/lighting.h"
#include "probebake/runtime_types.h"
#include "probebake/samples/scenes.h"
#include "probebake/scene/scene.h"
#include "runtime_test_util.h"

namespace probebake::test {
namespace {

using LoadTraceTest = RuntimeTest;

// The Cornell box (its ceiling emitter) with a white point light above the blocks, baked with 96 rays.
Baked bake_cornell_with_bulb() {
  samples::SceneBuilder scene = samples::cornell();
  scene.add_light_node("bulb", scene.add_light({.name = "bulb", .intensity = 0.3f}), {-0.1f, 0.42f, 0.05f});
  bake::BakeSettings settings = small_bake_settings();
  settings.lighting.rays = 96;
  return bake_generated(scene, "cornell-bulb", settings);
}

// Live probes among slots [first, last).
int live_in(const formats::ProbeVolume& volume, std::size_t first, std::size_t last) {
  int live = 0;
  for (std::size_t i = first; i < std::min(last, volume.probes.size()); ++i) live += volume.probes[i].link != 0;
  return live;
}

TEST_F(LoadTraceTest, ABudgetTracesEachSlotOnceAndKeepsTheBakeUntilTheWindowArrives) {
  const Baked b = bake_cornell_with_bulb();
  const std::size_t capacity = b.volume.probes.size();
  const std::size_t budget = (capacity + 3) / 4; // every slot in four frames
  runtime::Volume gpu = upload_sweeping(context(), b.volume);
  runtime::FrameInputs in;
  in.limits.max_traced_probes = int(budget);
  int traced = 0;
  for (std::size_t f = 0; f < 6; ++f) {
    auto stats = gpu.run_frame(in);
    ASSERT_TRUE(stats.ok()) << stats.status().message;
    const runtime::LightStats& light = stats.value().light;
    const std::size_t done = std::min(capacity, budget * (f + 1));
    EXPECT_EQ(light.traced_probes, live_in(b.volume, budget * f, done)) << "frame " << f;
    EXPECT_EQ(light.untraced_slots, int(capacity - done)) << "frame " << f;
    EXPECT_EQ(light.lit_probes, live_in(b.volume, 0, done)) << "frame " << f; // the others keep their light
    traced += light.traced_probes;
    if (f != 0) continue;
    const formats::ProbeVolume back = read_back(gpu);
    int kept = 0, changed = 0;
    for (std::size_t i = 0; i < capacity; ++i) {
      if (b.volume.probes[i].link == 0) continue;
      const bool same = std::equal(std::begin(back.probes[i].irradiance_sh), std::end(back.probes[i].irradiance_sh),
                                   std::begin(b.volume.probes[i].irradiance_sh));
      if (i >= budget)
        kept += same ? 1 : 0;
      else
        changed += same ? 0 : 1;
    }
    EXPECT_EQ(kept, live_in(b.volume, budget, capacity)); // bit for bit the bake's
    EXPECT_GT(changed, 0);                                // the window's probes were gathered
  }
  EXPECT_EQ(traced, live_in(b.volume, 0, capacity)); // each once
  in.limits.max_traced_probes = -1;
  EXPECT_EQ(gpu.run_frame(in).status().code, runtime::StatusCode::invalid_argument);
}

// UploadOptions::load_focus: the first window traces the live probes nearest the focus (a corner of the root),
// every other probe keeps the bake's bits, and the load still traces each live probe once.
TEST_F(LoadTraceTest, TheLoadFocusTracesTheNearestProbesFirst) {
  const Baked b = bake_cornell_with_bulb();
  const glm::vec3 focus = b.volume.info.root_min;
  auto uploaded = runtime::Volume::upload(context(), b.volume, {.hysteresis = 0.0f, .load_focus = focus});
  ASSERT_TRUE(uploaded.ok()) << uploaded.status().message;
  runtime::Volume& gpu = uploaded.value();
  std::vector<std::pair<float, std::size_t>> live; // (distance², slot), as the runtime orders them
  for (std::size_t i = 0; i < b.volume.probes.size(); ++i)
    if (b.volume.probes[i].link != 0) {
      const glm::vec3 d = b.volume.probes[i].position - focus;
      live.push_back({glm::dot(d, d), i});
    }
  std::sort(live.begin(), live.end());
  const std::size_t budget = live.size() / 4;
  runtime::FrameInputs in;
  in.limits.max_traced_probes = int(budget);
  auto first = gpu.run_frame(in);
  ASSERT_TRUE(first.ok()) << first.status().message;
  EXPECT_EQ(first.value().light.traced_probes, int(budget));
  const formats::ProbeVolume back = read_back(gpu);
  int kept_far = 0, changed_near = 0;
  for (std::size_t k = 0; k < live.size(); ++k) {
    const std::size_t i = live[k].second;
    const bool same = std::equal(std::begin(back.probes[i].irradiance_sh), std::end(back.probes[i].irradiance_sh),
                                 std::begin(b.volume.probes[i].irradiance_sh));
    if (k < budget)
      changed_near += same ? 0 : 1;
    else
      kept_far += same ? 1 : 0;
  }
  EXPECT_EQ(kept_far, int(live.size() - budget)); // the far ones wait, bit for bit the bake's
  EXPECT_GT(changed_near, 0);
  int traced = first.value().light.traced_probes;
  for (int f = 0; f < 8 && traced < int(live.size()); ++f) {
    auto stats = gpu.run_frame(in);
    ASSERT_TRUE(stats.ok()) << stats.status().message;
    traced += stats.value().light.traced_probes;
  }
  EXPECT_EQ(traced, int(live.size()));
  auto bad = runtime::Volume::upload(context(), b.volume, {.load_focus = glm::vec3(NAN, 0.0f, 0.0f)});
  EXPECT_EQ(bad.status().code, runtime::StatusCode::invalid_argument);
}

// A budget lifted midway: the next frame traces every slot left.
TEST_F(LoadTraceTest, LiftingTheBudgetMidwayTracesTheRestAtOnce) {
  const Baked b = bake_cornell_with_bulb();
  const std::size_t capacity = b.volume.probes.size(), budget = capacity / 3;
  runtime::Volume gpu = upload_sweeping(context(), b.volume);
  runtime::FrameInputs in;
  in.limits.max_traced_probes = int(budget);
  auto first = gpu.run_frame(in);
  ASSERT_TRUE(first.ok()) << first.status().message;
  EXPECT_EQ(first.value().light.untraced_slots, int(capacity - budget));
  in.limits.max_traced_probes = 0;
  auto rest = gpu.run_frame(in);
  ASSERT_TRUE(rest.ok()) << rest.status().message;
  EXPECT_EQ(rest.value().light.traced_probes, live_in(b.volume, budget, capacity));
  EXPECT_EQ(rest.value().light.load_window, int(capacity - budget));
  EXPECT_EQ(rest.value().light.untraced_slots, 0);
  EXPECT_EQ(rest.value().light.lit_probes, live_in(b.volume, 0, capacity));
}

// From zero irradiance, with the bulb moved in frame 1 (while the budgeted volume is still loading): both
// volumes reach the CPU bake of the moved light, and each other.
TEST_F(LoadTraceTest, ALoadSpreadOverFramesConvergesLikeATraceAtOnce) {
  Baked b = bake_cornell_with_bulb();
  const formats::ProbeVolume start = with_zero_irradiance(b.volume);
  std::vector<gpu::PunctualLight> moved = b.volume.punctual_lights;
  ASSERT_EQ(moved.size(), 1u);
  moved[0].position = {0.14f, 0.36f, -0.12f};
  b.scene->lights.at(0).position = moved[0].position;
  formats::ProbeVolume cpu = start;
  lighting::bake_lighting(*b.scene, *b.rays, cpu, b.settings.lighting);

  const int budget = int(start.probes.size() + 4) / 5;
  runtime::Volume spread = upload_sweeping(context(), start), at_once = upload_sweeping(context(), start);
  constexpr int kFrames = 80;
  for (int f = 0; f < kFrames; ++f) {
    runtime::FrameInputs in;
    if (f == 1) in.lights = moved;
    for (runtime::Volume* v : {&spread, &at_once}) {
      in.limits.max_traced_probes = v == &spread ? budget : 0;
      auto stats = v->run_frame(in);
      ASSERT_TRUE(stats.ok()) << stats.status().message;
    }
  }
  const formats::ProbeVolume x = read_back(spread), y = read_back(at_once);
  const float spread_vs_cpu = max_sh_difference(x, cpu), at_once_vs_cpu = max_sh_difference(y, cpu);
  const float between = max_sh_difference(x, y);
  std::printf("[load] cornell bulb from zero, %d of %zu slots traced per frame, bulb moved in frame 1, %d frames: "
              "max |SH| difference / brightest DC: spread vs CPU %.2e, at once vs CPU %.2e, spread vs at once %.2e\n",
              budget, start.probes.size(), kFrames, double(spread_vs_cpu), double(at_once_vs_cpu), double(between));
  EXPECT_GT(brightest_dc(cpu), 0.1f);
  EXPECT_LT(spread_vs_cpu, 2e-3f); // the CPU bake stops at an estimated relative error of 1e-4 per probe
  EXPECT_LT(between, 1e-4f);
}

} // namespace
} // namespace probebake::test
