// FrameLimits::frame_ms's controller (runtime/light_update/trace_budget.h) on made-up frame statistics, and on
// the GPU: the load windows it chose, replayed as max_traced_probes, give the same bits.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#include "light_update/trace_budget.h"
#include "probebake/samples/scenes.h"
#include "runtime_test_util.h"

namespace probebake::test {
namespace {

using runtime::detail::TraceBudget;

// A frame of a 1000-slot volume whose load window of `window` slots left `untraced`.
runtime::FrameStats frame(int window, int untraced, double trace_ms, double gather_ms, double other_ms) {
  runtime::FrameStats stats;
  stats.probe_capacity = 1000;
  stats.light.load_window = window;
  stats.light.untraced_slots = untraced;
  stats.passes = {{"probe_index", other_ms}, {"light_trace", trace_ms}, {"light_gather", gather_ms}};
  return stats;
}

TEST(TraceBudgetTest, StartsSmallThenFitsTheSpareTimeAndCorrectsHalfway) {
  TraceBudget budget;
  EXPECT_EQ(budget.next_window(1.0f, 1000), TraceBudget::kFirstWindow);
  EXPECT_EQ(budget.next_window(1.0f, 0), 0u); // nothing left
  // 16 slots traced in 0.32 ms (0.02 a slot) and gathered in 0.016 (0.001 a slot); 0.184 ms of other passes.
  budget.observe(frame(16, 984, 0.32, 0.016, 0.184));
  EXPECT_EQ(budget.next_window(1.0f, 984), 38u); // floor((1 - 0.2) / 0.021)
  EXPECT_EQ(budget.next_window(1.0f, 5), 5u);    // never more than are left
  // 0.04 ms a slot now, gathers 0.003 a slot: both estimates move halfway (0.03, 0.002); other 0.2 -> 0.35.
  budget.observe(frame(38, 946, 1.52, 0.162, 0.338));
  EXPECT_EQ(budget.next_window(1.0f, 946), 20u);   // floor(0.65 / 0.032) (0.35 of other passes)
  budget.observe(frame(20, 926, 0.8, 0.222, 2.0)); // other passes alone over the budget
  EXPECT_EQ(budget.next_window(1.0f, 926), 1u);    // one slot a frame: the load still ends
}

TEST(TraceBudgetTest, FramesWithoutAWindowOrTimestampsChangeNothing) {
  TraceBudget budget;
  budget.observe(frame(0, 1000, 5.0, 0.0, 0.1));   // no load window (a flagged trace)
  budget.observe(frame(16, 984, -1.0, -1.0, 0.1)); // no timestamps
  runtime::FrameStats partial = frame(16, 984, 0.3, 0.01, 0.1);
  partial.passes[0].gpu_ms = -1.0;
  budget.observe(partial);
  EXPECT_EQ(budget.next_window(1.0f, 1000), TraceBudget::kFirstWindow);
}

using TraceBudgetGpuTest = RuntimeTest;

// Twelve frames of a load under frame_ms: every window at least one slot, the slots left are the capacity less
// the windows, and the windows it chose, given back as max_traced_probes frame by frame, reproduce its probes
// bit for bit (the windows depend on the device's speed; the replay does not).
TEST_F(TraceBudgetGpuTest, TheWindowsAFrameBudgetChoseReplayBitForBit) {
  const formats::ProbeVolume& volume = baked_cornell_grid();
  int untraced = -1;
  const auto run = [&](const std::vector<int>* replay, std::vector<int>* windows) {
    auto gpu = runtime::Volume::upload(context(), volume);
    EXPECT_TRUE(gpu.ok()) << gpu.status().message;
    if (!gpu.ok()) return formats::ProbeVolume{};
    for (std::size_t f = 0; f < (replay ? replay->size() : 12u); ++f) {
      runtime::FrameInputs in;
      if (replay)
        in.limits.max_traced_probes = (*replay)[f];
      else
        in.limits.frame_ms = 2.0f;
      auto stats = gpu.value().run_frame(in);
      EXPECT_TRUE(stats.ok()) << stats.status().message;
      if (!stats.ok()) break;
      if (windows) windows->push_back(stats.value().light.load_window);
      if (windows) untraced = stats.value().light.untraced_slots;
    }
    auto back = gpu.value().read_back();
    return back.ok() ? std::move(back).value() : formats::ProbeVolume{};
  };
  std::vector<int> windows;
  const formats::ProbeVolume timed = run(nullptr, &windows);
  ASSERT_FALSE(windows.empty());
  int slots = 0;
  for (int w : windows) slots += w;
  std::printf("[trace budget] cornell grid, %zu slots, 12 frames of 2 ms: windows %d first, %d to %d later, %d "
              "slots left\n",
              volume.probes.size(), windows.front(), *std::min_element(windows.begin() + 1, windows.end()),
              *std::max_element(windows.begin() + 1, windows.end()), untraced);
  EXPECT_EQ(windows.front(), int(TraceBudget::kFirstWindow));
  EXPECT_GE(*std::min_element(windows.begin(), windows.end()), 1);
  EXPECT_EQ(untraced, int(volume.probes.size()) - slots);
  const formats::ProbeVolume replayed = run(&windows, nullptr);
  ASSERT_EQ(timed.probes.size(), replayed.probes.size());
  for (std::size_t i = 0; i < timed.probes.size(); ++i)
    ASSERT_TRUE(std::equal(std::begin(timed.probes[i].irradiance_sh), std::end(timed.probes[i].irradiance_sh),
                           std::begin(replayed.probes[i].irradiance_sh)))
        << "probe " << i;
  runtime::FrameInputs bad;
  bad.limits.frame_ms = -1.0f;
  auto gpu = runtime::Volume::upload(context(), volume);
  ASSERT_TRUE(gpu.ok());
  EXPECT_EQ(gpu.value().run_frame(bad).status().code, runtime::StatusCode::invalid_argument);
}

} // namespace
} // namespace probebake::test
