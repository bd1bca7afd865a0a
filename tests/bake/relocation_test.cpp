// Relocation's candidate test (is_valid_position) and the back-face rule (mostly_back_faces, also the
// sealed-triangle check's) decide with short rays and early exits, and must give exactly the verdict of
// the full lattice trace (is_dead over trace_probe) they replaced.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "bake_test_util.h"
#include "probebake/common/lattice.h"
#include "probebake/placement/probe_tracing.h"
#include "probebake/placement/relocation.h"
#include "probebake/samples/scenes.h"

namespace probebake::test {
namespace {

struct Verdicts {
  int valid = 0;
  int outside_cube = 0;
  int dead_by_clearance = 0;  // a surface nearer than the clearance
  int dead_by_back_faces = 0; // no surface that near, but mostly back faces: inside a solid
  int mismatches = 0;
};

// A jittered 24^3 grid over the scene bounds padded by 10 % (so some points lie outside the cube too),
// compared point by point with the full trace.
Verdicts compare_with_full_trace(const scene::Scene& s, float clearance) {
  const scene::RayScene rays(s);
  const std::vector<glm::vec3> directions = lattice_directions(Lattice::fibonacci, 128);
  const placement::RelocationContext ctx{&rays, nullptr, directions, clearance};
  const glm::vec3 lo = s.bounds.min, extent = s.bounds.max - s.bounds.min;
  const placement::Cube cube{lo, std::max({extent.x, extent.y, extent.z})};
  constexpr int n = 24;
  Verdicts v;
  for (int i = 0; i < n * n * n; ++i) {
    const glm::vec3 cell(float(i % n), float(i / n % n), float(i / (n * n)));
    const glm::vec3 jitter(std::fmod(0.618f * float(i), 1.0f), std::fmod(0.414f * float(i), 1.0f),
                           std::fmod(0.732f * float(i), 1.0f));
    const glm::vec3 p = lo - 0.1f * extent + (cell + jitter) / float(n) * 1.2f * extent;
    const placement::ProbeRays full = placement::trace_probe(rays, p, cube, directions);
    const bool expected = cube.contains(p) && !placement::is_dead(full, clearance);
    if (placement::is_valid_position(ctx, p, cube) != expected) ++v.mismatches;
    if (placement::mostly_back_faces(rays, p, directions) != (full.backface_fraction() > 0.5f)) ++v.mismatches;
    if (!cube.contains(p))
      ++v.outside_cube;
    else if (expected)
      ++v.valid;
    else if (full.nearest < clearance)
      ++v.dead_by_clearance;
    else
      ++v.dead_by_back_faces;
  }
  return v;
}

void expect_same_verdicts_on_every_kind_of_point(const scene::Scene& s, float clearance, bool expect_solids) {
  const Verdicts v = compare_with_full_trace(s, clearance);
  EXPECT_EQ(v.mismatches, 0);
  EXPECT_GT(v.valid, 1000);
  EXPECT_GT(v.outside_cube, 1000);
  if (clearance > 0.0f) {
    EXPECT_GT(v.dead_by_clearance, 100);
  }
  if (expect_solids) {
    EXPECT_GT(v.dead_by_back_faces, 10); // the inside of the blocks beyond the clearance
  }
}

TEST(Relocation, EarlyVerdictEqualsTheFullLatticeTraceInTheCornellBox) {
  const scene::Scene s = load_generated(samples::cornell(), "relocation_cornell");
  expect_same_verdicts_on_every_kind_of_point(s, placement::default_clearance(s), true);
  expect_same_verdicts_on_every_kind_of_point(s, 0.0f, true); // back-face rule alone
  expect_same_verdicts_on_every_kind_of_point(s, 0.05f, true);
}

// Double-sided surfaces: their backs are open space, so nothing is dead by back faces there.
TEST(Relocation, EarlyVerdictEqualsTheFullLatticeTraceWithDoubleSidedSurfaces) {
  const scene::Scene s = reversed_double_sided(load_generated(samples::cornell(), "relocation_cornell_ds"));
  expect_same_verdicts_on_every_kind_of_point(s, placement::default_clearance(s), false);
  EXPECT_EQ(compare_with_full_trace(s, placement::default_clearance(s)).dead_by_back_faces, 0);
}

} // namespace
} // namespace probebake::test
