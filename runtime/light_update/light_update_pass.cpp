#include "light_update/light_update_pass.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <string>

#include "core/error.h"
#include "core/pipelines.h"
#include "light_update/light_inputs.h"
#include "light_update/light_update_bindings.h"
#include "probebake/runtime_types.h"

namespace probebake::runtime::detail {
namespace {

constexpr VkBufferUsageFlags kScratchUsage =
    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;

Buffer create_scratch(Device& device, VkDeviceSize bytes, const char* name) {
  if (bytes > device.info.max_storage_buffer_range)
    fail(StatusCode::unsupported,
         std::string(name) + ": " + std::to_string(bytes) + " bytes exceed maxStorageBufferRange (" +
             std::to_string(device.info.max_storage_buffer_range) + ") of " + device.info.name +
             "; bake with fewer probes or lighting rays, or load with light_update = false");
  return device.allocator->create_buffer(bytes, kScratchUsage, MemoryUse::device, name);
}

} // namespace

bool LightUpdatePass::applies(const GpuVolume& volume) {
  return volume.elements(Section::lighting_info) == 1 && volume.elements(Section::probes) > 0;
}

LightUpdatePass::LightUpdatePass(Device& device, const GpuVolume& volume, int rays, float hysteresis,
                                 std::uint32_t rings, std::span<const gpu::EmitterScale> emitters, RecordSlots records,
                                 std::span<const std::int32_t> load_order)
    : device_(device), hysteresis_(hysteresis) {
  probe_capacity_ = static_cast<std::uint32_t>(volume.elements(Section::probes));
  indirect_records_ = records.kind != RecordSlots::Kind::own;
  retry_by_slot_ = records.kind == RecordSlots::Kind::own_marked;
  const bool handed_out = records.kind == RecordSlots::Kind::handed_out;
  record_capacity_ = handed_out ? std::min(records.count, probe_capacity_) : probe_capacity_;
  create_record_pages(rays);
  // light_emitters: a workgroup per LIGHT_WORKGROUP_SIZE records of a probe, one record a thread (each casts a
  // shadow ray per patch: with several records a thread, a small volume's frame is one workgroup's latency).
  record_chunks_ = (std::uint32_t(rays) + gpu::LIGHT_WORKGROUP_SIZE - 1) / gpu::LIGHT_WORKGROUP_SIZE;
  next_irradiance_ = create_scratch(device, VkDeviceSize(record_capacity_) * gpu::PROBE_SH_FLOATS * sizeof(float),
                                    "next irradiance"); // by record slot
  trace_flags_ = create_scratch(device, VkDeviceSize(probe_capacity_) * sizeof(std::uint32_t), "trace flags");
  // The header, the listed probe slots, the slots that trace this frame (light_trace_list.comp).
  const VkDeviceSize list_bytes =
      sizeof(gpu::LightListHeader) + 2 * VkDeviceSize(probe_capacity_) * sizeof(std::int32_t);
  if (list_bytes > device.info.max_storage_buffer_range)
    fail(StatusCode::unsupported, "light list: " + std::to_string(list_bytes) + " bytes exceed maxStorageBufferRange");
  light_list_ = device.allocator->create_buffer(list_bytes, kScratchUsage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                                                MemoryUse::device, "light list");
  relight_changes_ = create_scratch(
      device, sizeof(gpu::RelightChanges) + std::max<std::size_t>(emitters.size(), 1) * sizeof(gpu::EmitterScale),
      "relight changes");
  const VkDeviceSize tracked_bytes = VkDeviceSize(record_capacity_) * VkDeviceSize(rays) * 3 * sizeof(float);
  if (indirect_records_)
    record_slots_ = create_scratch(device, VkDeviceSize(probe_capacity_) * sizeof(std::int32_t), "record slots");
  tracking_ = tracked_bytes <= device.info.max_storage_buffer_range;
  tracked_punctual_ = create_scratch(device, tracking_ ? tracked_bytes : 16, "tracked punctual");
  if (!load_order.empty() && load_order.size() != 2 * std::size_t(probe_capacity_))
    fail(StatusCode::internal, "load order: " + std::to_string(load_order.size()) + " ints for " +
                                   std::to_string(probe_capacity_) + " probe slots");
  Buffer order_staging;
  if (!load_order.empty()) {
    load_order_ = create_scratch(device, load_order.size_bytes(), "load order");
    order_staging = device.allocator->create_buffer(load_order.size_bytes(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                                    MemoryUse::upload, "load order staging");
    std::memcpy(order_staging.mapped(), load_order.data(), load_order.size_bytes());
  }
  Buffer own_slots; // own_marked: record slot s for probe slot s, none marked unresolved
  if (retry_by_slot_) {
    own_slots = device.allocator->create_buffer(record_slots_.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                                MemoryUse::upload, "record slots staging");
    auto* slots = static_cast<std::int32_t*>(own_slots.mapped());
    for (std::uint32_t s = 0; s < probe_capacity_; ++s) slots[s] = std::int32_t(s);
  }
  {
    Submission clear(device);
    vkCmdFillBuffer(clear.cmd(), trace_flags_.get(), 0, VK_WHOLE_SIZE, 0);
    vkCmdFillBuffer(clear.cmd(), light_list_.get(), 0, VK_WHOLE_SIZE, 0);
    vkCmdFillBuffer(clear.cmd(), relight_changes_.get(), 0, VK_WHOLE_SIZE, 0);
    if (!emitters.empty()) {
      barrier(clear.cmd(), kTransferWrite, kTransferWrite);
      update_buffer(clear.cmd(), relight_changes_.get(), sizeof(gpu::RelightChanges), emitters.data(),
                    emitters.size_bytes());
    }
    // Slots that were never traced hold no records (kind 0 = miss) and no tracked share, not stale memory:
    // the relight walks every live slot, and the same input must give the same output.
    vkCmdFillBuffer(clear.cmd(), tracked_punctual_.get(), 0, VK_WHOLE_SIZE, 0);
    vkCmdFillBuffer(clear.cmd(), next_irradiance_.get(), 0, VK_WHOLE_SIZE, 0);
    if (own_slots) {
      const VkBufferCopy region{0, 0, record_slots_.size()};
      vkCmdCopyBuffer(clear.cmd(), own_slots.get(), record_slots_.get(), 1, &region);
    } else if (record_slots_) {
      vkCmdFillBuffer(clear.cmd(), record_slots_.get(), 0, VK_WHOLE_SIZE, 0xFFFFFFFFu); // -1: none
    }
    for (const Buffer& page : record_pages_) vkCmdFillBuffer(clear.cmd(), page.get(), 0, VK_WHOLE_SIZE, 0);
    if (order_staging) {
      const VkBufferCopy region{0, 0, load_order_.size()};
      vkCmdCopyBuffer(clear.cmd(), order_staging.get(), load_order_.get(), 1, &region);
    }
    barrier(clear.cmd(), kTransferWrite, kAnyDeviceAccess);
    clear.submit_and_wait();
  }
  counters_ = PassCounters<gpu::LightCounters>(device, "light counters", rings);
  untraced_by_ring_.assign(rings, 0u);
  shadow_pairs_.reserve(gpu::RELIGHT_MAX_SHADOW_PAIRS);
  load_window_by_ring_.assign(rings, 0u);
  std::array<VkBuffer, gpu::LIGHT_BINDING_COUNT> buffers{};
  for (std::uint32_t page = 0; page < gpu::LIGHT_RECORD_PAGES; ++page) // unused pages repeat page 0
    buffers[gpu::LIGHT_BINDING_RECORDS + page] = record_pages_[page < record_pages_.size() ? page : 0].get();
  buffers[gpu::LIGHT_BINDING_NEXT_IRRADIANCE] = next_irradiance_.get();
  buffers[gpu::LIGHT_BINDING_COUNTERS] = counters_.buffer();
  buffers[gpu::LIGHT_BINDING_TRACE_FLAGS] = trace_flags_.get();
  buffers[gpu::LIGHT_BINDING_LIGHT_LIST] = light_list_.get();
  buffers[gpu::LIGHT_BINDING_RELIGHT_CHANGES] = relight_changes_.get();
  buffers[gpu::LIGHT_BINDING_TRACKED_PUNCTUAL] = tracked_punctual_.get();
  // Read only with LightPush.indirect_records; otherwise any buffer satisfies the binding.
  buffers[gpu::LIGHT_BINDING_RECORD_SLOTS] = record_slots_ ? record_slots_.get() : trace_flags_.get();
  buffers[gpu::LIGHT_BINDING_LOAD_ORDER] = load_order_ ? load_order_.get() : trace_flags_.get(); // read if ordered
  volume_set_ = volume.volume_set();
  descriptors_ = make_pass_descriptor_set(device.vk(), device.compute_pipelines().set_layout(Layout::light), buffers);
}

void LightUpdatePass::create_record_pages(int rays) {
  if (rays < 1)
    fail(StatusCode::invalid_volume, "lighting_info: rays " + std::to_string(rays) + " < 1"); // unvalidated upload
  const VkDeviceSize probe_bytes = VkDeviceSize(rays) * sizeof(gpu::LightRecord);
  const VkDeviceSize fit = device_.info.max_storage_buffer_range / probe_bytes; // whole probes per page
  const VkDeviceSize pages = fit == 0 ? gpu::LIGHT_RECORD_PAGES + 1 : (VkDeviceSize(record_capacity_) + fit - 1) / fit;
  if (pages > gpu::LIGHT_RECORD_PAGES)
    fail(StatusCode::unsupported, "light records: " + std::to_string(VkDeviceSize(record_capacity_) * probe_bytes) +
                                      " bytes need " + std::to_string(pages) +
                                      " pages of at most maxStorageBufferRange (" +
                                      std::to_string(device_.info.max_storage_buffer_range) + ") of " +
                                      device_.info.name + ", more than " + std::to_string(gpu::LIGHT_RECORD_PAGES) +
                                      "; bake with fewer probes or lighting rays, or load with light_update = false");
  probes_per_page_ = static_cast<std::uint32_t>(std::min<VkDeviceSize>(fit, record_capacity_)); // applies(): >= 1 probe
  for (std::uint32_t first = 0; first < record_capacity_; first += probes_per_page_) {
    const std::uint32_t probes = std::min(probes_per_page_, record_capacity_ - first);
    record_pages_.push_back(create_scratch(device_, VkDeviceSize(probes) * probe_bytes, "light records"));
  }
}

void LightUpdatePass::relight(std::span<const gpu::LightChange> changes, std::size_t first) {
  if (changes_.count == 0) first_change_ = first;
  for (const gpu::LightChange& change : changes) {
    if (changes_.count == gpu::RELIGHT_MAX_CHANGES) {
      relight_everything_ = true;
      return;
    }
    changes_.changes[changes_.count++] = change;
  }
}

void LightUpdatePass::record_relight(VkCommandBuffer cmd, PassTimer& timer, std::uint32_t slot,
                                     const gpu::LightPush& window) {
  // A full trace reads the new sky and emitters itself. With FrameLimits::relight_frames the sky and the emitters
  // relight a window of slots a frame, the next period - 1 frames the others.
  // A new period while windows wait starts them over, so that every slot is covered.
  const auto restart = [&](bool changed, std::uint32_t& left, std::uint32_t& period) {
    if (changed || (left > 0 && period != window.relight_period)) left = period = window.relight_period;
  };
  restart(sky_changed_, sky_windows_left_, sky_window_period_);
  restart(emitters_changed_, emitter_windows_left_, emitter_window_period_);
  if (window.trace_mode == gpu::LIGHT_TRACE_EVERY) sky_windows_left_ = emitter_windows_left_ = 0;
  sky_relit_ = sky_windows_left_ > 0;
  emitters_relit_ = emitter_windows_left_ > 0;
  if (sky_relit_) --sky_windows_left_;
  if (emitters_relit_) --emitter_windows_left_;
  sky_changed_ = emitters_changed_ = false;
  const auto record_sky_and_emitters = [&] {
    if (sky_relit_) record_every_slot(cmd, Kernel::light_sky);
    if (sky_relit_ && emitters_relit_) barrier(cmd, kComputeReadWrite, kComputeReadWrite); // the same records
    if (emitters_relit_) record_every_slot(cmd, Kernel::light_emitters, record_chunks_);
  };
  const bool settling = settle_relight_windows(window.relight_period);
  const bool changed = relight_everything_ || changes_.count > 0;
  // A frame that recomputes whole sums everywhere (an object moved, or more than RELIGHT_MAX_CHANGES changes)
  // spends them on the gather window's probes; the others only note the change (stale) and catch up when the
  // window reaches them, within one period of windows. A few changes update every probe by differences
  // (one or two shadow rays per record: cheaper now than a whole sum later).
  // While probes catch up, later changes are deferred the same way.
  const bool windowed = window.slot_count < probe_capacity_ && (relight_everything_ || stale_frames_left_ > 0);
  const std::uint32_t period = (probe_capacity_ + window.slot_count - 1) / std::max(window.slot_count, 1u);
  if (windowed && changed) stale_frames_left_ = period; // this frame and the next period - 1 windows
  // A budget changed while probes wait: a whole period of the new windows from here covers every slot.
  if (stale_frames_left_ > 0 && window.slot_count != last_window_)
    stale_frames_left_ = std::max(stale_frames_left_, period);
  last_window_ = window.slot_count;
  const bool catching_up = stale_frames_left_ > 0;
  if (catching_up) --stale_frames_left_;
  relit_ = (changed || catching_up) && window.trace_mode != gpu::LIGHT_TRACE_EVERY; // a full trace caches afresh
  // One light changed: its E_after is tracked, and if it was the tracked light, E_before is read back. Not
  // while records may be stale: their catch-up does not write the tracked share.
  const bool single = tracking_ && !relight_everything_ && changes_.count == 1 && !windowed;
  const int changed_light = single ? int(first_change_) : -1;
  changes_.reuse_before = single && tracked_light_ == changed_light ? 1u : 0u;
  changes_.track_after = single ? 1u : 0u;
  if (changed) tracked_light_ = changed_light; // light_trace writes the shares of this light from now on
  // FrameLimits::relight_frames: the tracked light changing alone relights one window of slots (light_relight), so
  // the next period - 1 frames relight the others.
  if (!settling && changes_.reuse_before != 0u && window.relight_period > 1u) {
    light_windows_left_ = window.relight_period - 1u;
    light_window_period_ = window.relight_period;
    windowed_light_ = changes_.changes[0].after;
  }
  if (relit_) {
    changes_.everything = relight_everything_ ? 1u : 0u;
    // Objects moved and no light changed: only the records a moved box may shadow (light_relight).
    changes_.shadows_only =
        relight_everything_ && changes_.count == 0 && shadow_pairs_fit_ && !windows_dropped_ ? 1u : 0u;
    // Last frame's relight read the changes (the frame's opening barrier orders it before this write).
    vkCmdUpdateBuffer(cmd, relight_changes_.get(), 0,
                      offsetof(gpu::RelightChanges, changes) + changes_.count * sizeof(gpu::LightChange), &changes_);
    vkCmdUpdateBuffer(cmd, relight_changes_.get(), offsetof(gpu::RelightChanges, shadows_only),
                      sizeof(changes_.shadows_only), &changes_.shadows_only);
    barrier(cmd, kTransferWrite, kComputeReadWrite);
    gpu::LightPush push = window;
    push.tracked_light = tracked_light_;
    if (!windowed) push.first_slot = 0u, push.slot_count = probe_capacity_; // every probe now, stale ones too
    Pipelines& pipelines = device_.compute_pipelines();
    bind_sets_and_push(cmd, pipelines.layout(Layout::light), volume_set_, descriptors_.set, push);
    timer.begin(cmd, slot);
    if (windowed && changed) { // the probes outside the window note the change first
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines.kernel(Kernel::light_mark_stale));
      dispatch_groups(cmd, device_, probe_capacity_);
      barrier(cmd, kComputeReadWrite, kComputeReadWrite); // the relight reads and clears the flags it wrote
    }
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines.kernel(Kernel::light_relight));
    dispatch_groups(cmd, device_, push.slot_count);
    if (sky_relit_ || emitters_relit_) {
      barrier(cmd, kComputeReadWrite, kComputeReadWrite); // the same record pages (other records: kept simple)
      record_sky_and_emitters();
    }
    timer.end(cmd, slot);
    barrier(cmd, kComputeWrite, kComputeReadWrite);
  } else if (sky_relit_ || emitters_relit_) {
    Pipelines& pipelines = device_.compute_pipelines();
    bind_sets_and_push(cmd, pipelines.layout(Layout::light), volume_set_, descriptors_.set, window);
    timer.begin(cmd, slot);
    record_sky_and_emitters();
    timer.end(cmd, slot);
    barrier(cmd, kComputeWrite, kComputeReadWrite);
  }
  changes_.count = 0;
  relight_everything_ = windows_dropped_ = false;
}

// While windows of slots have not taken the tracked light's last change (light_windows_left_ > 0): a frame without
// changes re-submits that light unchanged, so that the next window takes it (returns true); the tracked light
// changing again goes on as usual; anything else (another change, moved objects, a new period) first recomputes
// every record's whole sum, so that no record keeps an older light in a sum that later differences build on.
bool LightUpdatePass::settle_relight_windows(std::uint32_t period) {
  if (light_windows_left_ == 0) return false;
  const bool tracked_again = !relight_everything_ && changes_.count == 1 && int(first_change_) == tracked_light_;
  if (tracked_again && period == light_window_period_) return false;
  if (!relight_everything_ && changes_.count == 0 && period == light_window_period_) {
    changes_.changes[0] = {windowed_light_, windowed_light_};
    changes_.count = 1;
    first_change_ = std::size_t(tracked_light_);
    --light_windows_left_;
    return true;
  }
  relight_everything_ = windows_dropped_ = true;
  light_windows_left_ = 0;
  return false;
}

// The sky or emitters changed: every slot with records takes them (light_sky, light_emitters), in the relight's
// timer slot, the sets and push constants already bound.
void LightUpdatePass::record_every_slot(VkCommandBuffer cmd, Kernel kernel, std::uint32_t chunks) {
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, device_.compute_pipelines().kernel(kernel));
  dispatch_groups(cmd, device_, probe_capacity_, chunks);
}

void LightUpdatePass::emitters_changed(VkCommandBuffer cmd, std::span<const gpu::EmitterScale> scales) {
  barrier(cmd, kAnyDeviceAccess, kTransferWrite); // last frame's passes read the table before it is overwritten
  update_buffer(cmd, relight_changes_.get(), sizeof(gpu::RelightChanges), scales.data(), scales.size_bytes());
  barrier(cmd, kTransferWrite, kAnyDeviceAccess);
  emitters_changed_ = true;
}

bool LightUpdatePass::record(VkCommandBuffer cmd, PassTimer& timer, const LightTimerSlots& slots,
                             const FrameLimits& limits) {
  Pipelines& pipelines = device_.compute_pipelines();
  const VkPipelineLayout layout = pipelines.layout(Layout::light);
  vkCmdFillBuffer(cmd, counters_.buffer(), 0, VK_WHOLE_SIZE, 0);
  // The load trace (slots from untraced_from_ on have no records): every slot in the first frame, or a
  // window of max_traced_probes slots per frame (the rest at once when the limit is lifted midway).
  const auto max_traced = std::uint32_t(limits.max_traced_probes);
  const bool trace_every = untraced_from_ == 0 && (max_traced == 0 || max_traced >= probe_capacity_);
  const std::uint32_t untraced = probe_capacity_ - untraced_from_;
  const std::uint32_t load_window = trace_every ? 0u : max_traced == 0 ? untraced : std::min(max_traced, untraced);
  // Objects moved: their boxes go into RelightChanges before any pass of this frame reads it (the frame's
  // opening barrier orders last frame's reads); a full trace needs no marks.
  const bool moved = !moved_boxes_.empty() && !trace_every;
  if (moved) upload_moved_boxes(cmd);
  const bool marked = moved && retrace_moved_;
  barrier(cmd, kTransferWrite, kComputeReadWrite);
  // The gather window (without the light list): max_gathered slots from the cursor on, every slot by default.
  const auto max_gathered = std::uint32_t(limits.max_gathered_probes);
  const std::uint32_t window =
      max_gathered == 0 || queue_driven_ ? probe_capacity_ : std::min(max_gathered, probe_capacity_);
  const std::uint32_t first = window == probe_capacity_ ? 0u : gather_cursor_;
  if (!queue_driven_ && probe_capacity_ > 0) gather_cursor_ = (first + window) % probe_capacity_;
  gpu::LightPush push{probe_capacity_,
                      hysteresis_,
                      0u,
                      0u,
                      first,
                      window,
                      probes_per_page_,
                      tracked_light_,
                      limits.shadow_rays_per_record,
                      frames_recorded_++,
                      indirect_records_ ? 1u : 0u,
                      0u,
                      null_leaf_,
                      0u,
                      0u,
                      0u,
                      untraced_from_,
                      load_order_ ? 1u : 0u,
                      std::uint32_t(std::max(limits.relight_frames, 1)),
                      0u};
  push.relight_phase = push.seed % push.relight_period; // consecutive frames: every phase within a period
  if (trace_every) push.trace_mode = gpu::LIGHT_TRACE_EVERY;
  record_relight(cmd, timer, slots.relight, push);
  // A probe of a window is gathered once every `period` frames: it blends with h^period, so that its
  // irradiance follows a change in as many frames as without a budget (the time constant stays 1 / (1 - h)
  // frames), only in coarser steps.
  const std::uint32_t period = (probe_capacity_ + window - 1) / std::max(window, 1u);
  const float hysteresis = queue_driven_ ? hysteresis_ : std::pow(hysteresis_, float(period));
  push.hysteresis = hysteresis;
  push.trace_lanes = trace_every ? 1u : gpu::LIGHT_TRACE_LANES; // throughput when every probe traces, else latency
  push.listed = queue_driven_ ? 1u : 0u;
  push.tracked_light = tracked_light_;
  push.first_slot = 0u, push.slot_count = probe_capacity_; // light_trace: every slot (its flags decide)
  // One workgroup per probe slot, or per listed probe (the list's indirect sizes, offset 0 or 16).
  const auto dispatch = [&](VkPipeline pipeline, std::uint32_t slot_groups, VkDeviceSize list_offset,
                            std::uint32_t z = 1) {
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    if (queue_driven_)
      vkCmdDispatchIndirect(cmd, light_list_.get(), list_offset);
    else
      dispatch_groups(cmd, device_, slot_groups, z);
  };
  const std::uint32_t retry_span = retry_by_slot_ ? probe_capacity_ : listed_; // list places or probe slots
  const bool retrying = retry_left_ > 0 && retry_span > 0;
  if (retrying) {
    push.retry_first = retry_cursor_ % retry_span;
    push.retry_count = std::min(retry_window_, retry_left_);
    push.retry_by_slot = retry_by_slot_ ? 1u : 0u;
    retry_cursor_ = (push.retry_first + push.retry_count) % retry_span;
    retry_left_ -= push.retry_count;
  }
  bind_sets_and_push(cmd, layout, volume_set_, descriptors_.set, push);
  // A list the memory update writes has new probes every frame; the host's only when it flagged some.
  const bool flagged = trace_every || (queue_driven_ && !host_listed_) || host_retrace_ || marked || retrying;
  const bool traced = flagged || load_window > 0;
  if (traced) { // L1: records and hit fractions (every probe, the flagged ones, the load window's)
    timer.begin(cmd, slots.trace);
    if (marked) record_mark_moved(cmd);
    record_trace_list(cmd, push, flagged, load_window);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipelines.kernel(Kernel::light_trace));
    vkCmdDispatchIndirect(cmd, light_list_.get(), offsetof(gpu::LightListHeader, trace_x));
    timer.end(cmd, slots.trace);
    barrier(cmd, kComputeWrite, kComputeReadWrite);
    host_retrace_ = false;
  }
  untraced_from_ = trace_every ? probe_capacity_ : untraced_from_ + load_window;
  untraced_by_ring_[timer.ring()] = probe_capacity_ - untraced_from_;
  load_window_by_ring_[timer.ring()] = trace_every ? probe_capacity_ : load_window;
  moved_boxes_.clear(); // a full trace covered them
  retrace_moved_ = false;
  shadow_pairs_fit_ = false;
  push.first_slot = first;
  push.slot_count = window;
  push.retry_count = 0;
  push.untraced_from = untraced_from_; // the gather keeps the probes without records
  bind_sets_and_push(cmd, layout, volume_set_, descriptors_.set, push);
  timer.begin(cmd, slots.gather); // L2: relight the records, gather into next_irradiance
  dispatch(pipelines.kernel(Kernel::light_gather), window, 0);
  timer.end(cmd, slots.gather);
  // The resolve overwrites probes the gather read (write after read) and reads what it wrote.
  barrier(cmd, kComputeReadWrite, kComputeReadWrite);
  timer.begin(cmd, slots.resolve); // end of L2 and L3
  dispatch(pipelines.kernel(Kernel::light_resolve),
           (window + gpu::RUNTIME_WORKGROUP_SIZE - 1) / gpu::RUNTIME_WORKGROUP_SIZE,
           offsetof(gpu::LightListHeader, resolve_x));
  timer.end(cmd, slots.resolve);
  counters_.record_end_of_pass_copy(cmd, timer.ring());
  return traced;
}

void LightUpdatePass::record_host_list(VkCommandBuffer cmd, std::span<const std::int32_t> slots,
                                       std::span<const formats::CellRange> retrace) {
  if (slots.size() > probe_capacity_) fail(StatusCode::internal, "light list: more slots than probes");
  // VkDispatchIndirectCommand sizes folded into y past LIGHT_LIST_MAX_GROUPS_X, as memory_begin.comp does.
  const auto folded = [](std::uint32_t groups, std::uint32_t* out) {
    const std::uint32_t x = std::min(groups, gpu::LIGHT_LIST_MAX_GROUPS_X);
    out[0] = x, out[1] = x == 0 ? 0 : (groups + x - 1) / x, out[2] = 1;
  };
  gpu::LightListHeader header{};
  header.count = std::uint32_t(slots.size());
  std::uint32_t groups[3], resolve[3];
  folded(header.count, groups);
  folded((header.count + gpu::RUNTIME_WORKGROUP_SIZE - 1) / gpu::RUNTIME_WORKGROUP_SIZE, resolve);
  header.groups_x = groups[0], header.groups_y = groups[1], header.groups_z = groups[2];
  header.resolve_x = resolve[0], header.resolve_y = resolve[1], header.resolve_z = resolve[2];
  vkCmdUpdateBuffer(cmd, light_list_.get(), 0, sizeof(header), &header);
  constexpr std::size_t kChunk = 65536 / sizeof(std::int32_t); // vkCmdUpdateBuffer's limit
  for (std::size_t i = 0; i < slots.size(); i += kChunk)
    vkCmdUpdateBuffer(cmd, light_list_.get(), sizeof(header) + i * sizeof(std::int32_t),
                      std::min(kChunk, slots.size() - i) * sizeof(std::int32_t), slots.data() + i);
  host_listed_ = true;
  listed_ = header.count;
  if (retry_left_ > 0) retry_left_ = listed_; // places moved: a whole pass over the new list
  for (const formats::CellRange& range : retrace) {
    if (range.count == 0) continue;
    vkCmdFillBuffer(cmd, trace_flags_.get(), VkDeviceSize(range.first) * 4, VkDeviceSize(range.count) * 4,
                    gpu::TRACE_FLAG_RETRACE);
    host_retrace_ = true;
  }
}

void LightUpdatePass::retry_unresolved(std::uint32_t window) {
  const std::uint32_t span = retry_by_slot_ ? probe_capacity_ : listed_;
  retry_window_ = window == 0 ? span : window;
  retry_left_ = span; // once over the list as it is now (call after record_host_list), or over every slot
}

void LightUpdatePass::record_record_slots(VkCommandBuffer cmd, std::span<const formats::CellRange> ranges,
                                          std::span<const std::int32_t> slots) {
  if (!record_slots_ || slots.size() != probe_capacity_) fail(StatusCode::internal, "record slots without streaming");
  constexpr std::uint32_t kChunk = 65536 / sizeof(std::int32_t); // vkCmdUpdateBuffer's limit
  for (const formats::CellRange& range : ranges)
    for (std::uint32_t i = 0; i < range.count; i += kChunk)
      vkCmdUpdateBuffer(cmd, record_slots_.get(), VkDeviceSize(range.first + i) * sizeof(std::int32_t),
                        std::min(kChunk, range.count - i) * sizeof(std::int32_t), slots.data() + range.first + i);
}

LightStats LightUpdatePass::stats(std::uint32_t ring) const {
  const gpu::LightCounters c = counters_.read(ring);
  LightStats s;
  s.active = true;
  s.traced_probes = c.traced_probes;
  s.front_hits = c.front_hits;
  s.backface_hits = c.backface_hits;
  s.misses = c.misses;
  s.lit_probes = c.lit_probes;
  s.indirect_misses = c.indirect_misses;
  s.non_finite = c.non_finite;
  s.want_split = c.want_split;
  s.want_free = c.want_free;
  s.relit_records = c.relit_records;
  s.reused_records = c.reused_records;
  s.unresolved_probes = c.unresolved_probes;
  s.untraced_slots = int(untraced_by_ring_[ring]);
  s.load_window = int(load_window_by_ring_[ring]);
  return s;
}

} // namespace probebake::runtime::detail
