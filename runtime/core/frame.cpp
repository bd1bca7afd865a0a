#include "core/frame.h"

namespace probebake::runtime::detail {

static_assert(kFramePassNames.size() == frame_pass::count); // the public names, in the timer slots' order

RecordedFrame record_frame(VkCommandBuffer cmd, PassTimer& timer, const FramePasses& passes,
                           const FrameInputs& inputs) {
  RecordedFrame frame;
  // Everything earlier on the queue (upload, last frame, sampling, and the host's own commands reading the
  // volume's buffers in any stage) before this frame's passes (thesis §3.2: a barrier between every two
  // shaders that touch the same buffers).
  barrier(cmd, kAnyCommandBefore, kAnyDeviceAccess);

  // 0a. Streaming: the cells around the host's camera (tracing blocks dropped and copied in, the light list).
  if (passes.streaming && passes.light) {
    frame.streaming = passes.streaming->record(cmd, timer, frame_pass::stream_upload, timer.ring(), *passes.light,
                                               frame.ran[frame_pass::stream_upload]);
    if (passes.memory) { // the probe tree follows the cells (memory_cells), and measures left undecided are made again
      passes.memory->change_cells(passes.streaming->take_tree_changes());
      if (frame.streaming.loaded_cells > 0) passes.memory->remeasure_unresolved();
    }
  }

  // 0. The host's punctual lights (FrameInputs::lights): the changed records, before anything reads them.
  if (inputs.lights && passes.light_inputs && passes.volume) {
    frame.uploaded_lights = passes.light_inputs->record(cmd, *passes.volume, *inputs.lights);
    if (passes.light) passes.light->relight(passes.light_inputs->changes(), passes.light_inputs->first_change());
  }

  // 0a'. The host's sky (FrameInputs::sky): when it changed, light_sky relights the rays that left the scene.
  if (inputs.sky && passes.sky_inputs && passes.volume && passes.sky_inputs->record(cmd, *passes.volume, *inputs.sky))
    if (passes.light) passes.light->sky_changed();
  // 0a''. The host's emitter strengths (FrameInputs::emitters): when one changed, light_emitters relights the
  //      records their light reaches.
  if (!inputs.emitters.empty() && passes.emitter_inputs && passes.light &&
      passes.emitter_inputs->apply(inputs.emitters))
    passes.light->emitters_changed(cmd, passes.emitter_inputs->scales());

  // 0b. The host's object poses: rows, refit, before anything traces. The memory update re-measures the
  //     leaves under each moved object's old and new world boxes; without it, L1 re-traces the probes whose
  //     rays cross those boxes (light_mark_moved).
  std::span<const Box> moved_boxes;
  if (passes.objects && !inputs.object_poses.empty()) {
    frame.moved_objects = passes.objects->record(cmd, inputs.object_poses);
    moved_boxes = passes.objects->moved_boxes();
    if (frame.moved_objects > 0 && passes.light && passes.light_inputs)
      passes.light->objects_moved(moved_boxes, passes.light_inputs->current(), !passes.memory);
  }

  // 1. Memory update (§3.2.1, M0-M4) and SVO refresh: allocates and frees before the probe index lists them.
  if (passes.memory) {
    passes.memory->record_memory_update(cmd, timer, frame_pass::memory_update, inputs, moved_boxes);
    frame.ran[frame_pass::memory_update] = true;
  }

  // 2. Probe index build (§3.2.3).
  passes.probe_index.record(cmd, timer, frame_pass::probe_index);
  frame.ran[frame_pass::probe_index] = true;

  // 3. Light update (§3.2.2): the transitions (L1 measures, L3 acts), the cached punctual irradiance where
  //    it went stale, then L1 records (first frame, then the flagged probes), L2 lighting and the L3 counts.
  if (passes.light) {
    if (passes.memory) {
      passes.memory->record_light_transitions(cmd, timer, frame_pass::light_transitions);
      frame.ran[frame_pass::light_transitions] = true;
    }
    const LightTimerSlots slots{frame_pass::light_relight, frame_pass::light_trace, frame_pass::light_gather,
                                frame_pass::light_resolve};
    frame.ran[frame_pass::light_trace] = passes.light->record(cmd, timer, slots, inputs.limits);
    frame.ran[frame_pass::light_relight] = passes.light->relit();
    frame.ran[frame_pass::light_gather] = frame.ran[frame_pass::light_resolve] = true;
  }

  // 4. The compact probes the lookups read, from the records as this frame left them.
  if (passes.codes) {
    passes.codes->record(cmd, &timer, frame_pass::probe_codes);
    frame.ran[frame_pass::probe_codes] = true;
  }

  // 5. The leaf queue's entries take their states from the keys; statistics to the host.
  if (passes.memory) passes.memory->record_end_of_frame(cmd, timer.ring());
  // The frame's writes before any later command of the host reads the buffers (its shaders sample them).
  barrier(cmd, kAnyDeviceAccess, kAnyCommandReadAfter);
  return frame;
}

std::vector<PassTime> RecordedFrame::pass_times(const PassTimer& timer, std::uint32_t ring) const {
  std::vector<PassTime> times;
  for (std::uint32_t pass = 0; pass < frame_pass::count; ++pass)
    if (ran[pass]) times.push_back({kFramePassNames[pass], timer.read_pass_ms(pass, ring)});
  return times;
}

} // namespace probebake::runtime::detail
