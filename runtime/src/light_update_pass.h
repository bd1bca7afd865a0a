// The light update (octree thesis §3.2.2) on a static octree: L1 traces every live probe's lighting rays
// and placement lattice once (light_trace.comp), L2 relights the kept records every frame and gathers
// them into the probes with hysteresis (light_gather.comp, then light_resolve.comp copies the result
// into the probes, so that the whole frame reads last frame's values), L3 compares hit fractions with the
// split thresholds (counted only: the memory update M0-M4 that would act on them is not built yet).
// Exists only for volumes that carry the runtime lighting sections (bake default).
#pragma once

#include <cstdint>

#include <vulkan/vulkan_core.h>

#include "allocator.h"
#include "commands.h"
#include "device.h"
#include "gpu_volume.h"
#include "handles.h"
#include "pass_counters.h"
#include "pipelines.h"
#include "probebake/runtime_types.h"
#include "probebake/runtime/runtime.h"

namespace probebake::runtime::detail {

struct LightTimerSlots {
  std::uint32_t trace, gather, resolve;
};

class LightUpdatePass {
public:
  // Throws RuntimeError(unsupported) when the per-ray records exceed maxStorageBufferRange.
  LightUpdatePass(Device& device, const GpuVolume& volume, int rays, float hysteresis);

  // Whether `volume` can run the light update: it has the lighting sections and probes.
  static bool applies(const GpuVolume& volume);

  // Records L1 (first frame only, or after retrace()), L2 and L3 between the timer slots' timestamps.
  // Returns whether L1 was recorded.
  bool record(VkCommandBuffer cmd, PassTimer& timer, const LightTimerSlots& slots);
  // After the submission: this frame's statistics.
  LightStats stats() const;
  void retrace() { trace_pending_ = true; }

private:
  Device& device_;
  std::uint32_t probe_capacity_ = 0;
  float hysteresis_ = 0.0f;
  bool trace_pending_ = true;
  Buffer records_;
  Buffer next_irradiance_;
  PassCounters<gpu::LightCounters> counters_;
  PassDescriptorSet descriptors_;
};

} // namespace probebake::runtime::detail
