// The leaf rule (shaders/include/probebake/leaf_rule.h) that TreeUpdate, the GPU passes and the bake share:
// the documented verdicts on both sides of every threshold (split_low, split_high, the back-face fraction,
// max depth, f = 0).
#include <cmath>

#include <gtest/gtest.h>

#include "probebake/leaf_rule.h"

namespace probebake::gpu {
namespace {

VolumeInfo thresholds() {
  VolumeInfo info{};
  info.max_depth = 3;
  info.split_low = 0.05f;
  info.split_high = 0.5f;
  return info;
}

int verdict(float f, float b, int depth) {
  return leaf_verdict(f, b, depth, thresholds(), LEAF_DEAD_BACKFACE_FRACTION);
}

float below(float x) { return std::nextafter(x, 0.0f); }
float above(float x) { return std::nextafter(x, 1.0f); }

TEST(LeafRule, SplitHighIsInclusiveBelowMaxDepthOnly) {
  EXPECT_EQ(verdict(0.5f, 0.0f, 2), LEAF_VERDICT_SPLIT);
  EXPECT_EQ(verdict(below(0.5f), 0.0f, 2), LEAF_VERDICT_KEEP);
  EXPECT_EQ(verdict(1.0f, 0.0f, 3), LEAF_VERDICT_KEEP); // at max depth a full view keeps its probe
  EXPECT_EQ(verdict(1.0f, 0.0f, 4), LEAF_VERDICT_KEEP); // deeper than max (a lowered max depth): no split
}

TEST(LeafRule, BelowSplitLowABlindCentreRefinesTowardsWhatItSeesOrIsFreed) {
  EXPECT_EQ(verdict(0.05f, 0.0f, 1), LEAF_VERDICT_KEEP);                       // split_low itself sees enough
  EXPECT_EQ(verdict(below(0.05f), 0.0f, 1), LEAF_VERDICT_SPLIT);               // blind, sees geometry: refine
  EXPECT_EQ(verdict(below(0.05f), 0.0f, 3), LEAF_VERDICT_FREE);                // ... unless at max depth
  EXPECT_EQ(verdict(0.0f, 0.0f, 1), LEAF_VERDICT_FREE);                        // sees nothing in its cube
  EXPECT_EQ(verdict(std::nextafter(0.0f, 1.0f), 0.0f, 1), LEAF_VERDICT_SPLIT); // the smallest f > 0
}

TEST(LeafRule, MostlyBackFacesMakeTheCentreBlindAboveTheFractionOnly) {
  EXPECT_EQ(verdict(0.3f, 0.5f, 1), LEAF_VERDICT_KEEP);                           // exactly the fraction: still sees
  EXPECT_EQ(verdict(0.3f, above(0.5f), 1), LEAF_VERDICT_SPLIT);                   // inside a solid, below max: refine
  EXPECT_EQ(verdict(0.3f, above(0.5f), 3), LEAF_VERDICT_FREE);                    // inside a solid at max depth: free
  EXPECT_EQ(leaf_verdict(0.3f, 0.7f, 3, thresholds(), 0.75f), LEAF_VERDICT_KEEP); // the fraction is a parameter
  EXPECT_TRUE(leaf_centre_blind(0.3f, above(0.5f), 0.05f, 0.5f));
  EXPECT_FALSE(leaf_centre_blind(0.05f, 0.5f, 0.05f, 0.5f));
}

TEST(LeafRule, TheBakesFormTakesGeometryInTheCubeFromItsCaller) {
  // A blind centre with no hit in its cube but triangles in it (the bake knows them) still refines.
  EXPECT_EQ(leaf_verdict_with(0.0f, true, true, false, 1, thresholds()), LEAF_VERDICT_SPLIT);
  EXPECT_EQ(leaf_verdict_with(0.0f, true, false, false, 1, thresholds()), LEAF_VERDICT_FREE);
  EXPECT_EQ(leaf_verdict_with(0.7f, false, false, false, 1, thresholds()), LEAF_VERDICT_SPLIT);
}

} // namespace
} // namespace probebake::gpu
