#include "flip_filter.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "probebake/common/parallel.h"
#include "probebake/formats/error.h"

namespace probebake::bake::flip {
namespace {

constexpr double kPi = std::numbers::pi;

// Contrast sensitivity functions as sums of Gaussians in the frequency domain, a1 exp(-b1 pi^2 f^2) + a2
// exp(-b2 pi^2 f^2), whose spatial kernels are a sqrt(pi / b) exp(-pi^2 x^2 / b) (x in degrees): HPG 2020,
// colour pipeline (a1, b1, a2, b2 per channel as the paper lists them; a2 = 0: one Gaussian).
struct Csf {
  double a1, b1, a2, b2;
};
constexpr Csf kAchromatic{1.0, 0.0047, 0.0, 0.0};
constexpr Csf kRedGreen{1.0, 0.0053, 0.0, 0.0};
constexpr Csf kBlueYellow{34.1, 0.04, 13.5, 0.025};
constexpr double kLargestB = 0.04; // one radius for all channels: 3 standard deviations of the widest Gaussian

// Feature detectors (HPG 2020, feature pipeline): Gaussian derivatives whose standard deviation is half the
// 0.082 degree peak-to-trough width of the human edge detector, radius 3 standard deviations.
constexpr double kFeatureWidthDegrees = 0.082;

Kernel to_float(const std::vector<double>& k) { return Kernel(k.begin(), k.end()); }

std::vector<CsfTerm> csf_terms(const Csf& csf, int radius, double pixels_per_degree) {
  const double dx = 1.0 / pixels_per_degree; // degrees per pixel
  std::vector<std::pair<double, std::vector<double>>> parts;
  double total = 0.0;
  for (const auto& [a, b] : {std::pair{csf.a1, csf.b1}, std::pair{csf.a2, csf.b2}}) {
    if (a == 0.0) continue;
    std::vector<double> g(std::size_t(2 * radius + 1));
    double sum = 0.0;
    for (int i = -radius; i <= radius; ++i) {
      const double x = double(i) * dx;
      g[std::size_t(i + radius)] = std::exp(-kPi * kPi * x * x / b);
      sum += g[std::size_t(i + radius)];
    }
    const double weight = a * std::sqrt(kPi / b);
    total += weight * sum * sum; // the 2D kernel's sum, to normalise it to 1
    parts.emplace_back(weight, std::move(g));
  }
  std::vector<CsfTerm> terms;
  for (auto& [weight, g] : parts) terms.push_back({float(weight / total), to_float(g)});
  return terms;
}

// Positive weights scaled to sum 1 and negative ones to sum -1 (HPG 2020, feature pipeline); a side that
// underflowed to nothing stays 0.
Kernel balance(std::vector<double> k) {
  double positive = 0.0, negative = 0.0;
  for (double w : k) (w > 0.0 ? positive : negative) += w;
  for (double& w : k) w = w > 0.0 ? (positive > 0.0 ? w / positive : 0.0) : (negative < 0.0 ? -w / negative : 0.0);
  return to_float(k);
}

void feature_kernels(Kernels& k, double pixels_per_degree) {
  const double sd = 0.5 * kFeatureWidthDegrees * pixels_per_degree;
  const int radius = int(std::ceil(3.0 * sd));
  std::vector<double> g, edge, point;
  double sum = 0.0;
  for (int i = -radius; i <= radius; ++i) {
    const double x = double(i), gauss = std::exp(-x * x / (2.0 * sd * sd));
    g.push_back(gauss);
    edge.push_back(-x * gauss);
    point.push_back((x * x / (sd * sd) - 1.0) * gauss);
    sum += gauss;
  }
  for (double& w : g) w = sum > 0.0 ? w / sum : 0.0;
  k.smooth = to_float(g);
  k.edge = balance(std::move(edge));
  k.point = balance(std::move(point));
}

// out(x, y) = sum_i k[i] in(x + i - r, y) (dir 0) or in(x, y + i - r) (dir 1), the index clamped to the image.
Plane pass(const Plane& in, const Kernel& k, int dir, int threads) {
  Plane out(in.width, in.height);
  const int r = int(k.size() / 2);
  parallel_for(std::size_t(in.height), threads, [&](std::size_t row) {
    const int y = int(row);
    for (int x = 0; x < in.width; ++x) {
      float s = 0.0f;
      for (int i = -r; i <= r; ++i) {
        const float w = k[std::size_t(i + r)];
        s += dir == 0 ? w * in.at(std::clamp(x + i, 0, in.width - 1), y)
                      : w * in.at(x, std::clamp(y + i, 0, in.height - 1));
      }
      out.at(x, y) = s;
    }
  });
  return out;
}

Plane norm(const Plane& a, const Plane& b) {
  Plane out(a.width, a.height);
  for (std::size_t i = 0; i < out.v.size(); ++i) out.v[i] = std::sqrt(a.v[i] * a.v[i] + b.v[i] * b.v[i]);
  return out;
}

} // namespace

Kernels make_kernels(double pixels_per_degree) {
  if (!(pixels_per_degree > 0.0) || !std::isfinite(pixels_per_degree))
    throw Error(ErrorKind::usage,
                "FLIP: pixels per degree must be positive and finite, not " + std::to_string(pixels_per_degree));
  const int radius = int(std::ceil(3.0 * std::sqrt(kLargestB / (2.0 * kPi * kPi)) * pixels_per_degree));
  Kernels k;
  k.csf = {csf_terms(kAchromatic, radius, pixels_per_degree), csf_terms(kRedGreen, radius, pixels_per_degree),
           csf_terms(kBlueYellow, radius, pixels_per_degree)};
  feature_kernels(k, pixels_per_degree);
  return k;
}

Plane filter_separable(const Plane& in, const Kernel& along_x, const Kernel& along_y, int threads) {
  return pass(pass(in, along_x, 0, threads), along_y, 1, threads);
}

Plane filter_csf(const Plane& in, const std::vector<CsfTerm>& terms, int threads) {
  Plane out(in.width, in.height);
  for (const CsfTerm& t : terms) {
    const Plane part = filter_separable(in, t.g, t.g, threads);
    for (std::size_t i = 0; i < out.v.size(); ++i) out.v[i] += t.weight * part.v[i];
  }
  return out;
}

Features detect_features(const Plane& luminance, const Kernels& k, int threads) {
  const Plane rows_edge = pass(luminance, k.edge, 0, threads);
  const Plane rows_smooth = pass(luminance, k.smooth, 0, threads);
  const Plane rows_point = pass(luminance, k.point, 0, threads);
  return {norm(pass(rows_edge, k.smooth, 1, threads), pass(rows_smooth, k.edge, 1, threads)),
          norm(pass(rows_point, k.smooth, 1, threads), pass(rows_smooth, k.point, 1, threads))};
}

} // namespace probebake::bake::flip
