// The public API (runtime.h): argument checks and the conversion of every exception into a Status.
#include "probebake/runtime/runtime.h"

#include <cmath>
#include <optional>
#include <string>
#include <utility>

#include "streaming/cell_source.h"
#include "core/device.h"
#include "core/error.h"
#include "probebake/dynamic/animation.h"
#include "probebake/formats/cell_file.h"
#include "probebake/formats/probes_file.h"
#include "probebake/formats/trace_mesh.h"
#include "probebake/memory_types.h"
#include "core/volume_state.h"

namespace probebake::runtime {
namespace {

using detail::guarded;
using detail::Section;

// invalid_volume naming the first violations, or ok.
Status status_of(const formats::ValidationReport& report) {
  if (report.valid()) return {};
  std::string message =
      report.name + ": " + std::to_string(report.violations.size()) + (report.truncated ? "+" : "") + " violation(s)";
  for (std::size_t i = 0; i < report.violations.size() && i < 3; ++i)
    message += (i == 0 ? ": " : "; ") + formats::format_violation(report.violations[i]);
  return {StatusCode::invalid_volume, message};
}

Status validated(const formats::ProbeVolume& volume, const formats::TracingView& tracing,
                 const std::filesystem::path& path) {
  formats::ValidationReport report = formats::validate(volume, tracing);
  report.name = path.string();
  return status_of(report);
}

// A file opened for streaming, checked and set to check its cells: a 1.7 file without its cells, each of which
// is then validated as it arrives; an older one validated whole, its cells' tracing in place in the file's
// mapping, each cell then held to the checksum of the bytes validated.
Status ready_to_stream(formats::OpenedCellFile& opened, bool validate, const std::filesystem::path& path) {
  if (opened.cells_unread) {
    std::vector<formats::CellEntry> entries;
    if (validate) {
      formats::ValidationReport report = formats::validate_without_cells(opened.volume, opened.tracing(), entries);
      report.name = path.string();
      if (const Status valid = status_of(report); !valid.ok()) return valid;
    }
    opened.file.expect_unread(opened.volume, std::move(entries));
    return {};
  }
  if (validate)
    if (const Status valid = validated(opened.volume, opened.tracing(), path); !valid.ok()) return valid;
  formats::upgrade_tracing(opened.volume); // 1.1-1.3 files (decoded whole): the shaders trace the compact layout only
  if (!opened.volume.cell_tracing.empty()) opened.file.expect(opened.volume, opened.tracing()); // after the upgrade
  return {};
}

Status check_options(const UploadOptions& options) {
  if (!(options.hysteresis >= 0.0f && options.hysteresis < 1.0f))
    return {StatusCode::invalid_argument, "hysteresis must be in [0, 1), got " + std::to_string(options.hysteresis)};
  const auto finite = [](glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  if (options.load_focus && !finite(*options.load_focus))
    return {StatusCode::invalid_argument, "load_focus must be finite"};
  if (options.frames_in_flight < 1 || options.frames_in_flight > 16)
    return {StatusCode::invalid_argument,
            "frames_in_flight must be in [1, 16], got " + std::to_string(options.frames_in_flight)};
  if (!(options.streaming.keep_margin >= 0.0f) || !std::isfinite(options.streaming.keep_margin))
    return {StatusCode::invalid_argument, "streaming.keep_margin must be finite and >= 0"};
  if (!(options.streaming.light_reach >= 0.0f) || !std::isfinite(options.streaming.light_reach))
    return {StatusCode::invalid_argument, "streaming.light_reach must be finite and >= 0"};
  const std::uint64_t seat_bytes = options.streaming.max_seat_bytes;
  if (seat_bytes != 0 && (seat_bytes < sizeof(gpu::CellSeat) || seat_bytes > std::uint64_t(gpu::MEMORY_SEAT_INTS) * 4))
    return {StatusCode::invalid_argument, "streaming.max_seat_bytes must be 0 or in [" +
                                              std::to_string(sizeof(gpu::CellSeat)) + ", " +
                                              std::to_string(std::uint64_t(gpu::MEMORY_SEAT_INTS) * 4) + "]"};
  if (options.streaming.max_joining_probes < 0 || options.streaming.max_lit_probes < 0)
    return {StatusCode::invalid_argument, "streaming.max_joining_probes and max_lit_probes must be >= 0"};
  if (options.light_headroom < 0)
    return {StatusCode::invalid_argument, "light_headroom must be >= 0, got " + std::to_string(options.light_headroom)};
  if (formats::sh_codec_name(options.probe_code) == "?")
    return {StatusCode::invalid_argument, "probe_code is no formats::ShCodec"};
  return {};
}

BufferView view(const detail::VolumeState& state, Section section) {
  if (state.streaming &&
      (section == Section::trace_nodes || section == Section::trace_faces || section == Section::trace_vertices))
    return {state.streaming->tracing().arena(), state.streaming->tracing().arena_size()};
  if (state.streaming && section == Section::trace_trees)
    return {state.streaming->tracing().trees(), state.streaming->tracing().trees_size()};
  const detail::Buffer& b = state.gpu->buffer(section);
  return {b.get(), b.size()};
}

// A streamed volume's read-back reports the file's tracing sections: the arena holds a renumbered part of
// them, which validate_live checks against them.
void with_file_tracing(formats::ProbeVolume& live, const formats::ProbeVolume& file) {
  live.trace_trees = file.trace_trees, live.trace_nodes = file.trace_nodes;
  live.trace_faces = file.trace_faces, live.trace_vertices = file.trace_vertices;
}

BufferView record_slots_view(const detail::VolumeState& s) {
  if (!s.light || s.light->record_slots() == VK_NULL_HANDLE) return {};
  return {s.light->record_slots(), s.light->record_slots_size()};
}

// The checks of run_frame and record_frame: ranges, and inputs the volume has no pass for.
Status check_inputs_for(const detail::VolumeState& state, const FrameInputs& inputs) {
  if (const Status checked = detail::check_frame_inputs(inputs); !checked.ok()) return checked;
  const bool reshapes = !inputs.changed_boxes.empty() || inputs.max_depth || inputs.split_low || inputs.split_high;
  if (reshapes && !state.memory)
    return Status{StatusCode::invalid_argument,
                  "run_frame: changed boxes and thresholds need the memory update "
                  "(UploadOptions::memory_update, an octree volume with lighting sections)"};
  if (inputs.lights) {
    if (!state.light_inputs)
      return Status{StatusCode::invalid_argument,
                    "run_frame: punctual lights need the light update (UploadOptions::light_update, "
                    "a volume with the runtime lighting sections)"};
    if (const Status lights = detail::check_lights(*inputs.lights, state.light_inputs->capacity()); !lights.ok())
      return lights;
  }
  if (inputs.sky) {
    if (!state.sky_inputs)
      return Status{StatusCode::invalid_argument,
                    "run_frame: a sky needs the light update (UploadOptions::light_update, a volume with the runtime "
                    "lighting sections)"};
    if (const Status sky = state.sky_inputs->check(*inputs.sky); !sky.ok()) return sky;
  }
  if (!inputs.emitters.empty()) {
    if (!state.emitter_inputs)
      return Status{StatusCode::invalid_argument,
                    "run_frame: emitter strengths need the light update (UploadOptions::light_update, a volume with "
                    "the runtime lighting sections)"};
    if (const Status emitters = state.emitter_inputs->check(inputs.emitters); !emitters.ok()) return emitters;
  }
  if (!inputs.object_poses.empty()) {
    if (!state.light)
      return Status{StatusCode::invalid_argument,
                    "run_frame: object poses need the light update (UploadOptions::light_update)"};
    if (const Status poses = detail::check_object_poses(inputs.object_poses, state.cpu_parts.dynamic_objects.size());
        !poses.ok())
      return poses;
  }
  return {};
}

} // namespace

// ---- Context ---------------------------------------------------------------------------------------------
Context::Context(std::shared_ptr<detail::Device> device) : device_(std::move(device)) {}
Context::Context(Context&&) noexcept = default;
Context& Context::operator=(Context&&) noexcept = default;
Context::~Context() = default;

Result<Context> Context::create(const ContextOptions& options) {
  return guarded([&]() -> Result<Context> { return Context(detail::create_device(options)); });
}

Result<Context> Context::borrow(const HostVulkan& host, const ContextOptions& options) {
  return guarded([&]() -> Result<Context> { return Context(detail::borrow_device(host, options)); });
}

const DeviceInfo& Context::device_info() const { return device_->info; }

HostVulkan Context::vulkan() const {
  return {device_->instance.get(), device_->physical_device, device_->vk(), device_->queue, device_->queue_family};
}
std::uint64_t Context::validation_message_count() const { return device_->log->count(); }
std::vector<std::string> Context::validation_messages() const { return device_->log->kept(); }
MemoryStats Context::memory_stats() const { return device_->allocator->stats(); }

// ---- Volume ----------------------------------------------------------------------------------------------
Volume::Volume(std::unique_ptr<detail::VolumeState> state) : state_(std::move(state)) {}
Volume::Volume(Volume&&) noexcept = default;
Volume& Volume::operator=(Volume&&) noexcept = default;
Volume::~Volume() = default;

Result<Volume> Volume::upload(Context& context, const formats::ProbeVolume& volume, const UploadOptions& options) {
  return guarded([&]() -> Result<Volume> {
    if (const Status checked = check_options(options); !checked.ok()) return checked;
    if (options.validate) {
      const Status valid = status_of(formats::validate(volume));
      if (!valid.ok()) return valid;
    }
    if (formats::has_float_tracing(volume)) { // a 1.1-1.3 volume: the shaders trace the compact layout only
      formats::ProbeVolume upgraded = volume;
      formats::upgrade_tracing(upgraded);
      return Volume(std::make_unique<detail::VolumeState>(context.device_, upgraded, options));
    }
    return Volume(std::make_unique<detail::VolumeState>(context.device_, volume, options));
  });
}

Result<Volume> Volume::load(Context& context, const std::filesystem::path& path, const UploadOptions& options) {
  return guarded([&]() -> Result<Volume> {
    if (const Status checked = check_options(options); !checked.ok()) return checked;
    if (options.streaming.budget_bytes == 0) {
      formats::ProbeVolume volume = formats::read_probes_file(path);
      if (options.validate)
        if (const Status valid = validated(volume, formats::tracing_view(volume), path); !valid.ok()) return valid;
      formats::upgrade_tracing(volume); // 1.1-1.3 files: the shaders trace the compact layout only
      return Volume(std::make_unique<detail::VolumeState>(context.device_, volume, options));
    }
    // Streaming reads each cell from disk when it loads (cell_file.h).
    formats::OpenedCellFile opened = formats::CellFile::open(path);
    if (const Status ready = ready_to_stream(opened, options.validate, path); !ready.ok()) return ready;
    if (opened.volume.cell_tracing.empty()) // VolumeState refuses to stream it
      return Volume(std::make_unique<detail::VolumeState>(context.device_, opened.volume, options));
    const formats::TracingView tracing = opened.tracing();
    return Volume(std::make_unique<detail::VolumeState>(context.device_, opened.volume, options,
                                                        detail::cell_source_on_disk(std::move(opened.file)), &tracing));
  });
}

Result<FrameStats> Volume::run_frame(const FrameInputs& inputs) {
  return guarded([&]() -> Result<FrameStats> {
    if (const Status checked = check_inputs_for(*state_, inputs); !checked.ok()) return checked;
    return state_->run_frame(inputs);
  });
}

Result<std::uint64_t> Volume::record_frame(VkCommandBuffer cmd, const FrameInputs& inputs) {
  return guarded([&]() -> Result<std::uint64_t> {
    if (cmd == VK_NULL_HANDLE) return Status{StatusCode::invalid_argument, "record_frame: null command buffer"};
    if (const Status checked = check_inputs_for(*state_, inputs); !checked.ok()) return checked;
    return state_->record(cmd, inputs);
  });
}

std::optional<FrameStats> Volume::poll_frame_stats() {
  auto polled = guarded([&]() -> Result<std::optional<FrameStats>> { return state_->poll(); });
  return polled.ok() ? std::move(polled.value()) : std::nullopt;
}

Result<std::vector<glm::vec3>> Volume::sample_irradiance(std::span<const glm::vec3> positions,
                                                         std::span<const glm::vec3> normals, SampleStats* stats,
                                                         SampleMethod method, std::vector<std::uint32_t>* flags) {
  return guarded([&]() -> Result<std::vector<glm::vec3>> {
    if (positions.size() != normals.size())
      return Status{StatusCode::invalid_argument, "sample_irradiance: " + std::to_string(positions.size()) +
                                                      " positions but " + std::to_string(normals.size()) + " normals"};
    if (method == SampleMethod::grid && state_->streaming)
      return Status{StatusCode::unsupported, "sample_irradiance: the grid sampler does not follow streamed probe "
                                             "slots yet; load the grid without streaming"};
    std::vector<glm::vec3> out(positions.size());
    SampleStats local;
    if (flags) flags->assign(positions.size(), 0u);
    state_->sample->run(positions, normals, out, local, method,
                        flags ? std::span<std::uint32_t>(*flags) : std::span<std::uint32_t>());
    if (stats) *stats = local;
    return out;
  });
}

Result<formats::ProbeVolume> Volume::read_back() {
  return guarded([&]() -> Result<formats::ProbeVolume> {
    formats::ProbeVolume out = state_->gpu->read_back(state_->cpu_parts);
    if (state_->streaming) with_file_tracing(out, state_->streaming->tracing().file_tracing());
    return out;
  });
}

Status Volume::stream_around(glm::vec3 position, float radius) {
  return guarded([&]() -> Status {
    if (!state_->streaming)
      return {StatusCode::invalid_argument, "stream_around: the volume was loaded without streaming"};
    if (!std::isfinite(position.x) || !std::isfinite(position.y) || !std::isfinite(position.z) ||
        !std::isfinite(radius) || radius < 0.0f)
      return {StatusCode::invalid_argument,
              "stream_around: the position must be finite and the radius finite and >= 0"};
    state_->streaming->set_camera(position, radius);
    return {};
  });
}

std::vector<int> Volume::resident_cells() const {
  return state_->streaming ? state_->streaming->resident_cells() : std::vector<int>{};
}

std::vector<std::string> Volume::stream_refusals() const {
  return state_->streaming ? state_->streaming->refusals() : std::vector<std::string>{};
}

Status Volume::set_stream_budget(std::uint64_t bytes) {
  return guarded([&]() -> Status {
    if (!state_->streaming)
      return {StatusCode::invalid_argument, "set_stream_budget: the volume was loaded without streaming"};
    if (bytes > state_->streaming->max_budget())
      return {StatusCode::invalid_argument, "set_stream_budget: " + std::to_string(bytes) + " bytes exceed the " +
                                                std::to_string(state_->streaming->max_budget()) +
                                                " allocated at upload"};
    state_->streaming->set_budget(bytes);
    return {};
  });
}

Status Volume::validate_live(formats::ValidationReport* report) {
  return guarded([&]() -> Status {
    formats::ProbeVolume live = state_->gpu->read_back(state_->cpu_parts);
    const formats::ProbeVolume file =
        state_->streaming ? state_->streaming->tracing().file_tracing() : formats::ProbeVolume{};
    if (state_->streaming) with_file_tracing(live, file);
    formats::ValidationReport checked = formats::validate(live);
    checked.name = "live volume";
    if (state_->streaming) // the cells as the file has them, whatever the memory update did to the probe tree
      for (const std::string& problem : state_->streaming->tracing().verify(file))
        checked.violations.push_back({"streamed_cell", "trace_nodes", -1, problem});
    Status status = status_of(checked);
    if (report) *report = std::move(checked);
    return status;
  });
}

VolumeBuffers Volume::buffers() const {
  const detail::VolumeState& s = *state_;
  return {view(s, Section::volume_info),
          view(s, Section::octree),
          view(s, Section::probes),
          view(s, Section::surfel_batches),
          view(s, Section::leaf_queue_header),
          view(s, Section::leaf_entries),
          view(s, Section::probe_index),
          view(s, Section::svo_nodes),
          view(s, Section::svo_leaves),
          view(s, Section::lighting_info),
          view(s, Section::ray_directions),
          view(s, Section::punctual_lights),
          view(s, Section::emitter_patches),
          view(s, Section::trace_trees),
          view(s, Section::trace_nodes),
          view(s, Section::trace_faces),
          view(s, Section::trace_vertices),
          view(s, Section::trace_materials),
          record_slots_view(s),
          s.streaming ? BufferView{} : view(s, Section::grid_lattice),
          s.codes ? BufferView{s.codes->points().get(), s.codes->points().size()} : BufferView{},
          s.codes ? BufferView{s.codes->codes().get(), s.codes->codes().size()} : BufferView{}};
}

const gpu::VolumeInfo& Volume::info() const { return state_->cpu_parts.info; }

std::span<const gpu::PunctualLight> Volume::lights() const {
  return state_->light_inputs ? state_->light_inputs->current() : std::span<const gpu::PunctualLight>{};
}

int Volume::light_capacity() const {
  return state_->light_inputs ? static_cast<int>(state_->light_inputs->capacity()) : 0;
}

std::optional<gpu::SkyHeader> Volume::sky() const {
  return state_->sky_inputs ? state_->sky_inputs->header() : std::nullopt;
}

std::span<const int> Volume::emitter_materials() const {
  return state_->emitter_inputs ? std::span<const int>(state_->emitter_inputs->materials()) : std::span<const int>{};
}

std::span<const gpu::DynamicObject> Volume::dynamic_objects() const { return state_->cpu_parts.dynamic_objects; }

bool Volume::runs_memory_update() const { return state_->memory != nullptr; }

glm::mat4 Volume::object_pose(int object) const {
  if (object < 0 || std::size_t(object) >= state_->cpu_parts.dynamic_objects.size()) return glm::mat4(1.0f);
  const std::size_t o = static_cast<std::size_t>(object);
  return state_->objects ? state_->objects->pose(o) : dynamic::rest_pose(state_->cpu_parts.dynamic_objects[o]);
}

} // namespace probebake::runtime
