#include "volume_state.h"

#include <chrono>
#include <utility>

namespace probebake::runtime::detail {
namespace {

// Passes of one frame, in order; the index is the timer slot. The light update (L0-L3) and memory update
// (M0-M4) of the thesis will run before the probe index build.
enum FramePass : std::uint32_t { kPassProbeIndex, kFramePasses };
constexpr const char* kFramePassNames[kFramePasses] = {"probe_index"};

} // namespace

VolumeState::VolumeState(std::shared_ptr<Device> shared_device, const formats::ProbeVolume& volume)
    : device(std::move(shared_device)) {
  cpu_parts.info = volume.info;
  cpu_parts.cell_depth = volume.cell_depth;
  cpu_parts.cells = volume.cells;
  cpu_parts.input_hash = volume.input_hash;
  gpu = std::make_unique<GpuVolume>(*device, volume);
  probe_index = std::make_unique<ProbeIndexPass>(*device, *gpu);
  sample = std::make_unique<SamplePass>(*device, *gpu);
  frame_timer = std::make_unique<PassTimer>(*device, kFramePasses);
}

FrameStats VolumeState::run_frame() {
  const auto start = std::chrono::steady_clock::now();
  Submission submission(*device);
  const VkCommandBuffer cmd = submission.cmd();
  frame_timer->reset(cmd);
  // Everything earlier on the queue (upload, last frame, sampling) before this frame's passes (thesis §3.2:
  // a barrier between every two shaders that touch the same buffers).
  barrier(cmd, kAnyDeviceAccess, kAnyDeviceAccess);
  probe_index->record(cmd, *frame_timer, kPassProbeIndex);
  submission.submit_and_wait();

  FrameStats stats;
  stats.frame = ++frames;
  const std::vector<double> ms = frame_timer->read_ms(kFramePasses);
  for (std::uint32_t pass = 0; pass < kFramePasses; ++pass) stats.passes.push_back({kFramePassNames[pass], ms[pass]});
  stats.live_probes = probe_index->live_probes();
  stats.probe_capacity = static_cast<int>(gpu->elements(Section::probes));
  stats.cpu_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

} // namespace probebake::runtime::detail
