// Context creation and ownership: the device picked, memory accounting (no leaks), a Volume that outlives its
// Context object, and a Context borrowed from a host that created its own Vulkan objects.
#include <cstring>
#include <vector>

#include <vulkan/vulkan_core.h>

#include "runtime_test_util.h"

namespace probebake::test {
namespace {

using ContextTest = RuntimeTest;

TEST_F(ContextTest, ReportsTheDeviceItRunsOn) {
  const runtime::DeviceInfo& d = context().device_info();
  EXPECT_FALSE(d.name.empty());
  EXPECT_GE(d.api_version, VK_API_VERSION_1_2);
  EXPECT_GE(d.max_storage_buffer_range, 1u << 27); // 128 MiB on lavapipe, more on GPUs
  EXPECT_TRUE(d.validation);
  EXPECT_FALSE(d.borrowed);
  if (d.name.find("llvmpipe") != std::string::npos) {
    EXPECT_EQ(d.type, "cpu");
    EXPECT_TRUE(d.timestamps); // lavapipe's compute queue has timestamps
  }
}

TEST_F(ContextTest, EveryBufferIsFreedWithItsVolume) {
  const runtime::MemoryStats before = context().memory_stats();
  {
    auto volume = runtime::Volume::upload(context(), baked_cornell_full());
    ASSERT_TRUE(volume.ok()) << volume.status().message;
    ASSERT_TRUE(volume->run_frame().ok());
    const runtime::MemoryStats during = context().memory_stats();
    EXPECT_GT(during.live_buffers, before.live_buffers + 9); // 9 sections + scratch + placeholder
    EXPECT_GT(during.live_bytes, before.live_bytes);
  }
  const runtime::MemoryStats after = context().memory_stats();
  EXPECT_EQ(after.live_buffers, before.live_buffers);
  EXPECT_EQ(after.live_bytes, before.live_bytes);
  EXPECT_GE(after.peak_bytes, after.live_bytes);
}

TEST_F(ContextTest, VolumeKeepsTheDeviceAliveAfterTheContextIsGone) {
  auto own = runtime::Context::create(validated_options());
  ASSERT_TRUE(own.ok()) << own.status().message;
  auto volume = runtime::Volume::upload(own.value(), baked_cornell_octree());
  ASSERT_TRUE(volume.ok()) << volume.status().message;
  { runtime::Context gone = std::move(own).value(); }
  auto frame = volume->run_frame();
  ASSERT_TRUE(frame.ok()) << frame.status().message;
  auto back = volume->read_back();
  ASSERT_TRUE(back.ok());
  EXPECT_EQ(back->probe_index, baked_cornell_octree().probe_index);
}

// ---- Borrowed: the host creates instance, device and queue; the runtime must not destroy them. ------------
TEST_F(ContextTest, BorrowsTheHostsDeviceAndLeavesItAlive) {
  HostVulkanObjects host(true);
  ASSERT_TRUE(host.ok());
  {
    auto borrowed = runtime::Context::borrow(host.host());
    ASSERT_TRUE(borrowed.ok()) << borrowed.status().message;
    EXPECT_TRUE(borrowed->device_info().borrowed);
    auto volume = runtime::Volume::upload(borrowed.value(), baked_cornell_octree());
    ASSERT_TRUE(volume.ok()) << volume.status().message;
    auto frame = volume->run_frame();
    ASSERT_TRUE(frame.ok()) << frame.status().message;
    EXPECT_EQ(frame->live_probes, live_probe_count(baked_cornell_octree()));
  }
  // Still usable by the host: the runtime destroyed nothing of it.
  EXPECT_EQ(vkDeviceWaitIdle(host.device), VK_SUCCESS);
}

TEST_F(ContextTest, BorrowRefusesMissingHandles) {
  auto borrowed = runtime::Context::borrow({});
  ASSERT_FALSE(borrowed.ok());
  EXPECT_EQ(borrowed.status().code, runtime::StatusCode::invalid_argument);
  EXPECT_NE(borrowed.status().message.find("borrow"), std::string::npos);
}

} // namespace
} // namespace probebake::test
