#include "frame.h"

namespace probebake::runtime::detail {
namespace {

constexpr const char* kFramePassNames[kFramePasses] = {"probe_index", "light_trace", "light_gather", "light_resolve"};

} // namespace

RecordedFrame record_frame(VkCommandBuffer cmd, PassTimer& timer, const FramePasses& passes) {
  RecordedFrame frame;
  timer.reset(cmd);
  // Everything earlier on the queue (upload, last frame, sampling) before this frame's passes (thesis §3.2:
  // a barrier between every two shaders that touch the same buffers).
  barrier(cmd, kAnyDeviceAccess, kAnyDeviceAccess);

  // 1. Memory update (§3.2.1, M0-M4): NOT BUILT YET. It goes here, before the probe index build, which must
  //    list the probes it allocates and frees; it ends with a barrier making its writes (octree, probes, surfel
  //    batches, leaf queue) visible to the compute reads and transfer writes of the build. Give it a timer slot
  //    before kPassProbeIndex in FramePass and kFramePassNames.

  // 2. Probe index build (§3.2.3).
  passes.probe_index.record(cmd, timer, kPassProbeIndex);
  frame.ran[kPassProbeIndex] = true;

  // 3. Light update (§3.2.2): L1 on the first frame only, then L2 and L3.
  if (passes.light) {
    frame.ran[kPassLightTrace] =
        passes.light->record(cmd, timer, {kPassLightTrace, kPassLightGather, kPassLightResolve});
    frame.ran[kPassLightGather] = frame.ran[kPassLightResolve] = true;
  }
  return frame;
}

std::vector<PassTime> RecordedFrame::pass_times(const PassTimer& timer) const {
  std::vector<PassTime> times;
  for (std::uint32_t pass = 0; pass < kFramePasses; ++pass)
    if (ran[pass]) times.push_back({kFramePassNames[pass], timer.read_pass_ms(pass)});
  return times;
}

} // namespace probebake::runtime::detail
