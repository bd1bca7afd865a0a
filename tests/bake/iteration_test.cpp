// The bounce iteration's solver (lighting/src/iteration.h) on hit caches written by hand, whose
// sweep is a known 2x2 or 1x1 linear map with a closed-form fixed point: the extrapolation must help
// where one error mode dominates and must be undone where an equally large negative mode hides behind
// the same steady ratios (two probes lighting each other: eigenvalues +g and -g).
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "iteration.h"
#include "probebake/probe_index/lookup.h"

namespace probebake::test {
namespace {

using lighting::detail::HitCache;
using lighting::detail::HitRecord;

// One ray per probe, projected onto the DC coefficient only, so every channel of probe i's DC becomes
// bases[i] + gain * DC(lit_by[i]) (the ray's surface reflects the other probe's irradiance, DC term only).
HitCache dc_map(const std::vector<float>& bases, const std::vector<int>& lit_by, float gain) {
  HitCache cache;
  cache.rays_per_probe = 1;
  cache.projection = {{1.0f, 0, 0, 0, 0, 0, 0, 0, 0}};
  for (std::size_t i = 0; i < bases.size(); ++i) {
    cache.probes.push_back(int(i));
    HitRecord r;
    r.base = glm::vec3(bases[i]);
    r.reflect = glm::vec3(gain / probe_index::kShY0); // E(n) of a DC-only probe is kShY0 * DC
    r.normal = glm::vec3(0.0f, 0.0f, 1.0f);
    r.stencil.probes = glm::ivec4(lit_by[i], -1, -1, -1);
    r.stencil.weights = glm::vec4(1.0f, 0.0f, 0.0f, 0.0f);
    cache.records.push_back(r);
  }
  return cache;
}

struct Solved {
  lighting::LightingReport report;
  std::vector<double> dc; // red DC per probe
};

Solved solve(const HitCache& cache, bool accelerate) {
  lighting::LightingSettings settings;
  settings.threads = 1;
  settings.accelerate = accelerate;
  settings.max_iterations = 2000;
  lighting::detail::ShBuffer sh(gpu::PROBE_SH_FLOATS * cache.probes.size(), 0.0);
  Solved out;
  lighting::detail::solve(cache, settings, sh, out.report);
  for (std::size_t i = 0; i < cache.probes.size(); ++i) out.dc.push_back(sh[gpu::PROBE_SH_FLOATS * i]);
  std::printf("[iteration] %zu probes, accelerate %d: %d sweeps, %d extrapolations kept, %d undone, converged %d\n",
              cache.probes.size(), int(accelerate), out.report.iterations, out.report.extrapolations,
              out.report.rejected_extrapolations, int(out.report.converged));
  return out;
}

// x = 1 + g x: one mode, eigenvalue g. Fixed point 1 / (1 - g).
TEST(BounceIteration, ExtrapolationRemovesASingleDominantMode) {
  const float g = 0.95f;
  const HitCache cache = dc_map({1.0f}, {0}, g);
  const Solved fast = solve(cache, true), plain = solve(cache, false);
  ASSERT_TRUE(fast.report.converged && plain.report.converged);
  EXPECT_GE(fast.report.extrapolations, 1);
  EXPECT_EQ(fast.report.rejected_extrapolations, 0);
  EXPECT_LT(fast.report.iterations * 5, plain.report.iterations);
  EXPECT_NEAR(fast.dc[0], 1.0 / (1.0 - g), 1e-3 / (1.0 - g));
}

// a = 1 + g b, b = g a: eigenvalues +g and -g. The changes alternate between the probes and their sum
// shrinks by exactly g per sweep, which looks like one dominant mode; extrapolating by g / (1 - g)
// multiplies the -g mode by -(g + 2 g^2 / (1 - g)) (-7.2 at g = 0.8), so kept steps would diverge.
TEST(BounceIteration, ExtrapolationIsUndoneWhenANegativeModeHidesBehindSteadyRatios) {
  const double g = 0.8;
  const HitCache cache = dc_map({1.0f, 0.0f}, {1, 0}, float(g));
  const Solved fast = solve(cache, true);
  ASSERT_TRUE(fast.report.converged);
  EXPECT_EQ(fast.report.rejected_extrapolations, 1);
  EXPECT_EQ(fast.report.extrapolations, 0);
  const double a = 1.0 / (1.0 - g * g), b = g * a;
  EXPECT_NEAR(fast.dc[0], a, 1e-3 * a);
  EXPECT_NEAR(fast.dc[1], b, 1e-3 * a);
  const Solved plain = solve(cache, false);
  EXPECT_LE(fast.report.iterations, plain.report.iterations + 1); // the undone sweep is the only extra cost
}

} // namespace
} // namespace probebake::test
