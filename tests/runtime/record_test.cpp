// Recording into the host's command buffer (Volume::record_frame, poll_frame_stats): frames recorded by the
// host and submitted together equal frames run one by one, statistics come back later without waiting,
// the frames-in-flight limit refuses without recording, and the steady state allocates nothing; all on a
// host's own device with the validation layer (synchronization validation) in the host's instance.
#include <cstring>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "runtime_test_util.h"

namespace probebake::test {
namespace {

using RecordTest = RuntimeTest;

// The host's command pool, one command buffer per submission, and a fence.
class HostCommands {
public:
  explicit HostCommands(const HostVulkanObjects& host) : host_(host) {
    VkCommandPoolCreateInfo pool{};
    pool.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
    pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool.queueFamilyIndex = host.family;
    EXPECT_EQ(vkCreateCommandPool(host.device, &pool, nullptr, &pool_), VK_SUCCESS);
    VkCommandBufferAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    alloc.commandPool = pool_;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    EXPECT_EQ(vkAllocateCommandBuffers(host.device, &alloc, &cmd_), VK_SUCCESS);
    VkFenceCreateInfo fence{};
    fence.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
    EXPECT_EQ(vkCreateFence(host.device, &fence, nullptr, &fence_), VK_SUCCESS);
  }
  ~HostCommands() {
    vkDeviceWaitIdle(host_.device);
    vkDestroyFence(host_.device, fence_, nullptr);
    vkDestroyCommandPool(host_.device, pool_, nullptr);
  }
  HostCommands(const HostCommands&) = delete;
  HostCommands& operator=(const HostCommands&) = delete;

  VkCommandBuffer begin() {
    vkResetCommandBuffer(cmd_, 0);
    VkCommandBufferBeginInfo info{};
    info.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
    info.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    EXPECT_EQ(vkBeginCommandBuffer(cmd_, &info), VK_SUCCESS);
    return cmd_;
  }
  void submit() {
    EXPECT_EQ(vkEndCommandBuffer(cmd_), VK_SUCCESS);
    VkSubmitInfo submit{};
    submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd_;
    EXPECT_EQ(vkResetFences(host_.device, 1, &fence_), VK_SUCCESS);
    EXPECT_EQ(vkQueueSubmit(host_.queue, 1, &submit, fence_), VK_SUCCESS);
  }
  void wait() { EXPECT_EQ(vkWaitForFences(host_.device, 1, &fence_, VK_TRUE, 60'000'000'000ull), VK_SUCCESS); }

private:
  const HostVulkanObjects& host_;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
};

// The host's device (validated), the runtime borrowing it, and the Cornell volume on it; destroyed in
// reverse order, the host's device last.
struct HostRuntime {
  HostVulkanObjects host{true};
  std::optional<runtime::Context> context;
  std::optional<runtime::Volume> volume;

  HostRuntime() {
    if (!host.ok()) return;
    auto borrowed = runtime::Context::borrow(host.host());
    if (!borrowed.ok()) {
      ADD_FAILURE() << borrowed.status().message;
      return;
    }
    context.emplace(std::move(borrowed).value());
    auto uploaded = runtime::Volume::upload(*context, baked_cornell_octree());
    if (!uploaded.ok()) {
      ADD_FAILURE() << uploaded.status().message;
      return;
    }
    volume.emplace(std::move(uploaded).value());
  }
  bool ok() const { return volume.has_value(); }
};

std::vector<float> irradiance_of(const formats::ProbeVolume& v) {
  std::vector<float> out;
  for (const gpu::Probe& p : v.probes) out.insert(out.end(), std::begin(p.irradiance_sh), std::end(p.irradiance_sh));
  return out;
}

TEST_F(RecordTest, FramesRecordedByTheHostEqualFramesRunOneByOne) {
  std::vector<runtime::FrameStats> submitted;
  std::vector<float> expected;
  {
    auto volume = runtime::Volume::upload(context(), baked_cornell_octree());
    ASSERT_TRUE(volume.ok()) << volume.status().message;
    for (int f = 0; f < 4; ++f) submitted.push_back(volume->run_frame().value());
    expected = irradiance_of(volume->read_back().value());
  }
  {
    HostRuntime runtime_on_host;
    ASSERT_TRUE(runtime_on_host.ok());
    runtime::Volume* volume = &*runtime_on_host.volume;
    HostCommands commands(runtime_on_host.host);
    // Three frames (UploadOptions::frames_in_flight) in one command buffer of the host, one submission.
    VkCommandBuffer cmd = commands.begin();
    for (std::uint64_t f = 1; f <= 3; ++f) EXPECT_EQ(volume->record_frame(cmd).value(), f);
    // A fourth would reuse frame 1's ring before it finished: refused, nothing recorded.
    auto over = volume->record_frame(cmd);
    ASSERT_FALSE(over.ok());
    EXPECT_EQ(over.status().code, runtime::StatusCode::invalid_argument);
    EXPECT_NE(over.status().message.find("frames_in_flight"), std::string::npos) << over.status().message;
    commands.submit();
    commands.wait();
    // Statistics of each frame, oldest first, polled before its ring is recorded again.
    const bool timed = runtime_on_host.context->device_info().timestamps;
    auto expect_stats = [&](std::uint64_t f) {
      const std::optional<runtime::FrameStats> stats = volume->poll_frame_stats();
      ASSERT_TRUE(stats.has_value()) << f;
      EXPECT_EQ(stats->frame, f);
      EXPECT_EQ(stats->live_probes, submitted[f - 1].live_probes);
      EXPECT_EQ(stats->light.lit_probes, submitted[f - 1].light.lit_probes);
      EXPECT_EQ(stats->light.traced_probes, submitted[f - 1].light.traced_probes);
      EXPECT_EQ(stats->passes.size(), submitted[f - 1].passes.size());
      for (const runtime::PassTime& pass : stats->passes) EXPECT_TRUE(!timed || pass.gpu_ms >= 0.0) << pass.name;
    };
    for (std::uint64_t f = 1; f <= 3; ++f) expect_stats(f);
    cmd = commands.begin();
    EXPECT_EQ(volume->record_frame(cmd).value(), 4u);
    commands.submit();
    commands.wait();
    expect_stats(4);
    EXPECT_EQ(irradiance_of(volume->read_back().value()), expected); // bit for bit
    EXPECT_FALSE(volume->poll_frame_stats().has_value());            // every frame returned once
  }
}

TEST_F(RecordTest, StatisticsArriveAfterTheHostsFenceWithoutWaitingInTheRuntime) {
  HostRuntime runtime_on_host;
  ASSERT_TRUE(runtime_on_host.ok());
  runtime::Volume* volume = &*runtime_on_host.volume;
  HostCommands commands(runtime_on_host.host);
  EXPECT_FALSE(volume->poll_frame_stats().has_value()); // nothing recorded
  VkCommandBuffer cmd = commands.begin();
  ASSERT_TRUE(volume->record_frame(cmd).ok());
  EXPECT_FALSE(volume->poll_frame_stats().has_value()); // recorded, not even submitted: not finished
  commands.submit();
  commands.wait();
  const std::optional<runtime::FrameStats> stats = volume->poll_frame_stats();
  ASSERT_TRUE(stats.has_value());
  EXPECT_EQ(stats->frame, 1u);
  EXPECT_EQ(stats->live_probes, live_probe_count(baked_cornell_octree()));
  EXPECT_GT(stats->light.traced_probes, 0); // the first frame traces every probe
  // run_frame after recorded frames continues the numbering.
  EXPECT_EQ(volume->run_frame().value().frame, 2u);
}

TEST_F(RecordTest, RecordingFramesAllocatesNothing) {
  HostRuntime runtime_on_host;
  ASSERT_TRUE(runtime_on_host.ok());
  runtime::Volume* volume = &*runtime_on_host.volume;
  HostCommands commands(runtime_on_host.host);
  const runtime::MemoryStats before = runtime_on_host.context->memory_stats();
  for (int round = 0; round < 4; ++round) {
    VkCommandBuffer cmd = commands.begin();
    for (int f = 0; f < 2; ++f) ASSERT_TRUE(volume->record_frame(cmd).ok());
    commands.submit();
    commands.wait();
    while (volume->poll_frame_stats()) {
    }
  }
  const runtime::MemoryStats after = runtime_on_host.context->memory_stats();
  EXPECT_EQ(after.allocations, before.allocations);
  EXPECT_EQ(after.live_buffers, before.live_buffers);
}

TEST_F(RecordTest, RefusesANullCommandBufferAndABadRingCount) {
  auto volume = runtime::Volume::upload(context(), baked_cornell_octree());
  ASSERT_TRUE(volume.ok());
  EXPECT_EQ(volume->record_frame(VK_NULL_HANDLE).status().code, runtime::StatusCode::invalid_argument);
  runtime::UploadOptions options;
  options.frames_in_flight = 0;
  EXPECT_EQ(runtime::Volume::upload(context(), baked_cornell_octree(), options).status().code,
            runtime::StatusCode::invalid_argument);
}

} // namespace
} // namespace probebake::test
