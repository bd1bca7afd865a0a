#include "light_update/trace_budget.h"

#include <algorithm>
#include <cmath>
#include <string_view>

namespace probebake::runtime::detail {
namespace {

// Each measurement moves the estimates halfway: quick to follow a change of scene or clock, while one noisy
// frame moves the window by at most half.
constexpr double kCorrection = 0.5;

} // namespace

std::uint32_t TraceBudget::next_window(float frame_ms, std::uint32_t untraced) const {
  if (untraced == 0) return 0;
  if (trace_ms_per_slot_ <= 0.0) return std::min(kFirstWindow, untraced);
  const double spare = double(frame_ms) - other_ms_;
  const double slots = std::floor(spare / (trace_ms_per_slot_ + gather_ms_per_slot_));
  if (!(slots >= 1.0)) return 1; // over budget already, or NaN: one slot keeps the load going
  return std::uint32_t(std::min(slots, double(untraced)));
}

void TraceBudget::observe(const FrameStats& stats) {
  if (stats.light.load_window <= 0) return;
  double trace_ms = -1.0, gather_ms = 0.0, other_ms = 0.0;
  for (const PassTime& pass : stats.passes) {
    if (pass.gpu_ms < 0.0) return; // no timestamps: nothing to measure
    const std::string_view name = pass.name;
    if (name == "light_trace") trace_ms = pass.gpu_ms;
    if (name == "light_gather") gather_ms = pass.gpu_ms;
    if (name != "light_trace") other_ms += pass.gpu_ms;
  }
  if (trace_ms < 0.0) return;
  const int traced = stats.probe_capacity - stats.light.untraced_slots; // >= load_window > 0
  const double trace_per_slot = trace_ms / double(stats.light.load_window);
  const double gather_per_slot = traced > 0 ? gather_ms / double(traced) : 0.0;
  const bool first = trace_ms_per_slot_ <= 0.0;
  const auto correct = [first](double& estimate, double measured) {
    estimate = first ? measured : estimate + kCorrection * (measured - estimate);
  };
  correct(trace_ms_per_slot_, trace_per_slot);
  correct(gather_ms_per_slot_, gather_per_slot);
  correct(other_ms_, other_ms);
}

} // namespace probebake::runtime::detail
