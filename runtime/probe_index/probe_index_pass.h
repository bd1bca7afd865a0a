// The probe index build (octree thesis §3.2.3): reset the list to PROBE_INDEX_END, then insert the
// allocated probes. Done as a deterministic stream compaction (count per block, scan, scatter; see
// probe_index.glsl), so the list is ascending and equals
// formats::rebuild_probe_index. Barriers between the steps are global memory barriers (commands.h).
#pragma once

#include <cstdint>

#include <vulkan/vulkan_core.h>

#include "core/allocator.h"
#include "core/commands.h"
#include "core/device.h"
#include "core/gpu_volume.h"
#include "core/handles.h"
#include "core/pass_counters.h"
#include "core/pipelines.h"
#include "probebake/runtime_types.h"

namespace probebake::runtime::detail {

class ProbeIndexPass {
public:
  ProbeIndexPass(Device& device, const GpuVolume& volume, std::uint32_t rings);

  // Records the pass between timer slot `timer_slot`'s timestamps, then copies the counters to the host
  // buffer (visible to the host after the submission completed).
  void record(VkCommandBuffer cmd, PassTimer& timer, std::uint32_t timer_slot) const;
  // After the submission: allocated probes found by the last recorded build.
  int live_probes(std::uint32_t ring) const; // of the frame recorded into `ring`, once it finished

private:
  Device& device_;
  const GpuVolume& volume_;
  std::uint32_t probe_capacity_ = 0;
  std::uint32_t block_count_ = 0;
  Buffer block_sums_;
  PassCounters<gpu::RuntimeCounters> counters_;
  PassDescriptorSet descriptors_;
};

} // namespace probebake::runtime::detail
