// The fixed-point iteration of the lighting stage: Jacobi sweeps over the hit cache, the convergence
// test and the optional geometric-series extrapolation (docs/LIGHTING.md, "Convergence").
#pragma once

#include <deque>
#include <vector>

#include "hit_cache.h"

namespace probebake::lighting::detail {

// SH of every probe slot of the volume (gpu::PROBE_SH_FLOATS per probe index; free probes stay 0), in double so that the
// changes between sweeps, and the rate estimated from them, are not quantised by float rounding.
using ShBuffer = std::vector<double>;

// next <- F(prev) for every cached probe: each probe's rays re-shaded with `prev` and projected.
void sweep(const HitCache& cache, const ShBuffer& prev, ShBuffer& next, int threads);

struct SweepChange {
  float relative = 0.0f; // max over probes and channels of |dDC| / max(|DC|, 1e-6 * max |DC|)
  double absolute = 0.0; // sum of |dDC| over probes and channels: its ratios estimate the contraction rate
};
SweepChange measure_change(const HitCache& cache, const ShBuffer& prev, const ShBuffer& next);

// Throws Error(input) naming the probe when a coefficient is Inf or NaN.
void check_finite(const HitCache& cache, const ShBuffer& sh, int sweep_number);

// current += (current - previous) * factor for every cached probe.
void extrapolate(const HitCache& cache, ShBuffer& current, const ShBuffer& previous, double factor);

// Decides convergence and extrapolation from the sequence of sweep changes.
//  - rate: the ratio of successive absolute changes (power-method estimate of the dominant eigenvalue
//    of the linear map, in the L1 norm), max of the last 3 since the last extrapolation; after an extrapolation, the
//    rate it used, unless later sweeps show a larger one below 1.
//  - converged: change == 0, or rate < 1 and both change and change * rate / (1 - rate) < tolerance.
//  - extrapolate (when enabled): 3 ratios since the last extrapolation within 5% of (1 - rate) of each
//    other, 0.5 <= rate <= 0.9999; factor rate / (1 - rate) removes the dominant error mode.
//  - keep an extrapolation only when the sweep after it changes less than the plain sweep before it. Steady
//    ratios do not prove one dominant mode: an eigenvalue -rate (a probe pair lighting each other through
//    a clamped SH lobe) gives the same ratios, and the step multiplies that mode by 1 + 2 * factor. A
//    rejected step is undone and acceleration stops for the rest of the solve.
class Convergence {
public:
  Convergence(float tolerance, bool accelerate) : tolerance_(tolerance), accelerate_(accelerate) {}
  // Records a plain sweep's change; returns whether the iteration has converged.
  bool add(const SweepChange& change);
  // The extrapolation factor to apply now (0: none). Resets the ratio history when non-zero.
  double extrapolation_factor();
  // Judges the first sweep after an extrapolation: true keeps the step (then add() the change as usual);
  // false means undo it, and turns acceleration off.
  bool keep_extrapolation(const SweepChange& after);
  float rate() const;
  float estimated_error() const;
  float change() const { return last_.relative; }

private:
  float tolerance_;
  bool accelerate_;
  SweepChange last_;
  std::deque<double> changes_; // absolute changes since the last extrapolation, at most 4
  double change_before_extrapolation_ = 0.0;
  float extrapolated_rate_ = 0.0f;
};

// Sweeps `sh` (the starting iterate; zero for a bake) until `convergence` says so or settings.max_iterations
// ran, extrapolating when settings.accelerate and the rates allow it. `sh` ends with the last plain iterate
// or an extrapolated one kept; fills the iteration fields of `report`.
void solve(const HitCache& cache, const LightingSettings& settings, ShBuffer& sh, LightingReport& report);

// The probes' Monte Carlo noise with the lighting `sh`: per probe, the standard error of the mean radiance of
// its rays (RGB mean) over that mean, as if the rays were independent; the median and 95th percentile over
// the probes whose mean is > 0. Fills report.noise_median and report.noise_p95.
void measure_noise(const HitCache& cache, const ShBuffer& sh, LightingReport& report);

} // namespace probebake::lighting::detail
