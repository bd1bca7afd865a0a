#include "probebake/eval/seams.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include <glm/geometric.hpp>

#include "probebake/bake/sampler.h"

namespace probebake::bake {
namespace {

constexpr int kSubSteps = 10;
constexpr int kStartTries = 64;

glm::vec3 random_direction(std::mt19937_64& rng) {
  std::normal_distribution<float> normal(0.0f, 1.0f);
  for (;;) {
    const glm::vec3 d(normal(rng), normal(rng), normal(rng));
    if (glm::dot(d, d) > 1e-6f) return glm::normalize(d);
  }
}

float luminance(glm::vec3 e) { return (e.x + e.y + e.z) / 3.0f; }

// One sample's unexplained jump (not yet divided by the local irradiance) and that irradiance.
struct Jump {
  double excess = 0.0;
  double local = 0.0;
};

Jump jump_at(const SeamLookup& lookup, glm::vec3 x, glm::vec3 d, glm::vec3 n, float h) {
  const auto at = [&](float t) { return double(luminance(lookup(x + t * d, n))); };
  const double e0 = at(0.0f), e1 = at(h);
  std::array<double, kSubSteps> left{}, right{};
  const float step = h / float(kSubSteps);
  double previous_left = e0, previous_right = e1;
  for (int k = 1; k <= kSubSteps; ++k) {
    const double l = at(-float(k) * step), r = at(h + float(k) * step);
    left[std::size_t(k - 1)] = (previous_left - l) / step;
    right[std::size_t(k - 1)] = (r - previous_right) / step;
    previous_left = l;
    previous_right = r;
  }
  const auto median = [](std::array<double, kSubSteps> v) {
    std::nth_element(v.begin(), v.begin() + kSubSteps / 2, v.end());
    return v[kSubSteps / 2];
  };
  const double predicted = double(h) * 0.5 * (median(left) + median(right));
  return {std::abs(e1 - e0 - predicted), 0.5 * (std::abs(e0) + std::abs(e1))};
}

} // namespace

SeamScore seam_score(const SeamLookup& lookup, const SeamCellSize& cell_size, glm::vec3 lo, glm::vec3 hi,
                     const SeamSettings& settings) {
  std::mt19937_64 rng(settings.seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<Jump> jumps;
  for (int line = 0; line < settings.lines; ++line) {
    const glm::vec3 d = random_direction(rng), n = random_direction(rng);
    glm::vec3 x(0.0f);
    bool found = false;
    for (int t = 0; t < kStartTries && !found; ++t) {
      x = lo + (hi - lo) * glm::vec3(unit(rng), unit(rng), unit(rng));
      found = cell_size(x, n) > 0.0f;
    }
    for (int s = 0; found && s < settings.samples_per_line; ++s) {
      const float size = cell_size(x, n);
      if (!(size > 0.0f)) break;
      const float h = 0.01f * size;
      if (cell_size(x + h * d, n) > 0.0f) jumps.push_back(jump_at(lookup, x, d, n, h));
      x += 0.25f * size * d;
    }
  }
  SeamScore out;
  out.samples = int(jumps.size());
  if (jumps.empty()) return out;
  // Dark places would divide by ~0: the local irradiance is floored at 1 % of the mean.
  double mean = 0.0;
  for (const Jump& j : jumps) mean += j.local / double(jumps.size());
  std::vector<double> relative;
  for (const Jump& j : jumps) relative.push_back(j.excess / std::max(j.local, 0.01 * mean + 1e-30));
  std::sort(relative.begin(), relative.end());
  out.p99 = relative[std::min(relative.size() - 1, std::size_t(0.99 * double(relative.size())))];
  out.max = relative.back();
  return out;
}

SeamScore svo_seam_score(const formats::ProbeVolume& volume, const SeamSettings& settings) {
  const float bias = normal_bias(volume.info);
  const auto lookup = [&](glm::vec3 p, glm::vec3 n) { return sample_irradiance(volume, p, n); };
  const auto cell = [&](glm::vec3 p, glm::vec3 n) {
    int depth = -1;
    if (find_svo_leaf(volume, p + n * bias, &depth) < 0) return 0.0f;
    return volume.info.root_size / float(1 << depth);
  };
  return seam_score(lookup, cell, volume.info.root_min, volume.info.root_min + glm::vec3(volume.info.root_size), settings);
}

} // namespace probebake::bake
