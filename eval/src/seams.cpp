#include "probebake/eval/seams.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include <glm/geometric.hpp>

#include "probebake/probe_index/grid_lookup.h"
#include "probebake/probe_index/lookup.h"

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

// One border's unexplained jump (not yet divided by the local irradiance) and that irradiance: the step
// of h from x.
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

// The point where the line leaves the cell it has at `a` for another, between a and b (ids differ).
glm::vec3 border_between(const SeamCellAt& cell, glm::vec3 a, glm::vec3 b, glm::vec3 n) {
  const std::int64_t first = cell(a, n).id;
  for (int i = 0; i < 24; ++i) {
    const glm::vec3 m = 0.5f * (a + b);
    (cell(m, n).id == first ? a : b) = m;
  }
  return 0.5f * (a + b);
}

} // namespace

SeamScore seam_score(const SeamLookup& lookup, const SeamCellAt& cell, const SeamOpen& open, glm::vec3 lo, glm::vec3 hi,
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
      found = cell(x, n).size > 0.0f;
    }
    for (int s = 0; found && s < settings.steps_per_line; ++s) {
      const SeamCell here = cell(x, n);
      const glm::vec3 next = x + 0.25f * here.size * d;
      const SeamCell there = cell(next, n);
      if (!(there.size > 0.0f) || !open(x, next, n)) break;
      if (there.id != here.id) {
        const float h = 0.01f * std::min(here.size, there.size);
        const glm::vec3 b = border_between(cell, x, next, n);
        if (cell(b - 0.5f * h * d, n).size > 0.0f && cell(b + 0.5f * h * d, n).size > 0.0f)
          jumps.push_back(jump_at(lookup, b - 0.5f * h * d, d, n, h));
      }
      x = next;
    }
  }
  SeamScore out;
  out.borders = int(jumps.size());
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

SeamScore svo_seam_score(const formats::ProbeVolume& volume, const scene::RayScene& rays,
                         const SeamSettings& settings) {
  return svo_seam_score(
      volume, rays, [&](glm::vec3 p, glm::vec3 n) { return probe_index::sample_irradiance(volume, p, n); }, settings);
}

namespace {

// A step from a to b is open when the biased points' segment and each point's bias cross no surface.
SeamOpen open_steps(const scene::RayScene& rays, float bias) {
  const auto clear = [&rays](glm::vec3 a, glm::vec3 b) {
    const glm::vec3 d = b - a;
    const float length = glm::length(d);
    return length == 0.0f || !rays.occluded(a, d / length, 0.0f, length);
  };
  return [clear, bias](glm::vec3 a, glm::vec3 b, glm::vec3 n) {
    return clear(a, a + n * bias) && clear(b, b + n * bias) && clear(a + n * bias, b + n * bias);
  };
}

} // namespace

SeamScore svo_seam_score(const formats::ProbeVolume& volume, const scene::RayScene& rays, const SeamLookup& lookup,
                         const SeamSettings& settings) {
  const float bias = probe_index::normal_bias(volume.info);
  const auto cell = [&](glm::vec3 p, glm::vec3 n) {
    int depth = -1;
    const int leaf = probe_index::find_svo_leaf(volume, p + n * bias, &depth);
    if (leaf < 0) return SeamCell{};
    return SeamCell{volume.info.root_size / float(1 << depth), leaf};
  };
  return seam_score(lookup, cell, open_steps(rays, bias), volume.info.root_min,
                    volume.info.root_min + glm::vec3(volume.info.root_size), settings);
}

SeamScore grid_seam_score(const formats::ProbeVolume& volume, const scene::RayScene& rays,
                          const SeamSettings& settings) {
  const std::optional<formats::GridLatticeView> lattice = formats::grid_lattice_view(volume);
  if (!lattice) return {};
  const gpu::GridLatticeHeader& h = lattice->header;
  const float bias = probe_index::grid_normal_bias(h);
  const int n = h.resolution;
  const float svo_bias = probe_index::normal_bias(volume.info);
  const auto cell = [&](glm::vec3 p, glm::vec3 normal) {
    // Lines stay where the SVO lookup's do (open space that probes reach), so that the scores compare.
    if (probe_index::find_svo_leaf(volume, p + normal * svo_bias) < 0) return SeamCell{};
    const glm::ivec3 c = formats::grid_cell_of(formats::grid_lattice_coordinates(h, p + normal * bias), n);
    return SeamCell{std::min({h.spacing.x, h.spacing.y, h.spacing.z}),
                    c.x + std::int64_t(n) * (c.y + std::int64_t(n) * c.z)};
  };
  const auto lookup = [&](glm::vec3 p, glm::vec3 normal) {
    return probe_index::sample_irradiance_grid(volume, p, normal);
  };
  return seam_score(lookup, cell, open_steps(rays, bias), volume.info.root_min,
                    volume.info.root_min + glm::vec3(volume.info.root_size), settings);
}

} // namespace probebake::bake
