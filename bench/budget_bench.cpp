// Error against frame cost of the gather budget (issue #14, FrameLimits::max_gathered_probes). For each
// budget, a fresh copy of the volume runs the same light motion: punctual light I orbits (a horizontal circle
// of RADIUS metres through its baked position, one turn every PERIOD frames) for MOTION frames, then stands
// still. At checkpoints after the motion stopped, the probes are read back and compared with the settled
// answer (the unbudgeted copy after SETTLE more still frames): relative RMS of the irradiance DC over the live
// probes. Next to it, the GPU time per frame of the light passes (median over the run). `--light all` moves
// every light at once (each on its own circle); `--shadow-rays LIST` crosses the gather budgets with the
// light sampling's budgets (FrameLimits::shadow_rays_per_record; 0 = one ray per light, exact), and the
// settled answer is the run with neither budget. Links only the runtime, so it runs on a bare GPU machine.
//
// Usage: probebake-bench-budget FILE.probes [--budgets 0,116,58] [--shadow-rays 0,3] [--light I|all] [--radius R]
//                               [--period P] [--motion M] [--after 0,10,30,100] [--settle S] [--hysteresis H]
//                               [--device NAME]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "probebake/formats/probes_file.h"
#include "probebake/runtime/runtime.h"

namespace {

using namespace probebake;

constexpr const char* kUsage =
    "usage: probebake-bench-budget FILE.probes [--budgets 0,116,58] [--shadow-rays 0,3] [--light I|all] [--radius R] "
    "[--period P] [--motion M] [--after 0,10,30,100] [--settle S] [--hysteresis H] [--device NAME]";

struct Options {
  std::string file, device;
  std::vector<int> budgets{0, 116, 58};
  std::vector<int> shadow_rays{0};
  std::vector<int> after{0, 10, 30, 100};
  int light = 0, period = 120, motion = 120, settle = 300; // light -1: every light
  float radius = 1.0f, hysteresis = 0.9f;
};

std::vector<int> int_list(const std::string& text) {
  std::vector<int> out;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) out.push_back(std::max(0, std::atoi(item.c_str())));
  if (out.empty()) throw std::runtime_error(kUsage);
  return out;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool value = i + 1 < argc;
    if (arg == "--budgets" && value)
      o.budgets = int_list(argv[++i]);
    else if (arg == "--after" && value)
      o.after = int_list(argv[++i]);
    else if (arg == "--shadow-rays" && value)
      o.shadow_rays = int_list(argv[++i]);
    else if (arg == "--light" && value)
      o.light = std::string(argv[i + 1]) == "all" ? (++i, -1) : std::max(0, std::atoi(argv[++i]));
    else if (arg == "--radius" && value)
      o.radius = std::strtof(argv[++i], nullptr);
    else if (arg == "--period" && value)
      o.period = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--motion" && value)
      o.motion = std::max(0, std::atoi(argv[++i]));
    else if (arg == "--settle" && value)
      o.settle = std::max(1, std::atoi(argv[++i]));
    else if (arg == "--hysteresis" && value)
      o.hysteresis = std::strtof(argv[++i], nullptr);
    else if (arg == "--device" && value)
      o.device = argv[++i];
    else if (o.file.empty() && !arg.empty() && arg[0] != '-')
      o.file = arg;
    else
      throw std::runtime_error(kUsage);
  }
  if (o.file.empty() || !(o.hysteresis >= 0.0f && o.hysteresis < 1.0f) || !std::isfinite(o.radius))
    throw std::runtime_error(kUsage);
  std::sort(o.after.begin(), o.after.end());
  return o;
}

template <class T>
T value_or_die(runtime::Result<T> result) {
  if (!result.ok()) throw std::runtime_error(result.status().message);
  return std::move(result).value();
}

// The DC terms (RGB) of the live probes, in slot order.
std::vector<float> dc_terms(runtime::Volume& volume) {
  const formats::ProbeVolume v = value_or_die(volume.read_back());
  std::vector<float> dc;
  for (const gpu::Probe& p : v.probes)
    if (p.link != 0) dc.insert(dc.end(), p.irradiance_sh, p.irradiance_sh + 3);
  return dc;
}

double relative_rms(const std::vector<float>& a, const std::vector<float>& reference) {
  if (a.size() != reference.size() || reference.empty()) return -1.0;
  double error = 0.0, norm = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    error += double(a[i] - reference[i]) * double(a[i] - reference[i]);
    norm += double(reference[i]) * double(reference[i]);
  }
  return norm > 0.0 ? std::sqrt(error / norm) : -1.0;
}

double median(std::vector<double> values) {
  if (values.empty()) return -1.0;
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

struct BudgetRun {
  int budget = 0, shadow_rays = 0;
  double light_ms = 0.0;                       // median GPU ms per frame of the light passes
  double moving_ms = 0.0;                      // ... over the frames in which lights moved
  std::vector<std::vector<float>> checkpoints; // DC terms at each --after frame
  std::vector<float> settled;                  // after the last checkpoint and --settle more frames
};

BudgetRun run_budget(runtime::Context& context, const formats::ProbeVolume& file, const Options& o, int budget,
                     int shadow_rays) {
  runtime::UploadOptions upload;
  upload.hysteresis = o.hysteresis;
  runtime::Volume volume = value_or_die(runtime::Volume::upload(context, file, upload));
  std::vector<gpu::PunctualLight> lights = file.punctual_lights;
  if (o.light >= int(lights.size()) || lights.empty())
    throw std::runtime_error("the file has no punctual light " + std::to_string(o.light));
  const std::vector<gpu::PunctualLight> baked = lights;
  BudgetRun out;
  out.budget = budget, out.shadow_rays = shadow_rays;
  std::vector<double> light_ms, moving_ms;
  const auto frame = [&](int f) {
    runtime::FrameInputs in;
    in.limits.max_gathered_probes = budget;
    in.limits.shadow_rays_per_record = shadow_rays;
    if (f <= o.motion) { // the last motion frame puts the lights back where they were baked
      const float angle = 6.2831853f * float(f) / float(o.period);
      for (std::size_t l = 0; l < lights.size(); ++l)
        if (o.light < 0 || std::size_t(o.light) == l)
          lights[l].position =
              f == o.motion ? baked[l].position
                            : baked[l].position + o.radius * glm::vec3(std::sin(angle), 0.0f, 1.0f - std::cos(angle));
      in.lights = lights;
    }
    const runtime::FrameStats stats = value_or_die(volume.run_frame(in));
    double ms = 0.0;
    for (const runtime::PassTime& p : stats.passes)
      if (std::string(p.name).starts_with("light_") && p.name != "light_trace") ms += std::max(0.0, p.gpu_ms);
    if (f > 0) light_ms.push_back(ms);
    if (f > 0 && f <= o.motion) moving_ms.push_back(ms);
  };
  int f = 0;
  for (; f <= o.motion; ++f) frame(f);
  for (int checkpoint : o.after) {
    for (; f <= o.motion + checkpoint; ++f) frame(f);
    out.checkpoints.push_back(dc_terms(volume));
  }
  for (int s = 0; s < o.settle; ++s) frame(f++);
  out.settled = dc_terms(volume);
  out.light_ms = median(light_ms);
  out.moving_ms = median(moving_ms);
  return out;
}

} // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    runtime::ContextOptions context_options;
    context_options.device_name_contains = o.device;
    runtime::Context context = value_or_die(runtime::Context::create(context_options));
    const formats::ProbeVolume file = formats::read_probes_file(o.file);
    std::printf("device: %s\nfile: %s, %zu probe slots, %zu punctual lights; %s orbits %.2f m (period %d) for %d "
                "frames, then stands at its baked position; hysteresis %.2f\n",
                context.device_info().name.c_str(), o.file.c_str(), file.probes.size(), file.punctual_lights.size(),
                o.light < 0 ? "every light" : ("light " + std::to_string(o.light)).c_str(), double(o.radius), o.period,
                o.motion, double(o.hysteresis));
    std::vector<BudgetRun> runs;
    for (int budget : o.budgets)
      for (int shadow_rays : o.shadow_rays) runs.push_back(run_budget(context, file, o, budget, shadow_rays));
    // The settled answer: the run without budgets, else the first, after its settle frames.
    const auto all =
        std::find_if(runs.begin(), runs.end(), [](const BudgetRun& r) { return r.budget == 0 && r.shadow_rays == 0; });
    const std::vector<float>& settled = (all != runs.end() ? *all : runs.front()).settled;
    std::printf("\n| gather budget (probes per frame) | shadow rays per record | light passes GPU ms per frame "
                "(median) | while lights move |");
    for (int k : o.after) std::printf(" error %d frames after |", k);
    std::printf(" error settled |\n|--:|--:|--:|--:|");
    for (std::size_t k = 0; k <= o.after.size(); ++k) std::printf("--:|");
    std::printf("\n");
    for (const BudgetRun& r : runs) {
      std::printf("| %s | %s | %.4f |", r.budget == 0 ? "all" : std::to_string(r.budget).c_str(),
                  r.shadow_rays == 0 ? "one per light" : std::to_string(r.shadow_rays).c_str(), r.light_ms);
      std::printf(" %.4f |", r.moving_ms);
      for (const std::vector<float>& dc : r.checkpoints) std::printf(" %.2e |", relative_rms(dc, settled));
      std::printf(" %.2e |\n", relative_rms(r.settled, settled));
    }
    std::printf("\nerror: relative RMS of the probes' irradiance DC (RGB, live probes) against the unbudgeted run "
                "settled %d frames after the last checkpoint\n",
                o.settle);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "probebake-bench-budget: %s\n", e.what());
    return 1;
  }
}
