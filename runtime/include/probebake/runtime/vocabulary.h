// probebake runtime: the values the runtime's functions take and return, shared by the public facade
// (probebake/runtime/runtime.h, which includes this header) and the passes inside the library: Status and
// Result, the Context's options and reports, the upload options, what a frame is told (FrameInputs) and what
// it reports (FrameStats), and the sampling statistics. Units, errors and ownership: runtime.h.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <vulkan/vulkan_core.h>

#include "probebake/formats/probe_volume.h"
#include "probebake/formats/sh_codec.h"
#include "probebake/runtime/frame_inputs.h" // Box, FrameLimits, ObjectPose, SkyInput, EmitterStrength, FrameInputs

namespace probebake::runtime {

// ---- Status ---------------------------------------------------------------------------------------------
enum class StatusCode {
  ok,
  invalid_argument, // the caller broke a documented precondition (sizes differ, null handles)
  file_error,       // the file cannot be read or is not a .probes file we can decode
  invalid_volume,   // the volume breaks an invariant of formats::validate()
  no_device,        // no Vulkan loader, no device with Vulkan 1.2 compute, or the validation layer is missing
  unsupported,      // the device cannot hold the volume (a buffer over maxStorageBufferRange, ...)
  out_of_memory,    // host or device memory exhausted
  vulkan_error,     // any other Vulkan failure (device lost, ...)
  too_slow,         // the device did not finish a submission within 60 s: ask less of a frame (FrameLimits)
  internal,         // a bug in the runtime
};
const char* to_string(StatusCode code);

struct Status {
  StatusCode code = StatusCode::ok;
  std::string message; // empty when ok
  bool ok() const { return code == StatusCode::ok; }
};

// A value or the Status that explains why there is none.
template <class T>
class Result {
public:
  Result(T value) : value_(std::move(value)) {}        // NOLINT: implicit by design
  Result(Status status) : status_(std::move(status)) { // NOLINT: implicit by design
    if (status_.ok()) status_ = {StatusCode::internal, "Result made from an ok Status without a value"};
  }
  bool ok() const { return value_.has_value(); }
  const Status& status() const { return status_; }
  // Precondition: ok().
  T& value() & { return *value_; }
  const T& value() const& { return *value_; }
  T&& value() && { return std::move(*value_); }
  T* operator->() { return &*value_; }
  const T* operator->() const { return &*value_; }

private:
  std::optional<T> value_;
  Status status_;
};

// ---- Context: the options and reports of the Vulkan device the runtime works on --------------------------
struct ValidationMessage {
  enum class Severity { info, warning, error };
  Severity severity = Severity::warning;
  std::string id; // VUID or message id name, e.g. "SYNC-HAZARD-WRITE-AFTER-READ"
  std::string text;
};

struct ContextOptions {
  // Enables VK_LAYER_KHRONOS_validation with synchronization validation and a debug-utils messenger that
  // counts every warning and error (Context::validation_message_count). no_device when the layer is absent.
  // Ignored by Context::borrow (the host owns the instance and its layers).
  bool validation = false;
  // Device choice for Context::create: the first device whose name contains this text, if not empty;
  // otherwise discrete GPU, then integrated, virtual, other, and CPU (lavapipe) last.
  std::string device_name_contains;
  // Called for every validation message, on the thread that made the Vulkan call, possibly while the
  // Context is being destroyed (the callback must outlive the Context). Optional.
  std::function<void(const ValidationMessage&)> on_validation_message;
  // The runtime acts as if the device's maxStorageBufferRange were at most this many bytes (0 = the device's
  // own): a way to see, on a large GPU, what a smaller one would refuse or page (light records are split
  // into pages that each fit; a section that does not fit is `unsupported`). Used by Context::borrow too.
  std::uint64_t storage_buffer_range_limit = 0;
};

// The host's Vulkan objects, for Context::borrow. The device must support Vulkan 1.2 and `queue` must be
// from family `queue_family_index` with compute support. The host keeps them alive until every Context and
// Volume that uses them is destroyed.
struct HostVulkan {
  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical_device = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  std::uint32_t queue_family_index = 0;
};

struct DeviceInfo {
  std::string name;                           // e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string type;                           // "discrete", "integrated", "virtual", "cpu", "other"
  std::uint32_t api_version = 0;              // VK_MAKE_API_VERSION encoded
  std::uint64_t max_storage_buffer_range = 0; // bytes; a larger section is refused (unsupported)
  bool timestamps = false;                    // per-pass GPU times are measured
  bool borrowed = false;
  bool validation = false;
};

struct MemoryStats {
  std::size_t live_buffers = 0;
  std::uint64_t live_bytes = 0; // device memory of live buffers
  std::uint64_t peak_bytes = 0;
  std::size_t allocations = 0; // vkAllocateMemory calls so far (one per buffer)
};

// ---- Volume: upload options, frame inputs and frame statistics -------------------------------------------
// Free elements the memory update can allocate from (octree thesis §3.2.1): at upload the octree, probe and
// surfel-batch buffers grow so that at least this many are free; -1 = the default. The pools never grow
// while running: an allocation that does not fit leaves its node as it was and counts as failed. With
// streaming, the defaults add room for the file's subtrees of the most cells the budget lets be resident at
// once, whatever the camera does (docs/RUNTIME_INTERNALS.md "With streaming"); a host that knows its radius
// sets less (FrameStats::memory says how many are free after each frame).
struct MemoryPools {
  int free_clusters = -1; // node clusters; default max(64, clusters in use)
  int free_probes = -1;   // probes; default max(512, probes in use)
  int free_batches = -1;  // surfel batches (volumes that store surfels); default free probes x batches per probe
};

// Streaming cells (issue #15; docs/RUNTIME.md "Streaming cells"): the static tracing tree is kept on the
// device only for the cells around the camera (Volume::stream_around), within a byte budget, and the light
// update lights only the probes of those cells; the others keep their irradiance (the bake's, or the last
// one they were lit with). Needs a file whose tracing tree is split by cell (format 1.5: bake with
// --cell-size or --cell-depth >= 1) and the light update. With the memory update the probe subtrees of the
// cells that are out go back to its pools (each cell's node keeps one probe with their mean irradiance) and
// come back from them as the file has them; measures that cross a cell that is out decide nothing until
// cells arrive.
struct StreamingOptions {
  // Device bytes for the resident cells' tracing blocks (each counted at its size class's slot, at most 1/32
  // above its own bytes); 0 = no streaming (the whole tree is uploaded). The top level, the dynamic objects'
  // trees and the per-cell bookkeeping come on top (a few KB).
  std::uint64_t budget_bytes = 0;
  // Bytes copied per frame at most (0 = no limit); one cell is always allowed, so a cell larger than this
  // still arrives. Bounds each frame's upload spike; the other cells wait, nearest first.
  std::uint64_t max_upload_bytes = 0;
  // Probes of arrived cells that start being lit per frame at most (0 = no limit): a probe traces its rays
  // in the frame it joins, which costs far more than the copy, so this bounds that frame's spike. Probes
  // join in arrival order of their cells and keep their irradiance while they wait.
  int max_joining_probes = 0;
  // Metres beyond the stream_around radius within which resident cells stay (after the cells inside the
  // radius, as the budget allows), so that a camera going back and forth at the edge does not reload them.
  float keep_margin = 0.0f;
  // Probes lit at once at most (0 = every probe of the file): the light records (64 B per lighting ray,
  // 16 KiB per probe at 256 rays) are allocated for this many probes, not for the whole world; arrived
  // probes wait while every record slot is taken (StreamStats::joining_probes). Must be 0 with the memory
  // update, which lights every probe of its tree (so must light_reach below).
  int max_lit_probes = 0;
  // Metres around a cell within which every cell with faces must be resident before the cell's probes are
  // lit (0: as soon as the cell itself is resident). A probe's rays see only resident geometry and pass
  // through a cell that is out; with the reach of the rays that light a probe (a room's size indoors) the
  // probes lit see what they see in the whole file, so neighbouring cells light alike whichever are
  // resident. The others keep their irradiance (kSampleNotLit).
  float light_reach = 0.0f;
  // Read arriving cells on a thread of their own: a frame takes the cells already read and asks for the
  // others, so that it never waits for the disk; a cell then arrives a frame or more after it is wanted,
  // depending on the disk (StreamStats::reading_cells). Off: each frame reads the cells it loads, and the
  // same camera path gives the same frames.
  bool read_in_background = false;
  // With the memory update: bytes of the arriving cells' file subtrees (their nodes and probes, 144 B a
  // probe) passed to the GPU per frame at most; 0 = the most, gpu::MEMORY_SEAT_INTS ints (192 KiB), else at
  // least sizeof(gpu::CellSeat) (32). The other arrivals wait, in order. A cell larger than this alone
  // grows back by measures instead (a level a frame, as the memory update grows any leaf).
  std::uint64_t max_seat_bytes = 0;
};

struct UploadOptions {
  // Run formats::validate() before uploading and refuse an invalid volume (invalid_volume). Turn off only
  // to test the runtime on deliberately broken data.
  bool validate = true;
  // Run the light update (thesis §3.2.2) every frame when the volume carries the runtime lighting sections
  // (the bake writes them unless --no-runtime-lighting). false, or a volume without them: probes keep
  // their baked irradiance and no light-update buffer is allocated.
  bool light_update = true;
  // Weight of a probe's previous irradiance in each frame's update, in [0, 1): 0 makes every frame one
  // full sweep of the bake's iteration (one more bounce); larger values spread a change over about
  // 1 / (1 - hysteresis) frames (smoother, slower). The converged irradiance does not depend on it.
  float hysteresis = 0.9f;
  // Run the memory update (M0-M4) and the light update's transitions (L0-L3) so that the octree reshapes
  // itself to the FrameInputs (docs/RUNTIME_INTERNALS.md). Needs octree placement and the lighting sections
  // (L1 measures leaves by tracing the static BVH) and light_update; ignored otherwise. The uploaded volume
  // then differs from the file: pools grown to `pools`, and a volume without a leaf queue, or with one
  // smaller than its octree, gets a fresh queue seeded with every leaf (L2 / L3); the cells' element ranges
  // are dropped (they describe a fixed tree; read_back() has none). Off by default until moving geometry
  // exists (issue #12): a static tree without FrameInputs never changes.
  bool memory_update = false;
  MemoryPools pools{};
  // Punctual lights the host may add beyond the file's (FrameInputs::lights): the light buffer holds the
  // file's count plus this many records, allocated once at upload. >= 0; needs the lighting sections.
  int light_headroom = 0;
  StreamingOptions streaming{};
  // Frames that may be recorded (Volume::record_frame) before the first of them finished on the GPU; each
  // keeps its own timestamps and counters until Volume::poll_frame_stats returns them. In [1, 16].
  int frames_in_flight = 3;
  // Compact probes for the lookups (docs/RUNTIME.md "Compact probes"): l2 (32 bytes of irradiance per probe)
  // or l1 (16 bytes, band 2 dropped) encodes every probe after each frame into Volume::buffers().probe_points
  // and probe_codes, which sample_irradiance and sample_grid then read instead of the 144-byte records (the
  // light update keeps relighting in floats). float32 (the default) allocates and runs nothing.
  formats::ShCodec probe_code = formats::ShCodec::float32;
  // The camera when the volume loads (finite): a spread load trace (FrameLimits::max_traced_probes, frame_ms)
  // takes the probes nearest it first. Two ints per probe slot on the GPU; nothing without it.
  std::optional<glm::vec3> load_focus = std::nullopt;
};

// The per-frame passes in execution order (the pass table's PROBEBAKE_TIMER rows): the names FrameStats::passes uses (a pass that did not run in a
// frame is left out of that frame's list).
inline constexpr std::array kFramePassNames = {
#define PROBEBAKE_TIMER(name) #name,
#include "probebake/runtime/passes.def"
};

struct PassTime {
  std::string name;   // one of kFramePassNames
  double gpu_ms = -1; // GPU timestamp difference; -1 when the queue has no timestamps
};

// Statistics of one frame's light update (all 0 and active = false when the volume has none).
struct LightStats {
  bool active = false;
  int traced_probes = 0; // L1 (records and hit fractions): the load trace, flagged and retried probes
  int front_hits = 0;    // lighting rays of traced probes that hit a front face (or a double-sided back) /
  int backface_hits = 0; // the back of a single-sided triangle (inside geometry) / nothing
  int misses = 0;
  int lit_probes = 0;      // L2: probes relit and gathered this frame
  int indirect_misses = 0; // front hits whose SVO lookup found no probe (no indirect light there)
  int non_finite = 0;      // probes whose new irradiance was not finite: kept their old value
  int want_split = 0;      // L3: leaves that the leaf rule (leaf_rule.h) would split / whose probe it would free
  int want_free = 0;       //     (counted by light_resolve; the memory update acts on L1 verdicts)
  int lights = 0;          // punctual lights lit this frame
  int uploaded_lights = 0; // of them, records uploaded this frame (changed by FrameInputs::lights)
  int relit_records = 0;   // records whose cached punctual irradiance was updated (in reach of a changed
                           // light: inside its range, or all for a light without range or after an object moved)
  int reused_records = 0;  // of them, updated with one shadow ray (the same light changed last time too)
  int moved_objects = 0;   // dynamic objects whose pose FrameInputs::object_poses changed this frame
  int load_window = 0, untraced_slots = 0; // the load trace: this frame's window, the slots it has still to reach
  int unresolved_probes = 0; // streaming: events of this frame that left a probe unresolved (its rays crossed a
                             // cell that is out before they hit anything): each trace that did, and each relight
                             // that newly did (a probe already unresolved is not counted again by the relight;
                             // one relit and then traced in the same frame counts twice). Such probes keep
                             // their irradiance until a trace after cells arrive sees that geometry
                             // (docs/RUNTIME.md "Streaming cells")
};

// Statistics of one frame's memory update and light transitions (all 0 and active = false without one).
struct MemoryUpdateStats {
  bool active = false;
  std::array<int, 9> processed{}; // leaf-queue entries processed, by state: M0..M4 (0-4), L0..L3 (5-8)
  int deferred = 0;               // entries left for a later frame by FrameLimits
  int probes_placed = 0;          // M1 and merged parents
  int probes_freed = 0;           // M2 and merged children
  int splits = 0;                 // M3
  int collapses = 0;              // M4 merges
  int failed_allocations = 0;     // a pool ran dry: the node kept its state (retried later)
  int lost_entries = 0;           // pushes into a full leaf-queue segment (0: segments hold every node)
  int stale_entries = 0;          // entries whose node no longer fits their state (e.g. M3 above a lowered max depth)
  int svo_slots_dropped = 0;      // SVO stencil slots whose probe was freed or moved
  int svo_leaves_refilled = 0;    // SVO leaves left empty and given the probe of the octree leaf at their centre
  int unresolved_measures = 0;    // streaming: leaf measures whose lattice crossed a cell that is out; the leaf
                                  // kept its shape and is measured again when cells arrive
  int cells_collapsed = 0;        // streaming: dropped cells whose subtree went back to the pools
  int free_clusters = 0, cluster_capacity = 0; // pool use after the frame
  int free_probes = 0, probe_capacity = 0;
  int free_batches = 0, batch_capacity = 0;
};

// Statistics of one frame's cell streaming (all 0 and active = false without it). The upload's GPU time is
// the "stream_upload" pass; its host time (numbering the blocks into the staging buffer) is upload_cpu_ms.
struct StreamStats {
  bool active = false;
  int resident_cells = 0;           // cells whose probes are lit (with their tracing block, if they have faces)
  std::uint64_t resident_bytes = 0; // their blocks' slots (StreamingOptions::budget_bytes), <= the budget
  int loaded_cells = 0, dropped_cells = 0;
  std::uint64_t loaded_bytes = 0;
  int waiting_cells = 0;  // wanted but left for later frames by max_upload_bytes
  int unplaced_cells = 0; // loads that found no free run in the fragmented arena (retried next frame)
  int moved_cells = 0;    // resident cells whose blocks moved to compact the arena for a load (GPU copies)
  int reading_cells = 0;  // wanted cells still being read on the background thread (read_in_background)
  int refused_cells = 0;  // loads whose bytes on disk could not be read or differ from those validated at
                          // load (never retried; Volume::stream_refusals says why)
  int joined_probes = 0;  // probes of resident cells that joined the light update this frame (traced)
  int joining_probes = 0; // probes of resident cells still waiting for max_joining_probes
  double upload_cpu_ms = 0.0;
};

struct FrameStats {
  std::uint64_t frame = 0;      // frames run on this Volume, this one included
  std::vector<PassTime> passes; // in execution order; passes a frame does not run are not listed
  double cpu_ms = 0.0;          // record + submit + wait, measured on the host
  int live_probes = 0;          // allocated probes found by this frame's probe index build
  int probe_capacity = 0;
  LightStats light;
  MemoryUpdateStats memory;
  StreamStats streaming;
};

struct SampleStats {
  std::size_t samples = 0;
  std::size_t misses = 0;  // lookups without a probe (as probe_index::SamplerStats)
  std::size_t not_lit = 0; // streaming: lookups that used a probe the light update does not light now (the
                           // cell is out, or its probes wait): its irradiance is the file's or the last lit
  std::size_t dispatches = 0;
  double gpu_ms = -1;  // sum over dispatches; -1 without timestamps
  double cpu_ms = 0.0; // including uploads and read-backs of queries and results
};

// What Volume::sample_irradiance says of each lookup besides its irradiance (bits).
inline constexpr std::uint32_t kSampleMiss = 1u;   // no probe: the irradiance is 0
inline constexpr std::uint32_t kSampleNotLit = 2u; // streaming: a probe it used is not being lit (kept irradiance)

// How Volume::sample_irradiance finds the probes of a point.
enum class SampleMethod {
  svo,        // the SVO probe index: the blended lookup of probe_index/lookup.h (what games use)
  grid,       // a grid bake's lattice, looked up as grid engines do (probe_index/grid_lookup.h, sample_grid.glsl);
              // unsupported for volumes without the grid_lattice section
  all_probes, // the octree thesis's baseline (§3.2.4): every live probe, one visibility ray each through the
              // BVH; for comparison only; needs the lighting sections (unsupported otherwise)
};

} // namespace probebake::runtime
