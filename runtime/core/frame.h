// One frame of the runtime: the per-frame passes of the octree thesis (§3.2, figure 3.4) in their order, in
// one command buffer: the host's light records, memory update (§3.2.1: M0-M4, then the SVO refresh), probe index build (§3.2.3), light
// update (§3.2.2: transitions L0-L3, L1 records, L2 lighting), end of the frame's queue work. The passes
// record their own steps and barriers; this file only orders them.
#pragma once

#include <cstdint>
#include <vector>

#include <vulkan/vulkan_core.h>

#include "streaming/cell_streaming.h"
#include "core/commands.h"
#include "core/gpu_volume.h"
#include "light_update/light_inputs.h"
#include "light_update/light_update_pass.h"
#include "light_update/emitter_inputs.h"
#include "light_update/sky_inputs.h"
#include "memory_update/memory_update_pass.h"
#include "objects/object_poses.h"
#include "probe_codes/probe_code_pass.h"
#include "probe_index/probe_index_pass.h"
#include "probebake/runtime/vocabulary.h"

namespace probebake::runtime::detail {

// Timer slots of a frame's passes: the pass table's PROBEBAKE_TIMER rows, in execution order (FrameStats lists
// them in this order).
namespace frame_pass {
enum : std::uint32_t {
#define PROBEBAKE_TIMER(name) name,
#include "probebake/runtime/passes.def"
  count
};
} // namespace frame_pass

// The passes of one volume; `light` is null when the volume runs no light update, `memory` when it runs no
// memory update (it runs only with a light update).
struct FramePasses {
  ProbeIndexPass& probe_index;
  LightUpdatePass* light = nullptr;
  MemoryUpdatePass* memory = nullptr;
  LightInputs* light_inputs = nullptr; // with `light`: the host's punctual lights, uploaded into `volume`
  GpuVolume* volume = nullptr;
  ObjectPoses* objects = nullptr;          // volumes with dynamic objects: the host's poses
  CellStreaming* streaming = nullptr;      // with `light`, UploadOptions::streaming: the cells around the camera
  ProbeCodePass* codes = nullptr;          // UploadOptions::probe_code l1 or l2: the lookups' compact probes
  SkyInputs* sky_inputs = nullptr;         // with `light`: the host's sky, uploaded into `volume`
  EmitterInputs* emitter_inputs = nullptr; // with `light`: the host's emitter strengths, uploaded into `light`
};

// The passes a recorded frame ran: their timer slots hold timestamps, the others stay unwritten.
struct RecordedFrame {
  bool ran[frame_pass::count] = {};
  int uploaded_lights = 0; // punctual light records the host changed this frame
  int moved_objects = 0;   // dynamic objects whose pose the host changed this frame
  StreamStats streaming;

  // After the submission completed: the GPU time of each pass that ran, in execution order.
  std::vector<PassTime> pass_times(const PassTimer& timer, std::uint32_t ring) const;
};

// Records one frame into `cmd`, timing each pass in `timer` (frame_pass::count slots, reset to the frame's ring
// by the caller).
RecordedFrame record_frame(VkCommandBuffer cmd, PassTimer& timer, const FramePasses& passes, const FrameInputs& inputs);

} // namespace probebake::runtime::detail
