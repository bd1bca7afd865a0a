#include "probebake/eval/flip.h"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>

#include <fmt/core.h>

#include "flip_color.h"
#include "flip_filter.h"
#include "probebake/common/parallel.h"
#include "probebake/formats/error.h"

namespace probebake::bake {
namespace {

using flip::Kernels;
using flip::Plane;

// HPG 2020, colour pipeline: HyAB raised to q_c compresses large differences; errors below
// p_c of the largest (cmax, green against blue) fill [0, p_t], the rest (p_t, 1].
constexpr float kQc = 0.7f;
constexpr float kPc = 0.4f;
constexpr float kPt = 0.95f;
// HPG 2020, feature pipeline: the exponent of the edge/point difference.
constexpr float kQf = 0.5f;
// The ACES filmic fit (Narkowicz 2016), y = (k0 x^2 + k1 x + k2) / (k3 x^2 + k4 x + k5), with its 0.6
// pre-exposure folded into the coefficients (EG 2021).
constexpr std::array<double, 6> kAces = {0.6 * 0.6 * 2.51, 0.6 * 0.03, 0.0, 0.6 * 0.6 * 2.43, 0.6 * 0.59, 0.14};
// EG 2021: the exposure range puts the reference's largest and median luminance at this
// tone-mapped value; luminance by the BT.709 / sRGB weights.
constexpr double kExposureTarget = 0.85;
constexpr glm::dvec3 kLuminance{0.2126, 0.7152, 0.0722};
// Past this the fit is above 1 (it crosses 1 near x = 12) and is clamped; it also keeps x^2 finite.
constexpr double kToneSaturated = 1e4;

// x where the tone mapper reaches t: the positive root of (k0 - t k3) x^2 + (k1 - t k4) x + (k2 - t k5).
double aces_inverse(double t) {
  const auto& k = kAces;
  const double c0 = (k[1] - k[4] * t) / (k[0] - k[3] * t), c1 = (k[2] - k[5] * t) / (k[0] - k[3] * t);
  return -0.5 * c0 + std::sqrt(0.25 * c0 * c0 - c1);
}

float tone_channel(float value, double exposure) {
  const double x = double(value) * std::exp2(exposure);
  if (!(x > 0.0)) return 0.0f; // negative, zero and NaN
  if (x >= kToneSaturated) return 1.0f;
  const auto& k = kAces;
  const double y = (k[0] * x * x + k[1] * x + k[2]) / (k[3] * x * x + k[4] * x + k[5]);
  return float(std::clamp(y, 0.0, 1.0));
}

float unit(float v) { return v > 0.0f ? std::min(v, 1.0f) : 0.0f; } // NaN reads as 0

// Channels read as non-negative finite values: NaN and negatives 0, +inf the largest float.
double finite_channel(float v) { return v > 0.0f ? double(std::min(v, FLT_MAX)) : 0.0; }

float largest_error() {
  static const float cmax = [] {
    const glm::vec3 green = flip::hunt_adjust(flip::linear_to_lab({0.0f, 1.0f, 0.0f}));
    const glm::vec3 blue = flip::hunt_adjust(flip::linear_to_lab({0.0f, 0.0f, 1.0f}));
    return std::pow(flip::hyab(green, blue), kQc);
  }();
  return cmax;
}

float redistribute(float e, float cmax) {
  const float knee = kPc * cmax;
  return e < knee ? (kPt / knee) * e : kPt + (e - knee) / (cmax - knee) * (1.0f - kPt);
}

void for_rows(int height, int threads, const std::function<void(int)>& row) {
  parallel_for(std::size_t(std::max(height, 0)), threads, [&](std::size_t y) { row(int(y)); });
}

// An LDR image in YCxCz, one plane a channel, and its luminance normalised to [0, 1], (Y + 16) / 116,
// which the feature detectors read.
struct Opponent {
  std::array<Plane, 3> c;
  Plane y;
};

Opponent to_opponent(const std::vector<glm::vec3>& rgb, int w, int h, int threads) {
  Opponent o{{Plane(w, h), Plane(w, h), Plane(w, h)}, Plane(w, h)};
  for_rows(h, threads, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const glm::vec3 v = flip::linear_to_ycxcz(rgb[std::size_t(y) * std::size_t(w) + std::size_t(x)]);
      for (int ch = 0; ch < 3; ++ch) o.c[std::size_t(ch)].at(x, y) = v[ch];
      o.y.at(x, y) = (v.x + 16.0f) / 116.0f;
    }
  });
  return o;
}

// The colour pipeline's side of one image: CSF-filtered, clamped to the RGB cube, Hunt-adjusted L*a*b*.
std::vector<glm::vec3> filtered_lab(const Opponent& o, const Kernels& k, int threads) {
  std::array<Plane, 3> f;
  for (std::size_t ch = 0; ch < 3; ++ch) f[ch] = flip::filter_csf(o.c[ch], k.csf[ch], threads);
  std::vector<glm::vec3> lab(o.y.v.size());
  const int w = o.y.width;
  for_rows(o.y.height, threads, [&](int y) {
    for (int x = 0; x < w; ++x) {
      const glm::vec3 rgb =
          glm::clamp(flip::ycxcz_to_linear({f[0].at(x, y), f[1].at(x, y), f[2].at(x, y)}), 0.0f, 1.0f);
      lab[std::size_t(y) * std::size_t(w) + std::size_t(x)] = flip::hunt_adjust(flip::linear_to_lab(rgb));
    }
  });
  return lab;
}

// LDR-FLIP of two images already in [0, 1].
std::vector<float> ldr_core(const std::vector<glm::vec3>& ref, const std::vector<glm::vec3>& test, int w, int h,
                            const Kernels& k, int threads) {
  const Opponent r = to_opponent(ref, w, h, threads), t = to_opponent(test, w, h, threads);
  const std::vector<glm::vec3> lab_r = filtered_lab(r, k, threads), lab_t = filtered_lab(t, k, threads);
  const flip::Features fr = flip::detect_features(r.y, k, threads), ft = flip::detect_features(t.y, k, threads);
  const float cmax = largest_error();
  std::vector<float> out(ref.size());
  for_rows(h, threads, [&](int y) {
    for (std::size_t i = std::size_t(y) * std::size_t(w), end = i + std::size_t(w); i < end; ++i) {
      const float colour = redistribute(std::pow(flip::hyab(lab_r[i], lab_t[i]), kQc), cmax);
      const float feature =
          std::max(std::fabs(fr.edges.v[i] - ft.edges.v[i]), std::fabs(fr.points.v[i] - ft.points.v[i]));
      const float f = std::pow(std::min(feature / std::numbers::sqrt2_v<float>, 1.0f), kQf);
      out[i] = std::pow(colour, 1.0f - f);
    }
  });
  return out;
}

void check_images(const Image& a, const Image& b) {
  const auto fits = [](const Image& i) {
    return i.width >= 0 && i.height >= 0 && i.pixels.size() == std::size_t(i.width) * std::size_t(i.height);
  };
  if (!fits(a) || !fits(b) || a.width != b.width || a.height != b.height)
    throw Error(ErrorKind::usage, fmt::format("FLIP: images of {}x{} ({} pixels) and {}x{} ({} pixels) differ", a.width,
                                              a.height, a.pixels.size(), b.width, b.height, b.pixels.size()));
}

std::vector<glm::vec3> mapped(const Image& image, int threads, const std::function<glm::vec3(glm::vec3)>& map) {
  std::vector<glm::vec3> out(image.pixels.size());
  for_rows(image.height, threads, [&](int y) {
    for (std::size_t i = std::size_t(y) * std::size_t(image.width), end = i + std::size_t(image.width); i < end; ++i)
      out[i] = map(image.pixels[i]);
  });
  return out;
}

double median(std::vector<double> v) {
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(mid), v.end());
  const double upper = v[mid];
  if (v.size() % 2 == 1) return upper;
  return 0.5 * (*std::max_element(v.begin(), v.begin() + std::ptrdiff_t(mid)) + upper);
}

} // namespace

std::vector<float> ldr_flip(const Image& reference, const Image& test, const FlipSettings& settings) {
  check_images(reference, test);
  const Kernels k = flip::make_kernels(settings.pixels_per_degree);
  const auto clamp = [](glm::vec3 c) { return glm::vec3(unit(c.x), unit(c.y), unit(c.z)); };
  return ldr_core(mapped(reference, settings.threads, clamp), mapped(test, settings.threads, clamp), reference.width,
                  reference.height, k, settings.threads);
}

glm::vec3 flip_tone_map(glm::vec3 linear, double exposure) {
  return {tone_channel(linear.x, exposure), tone_channel(linear.y, exposure), tone_channel(linear.z, exposure)};
}

FlipExposures flip_exposures(std::span<const glm::vec3> reference) {
  std::vector<double> lum, positive;
  lum.reserve(reference.size());
  for (const glm::vec3& c : reference) {
    lum.push_back(glm::dot(kLuminance, glm::dvec3(finite_channel(c.x), finite_channel(c.y), finite_channel(c.z))));
    if (lum.back() > 0.0) positive.push_back(lum.back());
  }
  if (positive.empty()) return {};
  const double lo = median(std::move(lum));
  const double stop_lum = lo > 0.0 ? lo : median(positive);
  const double x = aces_inverse(kExposureTarget);
  FlipExposures e;
  e.start = std::log2(x / *std::max_element(positive.begin(), positive.end()));
  e.stop = std::log2(x / stop_lum);
  e.count = e.start == e.stop ? 1 : std::clamp(int(std::ceil(e.stop - e.start)), 2, kMaxFlipExposures);
  return e;
}

std::vector<float> hdr_flip(const Image& reference, const Image& test, const FlipExposures& exposures,
                            const FlipSettings& settings) {
  check_images(reference, test);
  if (!std::isfinite(exposures.start) || !std::isfinite(exposures.stop) || exposures.count < 1 ||
      exposures.count > kMaxFlipExposures)
    throw Error(ErrorKind::usage, fmt::format("FLIP: exposures {} to {} in {} steps (1 to {} finite ones)",
                                              exposures.start, exposures.stop, exposures.count, kMaxFlipExposures));
  const Kernels k = flip::make_kernels(settings.pixels_per_degree);
  const double step = (exposures.stop - exposures.start) / double(std::max(exposures.count - 1, 1));
  std::vector<float> out(reference.pixels.size(), 0.0f);
  for (int i = 0; i < exposures.count; ++i) {
    const double exposure = exposures.start + double(i) * step;
    const auto tone = [exposure](glm::vec3 c) { return flip_tone_map(c, exposure); };
    const std::vector<float> ldr =
        ldr_core(mapped(reference, settings.threads, tone), mapped(test, settings.threads, tone), reference.width,
                 reference.height, k, settings.threads);
    for (std::size_t p = 0; p < out.size(); ++p) out[p] = std::max(out[p], ldr[p]);
  }
  return out;
}

std::vector<float> hdr_flip(const Image& reference, const Image& test, const FlipSettings& settings) {
  return hdr_flip(reference, test, flip_exposures(reference.pixels), settings);
}

} // namespace probebake::bake
