// Upload -> frames -> read-back: the buffers come back bit-identical to the volume that went up (the probe
// index build reproduces the baked index exactly), and the live state passes formats::validate() after
// 100 frames. Also through a .probes file, with every section present. The light update is off here (it
// rewrites the probes' irradiance and hit fractions by design; light_update_test.cpp checks that it
// writes nothing else).
#include <cstring>

#include "probebake/formats/probes_file.h"
#include "probebake/formats/validate.h"
#include "runtime_test_util.h"

namespace probebake::test {
namespace {

using RoundTripTest = RuntimeTest;
constexpr runtime::UploadOptions kStatic{.light_update = false};

void expect_identical_after_frames(runtime::Volume& volume, const formats::ProbeVolume& original, int frames) {
  double gpu_ms = 0.0;
  for (int f = 0; f < frames; ++f) {
    auto stats = volume.run_frame();
    ASSERT_TRUE(stats.ok()) << stats.status().message;
    gpu_ms += stats->passes.at(0).gpu_ms;
  }
  formats::ValidationReport report;
  const runtime::Status live = volume.validate_live(&report);
  EXPECT_TRUE(live.ok()) << live.message;
  EXPECT_TRUE(report.valid());
  auto back = volume.read_back();
  ASSERT_TRUE(back.ok()) << back.status().message;
  EXPECT_EQ(formats::write_probes(back.value()), formats::write_probes(original)) << "read-back differs";
  EXPECT_EQ(std::memcmp(&back->info, &original.info, sizeof(gpu::VolumeInfo)), 0);
  EXPECT_EQ(back->probe_index, original.probe_index);
  EXPECT_EQ(back->cells.size(), original.cells.size());
  std::printf("[round trip] %d frames, probe index build mean %.3f ms (GPU), read-back bit-identical and valid\n",
              frames, gpu_ms / frames);
}

TEST_F(RoundTripTest, HundredFramesLeaveTheVolumeBitIdenticalAndValid) {
  auto volume = runtime::Volume::upload(context(), baked_leak_octree(), kStatic);
  ASSERT_TRUE(volume.ok()) << volume.status().message;
  expect_identical_after_frames(volume.value(), baked_leak_octree(), 100);
}

TEST_F(RoundTripTest, EverySectionSurvivesTheRoundTripThroughAFile) {
  const formats::ProbeVolume& full = baked_cornell_full();
  ASSERT_FALSE(full.surfel_batches.empty());
  ASSERT_FALSE(full.leaf_entries.empty());
  const std::string path = temp_path("cornell-full.probes");
  formats::write_probes_file(path, full);
  auto volume = runtime::Volume::load(context(), path, kStatic);
  ASSERT_TRUE(volume.ok()) << volume.status().message;
  const runtime::VolumeBuffers buffers = volume->buffers();
  EXPECT_NE(buffers.surfel_batches.buffer, VK_NULL_HANDLE);
  EXPECT_EQ(buffers.surfel_batches.size, full.surfel_batches.size() * sizeof(gpu::SurfelBatch));
  EXPECT_NE(buffers.leaf_queue_header.buffer, VK_NULL_HANDLE);
  EXPECT_EQ(buffers.leaf_entries.size, full.leaf_entries.size() * sizeof(gpu::LeafEntry));
  expect_identical_after_frames(volume.value(), full, 3);
}

TEST_F(RoundTripTest, SectionsTheFileDoesNotUseGetNoBuffer) {
  auto volume = runtime::Volume::upload(context(), baked_cornell_octree(), kStatic);
  ASSERT_TRUE(volume.ok()) << volume.status().message;
  const runtime::VolumeBuffers buffers = volume->buffers();
  EXPECT_EQ(buffers.surfel_batches.buffer, VK_NULL_HANDLE);
  EXPECT_EQ(buffers.leaf_queue_header.buffer, VK_NULL_HANDLE);
  EXPECT_EQ(buffers.leaf_entries.buffer, VK_NULL_HANDLE);
  EXPECT_EQ(buffers.volume_info.size, sizeof(gpu::VolumeInfo));
  EXPECT_EQ(buffers.probes.size, baked_cornell_octree().probes.size() * sizeof(gpu::Probe));
  expect_identical_after_frames(volume.value(), baked_cornell_octree(), 1);
}

} // namespace
} // namespace probebake::test
