// probebake runtime: a baked probe volume (.probes) on a Vulkan device, its per-frame compute passes and
// irradiance lookups. This is the header a game includes; the values its functions take and return are in
// probebake/runtime/vocabulary.h, which it includes. docs/RUNTIME.md explains the buffers and how a game
// samples the volume in its own shaders; docs/RUNTIME_INTERNALS.md the passes and barriers.
//
// Units: world space in metres (glTF, Y up), irradiance in W/m^2 (docs/LIGHTING.md), times in ms.
// Errors: no function throws; each returns a Status, or a Result<T> holding a value or a Status. The
//         message is one line naming what failed ("<file>: <place>: <reason>" for file errors).
// Ownership: a Context owns the Vulkan objects it creates (instance, device, queue use, command pool,
//         memory); with Context::borrow it uses the host's instance, device and queue and destroys none of
//         them. A Volume owns its buffers and keeps its Context's device alive, so Volumes may outlive the
//         Context object they came from. Both are move-only.
// Thread-safety: none inside. Calls on one Context and on the Volumes made from it must not overlap (they
//         submit to one queue); distinct Contexts are independent. With a borrowed queue the host must not
//         use that VkQueue during a call (Vulkan requires external synchronisation of queues).
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <vulkan/vulkan_core.h>

#include "probebake/sky_map.h"

#include "probebake/formats/probe_volume.h"
#include "probebake/formats/validate.h"
#include "probebake/runtime/vocabulary.h"

namespace probebake::runtime {

namespace detail {
struct Device;
struct VolumeState;
} // namespace detail

// ---- Context: the Vulkan device the runtime works on ------------------------------------------------------
class Context {
public:
  // Creates an instance (Vulkan 1.2), picks a device (see ContextOptions) and creates a compute queue.
  static Result<Context> create(const ContextOptions& options = {});
  // Uses the host's objects (see HostVulkan); creates only a command pool and the runtime's own objects.
  static Result<Context> borrow(const HostVulkan& host, const ContextOptions& options = {});

  Context(Context&&) noexcept;
  Context& operator=(Context&&) noexcept;
  ~Context();

  const DeviceInfo& device_info() const;
  // The Vulkan objects the runtime works on (created or borrowed): a host that let Context::create make the
  // device records Volume::record_frame into command buffers of its own from a pool on this queue family.
  // The Context keeps owning what it created.
  HostVulkan vulkan() const;
  // Validation warnings and errors so far (0 without validation), and the first 64 of them as text.
  std::uint64_t validation_message_count() const;
  std::vector<std::string> validation_messages() const;
  MemoryStats memory_stats() const;

private:
  explicit Context(std::shared_ptr<detail::Device> device);
  friend class Volume;
  std::shared_ptr<detail::Device> device_;
};

// ---- Volume: one probe volume in GPU storage buffers ---------------------------------------------------
// A buffer of the volume for binding in the host's own descriptor sets; buffer is VK_NULL_HANDLE when the
// file has no such section. size in bytes; the whole buffer is the section, offset 0.
struct BufferView {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceSize size = 0;
};

// One storage buffer per .probes section, laid out exactly as the section (gpu_types.h, std430).
struct VolumeBuffers {
  BufferView volume_info, octree, probes, surfel_batches, leaf_queue_header, leaf_entries, probe_index, svo_nodes,
      svo_leaves;
  // Runtime lighting sections (format 1.1): the light update's inputs, e.g. for the game's own ray queries.
  BufferView lighting_info, ray_directions, punctual_lights, emitter_patches;
  // The scene as the shaders trace it (format 1.4, gpu_types.h "Compact tracing"; 1.1-1.3 files are
  // upgraded to it on load). With streaming, trace_nodes, trace_faces and trace_vertices are all the
  // streaming arena (the resident cells renumbered, docs/RUNTIME_INTERNALS.md "Streaming cells: internals")
  // and trace_trees its trees.
  BufferView trace_trees, trace_nodes, trace_faces, trace_vertices, trace_materials;
  // Streaming with a light update only (else empty): int per probe slot, < 0 where the probe has no light
  // records; bind it at PROBEBAKE_BINDING_RECORD_SLOTS for probebake_sample_irradiance_not_lit
  // (sample_irradiance.glsl). Not a file section.
  BufferView record_slots;
  // A grid bake's lattice (format 1.8): bind it at PROBEBAKE_BINDING_GRID_LATTICE for
  // probebake_sample_irradiance_grid (sample_grid.glsl). Empty for other volumes, and with streaming (whose
  // probe slots the lattice does not follow yet).
  BufferView grid_lattice;
  // UploadOptions::probe_code l1 or l2 (else empty): vec4 per probe slot (position, 1 allocated / 0 free) and
  // its code (1 or 2 uvec4 blocks, probebake/sh_code.h), rewritten after every frame; bind them at
  // PROBEBAKE_BINDING_PROBE_POINTS and PROBEBAKE_BINDING_PROBE_CODES with PROBEBAKE_PROBE_CODE_BANDS defined
  // (sample_irradiance.glsl): the lookups then read no probe record. Not file sections.
  BufferView probe_points, probe_codes;
};

class Volume {
public:
  // Reads the file (formats::read_probes_file), validates it and uploads it. With streaming the file stays
  // open: host memory keeps the global sections only, and each cell's tracing is read again from disk when
  // the cell loads, checked against the bytes validated here (a changed cell is refused, StreamStats).
  static Result<Volume> load(Context& context, const std::filesystem::path& path, const UploadOptions& options = {});
  // Uploads an in-memory volume (copied; the caller keeps its own).
  static Result<Volume> upload(Context& context, const formats::ProbeVolume& volume, const UploadOptions& options = {});

  Volume(Volume&&) noexcept;
  Volume& operator=(Volume&&) noexcept;
  ~Volume();

  // One frame of the runtime's passes on the queue, waited for (thesis figure 3.4): the memory update
  // (§3.2.1, M0-M4) and SVO refresh, the probe index build (§3.2.3), then the light update (§3.2.2: its
  // transitions L0-L3, L1 records, L2 lighting) when the volume has one. invalid_argument when `inputs`
  // break their ranges (non-finite or inverted boxes, thresholds outside [0, 1], max depth outside [0, 12]),
  // or carry boxes or thresholds for a volume that runs no memory update.
  Result<FrameStats> run_frame(const FrameInputs& inputs = {});

  // The same frame recorded into the host's command buffer (docs/RUNTIME.md "Recording into the host's
  // frame"): `cmd` is in the recording state, outside a render pass, and will be submitted to a queue of
  // the runtime's queue family after the frames recorded before it. Nothing is submitted or waited for and
  // nothing is allocated; the frame's first barrier orders it after every earlier command of the queue and
  // its last one before every later command's shader and transfer reads, so the host samples the updated
  // probes in any stage after it. Returns the frame's number. invalid_argument as run_frame, or when the
  // frame UploadOptions::frames_in_flight frames earlier has not finished on the GPU (nothing recorded).
  Result<std::uint64_t> record_frame(VkCommandBuffer cmd, const FrameInputs& inputs = {});
  // The statistics of the oldest recorded frame that finished on the GPU and were not returned yet, or
  // nullopt when none has finished; never waits. Call once per frame: a frame's statistics are dropped when
  // its ring is recorded again. FrameStats::cpu_ms is the time record_frame took.
  std::optional<FrameStats> poll_frame_stats();

  // Irradiance at each (position, unit normal) by the GPU sampling pass: the same lookup as
  // probe_index::sample_irradiance. Spans must have equal sizes (invalid_argument). Batches larger than the
  // device's maxStorageBufferRange allows are split into several dispatches.
  // `flags` (optional) receives each lookup's kSample* bits (kSampleNotLit only with streaming and the SVO method).
  Result<std::vector<glm::vec3>> sample_irradiance(std::span<const glm::vec3> positions,
                                                   std::span<const glm::vec3> normals, SampleStats* stats = nullptr,
                                                   SampleMethod method = SampleMethod::svo,
                                                   std::vector<std::uint32_t>* flags = nullptr);

  // Streaming (UploadOptions::streaming): the camera that the next recorded frames stream around: cells whose
  // cube lies within `radius` metres of `position`, nearest first, while they fit the budget. Until the
  // first call no cell is resident. invalid_argument for a non-finite position, a negative or non-finite
  // radius, or a volume loaded without streaming.
  Status stream_around(glm::vec3 position, float radius);
  // A new budget from the next frame on, at most UploadOptions::streaming.budget_bytes (invalid_argument).
  Status set_stream_budget(std::uint64_t bytes);
  // Cell::cell_index of every resident cell after the last recorded frame, ascending (empty without streaming).
  std::vector<int> resident_cells() const;
  // Why each refused cell (StreamStats::refused_cells) was refused, one line each ("<file>: cells[k] (cell N):
  // <reason>"), oldest first; empty without streaming.
  std::vector<std::string> stream_refusals() const;

  // Copies every GPU buffer back into a ProbeVolume; the CPU-only parts (streaming cells, cell depth, input
  // hash) come from the uploaded volume; with streaming, the tracing sections are the file's.
  Result<formats::ProbeVolume> read_back();
  // read_back() + formats::validate(): invalid_volume naming the first violations when the live state breaks
  // an invariant. With streaming, also every resident cell's tracing block read back and numbered back
  // equals the file's bytes and is the one its top-level word leads to, and every other cell's word is the
  // null leaf (violations "streamed_cell"). `report` (optional) receives the full report.
  Status validate_live(formats::ValidationReport* report = nullptr);

  // The buffers; punctual_lights holds light_capacity() records, the first lighting_info.lights live.
  VolumeBuffers buffers() const;
  const gpu::VolumeInfo& info() const;
  // The punctual lights the next frame lights (the file's until FrameInputs::lights changes them), and how
  // many the volume can hold (the file's count + UploadOptions::light_headroom; 0 without a light update).
  std::span<const gpu::PunctualLight> lights() const;
  int light_capacity() const;
  // The file's sky section's header (format 1.9: the map's size, the physical sky's turbidity, sun direction and
  // sun light), nothing for a constant sky or without a light update. FrameInputs::sky changes the sky.
  std::optional<gpu::SkyHeader> sky() const;
  // The glTF material of each emitter (format 1.10: the emissive materials whose light the file's emitter patches
  // carry), which FrameInputs::emitters switch; empty without a light update or with emitters in the probes.
  std::span<const int> emitter_materials() const;
  // The file's dynamic objects (empty for a static scene) and each one's current world_from_object (the
  // identity for an index out of range).
  std::span<const gpu::DynamicObject> dynamic_objects() const;
  // Whether frames run the memory update (UploadOptions::memory_update on a volume it applies to).
  bool runs_memory_update() const;
  glm::mat4 object_pose(int object) const;

private:
  explicit Volume(std::unique_ptr<detail::VolumeState> state);
  std::unique_ptr<detail::VolumeState> state_;
};

} // namespace probebake::runtime
