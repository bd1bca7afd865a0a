// Compute pipelines of the runtime, built once per device from the embedded SPIR-V (shader_library.h),
// and descriptor helpers. Every pass binds only storage buffers (set 0, bindings 0..n-1, compute stage)
// and one 16-byte push constant block.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include <vulkan/vulkan_core.h>

#include "handles.h"

namespace probebake::runtime::detail {

// Bindings of the probe index build (shaders/include/probebake/probe_index.glsl).
enum ProbeIndexBinding : std::uint32_t { kIndexProbes, kIndexList, kIndexBlockSums, kIndexCounters, kIndexBindings };
// Bindings of the sampling pass (shaders/include/probebake/sample_irradiance.glsl + sample_irradiance.comp).
enum SampleBinding : std::uint32_t {
  kSampleVolumeInfo,
  kSampleProbes,
  kSampleSvoNodes,
  kSampleSvoLeaves,
  kSampleQueries,
  kSampleResults,
  kSampleBindings
};

// Bindings of the all-probe baseline sampler (shaders/sample_all_probes.comp).
enum SampleAllBinding : std::uint32_t {
  kAllVolumeInfo,
  kAllProbes,
  kAllSvoNodes,
  kAllSvoLeaves,
  kAllProbeIndex,
  kAllLightingInfo,
  kAllBvhNodes,
  kAllTriangles,
  kAllQueries,
  kAllResults,
  kAllBindings
};

// Bindings of the light update passes (shaders/include/probebake/light_bindings.glsl).
enum LightBinding : std::uint32_t {
  kLightVolumeInfo,
  kLightProbes,
  kLightSvoNodes,
  kLightSvoLeaves,
  kLightOctree,
  kLightLightingInfo,
  kLightRayDirections,
  kLightBvhNodes,
  kLightTriangles,
  kLightPunctualLights,
  kLightEmitterPatches,
  kLightRecords,
  kLightNextIrradiance,
  kLightCounters,
  kLightBindings
};

struct PassLayout {
  DeviceObject<VkDescriptorSetLayout> set_layout;
  DeviceObject<VkPipelineLayout> layout;
};

class Pipelines {
public:
  explicit Pipelines(VkDevice device); // throws RuntimeError

  PassLayout probe_index;
  DeviceObject<VkPipeline> probe_index_count, probe_index_scan, probe_index_scatter;
  PassLayout sample;
  DeviceObject<VkPipeline> sample_irradiance;
  PassLayout sample_all;
  DeviceObject<VkPipeline> sample_all_probes;
  PassLayout light;
  DeviceObject<VkPipeline> light_trace, light_gather, light_resolve;
};

// A pool for `sets` descriptor sets of up to `buffers_per_set` storage buffers each.
DeviceObject<VkDescriptorPool> make_descriptor_pool(VkDevice device, std::uint32_t sets, std::uint32_t buffers_per_set);
VkDescriptorSet allocate_set(VkDevice device, VkDescriptorPool pool, VkDescriptorSetLayout layout);
// Binding i of `set` = the whole of buffers[i].
void write_storage_buffers(VkDevice device, VkDescriptorSet set, std::span<const VkBuffer> buffers);

} // namespace probebake::runtime::detail
