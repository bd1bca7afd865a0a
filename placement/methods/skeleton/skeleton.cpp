// Skeleton placement, the pipeline of skeleton.h: distance grid, ridge skeleton, candidates, greedy
// selection, optimisation (nonuniform-probe-placement-svo.txt §3.1-3.3).
#include "skeleton_internal.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/core.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "probebake/formats/error.h"

namespace probebake::placement {
namespace {

constexpr float kGridDivisions = 64.0f; // voxels along the domain's largest extent, by default
constexpr double kMaxGridVoxels = 16.0 * 1024 * 1024;
constexpr int kMaxSurfaceSamples = 1 << 20;
constexpr int kMaxCandidates = 1 << 16;
constexpr int kMaxIterations = 64;

void require(bool ok, const std::string& message) {
  if (!ok) throw Error(ErrorKind::usage, "skeleton placement: " + message);
}

void check_options(const SkeletonOptions& o) {
  require(o.probes >= 0, "--probes must be >= 0");
  require(std::isfinite(o.clearance) && o.clearance > 0.0f, "the clearance must be a finite distance > 0");
  require(std::isfinite(o.voxel_size) && o.voxel_size >= 0.0f, "the voxel size must be finite and >= 0");
  require(o.surface_samples >= 1 && o.surface_samples <= kMaxSurfaceSamples,
          fmt::format("surface samples must be in [1, {}]", kMaxSurfaceSamples));
  require(o.max_candidates >= 1 && o.max_candidates <= kMaxCandidates,
          fmt::format("candidates must be in [1, {}]", kMaxCandidates));
  require(o.iterations >= 0 && o.iterations <= kMaxIterations,
          fmt::format("iterations must be in [0, {}]", kMaxIterations));
  require(o.threads >= 0, "--threads must be >= 0");
  require(std::isfinite(o.falloff_scale) && o.falloff_scale > 0.0f, "the falloff scale must be finite and > 0");
}

float grid_voxel(const SkeletonOptions& o, const scene::Bounds& domain) {
  const glm::vec3 extent = domain.max - domain.min;
  const float voxel = o.voxel_size > 0.0f ? o.voxel_size : domain.largest_extent() / kGridDivisions;
  const glm::dvec3 cells = glm::dvec3(extent) / double(voxel) + 1.0;
  require(cells.x * cells.y * cells.z <= kMaxGridVoxels,
          fmt::format("a voxel of {:.3g} m gives more than {} distance samples", voxel, kMaxGridVoxels));
  return voxel;
}

double seen_area(const scene::Scene& scene) {
  double area = 0.0;
  for (std::size_t t = 0; t < scene.triangles.size(); ++t)
    area += scene::triangle_area(scene, t) * (scene::is_double_sided(scene, t) ? 2.0 : 1.0);
  return area;
}

} // namespace

scene::Bounds default_domain(const scene::Scene& scene, float clearance) {
  scene::Bounds b = scene.bounds;
  if (b.empty()) return b;
  b.min -= glm::vec3(3.0f * clearance);
  b.max += glm::vec3(3.0f * clearance);
  return b;
}

SdfSettings skeleton_sdf_settings(const scene::Bounds& domain) {
  SdfSettings s;
  const float largest = domain.largest_extent();
  if (!(largest > 0.0f)) return s;
  // Diagonal / 160: at / 110 the field is off by up to 0.04 m at 0.09 m under the ceiling of a 4 m room
  // (0.7 of its voxel), enough to raise false ridges there (the box-room test fails); / 160 passes.
  s.voxel_size = glm::length(domain.max - domain.min) / 160.0f;
  s.band_voxels = std::ceil(0.5f * largest / s.voxel_size) + 2.0f;
  return s;
}

SkeletonResult skeleton_probes(const scene::RayScene& rays, const SceneSdf& sdf, const SkeletonOptions& options) {
  check_options(options);
  const scene::Scene& scene = rays.scene();
  SkeletonResult result;
  SkeletonReport& report = result.report;
  const scene::Bounds domain = options.domain.empty() ? default_domain(scene, options.clearance) : options.domain;
  if (domain.empty() || !(domain.largest_extent() > 0.0f)) return result;

  const DistanceGrid grid = sample_distance(sdf, domain, grid_voxel(options, domain), options.threads);
  report.free_voxels =
      int(std::count_if(grid.distance.begin(), grid.distance.end(), [&](float d) { return d >= options.clearance; }));
  const std::vector<std::size_t> skeleton = skeleton_voxels(grid, options.clearance);
  report.skeleton_voxels = int(skeleton.size());
  const int max_candidates = std::max(options.max_candidates, 4 * options.probes);
  const std::vector<glm::vec3> candidates = skeleton_candidates(grid, skeleton, options.clearance, max_candidates);
  report.candidates = int(candidates.size());
  if (candidates.empty()) return result;

  const std::vector<SurfaceSample> samples = sample_surface(scene, options.surface_samples, options.seed);
  ObjectiveContext ctx{&rays, &sdf, &samples, domain.largest_extent(), options.clearance, domain, options.threads};
  // The budget's probe spacing over the surface: a sample is served well from about that far.
  if (options.probes > 0)
    ctx.falloff = options.falloff_scale * float(std::sqrt(seen_area(scene) / double(options.probes)));
  const QualityMatrix all = quality_matrix(ctx, candidates);
  const std::vector<std::size_t> chosen = select_greedy(all, options.probes, options.threads);
  if (chosen.empty()) { // no candidate sees any sample (e.g. no surface faces the free space): keep the deepest
    result.probes.push_back(candidates.front());
    return result;
  }
  report.objective_selected = objective(all, chosen);

  QualityMatrix rows;
  rows.rows = chosen.size();
  rows.cols = all.cols;
  for (std::size_t r : chosen) {
    result.probes.push_back(candidates[r]);
    rows.q.insert(rows.q.end(), all.row(r), all.row(r) + all.cols);
  }
  const float first_step = 0.5f * std::min(ctx.falloff, 0.125f * domain.largest_extent());
  const OptimiseResult opt =
      optimise_positions(ctx, result.probes, std::move(rows), first_step, options.iterations, options.seed);
  report.objective_final = opt.after;
  report.moves = opt.moves;
  report.coverage = coverage(rays, result.probes, candidates, samples, options.threads);
  return result;
}

} // namespace probebake::placement
