// Position optimisation of the selected probes (nonuniform-probe-placement-svo.txt §3.3): each probe in
// turn tries the 8 corners of a cube around it, randomly rotated (the paper's stochastic direction
// sampling, simplified to a random orientation of the support cube), and moves to the corner that raises
// R most, unless the move leaves a sample that the probes see unseen (coverage, the paper's first goal,
// never drops). Only improvements are accepted (skeleton.h says why), so R never decreases; the step
// halves every round.
#include "skeleton_internal.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include <glm/geometric.hpp>
#include <glm/gtc/quaternion.hpp>

namespace probebake::placement {
namespace {

// Best and second-best q of each sample over the probes, with the owner of each.
struct Column {
  float best = 0.0f, second = 0.0f;
  std::size_t best_owner = SIZE_MAX, second_owner = SIZE_MAX;
};

Column column(const QualityMatrix& m, std::size_t s) {
  Column c;
  for (std::size_t r = 0; r < m.rows; ++r) {
    const float q = m.row(r)[s];
    if (q > c.best) {
      c.second = c.best;
      c.second_owner = c.best_owner;
      c.best = q;
      c.best_owner = r;
    } else if (q > c.second) {
      c.second = q;
      c.second_owner = r;
    }
  }
  return c;
}

struct Delta {
  double gain = 0.0;         // R after replacing probe k's row, minus R now
  bool loses_sample = false; // a sample that some probe sees would be seen by none
};

Delta delta(const std::vector<Column>& cols, std::size_t k, const float* q) {
  Delta d;
  for (std::size_t s = 0; s < cols.size(); ++s) {
    const Column& c = cols[s];
    const float others = c.best_owner == k ? c.second : c.best;
    const float after = std::max(others, q[s]);
    d.gain += double(after - c.best);
    if (after == 0.0f && c.best > 0.0f) d.loses_sample = true;
  }
  return d;
}

// A uniformly random rotation from three uniforms (Shoemake).
glm::quat random_rotation(std::uint64_t seed, std::uint64_t stream) {
  const float u1 = hash_uniform(seed, stream, 0), u2 = hash_uniform(seed, stream, 1),
              u3 = hash_uniform(seed, stream, 2);
  const float a = std::sqrt(1.0f - u1), b = std::sqrt(u1), t2 = 6.2831853f * u2, t3 = 6.2831853f * u3;
  return glm::normalize(glm::quat(b * std::cos(t3), a * std::sin(t2), a * std::cos(t2), b * std::sin(t3)));
}

bool in_domain(const scene::Bounds& d, glm::vec3 p) {
  return p.x >= d.min.x && p.y >= d.min.y && p.z >= d.min.z && p.x <= d.max.x && p.y <= d.max.y && p.z <= d.max.z;
}

} // namespace

OptimiseResult optimise_positions(const ObjectiveContext& ctx, std::vector<glm::vec3>& probes, QualityMatrix rows,
                                  float first_step, int iterations, std::uint64_t seed) {
  OptimiseResult result;
  std::vector<Column> cols(rows.cols);
  for (std::size_t s = 0; s < rows.cols; ++s) cols[s] = column(rows, s);
  double total = 0.0;
  for (const Column& c : cols) total += double(c.best);
  result.before = total;
  std::vector<float> trial(rows.cols), best_trial(rows.cols);
  float step = first_step;
  for (int round = 0; round < iterations; ++round, step *= 0.5f) {
    for (std::size_t k = 0; k < probes.size(); ++k) {
      const glm::quat rotation = random_rotation(seed, (std::uint64_t(round) << 32) | k);
      double best_gain = 0.0;
      glm::vec3 best_position = probes[k];
      for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 offset(corner & 1 ? 1.0f : -1.0f, corner & 2 ? 1.0f : -1.0f, corner & 4 ? 1.0f : -1.0f);
        const glm::vec3 p = probes[k] + rotation * (step * offset);
        if (!in_domain(ctx.domain, p) || !(ctx.sdf->distance(p) >= ctx.clearance)) continue;
        quality_row(ctx, p, trial.data());
        const Delta d = delta(cols, k, trial.data());
        const double gain = d.loses_sample ? 0.0 : d.gain; // coverage first: never lose a seen sample
        if (gain > best_gain) { // strict: ties keep the earlier corner, and no move without a gain
          best_gain = gain;
          best_position = p;
          best_trial.swap(trial);
        }
      }
      if (!(best_gain > 1e-9 * std::max(total, 1.0))) continue;
      probes[k] = best_position;
      std::copy(best_trial.begin(), best_trial.end(), rows.row(k));
      for (std::size_t s = 0; s < rows.cols; ++s) {
        const Column& c = cols[s];
        if (c.best_owner == k || c.second_owner == k || rows.row(k)[s] > c.second) cols[s] = column(rows, s);
      }
      total += best_gain;
      ++result.moves;
    }
  }
  // The running total accumulates rounding; the final R is summed afresh.
  result.after = 0.0;
  for (const Column& c : cols) result.after += double(c.best);
  return result;
}

} // namespace probebake::placement
