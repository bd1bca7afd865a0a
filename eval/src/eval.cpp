// `probebake eval`: bake each configuration of a sweep, look up every reference point, compare.
#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/core.h>
#include <glm/trigonometric.hpp>

#include "eval_internal.h"
#include "eval_maps.h"
#include "probebake/bake/lighting.h"
#include "probebake/bake/sampler.h"
#include "probebake/formats/atomic_file.h"
#include "probebake/formats/error.h"
#include "probebake/formats/probes_file.h"

namespace probebake::bake {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// What every configuration is measured against: the points, their reference and their direct light.
struct Truth {
  const scene::Scene* scene = nullptr;
  const scene::RayScene* rays = nullptr;
  std::vector<SamplePoint> points;
  std::vector<glm::vec3> reference;
  std::vector<glm::vec3> direct;  // punctual lights: the runtime adds them per pixel, probes hold none
  double mean = 0.0;
};

// Looks up every point on this thread (timed), adds the direct light and scores the result.
template <class Lookup>
void score(EvalRow& row, const Truth& truth, Lookup&& lookup) {
  std::vector<glm::vec3> total(truth.points.size());
  SamplerStats stats;
  const auto start = Clock::now();
  for (std::size_t i = 0; i < truth.points.size(); ++i) total[i] = lookup(truth.points[i], stats);
  row.sample_ns = seconds_since(start) * 1e9 / double(std::max<std::size_t>(truth.points.size(), 1));
  for (std::size_t i = 0; i < total.size(); ++i) total[i] += truth.direct[i];
  const detail::ErrorStats e = detail::error_stats(total, truth.reference, truth.mean);
  row.rmse = e.rmse;
  row.relative_rmse = truth.mean > 0.0 ? e.rmse / truth.mean : 0.0;
  row.bias = truth.mean > 0.0 ? (detail::mean_irradiance(total) - truth.mean) / truth.mean : 0.0;
  row.p95 = e.p95;
  row.max_error = e.max;
  row.leak_rmse = e.leak_rmse;
  row.leak_points = e.leak_points;
  row.misses = stats.misses;
  row.coverage = truth.points.empty() ? 0.0 : 1.0 - double(stats.misses) / double(truth.points.size());
  row.relative_median = e.relative_median;
  row.relative_p95 = e.relative_p95;
}

EvalRow baked_row(const EvalConfig& config, const BakeResult& baked, double bake_seconds) {
  EvalRow row;
  row.label = config.label;
  row.sampler = "svo";
  row.bake = config.bake;
  row.probes = baked.report.probes;
  row.file_bytes = formats::write_probes(baked.volume).size();
  row.bake_seconds = bake_seconds;
  return row;
}

std::string baseline_label(const EvalSettings& s, const std::vector<EvalConfig>& configs) {
  if (!s.baseline.empty()) return s.baseline;
  for (const EvalConfig& c : configs)
    if (c.label == "octree-d4") return c.label;
  for (const EvalConfig& c : configs)
    if (c.bake.placement == Placement::octree) return c.label;
  return configs.front().label;
}

Truth make_truth(const scene::Scene& scene, const scene::RayScene& rays, const detail::ReferencePoints& r) {
  Truth t{&scene, &rays, r.points, r.values.irradiance, {}, detail::mean_irradiance(r.values.irradiance)};
  t.direct.reserve(t.points.size());
  for (const SamplePoint& p : t.points) t.direct.push_back(direct_irradiance(scene, rays, p.position, p.normal));
  return t;
}

double reference_noise(const ReferenceResult& r, double mean) {
  double sum = 0.0;
  for (const glm::vec3& se : r.standard_error) sum += double(glm::dot(se, se)) / 3.0;
  return mean > 0.0 && !r.standard_error.empty() ? std::sqrt(sum / double(r.standard_error.size())) / mean : 0.0;
}

constexpr int kSceneCameraPixels = 128; // image receivers of a glTF camera: 128 x 128 (--camera sets its own size)

EvalSettings with_scene_camera(const EvalSettings& settings, const scene::Scene& scene) {
  EvalSettings out = settings;
  if (out.camera || scene.cameras.empty()) return out;
  const scene::SceneCamera& c = scene.cameras.front();
  Camera camera;
  camera.position = c.position;
  camera.look_at = c.position + c.forward;
  camera.fov_degrees = glm::degrees(c.yfov);
  camera.width = camera.height = kSceneCameraPixels;
  out.camera = camera;
  return out;
}

} // namespace

EvalResult evaluate(const std::filesystem::path& scene_path, const EvalSettings& settings, const EvalProgress& progress) {
  check_eval_settings(settings);
  const std::vector<EvalConfig> configs = settings.configs.empty() ? default_sweep() : settings.configs;
  const std::string baseline = baseline_label(settings, configs);
  auto say = [&](const std::string& m) { if (progress) progress(m); };
  scene::LoadOptions load = settings.scene_input;
  load.require_triangles = true;
  const scene::Scene scene = scene::load_scene(scene_path, load);
  for (const auto& output : settings.outputs) check_output_path(output, scene.input_files);
  // Without --camera, the scene's first glTF camera anchors the player's region and adds image receivers.
  const EvalSettings effective = with_scene_camera(settings, scene);
  const scene::RayScene rays(scene);

  say("reference");
  const detail::ReferencePoints ref = detail::cached_reference(scene_path, scene, rays, effective);
  const Truth truth = make_truth(scene, rays, ref);
  EvalResult result;
  result.scene = scene_path;
  result.receivers = std::string(receiver_mode_name(effective.receivers));
  result.viewpoints = ref.viewpoints;
  result.points = int(truth.points.size());
  result.paths = effective.paths;
  result.seed = effective.seed;
  result.mean_reference = truth.mean;
  result.reference_noise = reference_noise(ref.values, truth.mean);
  result.reference_seconds = ref.from_cache ? 0.0 : ref.values.seconds;
  result.reference_from_cache = ref.from_cache;
  result.cache_file = ref.cache_file;
  result.cache_written = ref.cache_written;

  std::optional<detail::ErrorMaps> maps;
  if (effective.camera) {
    say("image reference");
    maps.emplace(scene, rays, effective);
    result.image_pixels = maps->pixels();
    result.image_mean_reference = maps->mean_reference();
    if (maps->writes()) result.error_maps.push_back(maps->reference_path());
  }
  for (const EvalConfig& config : configs) {
    say("bake " + config.label);
    BakeSettings bs = config.bake;
    bs.threads = effective.threads;
    const auto start = Clock::now();
    const BakeResult baked = bake(scene, bs);
    EvalRow row = baked_row(config, baked, seconds_since(start));
    const formats::ProbeVolume& v = baked.volume;
    score(row, truth, [&](const SamplePoint& p, SamplerStats& st) { return sample_irradiance(v, p.position, p.normal, &st); });
    if (maps)
      if (auto path = maps->score(row, v)) result.error_maps.push_back(*path);
    result.rows.push_back(row);
    if (config.label != baseline) continue;
    say("all-probes " + config.label);
    row.sampler = "all-probes";
    score(row, truth, [&](const SamplePoint& p, SamplerStats& st) {
      return sample_irradiance_all_probes(v, rays, p.position, p.normal, &st);
    });
    result.rows.push_back(row);
  }
  return result;
}

} // namespace probebake::bake
