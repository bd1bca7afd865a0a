#include "volume_state.h"

#include <chrono>
#include <utility>

#include "frame.h"

namespace probebake::runtime::detail {

VolumeState::VolumeState(std::shared_ptr<Device> shared_device, const formats::ProbeVolume& volume,
                         const UploadOptions& options)
    : device(std::move(shared_device)) {
  const bool dynamic_tree = options.light_update && options.memory_update && memory_update_applies(volume);
  const formats::ProbeVolume prepared = dynamic_tree ? prepare_for_memory_update(volume, options.pools) : formats::ProbeVolume{};
  const formats::ProbeVolume& uploaded = dynamic_tree ? prepared : volume;
  cpu_parts.info = uploaded.info;
  // Streaming cells list element ranges of a fixed tree: a tree that reshapes itself has none.
  if (!dynamic_tree) {
    cpu_parts.cell_depth = volume.cell_depth;
    cpu_parts.cells = volume.cells;
  }
  cpu_parts.input_hash = volume.input_hash;
  cpu_parts.dynamic_objects = volume.dynamic_objects;
  const bool lit = options.light_update && uploaded.lighting.has_value();
  gpu = std::make_unique<GpuVolume>(*device, uploaded, lit ? std::size_t(options.light_headroom) : 0u);
  if (!uploaded.dynamic_objects.empty()) objects = std::make_unique<ObjectPoses>(*device, *gpu, uploaded.dynamic_objects);
  probe_index = std::make_unique<ProbeIndexPass>(*device, *gpu);
  sample = std::make_unique<SamplePass>(*device, *gpu);
  if (options.light_update && LightUpdatePass::applies(*gpu)) {
    light = std::make_unique<LightUpdatePass>(*device, *gpu, volume.lighting->rays, options.hysteresis);
    light_inputs = std::make_unique<LightInputs>(uploaded.punctual_lights, gpu->capacity(Section::punctual_lights));
  }
  if (dynamic_tree && light) {
    memory = std::make_unique<MemoryUpdatePass>(*device, *gpu, prepared, light->trace_flags(), light->light_list());
    light->walk_light_list();
  }
  frame_timer = std::make_unique<PassTimer>(*device, kFramePasses);
}

FrameStats VolumeState::run_frame(const FrameInputs& inputs) {
  const auto start = std::chrono::steady_clock::now();
  Submission submission(*device);
  const FramePasses passes{*probe_index, light.get(), memory.get(), light_inputs.get(), gpu.get(), objects.get()};
  const RecordedFrame recorded = record_frame(submission.cmd(), *frame_timer, passes, inputs);
  submission.submit_and_wait();

  FrameStats stats;
  stats.frame = ++frames;
  stats.passes = recorded.pass_times(*frame_timer);
  if (light) {
    stats.light = light->stats();
    stats.light.lights = static_cast<int>(light_inputs->current().size());
    stats.light.uploaded_lights = recorded.uploaded_lights;
    stats.light.moved_objects = recorded.moved_objects;
  }
  if (memory) {
    stats.memory = memory->stats();
    cpu_parts.info = memory->info();
  }
  stats.live_probes = probe_index->live_probes();
  stats.probe_capacity = static_cast<int>(gpu->elements(Section::probes));
  stats.cpu_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

} // namespace probebake::runtime::detail
