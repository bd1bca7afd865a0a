// `probebake eval`: bake each configuration of a sweep, look up every reference point, compare.
#include <algorithm>
#include <chrono>
#include <cmath>

#include <fmt/core.h>
#include <glm/trigonometric.hpp>

#include "eval_internal.h"
#include "eval_maps.h"
#include "probebake/lighting/lighting.h"
#include "probebake/probe_index/grid_lookup.h"
#include "probebake/probe_index/lookup.h"
#include "probebake/formats/atomic_file.h"
#include "probebake/formats/error.h"
#include "probebake/eval/seams.h"
#include "probebake/formats/probes_file.h"
#include "probebake/formats/sh_codec.h"
#include "probebake/formats/volume_stats.h"

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
  std::vector<glm::vec3> direct;   // lighting::direct_irradiance: the runtime adds it per pixel, probes hold none
  std::vector<glm::vec3> indirect; // the reference minus the path tracer's own direct part
  double mean = 0.0;
  double indirect_mean = 0.0;
};

double relative(double value, double mean) { return mean > 0.0 ? value / mean : 0.0; }

// Looks up every point on this thread (timed), adds the direct light and scores the result; the lookup
// alone is scored against the indirect reference. Returns the lookups.
template <class Lookup>
std::vector<glm::vec3> score(EvalRow& row, const Truth& truth, Lookup&& lookup) {
  std::vector<glm::vec3> probes(truth.points.size());
  probe_index::SamplerStats stats;
  const auto start = Clock::now();
  for (std::size_t i = 0; i < truth.points.size(); ++i) probes[i] = lookup(truth.points[i], stats);
  row.sample_ns = seconds_since(start) * 1e9 / double(std::max<std::size_t>(truth.points.size(), 1));
  std::vector<glm::vec3> total(probes.size());
  for (std::size_t i = 0; i < total.size(); ++i) total[i] = probes[i] + truth.direct[i];
  const detail::ErrorStats e = detail::error_stats(total, truth.reference, truth.mean);
  row.rmse = e.rmse;
  row.relative_rmse = relative(e.rmse, truth.mean);
  row.bias = relative(detail::mean_irradiance(total) - truth.mean, truth.mean);
  row.p95 = e.p95;
  row.max_error = e.max;
  row.leak_rmse = e.leak_rmse;
  row.leak_points = e.leak_points;
  row.misses = stats.misses;
  row.coverage = truth.points.empty() ? 0.0 : 1.0 - double(stats.misses) / double(truth.points.size());
  row.relative_median = e.relative_median;
  row.relative_p95 = e.relative_p95;
  row.indirect_rmse = detail::error_stats(probes, truth.indirect, truth.indirect_mean).rmse;
  row.indirect_relative_rmse = relative(row.indirect_rmse, truth.indirect_mean);
  return probes;
}

// What the compact codes do to a row: the lookup of `coded` (its probes through a code) against the float
// lookup `exact` at the same receivers (the codec's own error), and against the reference.
template <class Lookup>
void score_codec(double& codec_error, double& relative_rmse, const Truth& truth, const std::vector<glm::vec3>& exact,
                 const formats::ProbeVolume& coded, const Lookup& lookup) {
  std::vector<glm::vec3> total(exact.size());
  double squares = 0.0;
  for (std::size_t i = 0; i < exact.size(); ++i) {
    const glm::vec3 e = lookup(coded, truth.points[i].position, truth.points[i].normal, nullptr);
    const glm::dvec3 d = glm::dvec3(e) - glm::dvec3(exact[i]);
    squares += glm::dot(d, d) / 3.0;
    total[i] = e + truth.direct[i];
  }
  codec_error = relative(std::sqrt(squares / double(std::max<std::size_t>(exact.size(), 1))), truth.mean);
  relative_rmse = relative(detail::error_stats(total, truth.reference, truth.mean).rmse, truth.mean);
}

// The bake's volume as a game sees it through each compact code.
struct CodedVolumes {
  formats::ProbeVolume l2, l1;
  explicit CodedVolumes(const formats::ProbeVolume& v)
      : l2(formats::with_sh_codec(v, formats::ShCodec::l2)), l1(formats::with_sh_codec(v, formats::ShCodec::l1)) {}
};

// Scores `row` with `lookup(v, position, normal, stats)` at the receivers and, with a camera, at its pixels
// (the error maps), and its codec columns with the same lookup of `coded`; adds it to the result.
template <class Lookup>
void add_scored_row(EvalRow row, const Truth& truth, const std::optional<detail::ErrorMaps>& maps, EvalResult& result,
                    const formats::ProbeVolume& v, const CodedVolumes& coded, const Lookup& lookup) {
  const std::vector<glm::vec3> exact = score(row, truth, [&](const SamplePoint& p, probe_index::SamplerStats& st) {
    return lookup(v, p.position, p.normal, &st);
  });
  score_codec(row.l2_codec_error, row.l2_relative_rmse, truth, exact, coded.l2, lookup);
  score_codec(row.l1_codec_error, row.l1_relative_rmse, truth, exact, coded.l1, lookup);
  if (maps)
    for (auto& path : maps->score(row, [&](glm::vec3 p, glm::vec3 n) { return lookup(v, p, n, nullptr); }))
      result.error_maps.push_back(std::move(path));
  result.rows.push_back(std::move(row));
}

// The row's lookup bytes with float, l2 and l1 probes.
void set_lookup_bytes(EvalRow& row, const formats::ProbeVolume& v, formats::LookupIndex index) {
  row.lookup_bytes = formats::lookup_bytes(v, index);
  row.l2_lookup_bytes = formats::lookup_bytes(v, index, formats::ShCodec::l2);
  row.l1_lookup_bytes = formats::lookup_bytes(v, index, formats::ShCodec::l1);
}

EvalRow baked_row(const EvalConfig& config, const BakeResult& baked, double bake_seconds) {
  EvalRow row;
  row.label = config.label;
  row.sampler = "svo";
  row.bake = config.bake;
  row.asked_probes = config.asked_probes;
  row.budget_by = config.budget_by;
  row.probes = baked.report.probes;
  row.file_bytes = formats::write_probes(baked.volume).size();
  set_lookup_bytes(row, baked.volume, formats::LookupIndex::svo);
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
  Truth t{&scene, &rays, r.points, r.values.irradiance, {}, indirect_irradiance(r.values), 0.0, 0.0};
  t.mean = detail::mean_irradiance(t.reference);
  t.indirect_mean = detail::mean_irradiance(t.indirect);
  t.direct.reserve(t.points.size());
  for (const SamplePoint& p : t.points)
    t.direct.push_back(lighting::direct_irradiance(scene, rays, p.position, p.normal));
  return t;
}

// RMS over points and channels of the standard errors, relative to `mean`.
double noise(const std::vector<glm::vec3>& standard_error, double mean) {
  double sum = 0.0;
  for (const glm::vec3& se : standard_error) sum += double(glm::dot(se, se)) / 3.0;
  return standard_error.empty() ? 0.0 : relative(std::sqrt(sum / double(standard_error.size())), mean);
}

// How far lighting::direct_irradiance (what a renderer adds per pixel) is from the path tracer's direct part.
void score_direct(EvalResult& result, const Truth& truth, const ReferenceResult& values) {
  const double mean = detail::mean_irradiance(values.direct);
  result.direct_relative_rmse = relative(detail::error_stats(truth.direct, values.direct, mean).rmse, mean);
  result.direct_bias = relative(detail::mean_irradiance(truth.direct) - mean, mean);
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

std::vector<EvalConfig> sweep_of(const EvalSettings& s, const scene::Scene& scene) {
  if (!s.configs.empty()) return s.configs;
  if (s.probe_ladder.empty()) return default_sweep();
  BakeSettings base = s.ladder_base;
  base.threads = s.threads;
  return ladder_sweep(scene, s.probe_ladder, base);
}

} // namespace

EvalResult evaluate(const std::filesystem::path& scene_path, const EvalSettings& settings,
                    const EvalProgress& progress) {
  check_eval_settings(settings);
  auto say = [&](const std::string& m) {
    if (progress) progress(m);
  };
  scene::LoadOptions load = settings.scene_input;
  load.require_triangles = true;
  const scene::Scene scene = scene::load_scene(scene_path, load);
  for (const auto& output : settings.outputs) check_output_path(output, scene.input_files);
  if (settings.configs.empty() && !settings.probe_ladder.empty()) say("probe ladder");
  const std::vector<EvalConfig> configs = sweep_of(settings, scene);
  const std::string baseline = baseline_label(settings, configs);
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
  result.reference_noise = noise(ref.values.standard_error, truth.mean);
  result.mean_indirect_reference = truth.indirect_mean;
  result.indirect_noise = noise(ref.values.indirect_standard_error, truth.indirect_mean);
  score_direct(result, truth, ref.values);
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
    result.image_flip_exposures = maps->flip_exposures();
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
    SeamSettings seams;
    seams.seed = effective.seed;
    row.seam_p99 = svo_seam_score(v, rays, seams).p99;
    const CodedVolumes coded(v);
    add_scored_row(row, truth, maps, result, v, coded,
                   [](const formats::ProbeVolume& volume, glm::vec3 p, glm::vec3 n, probe_index::SamplerStats* st) {
                     return probe_index::sample_irradiance(volume, p, n, st);
                   });
    if (!v.grid_lattice.empty()) {
      // The grid as grid engines look it up (probe_index/grid_lookup.h), beside the SVO's lookup of it.
      EvalRow grid = row;
      grid.sampler = "grid";
      set_lookup_bytes(grid, v, formats::LookupIndex::grid_lattice);
      grid.seam_p99 = grid_seam_score(v, rays, seams).p99;
      add_scored_row(grid, truth, maps, result, v, coded,
                     [](const formats::ProbeVolume& volume, glm::vec3 p, glm::vec3 n, probe_index::SamplerStats* st) {
                       return probe_index::sample_irradiance_grid(volume, p, n, st);
                     });
    }
    if (config.label != baseline) continue;
    say("all-probes " + config.label);
    row.sampler = "all-probes";
    row.lookup_bytes = formats::lookup_bytes(v, formats::LookupIndex::none);
    row.l2_lookup_bytes = row.l1_lookup_bytes = 0;
    row.seam_p99 = -1.0;
    row.l2_codec_error = row.l1_codec_error = row.l2_relative_rmse = row.l1_relative_rmse = -1.0;
    score(row, truth, [&](const SamplePoint& p, probe_index::SamplerStats& st) {
      return probe_index::sample_irradiance_all_probes(v, rays, p.position, p.normal, &st);
    });
    result.rows.push_back(row);
  }
  return result;
}

} // namespace probebake::bake
