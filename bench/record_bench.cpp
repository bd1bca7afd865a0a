// CPU cost of recording a frame into the host's command buffer (Volume::record_frame, issue #14's target:
// <= 0.05 ms per recorded frame) next to the submit-and-wait path (Volume::run_frame), on one volume, in one
// run. Links only the runtime, so it runs on a bare GPU machine.
//
// Usage: probebake-bench-record FILE.probes [--frames N] [--memory-update] [--device NAME]
// Each frame: begin the host's command buffer, record_frame (timed), end, submit, wait (not timed), then
// poll_frame_stats (timed). Then the same number of run_frame calls (their cpu_ms includes submit + wait).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "probebake/runtime/runtime.h"

namespace {

using namespace probebake;
using Clock = std::chrono::steady_clock;

struct Options {
  std::string file, device;
  int frames = 200;
  bool memory_update = false;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--frames" && i + 1 < argc)
      o.frames = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--device" && i + 1 < argc)
      o.device = argv[++i];
    else if (arg == "--memory-update")
      o.memory_update = true;
    else if (o.file.empty() && arg[0] != '-')
      o.file = arg;
    else
      throw std::runtime_error(
          "usage: probebake-bench-record FILE.probes [--frames N] [--memory-update] [--device NAME]");
  }
  if (o.file.empty())
    throw std::runtime_error(
        "usage: probebake-bench-record FILE.probes [--frames N] [--memory-update] [--device NAME]");
  return o;
}

void check(VkResult result, const char* what) {
  if (result != VK_SUCCESS) throw std::runtime_error(std::string(what) + " failed: " + std::to_string(result));
}

// The host's command pool, buffer and fence on the runtime's device.
struct HostFrame {
  VkDevice device;
  VkQueue queue;
  VkCommandPool pool = VK_NULL_HANDLE;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;

  explicit HostFrame(const runtime::HostVulkan& vk) : device(vk.device), queue(vk.queue) {
    VkCommandPoolCreateInfo pool_info{};
    pool_info.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
    pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool_info.queueFamilyIndex = vk.queue_family_index;
    check(vkCreateCommandPool(device, &pool_info, nullptr, &pool), "vkCreateCommandPool");
    VkCommandBufferAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    alloc.commandPool = pool;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    check(vkAllocateCommandBuffers(device, &alloc, &cmd), "vkAllocateCommandBuffers");
    VkFenceCreateInfo fence_info{};
    fence_info.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
    check(vkCreateFence(device, &fence_info, nullptr, &fence), "vkCreateFence");
  }
  ~HostFrame() {
    vkDeviceWaitIdle(device);
    vkDestroyFence(device, fence, nullptr);
    vkDestroyCommandPool(device, pool, nullptr);
  }
  HostFrame(const HostFrame&) = delete;
  HostFrame& operator=(const HostFrame&) = delete;

  void begin() {
    check(vkResetCommandBuffer(cmd, 0), "vkResetCommandBuffer");
    VkCommandBufferBeginInfo info{};
    info.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
    info.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vkBeginCommandBuffer(cmd, &info), "vkBeginCommandBuffer");
  }
  void submit_and_wait() {
    check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
    VkSubmitInfo submit{};
    submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    check(vkResetFences(device, 1, &fence), "vkResetFences");
    check(vkQueueSubmit(queue, 1, &submit, fence), "vkQueueSubmit");
    check(vkWaitForFences(device, 1, &fence, VK_TRUE, 60'000'000'000ull), "vkWaitForFences");
  }
};

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

struct Summary {
  double median = 0, p95 = 0, max = 0;
};

Summary summarise(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return {v[v.size() / 2], v[std::min(v.size() - 1, v.size() * 95 / 100)], v.back()};
}

double frame_gpu_ms(const runtime::FrameStats& stats) {
  double sum = 0.0;
  for (const runtime::PassTime& pass : stats.passes) sum += std::max(0.0, pass.gpu_ms);
  return sum;
}

int run(const Options& o) {
  runtime::ContextOptions context_options;
  context_options.device_name_contains = o.device;
  auto context = runtime::Context::create(context_options);
  if (!context.ok()) throw std::runtime_error(context.status().message);
  runtime::UploadOptions upload;
  upload.memory_update = o.memory_update;
  auto volume = runtime::Volume::load(context.value(), o.file, upload);
  if (!volume.ok()) throw std::runtime_error(volume.status().message);
  HostFrame host(context->vulkan());
  for (int f = 0; f < 5; ++f) volume->run_frame(); // warm-up: pipelines compiled, first L1 trace done

  std::vector<double> record_ms, poll_ms, recorded_gpu_ms, run_ms, run_gpu_ms;
  for (int f = 0; f < o.frames; ++f) {
    host.begin();
    const auto start = Clock::now();
    auto recorded = volume->record_frame(host.cmd);
    record_ms.push_back(ms_since(start));
    if (!recorded.ok()) throw std::runtime_error(recorded.status().message);
    host.submit_and_wait();
    const auto polled_at = Clock::now();
    const std::optional<runtime::FrameStats> stats = volume->poll_frame_stats();
    poll_ms.push_back(ms_since(polled_at));
    if (!stats) throw std::runtime_error("a finished frame had no statistics");
    recorded_gpu_ms.push_back(frame_gpu_ms(*stats));
  }
  for (int f = 0; f < o.frames; ++f) {
    auto stats = volume->run_frame();
    if (!stats.ok()) throw std::runtime_error(stats.status().message);
    run_ms.push_back(stats->cpu_ms);
    run_gpu_ms.push_back(frame_gpu_ms(stats.value()));
  }
  const Summary record = summarise(record_ms), poll = summarise(poll_ms), submitted = summarise(run_ms);
  const Summary gpu_recorded = summarise(recorded_gpu_ms), gpu_run = summarise(run_gpu_ms);
  std::printf("device %s; %s, %d frames%s\n", context->device_info().name.c_str(), o.file.c_str(), o.frames,
              o.memory_update ? ", memory update on" : "");
  std::printf("| host CPU per frame | median ms | p95 ms | max ms |\n|---|--:|--:|--:|\n");
  std::printf("| record_frame (host's command buffer) | %.4f | %.4f | %.4f |\n", record.median, record.p95, record.max);
  std::printf("| poll_frame_stats | %.4f | %.4f | %.4f |\n", poll.median, poll.p95, poll.max);
  std::printf("| run_frame (record + submit + wait) | %.4f | %.4f | %.4f |\n", submitted.median, submitted.p95,
              submitted.max);
  std::printf("GPU ms per frame, median: recorded %.4f, run_frame %.4f; record_frame / run_frame CPU: %.3f\n",
              gpu_recorded.median, gpu_run.median, record.median / submitted.median);
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  try {
    return run(parse(argc, argv));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "probebake-bench-record: %s\n", e.what());
    return 1;
  }
}
