// FLIP (eval/flip.h, issue #39): properties the papers state or their formulas imply, on synthetic
// images. No published mean FLIP is reproduced here: the papers' example images are not in the repository.
#include <cfloat>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

#include <gtest/gtest.h>

#include "probebake/eval/flip.h"
#include "probebake/formats/error.h"

namespace probebake::test {
namespace {

bake::Image constant(int w, int h, glm::vec3 c) {
  return {w, h, std::vector<glm::vec3>(std::size_t(w) * std::size_t(h), c)};
}

// A smooth HDR picture over about 8 stops with a bright square: something with edges and a range.
bake::Image hdr_scene(int w, int h) {
  bake::Image image = constant(w, h, glm::vec3(0.0f));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const float u = float(x) / float(w), v = float(y) / float(h);
      glm::vec3 c = std::exp2(8.0f * u - 4.0f) * glm::vec3(0.8f, 0.6f + 0.3f * v, 0.4f);
      if (x > w / 3 && x < w / 2 && y > h / 3 && y < h / 2) c = glm::vec3(40.0f, 35.0f, 30.0f);
      image.pixels[std::size_t(y) * std::size_t(w) + std::size_t(x)] = c;
    }
  return image;
}

// Each channel times (1 + amount * n), n uniform in [-1, 1], the same n for every amount.
bake::Image noisy(const bake::Image& image, float amount) {
  bake::Image out = image;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> n(-1.0f, 1.0f);
  for (glm::vec3& c : out.pixels) c *= glm::vec3(1.0f) + amount * glm::vec3(n(rng), n(rng), n(rng));
  return out;
}

double mean(const std::vector<float>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / double(v.size()); }

void expect_unit_and_finite(const std::vector<float>& v) {
  for (float e : v) {
    ASSERT_TRUE(std::isfinite(e));
    ASSERT_GE(e, 0.0f);
    ASSERT_LE(e, 1.0f);
  }
}

TEST(Flip, IdenticalImagesScoreZeroEverywhere) {
  const bake::Image a = hdr_scene(48, 32);
  for (float e : bake::hdr_flip(a, a)) ASSERT_EQ(e, 0.0f);
  const bake::Image ldr = constant(16, 16, glm::vec3(0.3f, 0.5f, 0.7f));
  for (float e : bake::ldr_flip(ldr, ldr)) ASSERT_EQ(e, 0.0f);
}

// cmax is by definition the Hunt-adjusted HyAB distance of pure green and pure blue (HPG 2020, colour
// pipeline), mapped to 1: flat fields of the two, with no features, give exactly that.
TEST(Flip, PureGreenAgainstPureBlueIsTheLargestError) {
  const auto e = bake::ldr_flip(constant(12, 10, {0, 1, 0}), constant(12, 10, {0, 0, 1}));
  for (float v : e) ASSERT_NEAR(v, 1.0f, 1e-5f);
}

// Black against white: HyAB = 100 (lightness only), so the error is p_t + (100^q_c - p_c cmax) /
// ((1 - p_c) cmax) (1 - p_t), with cmax from the published CIELAB values of sRGB green (87.7347, -86.1827,
// 83.1793) and blue (32.3026, 79.1967, -107.8637): about 0.967, not 1.
TEST(Flip, BlackAgainstWhiteFollowsTheRedistribution) {
  const auto hunt = [](double l, double a, double b) { return std::array{l, 0.01 * l * a, 0.01 * l * b}; };
  const auto g = hunt(87.7347, -86.1827, 83.1793), b = hunt(32.3026, 79.1967, -107.8637);
  const double cmax = std::pow(std::fabs(g[0] - b[0]) + std::hypot(g[1] - b[1], g[2] - b[2]), 0.7);
  const double expected = 0.95 + (std::pow(100.0, 0.7) - 0.4 * cmax) / (0.6 * cmax) * 0.05;
  ASSERT_GT(expected, 0.95);
  ASSERT_LT(expected, 1.0);
  for (float v : bake::ldr_flip(constant(8, 8, glm::vec3(0.0f)), constant(8, 8, glm::vec3(1.0f))))
    ASSERT_NEAR(v, expected, 2e-4);
}

TEST(Flip, MoreNoiseScoresHigher) {
  const bake::Image ref = hdr_scene(64, 48);
  double previous = 0.0;
  for (float amount : {0.01f, 0.05f, 0.2f, 0.6f}) {
    const auto e = bake::hdr_flip(ref, noisy(ref, amount));
    expect_unit_and_finite(e);
    const double m = mean(e);
    EXPECT_GT(m, previous) << "noise " << amount;
    previous = m;
  }
  EXPECT_LT(previous, 1.0);
}

// HDR-FLIP is the per-pixel maximum of LDR-FLIP over the tone-mapped exposures (EG 2021).
TEST(Flip, HdrFlipIsTheLargestLdrFlipOverItsExposures) {
  const bake::Image ref = hdr_scene(40, 30), test = noisy(ref, 0.2f);
  const bake::FlipExposures ex = bake::flip_exposures(ref.pixels);
  ASSERT_GE(ex.count, 2);
  const auto hdr = bake::hdr_flip(ref, test, ex);
  std::vector<float> largest(hdr.size(), 0.0f);
  for (int i = 0; i < ex.count; ++i) {
    const double exposure = ex.start + double(i) * ((ex.stop - ex.start) / double(ex.count - 1));
    bake::Image r = ref, t = test;
    for (auto& c : r.pixels) c = bake::flip_tone_map(c, exposure);
    for (auto& c : t.pixels) c = bake::flip_tone_map(c, exposure);
    const auto ldr = bake::ldr_flip(r, t);
    for (std::size_t p = 0; p < hdr.size(); ++p) {
      ASSERT_GE(hdr[p], ldr[p]);
      largest[p] = std::max(largest[p], ldr[p]);
    }
  }
  EXPECT_EQ(hdr, largest);
}

// EG 2021: the shortest exposure maps the largest luminance, the longest the median, to 0.85 after
// tone mapping; one exposure per stop between them.
TEST(Flip, ExposuresSpanTheReferenceFromItsMaximumToItsMedian) {
  std::vector<glm::vec3> pixels = {glm::vec3(0.25f), glm::vec3(0.5f), glm::vec3(0.5f), glm::vec3(2.0f),
                                   glm::vec3(8.0f)};
  const bake::FlipExposures ex = bake::flip_exposures(pixels);
  EXPECT_NEAR(bake::flip_tone_map(glm::vec3(8.0f), ex.start).x, 0.85f, 1e-5f);
  EXPECT_NEAR(bake::flip_tone_map(glm::vec3(0.5f), ex.stop).x, 0.85f, 1e-5f);
  EXPECT_NEAR(ex.stop - ex.start, 4.0, 1e-9);
  EXPECT_EQ(ex.count, 4);
  const bake::FlipExposures flat = bake::flip_exposures(std::vector<glm::vec3>(9, glm::vec3(3.0f)));
  EXPECT_EQ(flat.count, 1);
  EXPECT_EQ(flat.start, flat.stop);
  const bake::FlipExposures dark = bake::flip_exposures(std::vector<glm::vec3>(9, glm::vec3(0.0f)));
  EXPECT_EQ(dark.count, 1);
  EXPECT_EQ(dark.start, 0.0);
  // Mostly black (the background of a camera view): the median of the lit pixels.
  std::vector<glm::vec3> sparse(20, glm::vec3(0.0f));
  sparse[3] = glm::vec3(1.0f), sparse[4] = glm::vec3(4.0f), sparse[5] = glm::vec3(16.0f);
  const bake::FlipExposures s = bake::flip_exposures(sparse);
  EXPECT_NEAR(s.stop - s.start, 2.0, 1e-9); // log2(16 / 4)
  EXPECT_EQ(s.count, 2);
}

TEST(Flip, ZeroHugeAndNonFiniteInputsGiveFiniteErrors) {
  const bake::Image black = constant(20, 20, glm::vec3(0.0f));
  for (float e : bake::hdr_flip(black, black)) ASSERT_EQ(e, 0.0f);
  bake::Image wild = hdr_scene(20, 20);
  const float specials[] = {
      FLT_MAX, 1e30f, std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN(), -5.0f, 1e-40f};
  for (std::size_t i = 0; i < wild.pixels.size(); i += 7) wild.pixels[i] = glm::vec3(specials[(i / 7) % 6]);
  expect_unit_and_finite(bake::hdr_flip(wild, hdr_scene(20, 20)));
  expect_unit_and_finite(bake::hdr_flip(hdr_scene(20, 20), wild));
  expect_unit_and_finite(bake::hdr_flip(black, wild));
  expect_unit_and_finite(bake::hdr_flip(wild, black));
  expect_unit_and_finite(bake::ldr_flip(wild, black));
  const bake::FlipExposures ex = bake::flip_exposures(wild.pixels);
  EXPECT_TRUE(std::isfinite(ex.start));
  EXPECT_TRUE(std::isfinite(ex.stop));
  EXPECT_LE(ex.count, bake::kMaxFlipExposures);
}

TEST(Flip, SameResultForAnyThreadCount) {
  const bake::Image ref = hdr_scene(50, 37), test = noisy(ref, 0.1f);
  const auto one = bake::hdr_flip(ref, test, {.threads = 1});
  EXPECT_EQ(one, bake::hdr_flip(ref, test, {.threads = 2}));
  EXPECT_EQ(one, bake::hdr_flip(ref, test, {.threads = 0}));
}

// The filters reach about 10 pixels at the default 67 pixels per degree: a change to one pixel leaves the
// error exactly 0 further away, and is seen where it is.
TEST(Flip, ErrorsStayNearTheirCause) {
  const bake::Image ref = constant(61, 61, glm::vec3(0.5f));
  bake::Image test = ref;
  test.pixels[30 * 61 + 30] = glm::vec3(1.0f);
  const auto e = bake::ldr_flip(ref, test);
  EXPECT_GT(e[30 * 61 + 30], 0.1f);
  for (int y = 0; y < 61; ++y)
    for (int x = 0; x < 61; ++x) {
      const bool far = std::max(std::abs(x - 30), std::abs(y - 30)) > 10;
      ASSERT_TRUE(!far || e[std::size_t(y * 61 + x)] == 0.0f) << x << ", " << y;
    }
}

TEST(Flip, RefusesMismatchedImagesAndBadSettings) {
  const bake::Image a = constant(4, 4, glm::vec3(1.0f)), b = constant(4, 5, glm::vec3(1.0f));
  EXPECT_THROW(bake::hdr_flip(a, b), Error);
  EXPECT_THROW(bake::ldr_flip(a, a, {.pixels_per_degree = 0.0}), Error);
  EXPECT_THROW(bake::hdr_flip(a, a, {.start = 0.0, .stop = 1.0, .count = 0}), Error);
  EXPECT_TRUE(bake::hdr_flip(constant(0, 0, glm::vec3(0.0f)), constant(0, 0, glm::vec3(0.0f))).empty());
}

} // namespace
} // namespace probebake::test
