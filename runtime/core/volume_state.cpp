#include "core/volume_state.h"

#include <chrono>
#include <utility>

#include "core/error.h"
#include "core/frame.h"
#include "streaming/streamed_tracing.h"
#include "streaming/streamed_tree.h"

namespace probebake::runtime::detail {
namespace {

// The tree the memory update starts from: the file's, or with streaming its cells collapsed, to arrive
// through pools sized by the budget (streamed_tree.h).
formats::ProbeVolume prepare_tree(const formats::ProbeVolume& volume, const UploadOptions& options, bool streams) {
  if (!streams || volume.cell_tracing.empty()) return prepare_for_memory_update(volume, options.pools);
  const SeatRoom seats =
      resident_seat_room(volume, StreamedTracing::footprints(volume), options.streaming.budget_bytes);
  return prepare_for_memory_update(collapse_cells(volume), options.pools, seats);
}

} // namespace

VolumeState::VolumeState(std::shared_ptr<Device> shared_device, const formats::ProbeVolume& volume,
                         const UploadOptions& options, std::unique_ptr<CellSource> cells,
                         const formats::TracingView* tracing)
    : device(std::move(shared_device)) {
  const bool dynamic_tree = options.light_update && options.memory_update && memory_update_applies(volume);
  const bool streams = options.streaming.budget_bytes > 0;
  const formats::ProbeVolume prepared = dynamic_tree ? prepare_tree(volume, options, streams) : formats::ProbeVolume{};
  const formats::ProbeVolume& uploaded = dynamic_tree ? prepared : volume;
  cpu_parts.info = uploaded.info;
  // Streaming cells list element ranges of a fixed tree: a tree that reshapes itself has none.
  if (!dynamic_tree) {
    cpu_parts.cell_depth = volume.cell_depth;
    cpu_parts.cells = volume.cells;
    cpu_parts.cell_tracing = volume.cell_tracing;
  }
  cpu_parts.input_hash = volume.input_hash;
  cpu_parts.dynamic_objects = volume.dynamic_objects;
  const bool lit = options.light_update && uploaded.lighting.has_value();
  if (streams && !lit)
    fail(StatusCode::invalid_argument, "streaming cells needs the light update and the lighting sections");
  // With the memory update the tree's probes are the GPU's: the memory update lists the probes to light.
  if (streams && dynamic_tree && (options.streaming.max_lit_probes > 0 || options.streaming.light_reach > 0.0f))
    fail(StatusCode::invalid_argument, "streaming.max_lit_probes and light_reach need a fixed tree: the memory update "
                                       "lights every probe of its tree");
  gpu = std::make_unique<GpuVolume>(*device, uploaded, lit ? std::size_t(options.light_headroom) : 0u, streams);
  if (streams) { // the tracing is the file's whatever the memory update does to the probe tree
    if (!cells) cells = cell_source_in_memory(volume);
    streaming = std::make_unique<CellStreaming>(*device, volume, tracing ? *tracing : formats::tracing_view(volume),
                                                std::move(cells), options.streaming,
                                                std::uint32_t(options.frames_in_flight), !dynamic_tree);
    gpu->set_streamed_tracing(streaming->tracing().trees(), streaming->tracing().arena());
  }
  if (!uploaded.dynamic_objects.empty())
    objects = std::make_unique<ObjectPoses>(*device, *gpu, uploaded.dynamic_objects);
  const auto ring_count = static_cast<std::uint32_t>(options.frames_in_flight);
  probe_index = std::make_unique<ProbeIndexPass>(*device, *gpu, ring_count);
  sample = std::make_unique<SamplePass>(*device, *gpu);
  if (options.light_update && LightUpdatePass::applies(*gpu)) {
    const std::vector<std::int32_t> load_order =
        options.load_focus
            ? load_order_nearest(uploaded.probes, std::uint32_t(gpu->elements(Section::probes)), *options.load_focus)
            : std::vector<std::int32_t>{};
    emitter_inputs = std::make_unique<EmitterInputs>(uploaded.emitter_patches);
    light = std::make_unique<LightUpdatePass>(*device, *gpu, volume.lighting->rays, options.hysteresis, ring_count,
                                              emitter_inputs->scales(),
                                              streaming ? streaming->record_slots() : RecordSlots{}, load_order);
    light_inputs = std::make_unique<LightInputs>(uploaded.punctual_lights, gpu->capacity(Section::punctual_lights));
    sky_inputs = std::make_unique<SkyInputs>(uploaded.lighting->sky_radiance, uploaded.sky);
  }
  if (dynamic_tree && light) {
    const std::uint64_t seat_ints =
        options.streaming.max_seat_bytes != 0 ? options.streaming.max_seat_bytes / 4 : gpu::MEMORY_SEAT_INTS;
    memory = std::make_unique<MemoryUpdatePass>(*device, *gpu, prepared, light->trace_flags(), light->light_list(),
                                                ring_count, streaming ? std::uint32_t(seat_ints) : 0u,
                                                streaming ? &volume : nullptr);
    light->walk_light_list();
  }
  if (streaming && light) {
    light->walk_light_list(); // the host lists the resident cells' probes, or the memory update its leaves'
    light->set_null_leaf(streaming->tracing().null_leaf());
    if (memory) {
      memory->set_null_leaf(streaming->tracing().null_leaf());
    }
    sample->set_record_slots(light->record_slots());
  }
  if (options.probe_code != formats::ShCodec::float32) {
    codes = std::make_unique<ProbeCodePass>(*device, *gpu, options.probe_code);
    sample->set_probe_codes(codes->points().get(), codes->codes().get(), codes->code_bands());
    Submission submission(*device); // the uploaded probes' codes, before any frame
    codes->record(submission.cmd());
    submission.submit_and_wait();
  }
  frame_timer = std::make_unique<PassTimer>(*device, frame_pass::count, ring_count);
  rings.resize(ring_count);
  for (FrameRing& ring : rings) {
    auto info = vk_struct<VkEventCreateInfo>(VK_STRUCTURE_TYPE_EVENT_CREATE_INFO);
    VkEvent event = VK_NULL_HANDLE;
    check_vk(vkCreateEvent(device->vk(), &info, nullptr, &event), "vkCreateEvent");
    ring.done = DeviceObject<VkEvent>(device->vk(), event, vkDestroyEvent);
  }
}

std::uint64_t VolumeState::record(VkCommandBuffer cmd, const FrameInputs& inputs) {
  const auto start = std::chrono::steady_clock::now();
  const auto index = static_cast<std::uint32_t>(frames % rings.size());
  FrameRing& ring = rings[index];
  if (ring.pending) {
    if (vkGetEventStatus(device->vk(), ring.done.get()) != VK_EVENT_SET)
      fail(StatusCode::invalid_argument, "frame " + std::to_string(frames + 1) + ": frame " +
                                             std::to_string(ring.frame) + " has not finished; at most " +
                                             std::to_string(rings.size()) +
                                             " frames may be in flight (UploadOptions::frames_in_flight)");
    ring.pending = false; // finished but never polled: its statistics are dropped
  }
  check_vk(vkResetEvent(device->vk(), ring.done.get()), "vkResetEvent");
  frame_timer->reset(cmd, index);
  const FramePasses passes{*probe_index,  light.get(),     memory.get(), light_inputs.get(), gpu.get(),
                           objects.get(), streaming.get(), codes.get(),  sky_inputs.get(),   emitter_inputs.get()};
  if (light && inputs.limits.frame_ms > 0.0f && light->untraced_slots() > 0) { // the load window by time
    FrameInputs timed = inputs;
    timed.limits.max_traced_probes = int(trace_budget.next_window(inputs.limits.frame_ms, light->untraced_slots()));
    ring.recorded = record_frame(cmd, *frame_timer, passes, timed);
  } else {
    ring.recorded = record_frame(cmd, *frame_timer, passes, inputs);
  }
  vkCmdSetEvent(cmd, ring.done.get(), VK_PIPELINE_STAGE_ALL_COMMANDS_BIT);
  if (memory) cpu_parts.info = memory->info();
  ring.lights = light_inputs ? static_cast<int>(light_inputs->current().size()) : 0;
  ring.frame = ++frames;
  ring.pending = true;
  ring.cpu_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return ring.frame;
}

std::optional<FrameStats> VolumeState::poll() {
  FrameRing* oldest = nullptr;
  for (FrameRing& ring : rings)
    if (ring.pending && (!oldest || ring.frame < oldest->frame)) oldest = &ring;
  if (!oldest || vkGetEventStatus(device->vk(), oldest->done.get()) != VK_EVENT_SET) return std::nullopt;
  return collect(*oldest);
}

FrameStats VolumeState::collect(FrameRing& ring) {
  const auto index = static_cast<std::uint32_t>(&ring - rings.data());
  ring.pending = false;
  FrameStats stats;
  stats.frame = ring.frame;
  stats.passes = ring.recorded.pass_times(*frame_timer, index);
  if (light) {
    stats.light = light->stats(index);
    stats.light.lights = ring.lights;
    stats.light.uploaded_lights = ring.recorded.uploaded_lights;
    stats.light.moved_objects = ring.recorded.moved_objects;
  }
  if (memory) stats.memory = memory->stats(index);
  stats.streaming = ring.recorded.streaming;
  stats.live_probes = probe_index->live_probes(index);
  stats.probe_capacity = static_cast<int>(gpu->elements(Section::probes));
  stats.cpu_ms = ring.cpu_ms;
  trace_budget.observe(stats);
  return stats;
}

FrameStats VolumeState::run_frame(const FrameInputs& inputs) {
  const auto start = std::chrono::steady_clock::now();
  Submission submission(*device);
  const std::uint64_t frame = record(submission.cmd(), inputs);
  submission.submit_and_wait();
  FrameStats stats = collect(rings[(frame - 1) % rings.size()]);
  stats.cpu_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

} // namespace probebake::runtime::detail
