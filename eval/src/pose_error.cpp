#include "probebake/eval/pose_error.h"

#include <chrono>
#include <cmath>

#include "eval_internal.h"
#include "probebake/formats/error.h"
#include "probebake/scene/ray_scene.h"

namespace probebake::bake {

PoseReference pose_reference(const scene::Scene& posed_scene, const PoseReferenceSettings& settings) {
  const auto start = std::chrono::steady_clock::now();
  const scene::RayScene rays(posed_scene);
  PoseReference out;
  out.points = make_receivers(posed_scene, rays, settings.receivers).points;
  const ReferenceResult reference = reference_irradiance(posed_scene, rays, out.points, settings.reference);
  out.indirect = indirect_irradiance(reference);
  out.indirect_standard_error = reference.indirect_standard_error;
  out.mean_indirect = detail::mean_irradiance(out.indirect);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

PoseError pose_error(const PoseReference& reference, const std::vector<glm::vec3>& indirect_estimate) {
  if (indirect_estimate.size() != reference.indirect.size())
    throw Error(ErrorKind::internal, "pose_error: estimate and reference sizes differ");
  PoseError out;
  out.points = static_cast<int>(reference.points.size());
  if (out.points == 0 || !(reference.mean_indirect > 0.0)) return out;
  const detail::ErrorStats stats = detail::error_stats(indirect_estimate, reference.indirect, reference.mean_indirect);
  out.relative_rmse = stats.rmse / reference.mean_indirect;
  out.relative_median = stats.relative_median;
  double noise = 0.0;
  for (const glm::vec3& se : reference.indirect_standard_error) noise += double(glm::dot(se, se)) / 3.0;
  out.reference_noise = std::sqrt(noise / double(out.points)) / reference.mean_indirect;
  return out;
}

} // namespace probebake::bake
