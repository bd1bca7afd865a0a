// The run driver behind `probebake run` and the runtime-only `probebake-run`: loads a .probes file onto a
// Vulkan device, runs the runtime's per-frame passes, prints per-pass GPU times and statistics
// (docs/RUNTIME.md). The only place that turns a runtime Status into an exit code.
#include "run_driver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <unistd.h>

#include <glm/geometric.hpp>

#include <glm/trigonometric.hpp>

#include "probebake/dynamic/animation.h"
#include "probebake/formats/error.h"
#include "probebake/formats/file_mapping.h"
#include "probebake/runtime/runtime.h"
#include "probebake/streaming/camera_path.h"
#include "run_report.h"
#include "run_lighting_changes.h"
#include "run_samples.h"

namespace probebake::run {
namespace {

using namespace probebake;

int exit_code_of(runtime::StatusCode code) {
  switch (code) {
  case runtime::StatusCode::ok: return 0;
  case runtime::StatusCode::invalid_argument: return 1;
  case runtime::StatusCode::file_error:
  case runtime::StatusCode::invalid_volume: return 2;
  case runtime::StatusCode::too_slow: return 5;
  default: return 4;
  }
}

int report(const RunOptions& options, const runtime::Status& status) {
  std::fprintf(stderr, "%s: %s: %s\n", options.program.c_str(), runtime::to_string(status.code),
               status.message.c_str());
  return exit_code_of(status.code);
}

struct PassSummary {
  std::vector<double> ms;
  void add(double value) { ms.push_back(value); }
  // "mean M median D min A max B over N frames" (the median hides lavapipe's shader JIT in frame 1).
  std::string text() const {
    std::vector<double> sorted = ms;
    std::sort(sorted.begin(), sorted.end());
    double sum = 0.0;
    for (double v : sorted) sum += v;
    char line[160];
    std::snprintf(line, sizeof(line), "mean %.3f median %.3f min %.3f max %.3f over %zu frames",
                  sum / double(sorted.size()), sorted[sorted.size() / 2], sorted.front(), sorted.back(), sorted.size());
    return line;
  }
};

void print_device(const runtime::DeviceInfo& d) {
  std::printf("device: %s (%s, Vulkan %u.%u.%u), maxStorageBufferRange %llu bytes, timestamps %s%s\n", d.name.c_str(),
              d.type.c_str(), VK_API_VERSION_MAJOR(d.api_version), VK_API_VERSION_MINOR(d.api_version),
              VK_API_VERSION_PATCH(d.api_version), static_cast<unsigned long long>(d.max_storage_buffer_range),
              d.timestamps ? "yes" : "no", d.validation ? ", validation layer on" : "");
}

// The --orbit-light pose of light `orbit.light` in frame `frame` (0: the baked pose): turned by
// 2 pi frame / period about the vertical axis through the circle's centre, RADIUS along -X from the light.
gpu::PunctualLight orbit_pose(const gpu::PunctualLight& baked, const LightOrbit& orbit, int frame) {
  constexpr float kTwoPi = 6.28318531f;
  const float angle = kTwoPi * float(frame % orbit.period) / float(orbit.period);
  const float c = std::cos(angle), s = std::sin(angle);
  gpu::PunctualLight light = baked;
  if (light.type == gpu::LIGHT_DIRECTIONAL) {
    light.direction = glm::normalize(glm::vec3(c * baked.direction.x + s * baked.direction.z, baked.direction.y,
                                               -s * baked.direction.x + c * baked.direction.z));
    return light;
  }
  const glm::vec3 centre = baked.position - glm::vec3(orbit.radius, 0.0f, 0.0f);
  light.position = centre + orbit.radius * glm::vec3(c, 0.0f, -s);
  return light;
}

// The --animate poses of the frame: only the objects whose pose changes (the runtime re-measures where they
// moved).
std::vector<runtime::ObjectPose> animated_poses(const RunOptions& options, const runtime::Volume& volume, int frame) {
  std::vector<runtime::ObjectPose> poses;
  if (!options.animate) return poses;
  const std::span<const gpu::DynamicObject> objects = volume.dynamic_objects();
  for (std::size_t o = 0; o < objects.size(); ++o) {
    const auto& only = options.animated_objects;
    if (!only.empty() && std::find(only.begin(), only.end(), int(o)) == only.end()) continue;
    const glm::mat4 pose = dynamic::animated_pose(*options.animate, frame, objects[o]);
    if (pose != volume.object_pose(int(o))) poses.push_back({int(o), pose});
  }
  return poses;
}

// The frame's inputs: the --orbit-light pose, the --animate poses, the limits and --max-depth, and the
// --depth-cycle schedule (at frames 0, P, 2P, ... the max depth becomes HIGH, LOW, HIGH, ... and the whole
// root cube is marked changed).
runtime::FrameInputs frame_inputs(const RunOptions& options, const runtime::Volume& volume,
                                  std::span<const gpu::PunctualLight> baked_lights, int frame) {
  const gpu::VolumeInfo& info = volume.info();
  runtime::FrameInputs in;
  in.object_poses = animated_poses(options, volume, frame);
  in.limits = options.limits; // the memory update's limits are ignored without one
  if (frame == 0 && options.max_depth) in.max_depth = options.max_depth;
  if (options.orbit_light) {
    in.lights.emplace(baked_lights.begin(), baked_lights.end());
    for (std::size_t l = 0; l < baked_lights.size(); ++l)
      if (options.orbit_light->light == LightOrbit::kEveryLight || std::size_t(options.orbit_light->light) == l)
        (*in.lights)[l] = orbit_pose(baked_lights[l], *options.orbit_light, frame);
  }
  if (options.day_cycle) add_day_cycle(in, volume, *options.day_cycle, frame);
  if (options.switch_emitters) add_emitter_switch(in, volume, *options.switch_emitters, frame);
  if (!options.depth_cycle || frame % options.depth_cycle->period != 0) return in;
  const bool high = (frame / options.depth_cycle->period) % 2 == 0;
  in.max_depth = high ? options.depth_cycle->high : options.depth_cycle->low;
  in.changed_boxes = {{info.root_min, info.root_min + glm::vec3(info.root_size)}};
  return in;
}

// "hour,emitters_on" of the frame: the day cycle's hour and whether the switched emitters are on (empty without).
std::string lighting_columns(const RunOptions& options, int frame) {
  std::string hour = options.day_cycle ? std::to_string(day_hour(*options.day_cycle, frame)) : std::string();
  return hour + ',' + (options.switch_emitters ? (emitters_on(*options.switch_emitters, frame) ? "1" : "0") : "");
}

// "x,y,z" of the orbiting light (or of light 0) after the frame; empty fields without lights.
std::string light_position(const runtime::Volume& volume, const RunOptions& options) {
  const std::size_t index = options.orbit_light ? std::size_t(std::max(options.orbit_light->light, 0)) : 0;
  if (index >= volume.lights().size()) return ",,";
  const glm::vec3 p = volume.lights()[index].position;
  return std::to_string(p.x) + ',' + std::to_string(p.y) + ',' + std::to_string(p.z);
}

void print_frame(const runtime::FrameStats& f) {
  std::printf("frame %llu:", static_cast<unsigned long long>(f.frame));
  for (const runtime::PassTime& p : f.passes) std::printf(" %s %.3f ms", p.name.c_str(), p.gpu_ms);
  std::printf(" | cpu %.3f ms | live probes %d / %d", f.cpu_ms, f.live_probes, f.probe_capacity);
  const runtime::LightStats& l = f.light;
  if (l.active) {
    std::printf(" | lit %d, lights %d (%d uploaded), relit records %d (%d with one shadow ray)", l.lit_probes, l.lights,
                l.uploaded_lights, l.relit_records, l.reused_records);
    if (l.traced_probes > 0)
      std::printf(", traced %d (rays: %d front, %d back, %d miss)", l.traced_probes, l.front_hits, l.backface_hits,
                  l.misses);
    std::printf(", indirect misses %d, non-finite %d, L3 split %d free %d", l.indirect_misses, l.non_finite,
                l.want_split, l.want_free);
  }
  const runtime::MemoryUpdateStats& m = f.memory;
  if (m.active)
    std::printf(" | memory: %d splits, %d merges, %d placed, %d freed, %d failed, %d deferred, %d unresolved, %d cells "
                "collapsed, free %d/%d probes",
                m.splits, m.collapses, m.probes_placed, m.probes_freed, m.failed_allocations, m.deferred,
                m.unresolved_measures, m.cells_collapsed, m.free_probes, m.probe_capacity);
  std::printf("\n");
}

} // namespace

int run_volume(const RunOptions& options) {
  runtime::ContextOptions context_options;
  context_options.validation = options.vulkan_validation;
  context_options.device_name_contains = options.device;
  context_options.on_validation_message = [](const runtime::ValidationMessage& m) {
    std::fprintf(stderr, "vulkan validation: %s: %s\n", m.id.c_str(), m.text.c_str());
  };
  auto context = runtime::Context::create(context_options);
  if (!context.ok()) return report(options, context.status());
  print_device(context->device_info());

  runtime::UploadOptions upload;
  upload.light_update = options.light_update;
  upload.hysteresis = options.hysteresis, upload.probe_code = options.probe_code;
  upload.load_focus = options.load_focus;
  upload.memory_update = !options.no_memory_update &&
                         (options.depth_cycle.has_value() || options.memory_update || options.animate.has_value());
  if (options.pool_probes) upload.pools.free_probes = *options.pool_probes;
  std::vector<streaming::PathPoint> path;
  if (options.stream) {
    upload.streaming = {.budget_bytes = options.stream->budget,
                        .max_upload_bytes = options.stream->max_upload,
                        .max_joining_probes = options.stream->max_joining,
                        .keep_margin = options.stream->keep_margin,
                        .max_lit_probes = options.stream->max_lit,
                        .light_reach = options.stream->light_reach,
                        .read_in_background = options.stream->background_reads};
    try {
      path = streaming::read_camera_path(options.stream->path);
      if (!upload.load_focus && !path.empty()) upload.load_focus = path.front().position;
    } catch (const Error& e) {
      return report(options, {runtime::StatusCode::file_error, e.what()});
    }
  }
  const int frames = options.stream ? int(path.size()) : options.frames;
  const auto load_start = std::chrono::steady_clock::now();
  std::optional<formats::MappedReadGuard> guard;
  if (options.stream) guard.emplace("probebake-run", options.input); // the load maps the file (cell_file.h)
  auto volume = runtime::Volume::load(context.value(), options.input, upload);
  guard.reset();
  if (!volume.ok()) return report(options, volume.status());
  const double load_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - load_start).count();
  const HostMemory after_load = host_memory();
  const gpu::VolumeInfo& info = volume->info();
  std::printf(
      "volume: %s: %d probe slots, %d octree elements, %d SVO nodes, %d SVO leaves, %d punctual lights, %llu bytes "
      "on the GPU, loaded in %.1f ms\n",
      options.input.c_str(), info.probe_capacity, info.octree_elements, info.svo_nodes, info.svo_leaves,
      int(volume->lights().size()), static_cast<unsigned long long>(context->memory_stats().live_bytes), load_ms);
  const std::vector<gpu::PunctualLight> baked_lights(volume->lights().begin(), volume->lights().end());
  if (options.orbit_light && options.orbit_light->light >= int(baked_lights.size()))
    return report(
        options,
        {runtime::StatusCode::invalid_argument,
         "--orbit-light " + std::to_string(options.orbit_light->light) + ": the volume has " +
             std::to_string(baked_lights.size()) + " punctual light(s)" +
             (volume->light_capacity() == 0 && options.light_update ? " (no runtime lighting sections)" : "")});

  if (options.day_cycle) {
    if (const auto refusal = day_cycle_refusal(volume.value()))
      return report(options, {runtime::StatusCode::invalid_argument, options.input + ": " + *refusal});
    std::printf("day cycle: a day in %g s (%g frames), sun from 6:00\n", double(*options.day_cycle),
                double(*options.day_cycle * kDayFramesPerSecond));
  }
  if (options.switch_emitters) {
    if (const auto refusal = emitter_switch_refusal(volume.value()))
      return report(options, {runtime::StatusCode::invalid_argument, options.input + ": " + *refusal});
    std::printf("emitters: %zu switched off and on every %d frames\n", volume->emitter_materials().size(),
                *options.switch_emitters);
  }
  if (options.animate && volume->dynamic_objects().empty())
    return report(options, {runtime::StatusCode::invalid_argument,
                            options.input + ": --animate: the file has no dynamic objects to move"});
  if (options.animate)
    std::printf("animation: %s over %d frames, %zu dynamic object(s), memory update %s\n",
                dynamic::to_string(*options.animate), options.frames, volume->dynamic_objects().size(),
                volume->runs_memory_update() ? "on"
                : options.no_memory_update   ? "off (--no-memory-update)"
                                             : "off (needs octree placement and lighting)");
  std::ofstream csv;
  if (options.csv) {
    csv.open(*options.csv);
    if (!csv) {
      std::fprintf(stderr, "%s: %s: cannot be written\n", options.program.c_str(), options.csv->c_str());
      return 3;
    }
    if (options.animate || options.stream)
      write_frame_header(csv);
    else
      csv << "frame,pass,gpu_ms,cpu_ms,live_probes,probe_capacity,lit_probes,indirect_misses,non_finite,splits,merges,"
             "failed_allocations,free_probes,lights,uploaded_lights,light_x,light_y,light_z,hour,emitters_on\n";
  }
  std::map<std::string, PassSummary> summary;
  PassSummary cpu;
  std::vector<FrameRow> rows;
  const bool terminal = isatty(fileno(stdout)) != 0;
  int most_probes_in_use = 0, failed_allocations = 0; // the memory update's probe pool over the run
  for (int frame = 0; frame < frames; ++frame) {
    if (options.stream) {
      const runtime::Status moved = volume->stream_around(path[std::size_t(frame)].position, options.stream->radius);
      if (!moved.ok()) return report(options, moved);
    }
    auto stats = volume->run_frame(frame_inputs(options, volume.value(), baked_lights, frame));
    if (!stats.ok()) return report(options, stats.status());
    const double angle = options.animate ? glm::degrees(dynamic::animation_angle(*options.animate, frame)) : 0.0;
    rows.push_back(frame_row(frame, angle, stats.value()));
    if (options.stream) {
      const glm::vec3 camera = path[std::size_t(frame)].position;
      rows.back().camera = {camera.x, camera.y, camera.z};
      std::printf("%s", stream_frame_line(rows.back()).c_str());
    }
    if (csv.is_open() && (options.animate || options.stream)) write_frame_row(csv, rows.back());
    // One line per frame with --verbose; otherwise a progress bar redrawn in place on a terminal, or a
    // progress line every 100 frames into a file or pipe; then the summary.
    if (options.verbose) {
      print_frame(stats.value());
    } else if (options.stream) {
      // the streaming line above is the frame's line
    } else if (terminal) {
      std::printf("\r%s  live probes %d, gpu %.3f ms   ", progress_bar(frame + 1, frames).c_str(), stats->live_probes,
                  rows.back().gpu_ms);
      if (frame + 1 == frames) std::printf("\n");
      std::fflush(stdout);
    } else if ((frame + 1) % 100 == 0 || frame + 1 == frames) {
      std::printf("frame %d/%d: live probes %d, gpu %.3f ms\n", frame + 1, frames, stats->live_probes,
                  rows.back().gpu_ms);
    }
    cpu.add(stats->cpu_ms);
    most_probes_in_use = std::max(most_probes_in_use, stats->memory.probe_capacity - stats->memory.free_probes);
    failed_allocations += stats->memory.failed_allocations;
    if (options.after_frame) {
      const runtime::Status done = options.after_frame(frame, volume.value());
      if (!done.ok()) return report(options, done);
    }
    for (const runtime::PassTime& p : stats->passes) {
      summary[p.name].add(p.gpu_ms);
      if (csv.is_open() && !options.animate && !options.stream)
        csv << stats->frame << ',' << p.name << ',' << p.gpu_ms << ',' << stats->cpu_ms << ',' << stats->live_probes
            << ',' << stats->probe_capacity << ',' << stats->light.lit_probes << ',' << stats->light.indirect_misses
            << ',' << stats->light.non_finite << ',' << stats->memory.splits << ',' << stats->memory.collapses << ','
            << stats->memory.failed_allocations << ',' << stats->memory.free_probes << ',' << stats->light.lights << ','
            << stats->light.uploaded_lights << ',' << light_position(volume.value(), options) << ','
            << lighting_columns(options, frame) << '\n';
    }
    if (options.validate) {
      const runtime::Status valid = volume->validate_live();
      if (!valid.ok()) return report(options, valid);
    }
  }
  for (const auto& [name, s] : summary) std::printf("summary: %s gpu ms %s\n", name.c_str(), s.text().c_str());
  std::printf("summary: cpu ms per frame %s%s\n", cpu.text().c_str(),
              options.validate ? "; live state valid after every frame" : "");
  std::printf("%s", summary_table(rows, options.animate).c_str());
  std::printf("%s", frame_time_line(rows, options.limits.frame_ms).c_str());
  if (volume->runs_memory_update())
    std::printf("memory update pools: at most %d of %d probe slots in use, %d failed allocations\n", most_probes_in_use,
                volume->info().probe_capacity, failed_allocations);
  if (options.stream) {
    std::printf("%s", stream_summary(rows, options.stream->budget).c_str());
    for (const std::string& refusal : volume->stream_refusals())
      std::printf("streaming: refused %s\n", refusal.c_str());
    std::printf("%s", host_memory_line(after_load, host_memory()).c_str());
  }
  if (options.plots && (options.animate || options.stream)) {
    try {
      const auto written = options.animate ? write_plots(*options.plots, rows, *options.animate)
                                           : write_stream_plots(*options.plots, rows);
      for (const std::string& file : written) std::printf("wrote %s\n", file.c_str());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: %s\n", options.program.c_str(), e.what());
      return 3;
    }
  }
  if (options.samples > 0) {
    const runtime::Status sampled = run_samples(volume.value(), options.samples, options.compare_all_probes);
    if (!sampled.ok()) return report(options, sampled);
  }
  if (csv.is_open() && !csv.flush()) {
    std::fprintf(stderr, "%s: %s: write failed\n", options.program.c_str(), options.csv->c_str());
    return 3;
  }
  if (options.vulkan_validation) {
    std::printf("validation messages: %llu\n", static_cast<unsigned long long>(context->validation_message_count()));
    for (const std::string& m : context->validation_messages()) std::printf("  %s\n", m.c_str());
    if (context->validation_message_count() > 0) return 4;
  }
  return 0;
}

} // namespace probebake::run
