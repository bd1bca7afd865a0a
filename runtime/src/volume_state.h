// Everything behind a runtime::Volume. Members are destroyed in reverse order: passes, buffers, then the
// device reference (which may be the last one, destroying the device).
#pragma once

#include <cstdint>
#include <memory>

#include "commands.h"
#include "device.h"
#include "gpu_volume.h"
#include "light_inputs.h"
#include "light_update_pass.h"
#include "memory_update_pass.h"
#include "object_poses.h"
#include "probe_index_pass.h"
#include "probebake/formats/probe_volume.h"
#include "sample_pass.h"

namespace probebake::runtime::detail {

struct VolumeState {
  std::shared_ptr<Device> device;
  formats::ProbeVolume cpu_parts; // info, cells, cell_depth, input_hash of the uploaded volume; no buffers
  std::unique_ptr<GpuVolume> gpu;
  std::unique_ptr<ProbeIndexPass> probe_index;
  std::unique_ptr<SamplePass> sample;
  std::unique_ptr<LightUpdatePass> light; // only for volumes with the lighting sections
  std::unique_ptr<LightInputs> light_inputs; // with `light`: the host's punctual lights
  std::unique_ptr<ObjectPoses> objects; // only for volumes with dynamic objects
  std::unique_ptr<MemoryUpdatePass> memory; // only with a light update, on octree volumes (memory_update_applies)
  std::unique_ptr<PassTimer> frame_timer; // one slot per FramePass (frame.h)
  std::uint64_t frames = 0;

  VolumeState(std::shared_ptr<Device> shared_device, const formats::ProbeVolume& volume, const UploadOptions& options);
  FrameStats run_frame(const FrameInputs& inputs);
};

} // namespace probebake::runtime::detail
