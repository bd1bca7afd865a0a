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

// Nearest rank of ascending `values`.
double percentile(const std::vector<double>& values, double q) {
  const auto rank = std::size_t(std::ceil(q * double(values.size())));
  return values[std::clamp<std::size_t>(rank, 1, values.size()) - 1];
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
  std::vector<double> errors(reference.size()), relative(reference.size());
  double squares = 0.0, leak_squares = 0.0;
  for (std::size_t i = 0; i < reference.size(); ++i) {
    errors[i] = rgb_rms(estimate[i], reference[i]);
    // A floor of 1% of the mean keeps dark receivers (the leak points) from dividing by ~0.
    relative[i] = errors[i] / std::max(rgb_rms(reference[i], glm::vec3(0.0f)), 0.01 * mean_reference);
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
  std::sort(relative.begin(), relative.end());
  s.p95 = percentile(errors, 0.95);
  s.max = errors.back();
  s.relative_median = percentile(relative, 0.5);
  s.relative_p95 = percentile(relative, 0.95);
  return s;
}

} // namespace probebake::bake::detail
