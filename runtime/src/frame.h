// One frame of the runtime: the per-frame passes of the octree thesis (§3.2, figure 3.4) in their order, in
// one command buffer: memory update (M0-M4, not built yet), probe index build (§3.2.3), light update
// (§3.2.2: L1-L3). The passes record their own steps and barriers; this file only orders them.
#pragma once

#include <cstdint>
#include <vector>

#include <vulkan/vulkan_core.h>

#include "commands.h"
#include "light_update_pass.h"
#include "probe_index_pass.h"
#include "probebake/runtime/runtime.h"

namespace probebake::runtime::detail {

// Timer slots of a frame's passes, in execution order (FrameStats lists them in this order).
enum FramePass : std::uint32_t { kPassProbeIndex, kPassLightTrace, kPassLightGather, kPassLightResolve, kFramePasses };

// The passes of one volume; `light` is null when the volume runs no light update.
struct FramePasses {
  ProbeIndexPass& probe_index;
  LightUpdatePass* light = nullptr;
};

// The passes a recorded frame ran: their timer slots hold timestamps, the others stay unwritten.
struct RecordedFrame {
  bool ran[kFramePasses] = {};

  // After the submission completed: the GPU time of each pass that ran, in execution order.
  std::vector<PassTime> pass_times(const PassTimer& timer) const;
};

// Records one frame into `cmd`, timing each pass in `timer` (kFramePasses slots).
RecordedFrame record_frame(VkCommandBuffer cmd, PassTimer& timer, const FramePasses& passes);

} // namespace probebake::runtime::detail
