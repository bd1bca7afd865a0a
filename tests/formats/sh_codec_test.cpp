// The compact probe irradiance codes (probebake/sh_code.h): round trips within the bounds the quantisation
// implies, on physical probes (irradiance of non-negative radiance), over the whole float range, and on
// hostile input.
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "probebake/formats/sh_codec.h"
#include "probebake/probe_index/lookup.h"

namespace probebake::formats {
namespace {

using gpu::SH_CODE_L1_RANGE;
using probe_index::evaluate_sh;
using probe_index::sh_basis;

glm::vec3 random_direction(std::mt19937& rng) {
  std::normal_distribution<float> g;
  for (;;) {
    const glm::vec3 d(g(rng), g(rng), g(rng));
    if (glm::length(d) > 1e-3f) return glm::normalize(d);
  }
}

// Irradiance SH of radiance made of `lights` coloured directional deltas over a coloured ambient term.
ShCoefficients physical_probe(std::mt19937& rng, int lights, float ambient) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const float band[3] = {probe_index::kShBand0, probe_index::kShBand1, probe_index::kShBand2};
  ShCoefficients sh{};
  for (int c = 0; c < 3; ++c) sh[std::size_t(c)] = ambient * u(rng) * band[0] * probe_index::kShY0 * 4.0f;
  for (int i = 0; i < lights; ++i) {
    const std::array<float, 9> y = sh_basis(random_direction(rng));
    const glm::vec3 colour(u(rng), u(rng), u(rng));
    for (int k = 0; k < 9; ++k) {
      const float a = band[k == 0 ? 0 : (k < 4 ? 1 : 2)];
      for (int c = 0; c < 3; ++c) sh[std::size_t(3 * k + c)] += a * y[std::size_t(k)] * colour[c];
    }
  }
  return sh;
}

// Largest and RMS error over directions of `coded` against `exact`, per channel relative to the channel's
// mean irradiance over the sphere (its L0 term).
struct CodeError {
  double max = 0.0, rms = 0.0;
};
CodeError code_error(const ShCoefficients& exact, const ShCoefficients& coded, std::mt19937& rng) {
  CodeError e;
  double squares = 0.0;
  int n = 0;
  for (int i = 0; i < 256; ++i) {
    const glm::vec3 d = random_direction(rng);
    const glm::vec3 a = evaluate_sh(exact.data(), d), b = evaluate_sh(coded.data(), d);
    for (int c = 0; c < 3; ++c) {
      const double mean = double(exact[std::size_t(c)]) * probe_index::kShY0;
      if (mean <= 0.0) continue;
      const double r = std::abs(double(b[c]) - double(a[c])) / mean;
      e.max = std::max(e.max, r);
      squares += r * r;
      ++n;
    }
  }
  e.rms = n ? std::sqrt(squares / n) : 0.0;
  return e;
}

TEST(ShCodec, SizesAndNames) {
  EXPECT_EQ(sh_codec_bytes(ShCodec::float32), 108);
  EXPECT_EQ(sh_codec_bytes(ShCodec::l2), 32);
  EXPECT_EQ(sh_codec_bytes(ShCodec::l1), 16);
  for (ShCodec c : kShCodecs) EXPECT_EQ(parse_sh_codec(sh_codec_name(c)), c);
  EXPECT_FALSE(parse_sh_codec("half").has_value());
}

TEST(ShCodec, AUniformProbeKeepsItsBandsExactlyZero) {
  ShCoefficients sh{};
  sh[0] = 0.3f, sh[1] = 2.5f, sh[2] = 1e-3f;
  for (ShCodec codec : {ShCodec::l2, ShCodec::l1}) {
    const ShCoefficients d = round_trip_sh(codec, sh);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(d[std::size_t(c)], sh[std::size_t(c)], sh[std::size_t(c)] * 0x1p-11f);
    for (std::size_t j = 3; j < d.size(); ++j) EXPECT_EQ(d[j], 0.0f) << j;
  }
}

// The bound of the quantisation: half a step of band 1 (its scale s1 <= 2/sqrt(3), over 63 steps of 7 bits)
// on each of three coefficients, half a step of band 2 (s2 <= sqrt(5)/4 over 127 steps) on each of five,
// L0 to half-float rounding. Per direction, relative to the mean irradiance Y0 * L0: band 1
// <= 0.5 * (2/sqrt(3))/63 * Y1 * sqrt(3) / Y0 = 2.75%, band 2 <= 0.5 * (sqrt(5)/4)/127 * (sum |Y2m| <= 1.6) / Y0
// = 1.25%. The test's probes are lit by one to six directions, the hardest case for the per-probe scales.
TEST(ShCodec, PhysicalProbesRoundTripWithinTheQuantisationBound) {
  std::mt19937 rng(7);
  CodeError worst2, worst1_band;
  double rms2 = 0.0;
  const int probes = 2000;
  for (int i = 0; i < probes; ++i) {
    const ShCoefficients sh = physical_probe(rng, 1 + i % 6, i % 3 == 0 ? 0.0f : 0.5f);
    const CodeError e2 = code_error(sh, round_trip_sh(ShCodec::l2, sh), rng);
    worst2.max = std::max(worst2.max, e2.max);
    rms2 += e2.rms * e2.rms;
    // L1 is L2's first block: its bands 0-1 equal L2's, and band 2 is dropped.
    const ShCoefficients d2 = round_trip_sh(ShCodec::l2, sh), d1 = round_trip_sh(ShCodec::l1, sh);
    for (std::size_t j = 0; j < 12; ++j) ASSERT_EQ(d1[j], d2[j]) << j;
    for (std::size_t j = 12; j < 27; ++j) ASSERT_EQ(d1[j], 0.0f) << j;
    ShCoefficients truncated = sh;
    for (std::size_t j = 12; j < 27; ++j) truncated[j] = 0.0f;
    worst1_band.max = std::max(worst1_band.max, code_error(truncated, d1, rng).max);
  }
  EXPECT_LT(worst2.max, 0.0275 + 0.0125 + 0.001);
  EXPECT_LT(worst1_band.max, 0.0275 + 0.001);
  // Rounding errors are uniform over a step, so the RMS is far below the bound.
  EXPECT_LT(std::sqrt(rms2 / probes), 0.006);
  RecordProperty("l2_max_error", std::to_string(worst2.max));
  RecordProperty("l2_rms_error", std::to_string(std::sqrt(rms2 / probes)));
}

// Each band's scale is the probe's own: a nearly uniform probe keeps its faint gradient to half a step of its
// largest ratio (not of the largest ratio any probe can have).
TEST(ShCodec, AFaintGradientKeepsItsPrecision) {
  std::mt19937 rng(5);
  for (int i = 0; i < 200; ++i) {
    ShCoefficients sh = physical_probe(rng, 2, 0.0f);
    const float ambient = 20.0f * std::max({sh[0], sh[1], sh[2]}); // a uniform term 20 times the lights'
    for (int c = 0; c < 3; ++c) sh[std::size_t(c)] += ambient;
    const ShCoefficients d = round_trip_sh(ShCodec::l2, sh);
    for (std::size_t band = 1; band <= 2; ++band) {
      const std::size_t first = band == 1 ? 3 : 12, last = band == 1 ? 12 : 27;
      const float steps = band == 1 ? 63.0f : 127.0f;
      for (std::size_t j = first; j < last; ++j) {
        float largest = 0.0f; // of the band's ratios to their channel's L0
        for (std::size_t k = first; k < last; ++k) largest = std::max(largest, std::abs(sh[k] / sh[k % 3]));
        ASSERT_LT(largest, 0.1f); // the case this test is about: a tenth of band 1's range or less
        const float range = band == 1 ? SH_CODE_L1_RANGE : gpu::SH_CODE_L2_RANGE;
        const float half_step = 0.5f * (largest + range / 255.0f) / steps; // the scale is rounded up
        EXPECT_NEAR(d[j] / d[j % 3], sh[j] / sh[j % 3], half_step * 1.001f + 1e-6f) << i << " " << j;
      }
    }
  }
}

TEST(ShCodec, AnyFloatRangeFitsAndTinyProbesAreBlack) {
  std::mt19937 rng(3);
  const ShCoefficients base = physical_probe(rng, 3, 0.5f);
  for (float scale : {1e-37f, 1e-20f, 1e-3f, 1.0f, 1e6f, 1e20f, 1e36f}) {
    ShCoefficients sh = base;
    for (float& v : sh) v *= scale;
    const ShCoefficients d = round_trip_sh(ShCodec::l2, sh);
    for (float v : d) ASSERT_TRUE(std::isfinite(v)) << scale;
    EXPECT_LT(code_error(sh, d, rng).max, 0.0275 + 0.0125 + 0.001) << scale;
  }
  ShCoefficients brightest{};
  brightest[0] = std::numeric_limits<float>::max();
  EXPECT_NEAR(round_trip_sh(ShCodec::l2, brightest)[0] / brightest[0], 1.0f, 0x1p-10f);
  ShCoefficients tiny{};
  tiny[1] = 1e-39f; // denormal: black
  for (float v : round_trip_sh(ShCodec::l2, tiny)) EXPECT_EQ(v, 0.0f);
}

TEST(ShCodec, HostileCoefficientsDecodeFinite) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  for (int i = 0; i < 1000; ++i) {
    ShCoefficients sh{};
    for (float& v : sh) v = u(rng);
    const float special[] = {nan, inf, -inf, -1.0f, 0.0f, 1e38f};
    sh[std::size_t(i % 27)] = special[i % 6];
    sh[std::size_t((i * 7) % 27)] = special[(i / 6) % 6];
    for (ShCodec codec : {ShCodec::l2, ShCodec::l1})
      for (float v : round_trip_sh(codec, sh)) ASSERT_TRUE(std::isfinite(v)) << i;
  }
  ShCoefficients bad{};
  bad[0] = nan, bad[1] = 1.0f, bad[2] = 1.0f; // NaN L0 channel: that channel is black, the others kept
  const ShCoefficients d = round_trip_sh(ShCodec::l2, bad);
  EXPECT_EQ(d[0], 0.0f);
  EXPECT_NEAR(d[1], 1.0f, 1e-3f);
}

} // namespace
} // namespace probebake::formats
