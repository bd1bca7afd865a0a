// Internals of the skeleton placement shared by its files (skeleton.h describes the method).
#pragma once

#include <cstddef>
#include <vector>

#include "skeleton.h"

namespace probebake::placement {

// Poisson-disc subset of the skeleton voxels (deepest first), at most max_candidates; every free voxel
// when the skeleton is empty.
std::vector<glm::vec3> skeleton_candidates(const DistanceGrid& grid, const std::vector<std::size_t>& skeleton,
                                           float clearance, int max_candidates);

// q(row position, sample) for every pair: rows() x cols(), row-major.
struct QualityMatrix {
  std::size_t rows = 0, cols = 0;
  std::vector<float> q;
  const float* row(std::size_t r) const { return q.data() + r * cols; }
  float* row(std::size_t r) { return q.data() + r * cols; }
};

struct ObjectiveContext {
  const scene::RayScene* rays = nullptr;
  const SceneSdf* sdf = nullptr;
  const std::vector<SurfaceSample>* samples = nullptr;
  float falloff = 1.0f; // l in q's l^2 / (l^2 + d^2)
  float clearance = 0.0f;
  scene::Bounds domain;
  int threads = 0;
};

QualityMatrix quality_matrix(const ObjectiveContext& ctx, const std::vector<glm::vec3>& positions);
void quality_row(const ObjectiveContext& ctx, glm::vec3 position, float* out);

// Greedy selection (row indices, in selection order). budget > 0: maximise R (facility location) for
// `budget` picks or until no pick raises R. budget == 0: maximise the samples seen (q > 0, ties by R)
// until no pick sees a new sample.
std::vector<std::size_t> select_greedy(const QualityMatrix& m, int budget, int threads);

// R(P) for the rows listed.
double objective(const QualityMatrix& m, const std::vector<std::size_t>& rows);

struct OptimiseResult {
  double before = 0.0, after = 0.0;
  int moves = 0;
};

// The sampled gradient ascent of skeleton.h step 5, in place. `rows` holds q of each probe (rows of
// `probes`).
OptimiseResult optimise_positions(const ObjectiveContext& ctx, std::vector<glm::vec3>& probes, QualityMatrix rows,
                                  float first_step, int iterations, std::uint64_t seed);

} // namespace probebake::placement
