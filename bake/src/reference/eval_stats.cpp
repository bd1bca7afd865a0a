// Error statistics of `probebake eval`.
#include <algorithm>
#include <cmath>

#include "eval_internal.h"

namespace probebake::bake::detail {
namespace {

double mean_channel(const glm::vec3& v) { return (double(v.x) + double(v.y) + double(v.z)) / 3.0; }

// RMS over the three channels of estimate - reference.
double rgb_rms(const glm::vec3& a, const glm::vec3& b) {
  const glm::dvec3 d = glm::dvec3(a) - glm::dvec3(b);
  return std::sqrt((d.x * d.x + d.y * d.y + d.z * d.z) / 3.0);
}

} // namespace

double mean_irradiance(const std::vector<glm::vec3>& values) {
  double sum = 0.0;
  for (const glm::vec3& v : values) sum += mean_channel(v);
  return values.empty() ? 0.0 : sum / double(values.size());
}

ErrorStats error_stats(const std::vector<glm::vec3>& estimate, const std::vector<glm::vec3>& reference,
                       double mean_reference) {
  ErrorStats s;
  if (reference.empty()) return s;
  std::vector<double> errors(reference.size());
  double squares = 0.0, leak_squares = 0.0;
  for (std::size_t i = 0; i < reference.size(); ++i) {
    errors[i] = rgb_rms(estimate[i], reference[i]);
    squares += errors[i] * errors[i];
    // Leak points: the reference is (nearly) dark, so whatever the probes put there came through walls.
    if (mean_channel(reference[i]) < 0.01 * mean_reference) {
      leak_squares += errors[i] * errors[i];
      ++s.leak_points;
    }
  }
  s.rmse = std::sqrt(squares / double(errors.size()));
  s.leak_rmse = s.leak_points > 0 ? std::sqrt(leak_squares / s.leak_points) : 0.0;
  std::sort(errors.begin(), errors.end());
  // Nearest-rank 95th percentile.
  const auto rank = std::size_t(std::ceil(0.95 * double(errors.size())));
  s.p95 = errors[std::clamp<std::size_t>(rank, 1, errors.size()) - 1];
  s.max = errors.back();
  return s;
}

} // namespace probebake::bake::detail
