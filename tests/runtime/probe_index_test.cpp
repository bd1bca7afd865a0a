// The GPU probe index build (octree thesis §3.2.3) against formats::rebuild_probe_index: baked volumes whose
// uploaded index was scrambled, volumes with freed probes (holes), a large random volume that needs several
// scan chunks, and a volume without probes.
#include <algorithm>
#include <random>

#include "probebake/formats/octree.h"
#include "runtime_test_util.h"

namespace probebake::test {
namespace {

using ProbeIndexTest = RuntimeTest;

// Uploads `volume` with its probe index overwritten by junk, runs `frames` frames and returns the GPU index.
std::vector<std::int32_t> gpu_index(runtime::Context& context, formats::ProbeVolume volume, int frames,
                                    int* live_probes = nullptr) {
  std::fill(volume.probe_index.begin(), volume.probe_index.end(), 12345); // the pass must rewrite all of it
  auto uploaded = runtime::Volume::upload(context, volume, {.validate = false, .light_update = false});
  EXPECT_TRUE(uploaded.ok()) << uploaded.status().message;
  if (!uploaded.ok()) return {};
  for (int f = 0; f < frames; ++f) {
    auto stats = uploaded->run_frame();
    EXPECT_TRUE(stats.ok()) << stats.status().message;
    if (!stats.ok()) return {};
    if (live_probes) *live_probes = stats->live_probes;
    EXPECT_EQ(stats->passes.size(), 1u);
    EXPECT_EQ(stats->passes.at(0).name, "probe_index");
    if (context.device_info().timestamps) {
      EXPECT_GE(stats->passes.at(0).gpu_ms, 0.0);
    }
  }
  auto back = uploaded->read_back();
  EXPECT_TRUE(back.ok()) << back.status().message;
  return back.ok() ? back->probe_index : std::vector<std::int32_t>{};
}

std::vector<std::int32_t> cpu_index(formats::ProbeVolume volume) {
  formats::rebuild_probe_index(volume);
  return volume.probe_index;
}

void expect_gpu_equals_cpu(runtime::Context& context, const formats::ProbeVolume& volume, const char* what) {
  int live = -1;
  const std::vector<std::int32_t> gpu = gpu_index(context, volume, 2, &live);
  const std::vector<std::int32_t> cpu = cpu_index(volume);
  EXPECT_EQ(gpu, cpu) << what;
  EXPECT_EQ(live, live_probe_count(volume)) << what;
  std::printf("[probe index] %s: %zu slots, %d live, GPU == CPU: %s\n", what, volume.probes.size(), live,
              gpu == cpu ? "yes" : "NO");
}

TEST_F(ProbeIndexTest, BakedVolumesMatchTheCpuRebuild) {
  expect_gpu_equals_cpu(context(), baked_cornell_octree(), "cornell octree");
  expect_gpu_equals_cpu(context(), baked_leak_octree(), "leak octree");
  expect_gpu_equals_cpu(context(), baked_cornell_grid(), "cornell grid");
  expect_gpu_equals_cpu(context(), baked_cornell_full(), "cornell with surfels and leaf queue");
}

TEST_F(ProbeIndexTest, FreedProbesLeaveHolesThatTheIndexSkips) {
  formats::ProbeVolume volume = baked_leak_octree();
  {
    formats::Octree octree(volume);
    for (std::size_t p = 0; p < volume.probes.size(); p += 3)
      if (volume.probes[p].link != 0) octree.free_probe(static_cast<int>(p));
  }
  ASSERT_LT(live_probe_count(volume), live_probe_count(baked_leak_octree()));
  expect_gpu_equals_cpu(context(), volume, "leak with every third probe freed");
}

TEST_F(ProbeIndexTest, LargeRandomVolumeNeedsSeveralScanChunks) {
  // 300,000 slots = 293 blocks of 1024 probes: the single-workgroup scan runs three steps of 128 blocks
  // with a carry.
  formats::ProbeVolume volume = baked_cornell_octree();
  std::mt19937 rng(7);
  volume.probes.resize(300000);
  for (gpu::Probe& p : volume.probes) p.link = (rng() % 5 == 0) ? 0 : ~gpu::PROBE_NO_SURFELS;
  for (std::size_t i = 100000; i < 100000 + 3 * 1024; ++i) volume.probes[i].link = 0; // whole empty blocks
  volume.probes.back().link = ~gpu::PROBE_NO_SURFELS;
  volume.probe_index.resize(volume.probes.size() + 1);
  formats::sync_info_counts(volume);
  expect_gpu_equals_cpu(context(), volume, "300k random slots");
}

TEST_F(ProbeIndexTest, AllFreeAndAllLive) {
  formats::ProbeVolume volume = baked_cornell_octree();
  volume.probes.resize(1000);
  volume.probe_index.resize(1001);
  formats::sync_info_counts(volume);
  for (gpu::Probe& p : volume.probes) p.link = 0;
  expect_gpu_equals_cpu(context(), volume, "1000 free slots");
  for (gpu::Probe& p : volume.probes) p.link = ~gpu::PROBE_NO_SURFELS;
  expect_gpu_equals_cpu(context(), volume, "1000 live slots");
}

TEST_F(ProbeIndexTest, VolumeWithoutProbes) {
  gpu::VolumeInfo settings = baked_cornell_octree().info;
  const formats::ProbeVolume empty = formats::make_empty_volume(settings);
  ASSERT_TRUE(empty.probes.empty());
  ASSERT_EQ(empty.probe_index.size(), 1u);
  expect_gpu_equals_cpu(context(), empty, "no probes");
}

} // namespace
} // namespace probebake::test
