// The seam score (eval/seams.h) finds discontinuities, not steep gradients: exact fields with known
// answers, then the lookups of baked scenes: one leaf's stencil has steps at its borders, the blend has none
// (issue #39).
#include <cmath>

#include <gtest/gtest.h>

#include "bake_test_util.h"
#include "probebake/probe_index/lookup.h"
#include "probebake/eval/seams.h"
#include "probebake/samples/scenes.h"

namespace probebake::test {
namespace {

const glm::vec3 kLo(0.0f), kHi(1.0f);
constexpr float kCell = 0.1f;

// Cells of kCell metres over the unit cube, numbered.
bake::SeamCell cells(glm::vec3 p, glm::vec3) {
  if (!glm::all(glm::greaterThanEqual(p, kLo)) || !glm::all(glm::lessThan(p, kHi))) return {};
  const glm::ivec3 c(glm::floor(p / kCell));
  return {kCell, c.x + 16 * (c.y + 16 * c.z)};
}

glm::vec3 grey(float e) { return glm::vec3(e); }

bool no_geometry(glm::vec3, glm::vec3, glm::vec3) { return true; }

TEST(SeamScore, LinearAndSteepSmoothFieldsScoreZero) {
  const auto linear = [](glm::vec3 p, glm::vec3) { return grey(1.0f + 50.0f * p.x - 20.0f * p.y + 5.0f * p.z); };
  const bake::SeamScore flat = bake::seam_score(linear, cells, no_geometry, kLo, kHi);
  EXPECT_GT(flat.borders, 1000);
  EXPECT_LT(flat.p99, 1e-4);
  // Steep but smooth: a Gaussian bump rising by 10x over 0.1 m; the excess is h^2 times its curvature.
  const auto bump = [](glm::vec3 p, glm::vec3) {
    const glm::vec3 d = p - glm::vec3(0.5f);
    return grey(1.0f + 10.0f * std::exp(-glm::dot(d, d) / 0.01f));
  };
  EXPECT_LT(bake::seam_score(bump, cells, no_geometry, kLo, kHi).p99, 2e-3);
  // A kink (C0, its slope changes sign) is not a seam either.
  const auto kink = [](glm::vec3 p, glm::vec3) { return grey(1.0f + 3.0f * std::abs(p.x - 0.5f)); };
  EXPECT_LT(bake::seam_score(kink, cells, no_geometry, kLo, kHi).p99, 1e-2);
}

TEST(SeamScore, StepsBetweenCellsScoreTheirSize) {
  // A 3D checkerboard of cells 0.1 m wide whose values differ by 10 %: every border is a seam of 0.1 / 1.05.
  const auto steps = [](glm::vec3 p, glm::vec3) {
    const glm::ivec3 c(glm::floor(p / kCell));
    return grey((c.x + c.y + c.z) % 2 == 0 ? 1.0f : 1.1f);
  };
  const bake::SeamScore s = bake::seam_score(steps, cells, no_geometry, kLo, kHi);
  EXPECT_NEAR(s.max, 0.1 / 1.05, 1e-3);
  EXPECT_NEAR(s.p99, 0.1 / 1.05, 1e-3); // every border is a seam of the same size
  // Same seed, same score; another seed, other lines.
  EXPECT_EQ(bake::seam_score(steps, cells, no_geometry, kLo, kHi).p99, s.p99);
}

struct OctreeSeams {
  bake::SeamScore blended; // the lookup a game sees (sample_irradiance)
  bake::SeamScore leaf;    // one leaf's stencil alone, the lookup before the blend
};

// The seam scores of a generated scene's lookups, octree depth 3, printed.
OctreeSeams octree_seams(const samples::SceneBuilder& builder, const std::string& name) {
  const scene::Scene scene = load_generated(builder, name);
  bake::BakeSettings settings;
  settings.max_depth = 3;
  const bake::BakeResult baked = bake::bake(scene, settings);
  const scene::RayScene rays(scene);
  const formats::ProbeVolume& v = baked.volume;
  OctreeSeams s{bake::svo_seam_score(v, rays), bake::svo_seam_score(v, rays, [&](glm::vec3 p, glm::vec3 n) {
                  return probe_index::apply_stencil(v, probe_index::svo_stencil(v, p, n), n);
                })};
  std::printf("[seams] %s octree depth 3: blended lookup p99 %.4f, max %.3f over %d borders; one leaf's stencil p99 "
              "%.4f, max %.3f\n",
              name.c_str(), s.blended.p99, s.blended.max, s.blended.borders, s.leaf.p99, s.leaf.max);
  return s;
}

// The Cornell box: one leaf's stencil is constant inside the leaf, so its borders are steps a player sees
// (p99 0.26 at 4372ab6). The blend of the eight finest-voxel centres' leaves is continuous: the issue's
// goal is 1 % of the local irradiance.
TEST(SeamScore, TheBlendedLookupOfTheCornellBoxHasNoSeams) {
  const OctreeSeams s = octree_seams(samples::cornell(), "seams-cornell");
  EXPECT_GT(s.blended.borders, 1000);
  EXPECT_GT(s.leaf.p99, 0.05); // the metric sees the steps that were there
  EXPECT_LT(s.blended.p99, 0.01);
}

// A wall is not a seam: lines end at surfaces. The leak scene's rooms, one lit and one dark, meet at a
// 2 cm wall; a line (or a lookup's normal bias) that crossed it would score the full step of light, 2x
// the local irradiance (before lines ended at surfaces: max 2.0; after: 0.105).
TEST(SeamScore, LinesEndAtSurfaces) {
  const OctreeSeams s = octree_seams(samples::leak(), "seams-leak");
  EXPECT_GT(s.blended.borders, 500);
  EXPECT_LT(s.leaf.max, 0.5);
  EXPECT_LT(s.blended.max, 0.5);
}

} // namespace
} // namespace probebake::test
