// Jacobi sweeps, convergence test and geometric-series extrapolation of the lighting stage.
#include "iteration.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include <fmt/core.h>

#include "probebake/common/parallel.h"
#include "probebake/probe_index/stencil.h"
#include "probebake/formats/error.h"

namespace probebake::lighting::detail {
namespace {

// Radiance a cached ray brings back with the probes' SH `sh`: L = base + reflect * E_indirect.
glm::dvec3 ray_radiance(const HitRecord& h, const ShBuffer& sh) {
  const auto sh_of = [&](int probe) { return sh.data() + gpu::PROBE_SH_FLOATS * std::size_t(probe); };
  return glm::dvec3(h.base) +
         glm::dvec3(h.reflect) * probe_index::detail::apply_stencil<double>(h.stencil, h.normal, sh_of);
}

// Radiance of every ray of cached probe i, projected onto the irradiance SH.
void shade_probe(const HitCache& cache, std::size_t i, const ShBuffer& prev, double* out) {
  const std::size_t r = std::size_t(cache.rays_per_probe);
  const HitRecord* hits = cache.records.data() + i * r;
  double acc[gpu::PROBE_SH_FLOATS] = {};
  for (std::size_t j = 0; j < r; ++j) {
    const glm::dvec3 radiance = ray_radiance(hits[j], prev);
    const std::array<float, 9>& y = cache.projection[j];
    for (std::size_t k = 0; k < 9; ++k)
      for (int c = 0; c < 3; ++c) acc[3 * k + std::size_t(c)] += radiance[c] * double(y[k]);
  }
  for (int v = 0; v < gpu::PROBE_SH_FLOATS; ++v) out[v] = acc[v];
}

// Max of the last three ratios of absolute changes; -1 when fewer than three are known.
float recent_rate(const std::deque<double>& changes) {
  if (changes.size() < 4) return -1.0f;
  double rate = 0.0;
  for (std::size_t i = 1; i < changes.size(); ++i)
    rate = std::max(rate, changes[i - 1] > 0.0 ? changes[i] / changes[i - 1] : (changes[i] > 0.0 ? 2.0 : 0.0));
  return float(rate);
}

} // namespace

void measure_noise(const HitCache& cache, const ShBuffer& sh, LightingReport& report) {
  const std::size_t r = std::size_t(cache.rays_per_probe);
  std::vector<double> noise;
  for (std::size_t i = 0; i < cache.probes.size() && r > 1; ++i) {
    double sum = 0.0, sum_squares = 0.0;
    for (std::size_t j = 0; j < r; ++j) {
      const glm::dvec3 radiance = ray_radiance(cache.records[i * r + j], sh);
      const double l = (radiance.x + radiance.y + radiance.z) / 3.0;
      sum += l;
      sum_squares += l * l;
    }
    const double mean = sum / double(r);
    const double variance = std::max(0.0, (sum_squares - double(r) * mean * mean) / double(r - 1));
    if (mean > 0.0) noise.push_back(std::sqrt(variance / double(r)) / mean);
  }
  if (noise.empty()) return;
  std::sort(noise.begin(), noise.end());
  report.noise_median = float(noise[noise.size() / 2]);
  report.noise_p95 = float(noise[std::min(noise.size() - 1, noise.size() * 95 / 100)]);
}

void sweep(const HitCache& cache, const ShBuffer& prev, ShBuffer& next, int threads) {
  parallel_for(cache.probes.size(), threads, [&](std::size_t i) {
    shade_probe(cache, i, prev, next.data() + gpu::PROBE_SH_FLOATS * std::size_t(cache.probes[i]));
  });
}

SweepChange measure_change(const HitCache& cache, const ShBuffer& prev, const ShBuffer& next) {
  double largest = 0.0;
  for (int p : cache.probes)
    for (int c = 0; c < 3; ++c)
      largest = std::max(largest, std::abs(next[gpu::PROBE_SH_FLOATS * std::size_t(p) + std::size_t(c)]));
  const double floor = std::max(1e-6 * largest, double(FLT_MIN));
  double relative = 0.0;
  SweepChange change;
  for (int p : cache.probes)
    for (int c = 0; c < 3; ++c) {
      const std::size_t v = gpu::PROBE_SH_FLOATS * std::size_t(p) + std::size_t(c);
      const double delta = std::abs(next[v] - prev[v]);
      relative = std::max(relative, delta / std::max(std::abs(next[v]), floor));
      change.absolute += delta;
    }
  change.relative = float(relative);
  return change;
}

void check_finite(const HitCache& cache, const ShBuffer& sh, int sweep_number) {
  for (int p : cache.probes)
    for (int v = 0; v < gpu::PROBE_SH_FLOATS; ++v)
      if (!std::isfinite(
              float(sh[gpu::PROBE_SH_FLOATS * std::size_t(p) + std::size_t(v)]))) // must fit the file's floats
        throw Error(ErrorKind::input,
                    fmt::format("lighting: probe {}: irradiance is not finite after sweep {} (emission "
                                "or light intensity beyond 32-bit float range?)",
                                p, sweep_number));
}

void extrapolate(const HitCache& cache, ShBuffer& current, const ShBuffer& previous, double factor) {
  for (int p : cache.probes)
    for (int v = 0; v < gpu::PROBE_SH_FLOATS; ++v) {
      const std::size_t i = gpu::PROBE_SH_FLOATS * std::size_t(p) + std::size_t(v);
      current[i] += (current[i] - previous[i]) * factor;
    }
}

bool Convergence::add(const SweepChange& change) {
  last_ = change;
  changes_.push_back(change.absolute);
  if (changes_.size() > 4) changes_.pop_front();
  if (change.relative == 0.0f) return true;
  const float r = rate();
  return r >= 0.0f && r < 1.0f && change.relative < tolerance_ && estimated_error() < tolerance_;
}

float Convergence::rate() const {
  const float recent = recent_rate(changes_);
  if (extrapolated_rate_ <= 0.0f) return recent;
  return recent >= 0.0f && recent < 1.0f ? std::max(extrapolated_rate_, recent) : extrapolated_rate_;
}

float Convergence::estimated_error() const {
  const float r = rate();
  return r >= 0.0f && r < 1.0f ? last_.relative * r / (1.0f - r) : -1.0f;
}

double Convergence::extrapolation_factor() {
  if (!accelerate_ || changes_.size() < 4) return 0.0;
  double lo = 2.0, hi = 0.0;
  for (std::size_t i = 1; i < changes_.size(); ++i) {
    if (!(changes_[i - 1] > 0.0)) return 0.0;
    const double ratio = changes_[i] / changes_[i - 1];
    lo = std::min(lo, ratio);
    hi = std::max(hi, ratio);
  }
  const double rate = changes_.back() / changes_[changes_.size() - 2];
  if (!(rate >= 0.5 && rate <= 0.9999) || hi - lo > 0.05 * (1.0 - rate)) return 0.0;
  extrapolated_rate_ = float(rate);
  change_before_extrapolation_ = changes_.back();
  changes_.clear();
  return rate / (1.0 - rate);
}

bool Convergence::keep_extrapolation(const SweepChange& after) {
  if (after.absolute < change_before_extrapolation_) return true;
  accelerate_ = false;
  extrapolated_rate_ = 0.0f;
  changes_.clear();
  return false;
}

void solve(const HitCache& cache, const LightingSettings& settings, ShBuffer& sh, LightingReport& report) {
  ShBuffer previous(sh.size(), 0.0), before_extrapolation;
  Convergence convergence(settings.tolerance, settings.accelerate);
  for (int number = 1; number <= settings.max_iterations; ++number) {
    sweep(cache, sh, previous, settings.threads);
    check_finite(cache, previous, number);
    const SweepChange change = measure_change(cache, sh, previous);
    std::swap(sh, previous); // sh = the new iterate, previous = the one it came from
    report.iterations = number;
    if (!before_extrapolation.empty()) {
      const bool keep = convergence.keep_extrapolation(change);
      if (!keep) {
        sh.swap(before_extrapolation); // back to the plain iterate; this sweep is discarded
        --report.extrapolations;
        ++report.rejected_extrapolations;
      }
      ShBuffer().swap(before_extrapolation);
      if (!keep) continue;
    }
    report.converged = convergence.add(change);
    if (report.converged) break;
    if (number == settings.max_iterations) break; // an extrapolation is only kept after a sweep judged it
    if (const double factor = convergence.extrapolation_factor(); factor > 0.0) {
      before_extrapolation = sh;
      extrapolate(cache, sh, previous, factor);
      check_finite(cache, sh, number);
      ++report.extrapolations;
    }
  }
  report.change = convergence.change();
  report.rate = std::max(convergence.rate(), 0.0f);
  report.estimated_error = convergence.estimated_error();
}

} // namespace probebake::lighting::detail
