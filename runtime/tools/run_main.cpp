// probebake-run: loads a .probes file onto a Vulkan device and runs the runtime's per-frame passes,
// printing per-pass GPU times and statistics (docs/RUNTIME.md). main() is the only place that turns a
// runtime Status into an exit code.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "probebake/runtime/runtime.h"
#include "run_options.h"

namespace {

using namespace probebake;

int exit_code_of(runtime::StatusCode code) {
  switch (code) {
  case runtime::StatusCode::ok: return 0;
  case runtime::StatusCode::invalid_argument: return 1;
  case runtime::StatusCode::file_error:
  case runtime::StatusCode::invalid_volume: return 2;
  default: return 4;
  }
}

int report(const runtime::Status& status) {
  std::fprintf(stderr, "probebake-run: %s: %s\n", runtime::to_string(status.code), status.message.c_str());
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

void print_frame(const runtime::FrameStats& f) {
  std::printf("frame %llu:", static_cast<unsigned long long>(f.frame));
  for (const runtime::PassTime& p : f.passes) std::printf(" %s %.3f ms", p.name.c_str(), p.gpu_ms);
  std::printf(" | cpu %.3f ms | live probes %d / %d\n", f.cpu_ms, f.live_probes, f.probe_capacity);
}

// Random points in the root cube with random unit normals; returns the Status of the lookup.
runtime::Status run_samples(runtime::Volume& volume, int count) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::normal_distribution<float> gauss;
  const gpu::VolumeInfo& info = volume.info();
  std::vector<glm::vec3> positions(static_cast<std::size_t>(count)), normals(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i) {
    positions[i] = info.root_min + info.root_size * glm::vec3(unit(rng), unit(rng), unit(rng));
    glm::vec3 n(gauss(rng), gauss(rng), gauss(rng));
    normals[i] = glm::length(n) > 1e-6f ? glm::normalize(n) : glm::vec3(0, 1, 0);
  }
  runtime::SampleStats stats;
  auto result = volume.sample_irradiance(positions, normals, &stats);
  if (!result.ok()) return result.status();
  std::printf("samples: %zu lookups, %zu misses, %zu dispatch(es), gpu %.3f ms, cpu %.3f ms (with copies)\n",
              stats.samples, stats.misses, stats.dispatches, stats.gpu_ms, stats.cpu_ms);
  return {};
}

int run_tool(const run::RunOptions& options) {
  runtime::ContextOptions context_options;
  context_options.validation = options.vulkan_validation;
  context_options.device_name_contains = options.device;
  context_options.on_validation_message = [](const runtime::ValidationMessage& m) {
    std::fprintf(stderr, "vulkan validation: %s: %s\n", m.id.c_str(), m.text.c_str());
  };
  auto context = runtime::Context::create(context_options);
  if (!context.ok()) return report(context.status());
  print_device(context->device_info());

  auto volume = runtime::Volume::load(context.value(), options.input);
  if (!volume.ok()) return report(volume.status());
  const gpu::VolumeInfo& info = volume->info();
  std::printf("volume: %s: %d probe slots, %d octree elements, %d SVO nodes, %d SVO leaves, %llu bytes on the GPU\n",
              options.input.c_str(), info.probe_capacity, info.octree_elements, info.svo_nodes, info.svo_leaves,
              static_cast<unsigned long long>(context->memory_stats().live_bytes));

  std::ofstream csv;
  if (options.csv) {
    csv.open(*options.csv);
    if (!csv) {
      std::fprintf(stderr, "probebake-run: %s: cannot be written\n", options.csv->c_str());
      return 3;
    }
    csv << "frame,pass,gpu_ms,cpu_ms,live_probes,probe_capacity\n";
  }
  std::map<std::string, PassSummary> summary;
  PassSummary cpu;
  for (int frame = 0; frame < options.frames; ++frame) {
    auto stats = volume->run_frame();
    if (!stats.ok()) return report(stats.status());
    print_frame(stats.value());
    cpu.add(stats->cpu_ms);
    for (const runtime::PassTime& p : stats->passes) {
      summary[p.name].add(p.gpu_ms);
      if (csv.is_open())
        csv << stats->frame << ',' << p.name << ',' << p.gpu_ms << ',' << stats->cpu_ms << ',' << stats->live_probes
            << ',' << stats->probe_capacity << '\n';
    }
    if (options.validate) {
      const runtime::Status valid = volume->validate_live();
      if (!valid.ok()) return report(valid);
    }
  }
  for (const auto& [name, s] : summary) std::printf("summary: %s gpu ms %s\n", name.c_str(), s.text().c_str());
  std::printf("summary: cpu ms per frame %s%s\n", cpu.text().c_str(),
              options.validate ? "; live state valid after every frame" : "");
  if (options.samples > 0) {
    const runtime::Status sampled = run_samples(volume.value(), options.samples);
    if (!sampled.ok()) return report(sampled);
  }
  if (csv.is_open() && !csv.flush()) {
    std::fprintf(stderr, "probebake-run: %s: write failed\n", options.csv->c_str());
    return 3;
  }
  if (options.vulkan_validation) {
    std::printf("validation messages: %llu\n", static_cast<unsigned long long>(context->validation_message_count()));
    for (const std::string& m : context->validation_messages()) std::printf("  %s\n", m.c_str());
    if (context->validation_message_count() > 0) return 4;
  }
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  std::string message;
  int exit_code = 0;
  const auto options = probebake::run::parse_run_options(argc, argv, message, exit_code);
  if (!options) {
    std::fputs(message.c_str(), exit_code == 0 ? stdout : stderr);
    return exit_code;
  }
  try {
    return run_tool(*options);
  } catch (const std::exception& e) { // the runtime does not throw; this covers the tool's own I/O
    std::fprintf(stderr, "probebake-run: internal error: %s\n", e.what());
    return 4;
  }
}
