// The light update (octree thesis §3.2.2) on a static octree: L1 traces every live probe's lighting rays
// and placement lattice once (light_trace.comp) and caches each record's punctual irradiance, which
// light_relight.comp updates only where lights or objects changed; L2 relights the kept records every frame and gathers
// them into the probes with hysteresis (light_gather.comp, then light_resolve.comp copies the result
// into the probes, so that the whole frame reads last frame's values), L3 compares hit fractions with the
// split thresholds by the leaf rule (counted; the memory update acts on its own L1 measures).
// Exists only for volumes that carry the runtime lighting sections (bake default).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <vulkan/vulkan_core.h>

#include "core/allocator.h"
#include "core/commands.h"
#include "core/device.h"
#include "core/gpu_volume.h"
#include "core/handles.h"
#include "core/pass_counters.h"
#include "core/pipelines.h"
#include "probebake/formats/probe_volume.h"
#include "probebake/runtime_types.h"
#include "probebake/runtime/vocabulary.h"

namespace probebake::runtime::detail {

struct LightTimerSlots {
  std::uint32_t relight, trace, gather, resolve;
};

// Where a probe slot's light records are (LIGHT_BINDING_RECORD_SLOTS, light_update_bindings.h).
struct RecordSlots {
  enum class Kind {
    own,        // each probe slot has its own records; no record-slot buffer
    handed_out, // streaming: `count` record slots, handed out by the host (record_record_slots)
    own_marked, // streaming with the memory update: each probe slot its own, the buffer holding the
                // RECORD_SLOT_UNRESOLVED marks; retries count probe slots (the GPU writes the light list)
  };
  Kind kind = Kind::own;
  std::uint32_t count = 0; // handed_out
};

// UploadOptions::load_focus: the `capacity` probe slots by distance of their probe to `focus`, nearest first (free
// slots and slots past `probes` last, ties by slot), then each slot's rank in that order: 2 * capacity ints.
std::vector<std::int32_t> load_order_nearest(std::span<const gpu::Probe> probes, std::uint32_t capacity,
                                             glm::vec3 focus);

class LightUpdatePass {
public:
  // The per-ray records are split into up to LIGHT_RECORD_PAGES pages of whole probes, each within
  // maxStorageBufferRange; throws RuntimeError(unsupported) when they need more.
  // `rings`: frames in flight whose statistics are kept apart (PassCounters).
  // `records`: how a probe slot finds its records (RecordSlots).
  // `load_order`: empty (the load trace in slot order) or load_order_nearest()'s.
  // `emitters`: the file's emitters at their baked strength (EmitterInputs::scales()).
  LightUpdatePass(Device& device, const GpuVolume& volume, int rays, float hysteresis, std::uint32_t rings,
                  std::span<const gpu::EmitterScale> emitters, RecordSlots records = {},
                  std::span<const std::int32_t> load_order = {});

  // Whether `volume` can run the light update: it has the lighting sections and probes.
  static bool applies(const GpuVolume& volume);

  // Records L1 (first frame every probe, or with limits.max_traced_probes a window of slots per frame until
  // every slot was traced once; after objects_moved(), or with walk_light_list() in every later frame,
  // the flagged probes), L2 and L3 between the timer slots' timestamps.
  // `limits.max_gathered_probes`: probes gathered and resolved this frame when the pass does not walk the
  // light list, a window of slots that moves on every frame (0 = every slot); `limits.shadow_rays_per_record`:
  // the light sampling's budget of whole punctual sums (0 = exact). Returns whether L1 was recorded.
  bool record(VkCommandBuffer cmd, PassTimer& timer, const LightTimerSlots& slots, const FrameLimits& limits);
  // Probe slots the load trace has not reached yet (none once it ended).
  std::uint32_t untraced_slots() const { return probe_capacity_ - untraced_from_; }
  // Whether the last record() updated cached punctual irradiance (light_relight), the sky's records (light_sky)
  // or the emitters' (light_emitters).
  bool relit() const { return relit_ || sky_relit_ || emitters_relit_; }
  // The host changed the sky (SkyInputs uploaded it): the next record() relights every miss record (light_sky).
  void sky_changed() { sky_changed_ = true; }
  // The host changed emitter strengths: records the upload of the new table (one EmitterScale per emitter), and
  // the next record() sums the front records' emitter light again (light_emitters; windowed by relight_frames).
  void emitters_changed(VkCommandBuffer cmd, std::span<const gpu::EmitterScale> scales);
  // After the submission: this frame's statistics.
  LightStats stats(std::uint32_t ring) const; // of the frame recorded into `ring`, once it finished
  // Objects moved through `boxes` (each the union of an object's old and new box; more than
  // RELIGHT_MAX_MOVED_BOXES are merged into the last): the next record() recomputes the punctual sums whose
  // shadow ray to one of `lights` (the current ones) may cross a box, and with `retrace` (no memory update)
  // re-traces the probes whose lighting rays cross one (light_mark_moved); the other records are kept.
  void objects_moved(std::span<const Box> boxes, std::span<const gpu::PunctualLight> lights, bool retrace);
  // Lights changed: the next record() updates the cached punctual irradiance of the records they reach
  // (light_relight); more than RELIGHT_MAX_CHANGES changes before a record() recompute every record's sum.
  // `first`: the light index of changes[0] (the others follow it).
  void relight(std::span<const gpu::LightChange> changes, std::size_t first);
  // From now on the memory update's light transitions fill the light list: trace, gather and resolve walk
  // it (indirect dispatches) instead of every slot, and light_trace runs every frame for flagged probes.
  void walk_light_list() { queue_driven_ = true; }
  // Streaming: the child word of a cell that is out; light_trace flags probes whose rays cross one
  // (RECORD_SLOT_UNRESOLVED) and the gather keeps their irradiance.
  void set_null_leaf(std::uint32_t word) { null_leaf_ = word; }
  // Streaming: cells arrived, so unresolved probes may now see their geometry. From the next record() on,
  // light_trace retraces the unresolved probes among `window` places of the light list per frame (0 = all),
  // moving on until it has passed the whole list once (again from the start when the list changes under it:
  // places move): a bounded cost per frame, whatever was unresolved. Call after this frame's record_host_list.
  // With RecordSlots::own_marked the window counts probe slots instead of list places.
  void retry_unresolved(std::uint32_t window);
  // Streaming (walk_light_list() on, no memory update): the host's list of the probe slots to light, and
  // the slot ranges [first, first + count) whose records the next light_trace makes afresh (probes whose
  // geometry just arrived). Recorded before record(); at most LightListHeader + probe_capacity entries.
  void record_host_list(VkCommandBuffer cmd, std::span<const std::int32_t> slots,
                        std::span<const formats::CellRange> retrace);
  // Streaming: uploads the record slot (-1: none) of the probes in `ranges` from `slots` (one per probe slot).
  void record_record_slots(VkCommandBuffer cmd, std::span<const formats::CellRange> ranges,
                           std::span<const std::int32_t> slots);
  // uint per probe slot, 1 = trace its records in the next light_trace (cleared there).
  VkBuffer trace_flags() const { return trace_flags_.get(); }
  // Streaming: int per probe slot, its record slot (-1: not lit); VK_NULL_HANDLE otherwise.
  VkBuffer record_slots() const { return record_slots_ ? record_slots_.get() : VK_NULL_HANDLE; }
  VkDeviceSize record_slots_size() const { return record_slots_ ? record_slots_.size() : 0; }
  // LightListHeader + int per probe slot (runtime_types.h), written by the light transitions.
  VkBuffer light_list() const { return light_list_.get(); }

private:
  // Pages of whole probes' records, each within maxStorageBufferRange (probes_per_page_).
  void create_record_pages(int rays);
  // Uploads the pending changes and records light_relight between the slot's timestamps, when any change is
  // pending or probes outside earlier gather windows may still be stale. `window`: this frame's gather
  // window (first_slot, slot_count) and light sampling (shadow_rays, seed).
  void record_relight(VkCommandBuffer cmd, PassTimer& timer, std::uint32_t slot, const gpu::LightPush& window);
  bool settle_relight_windows(std::uint32_t period);
  // light_sky or light_emitters over every slot with records (`chunks` workgroups each, gl_WorkGroupID.z), the sets
  // and push constants already bound.
  void record_every_slot(VkCommandBuffer cmd, Kernel kernel, std::uint32_t chunks = 1);
  // The pending moved boxes and their (box, light) shadow pairs into RelightChanges (shadow_pairs_fit_);
  // light_mark_moved flags the probes whose rays cross them.
  void upload_moved_boxes(VkCommandBuffer cmd);
  void record_mark_moved(VkCommandBuffer cmd);
  // The places of the probes that trace this frame, and light_trace's dispatch size (light_trace_list.comp):
  // with `flagged`, the flagged (or every) probe of the list or of every slot, by `push`; then the
  // `load_window` slots from untraced_from_ on that are not flagged.
  void record_trace_list(VkCommandBuffer cmd, const gpu::LightPush& push, bool flagged, std::uint32_t load_window);

  Device& device_;
  std::uint32_t probe_capacity_ = 0;
  std::uint32_t record_capacity_ = 0; // probes whose records the pages hold
  bool indirect_records_ = false;     // records by LIGHT_BINDING_RECORD_SLOTS (streaming)
  bool retry_by_slot_ = false;        // RecordSlots::own_marked: retry windows over probe slots
  std::uint32_t null_leaf_ = 0;       // streaming's null leaf word (LightPush::null_leaf), 0 = none
  float hysteresis_ = 0.0f;
  std::uint32_t untraced_from_ = 0;                // slots from here on have no records yet (the load trace)
  std::vector<std::uint32_t> untraced_by_ring_;    // probe_capacity_ - untraced_from_ after each ring's frame
  std::vector<std::uint32_t> load_window_by_ring_; // slots of each ring's frame's load window
  bool queue_driven_ = false;
  bool host_listed_ = false;       // the host writes the light list (streaming): trace only when it asks
  bool host_retrace_ = false;      // record_host_list flagged probes since the last trace
  std::uint32_t listed_ = 0;       // entries of the host's light list
  std::uint32_t retry_cursor_ = 0; // first list place of the next retry window
  std::uint32_t retry_window_ = 0; // list places per frame
  std::uint32_t retry_left_ = 0;   // list places still to retry since cells last arrived
  bool relight_everything_ = false;
  bool sky_changed_ = false, sky_relit_ = false;
  bool emitters_changed_ = false, emitters_relit_ = false;
  bool relit_ = false;
  std::uint32_t gather_cursor_ = 0;               // first slot of the next frame's gather window
  std::uint32_t frames_recorded_ = 0;             // the light sampling's seed: the same frames, the same draws
  std::uint32_t stale_frames_left_ = 0;           // frames until every window has caught up with the last change
  std::uint32_t last_window_ = 0;                 // the last frame's window size
  std::vector<gpu::MovedBox> moved_boxes_;        // pending objects_moved boxes (empty: none)
  std::vector<gpu::PunctualLight> shadow_lights_; // the lights of the last objects_moved
  bool retrace_moved_ = false;                    // objects_moved asked for light_mark_moved
  bool shadow_pairs_fit_ = false;                 // the uploaded boxes' pairs fit RELIGHT_MAX_SHADOW_PAIRS
  std::vector<gpu::ShadowPair> shadow_pairs_;     // the last uploaded (box, light) pairs
  gpu::RelightChanges changes_{};                 // pending changes (changes_.count), uploaded by record()
  std::size_t first_change_ = 0;                  // light index of changes_.changes[0]
  // FrameLimits::relight_frames: frames left until every window of slots took the tracked light's last change,
  // their period and that light; windows_dropped_: this frame recomputes whole sums instead (no shadows_only);
  // frames left until every window took the last sky, and the last emitter strengths.
  std::uint32_t light_windows_left_ = 0, light_window_period_ = 0;
  gpu::PunctualLight windowed_light_{};
  bool windows_dropped_ = false;
  std::uint32_t sky_windows_left_ = 0, sky_window_period_ = 0, emitter_windows_left_ = 0, emitter_window_period_ = 0;
  Buffer relight_changes_; // RelightChanges, then an EmitterScale per emitter
  // The tracked light (RelightChanges): its E at every front record is in tracked_punctual_; -1 = none.
  // Left out (tracking_ = false) when that buffer would exceed maxStorageBufferRange.
  int tracked_light_ = -1;
  bool tracking_ = false;
  Buffer tracked_punctual_;
  std::vector<Buffer> record_pages_; // 1 to LIGHT_RECORD_PAGES
  std::uint32_t probes_per_page_ = 0;
  std::uint32_t record_chunks_ = 1; // light_emitters' workgroups per probe
  Buffer next_irradiance_;
  Buffer trace_flags_;
  Buffer record_slots_; // streaming: int per probe slot
  Buffer load_order_;   // UploadOptions::load_focus: LIGHT_BINDING_LOAD_ORDER
  Buffer light_list_;
  PassCounters<gpu::LightCounters> counters_;
  VkDescriptorSet volume_set_ = VK_NULL_HANDLE; // the volume's (set 0)
  PassDescriptorSet descriptors_;               // set 1
};

} // namespace probebake::runtime::detail
