// Everything behind a runtime::Volume. Members are destroyed in reverse order: passes, buffers, then the
// device reference (which may be the last one, destroying the device).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "streaming/cell_streaming.h"
#include "core/commands.h"
#include "core/device.h"
#include "core/frame.h"
#include "core/handles.h"
#include "core/gpu_volume.h"
#include "light_update/light_inputs.h"
#include "light_update/emitter_inputs.h"
#include "light_update/sky_inputs.h"
#include "light_update/light_update_pass.h"
#include "light_update/trace_budget.h"
#include "memory_update/memory_update_pass.h"
#include "objects/object_poses.h"
#include "probe_codes/probe_code_pass.h"
#include "probe_index/probe_index_pass.h"
#include "probebake/formats/probe_volume.h"
#include "sampling/sample_pass.h"

namespace probebake::runtime::detail {

// One frame in flight (UploadOptions::frames_in_flight of them, used in turn): the host learns that its
// GPU work finished from `done`, an event its last command sets, without waiting; its statistics sit in
// the ring's query and counter copies until returned.
struct FrameRing {
  DeviceObject<VkEvent> done;
  bool pending = false; // recorded, statistics not returned yet
  std::uint64_t frame = 0;
  RecordedFrame recorded;
  int lights = 0;
  double cpu_ms = 0.0;
};

struct VolumeState {
  std::shared_ptr<Device> device;
  formats::ProbeVolume cpu_parts; // info, cells, cell_depth, input_hash of the uploaded volume; no buffers
  std::unique_ptr<GpuVolume> gpu;
  std::unique_ptr<ProbeIndexPass> probe_index;
  std::unique_ptr<SamplePass> sample;
  std::unique_ptr<LightUpdatePass> light;        // only for volumes with the lighting sections
  std::unique_ptr<LightInputs> light_inputs;     // with `light`: the host's punctual lights
  std::unique_ptr<SkyInputs> sky_inputs;         // with `light`: the host's sky
  std::unique_ptr<EmitterInputs> emitter_inputs; // with `light`: the host's emitter strengths
  std::unique_ptr<ObjectPoses> objects;          // only for volumes with dynamic objects
  std::unique_ptr<MemoryUpdatePass> memory;      // only with a light update, on octree volumes (memory_update_applies)
  std::unique_ptr<CellStreaming> streaming;      // only with UploadOptions::streaming (and a light update)
  std::unique_ptr<ProbeCodePass> codes;          // only with UploadOptions::probe_code l1 or l2
  std::unique_ptr<PassTimer> frame_timer;        // one slot per FramePass (frame.h), one ring per frame in flight
  std::vector<FrameRing> rings;
  std::uint64_t frames = 0;
  TraceBudget trace_budget; // FrameLimits::frame_ms

  // `cells`: where streaming reads cells (cell_source.h); null: a copy of the volume's tracing. `tracing`:
  // the volume's trace nodes, faces and vertices during the constructor (a streaming load's, in the file's
  // mapping); null: the volume's own.
  VolumeState(std::shared_ptr<Device> shared_device, const formats::ProbeVolume& volume, const UploadOptions& options,
              std::unique_ptr<CellSource> cells = nullptr, const formats::TracingView* tracing = nullptr);
  // Records one frame into the host's command buffer; no submit, no wait. Returns its number (1, 2, ...).
  // Throws RuntimeError(invalid_argument) when its ring still holds a frame that has not finished.
  std::uint64_t record(VkCommandBuffer cmd, const FrameInputs& inputs);
  // The statistics of the oldest recorded frame that finished and was not returned yet, or nullopt.
  std::optional<FrameStats> poll();
  // record() into a command buffer of its own, submitted and waited for; this frame's statistics.
  FrameStats run_frame(const FrameInputs& inputs);

private:
  FrameStats collect(FrameRing& ring);
};

} // namespace probebake::runtime::detail
