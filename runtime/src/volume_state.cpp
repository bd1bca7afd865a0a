#include "volume_state.h"

#include <chrono>
#include <utility>

namespace probebake::runtime::detail {
namespace {

// Passes of one frame, in order; the index is the timer slot. The memory update (M0-M4) of the thesis will
// run before the probe index build.
enum FramePass : std::uint32_t { kPassProbeIndex, kPassLightTrace, kPassLightGather, kPassLightResolve, kFramePasses };
constexpr const char* kFramePassNames[kFramePasses] = {"probe_index", "light_trace", "light_gather", "light_resolve"};

} // namespace

VolumeState::VolumeState(std::shared_ptr<Device> shared_device, const formats::ProbeVolume& volume,
                         const UploadOptions& options)
    : device(std::move(shared_device)) {
  cpu_parts.info = volume.info;
  cpu_parts.cell_depth = volume.cell_depth;
  cpu_parts.cells = volume.cells;
  cpu_parts.input_hash = volume.input_hash;
  gpu = std::make_unique<GpuVolume>(*device, volume);
  probe_index = std::make_unique<ProbeIndexPass>(*device, *gpu);
  sample = std::make_unique<SamplePass>(*device, *gpu);
  if (options.light_update && LightUpdatePass::applies(*gpu))
    light = std::make_unique<LightUpdatePass>(*device, *gpu, volume.lighting->rays, options.hysteresis);
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
  bool ran[kFramePasses] = {true, false, false, false};
  if (light) {
    ran[kPassLightTrace] = light->record(cmd, *frame_timer, {kPassLightTrace, kPassLightGather, kPassLightResolve});
    ran[kPassLightGather] = ran[kPassLightResolve] = true;
  }
  submission.submit_and_wait();

  FrameStats stats;
  stats.frame = ++frames;
  for (std::uint32_t pass = 0; pass < kFramePasses; ++pass)
    if (ran[pass]) stats.passes.push_back({kFramePassNames[pass], frame_timer->read_pass_ms(pass)});
  if (light) stats.light = light->stats();
  stats.live_probes = probe_index->live_probes();
  stats.probe_capacity = static_cast<int>(gpu->elements(Section::probes));
  stats.cpu_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

} // namespace probebake::runtime::detail
