// The probe ladder of `probebake eval --probes`: every placement method that meets a probe budget, baked
// to about each rung's probe count (eval.h, ladder_sweep).
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <map>
#include <vector>

#include <fmt/core.h>

#include "probebake/eval/eval.h"
#include "probebake/formats/error.h"
#include "probebake/formats/placement_kind.h"

namespace probebake::bake {
namespace {

constexpr int kMaxGridResolution = 256;

// Live probes of a placement-only bake (no lighting, no runtime sections, no SVO: none changes the count).
// A bake that places no probe is refused by bake(); here it is a count of 0.
int live_probes(const scene::Scene& scene, BakeSettings s) {
  s.lighting.enabled = false;
  s.runtime_lighting = false;
  s.svo_depth = 0;
  try {
    return bake(scene, s).report.probes;
  } catch (const Error& e) {
    if (e.kind() == ErrorKind::input) return 0;
    throw;
  }
}

// The parameter in [lo, hi] whose count is nearest `budget`, for counts that grow with the parameter:
// walks one step at a time from `start` until the count crosses the budget, or stops growing (an octree
// whose rule splits no further), and takes the nearest of the parameters it counted (ties: the smaller).
// `count` is memoised by the caller.
int nearest_parameter(int start, int lo, int hi, int budget, const std::function<int(int)>& count) {
  int p = std::clamp(start, lo, hi);
  std::vector<int> seen = {p};
  if (count(p) < budget) {
    while (p < hi && count(p) < budget) {
      seen.push_back(++p);
      if (count(p) <= count(p - 1)) break;
    }
  } else {
    while (p > lo && count(p) >= budget) seen.push_back(--p);
  }
  std::sort(seen.begin(), seen.end());
  int best = seen.front();
  for (int q : seen)
    if (std::abs(count(q) - budget) < std::abs(count(best) - budget)) best = q;
  return best;
}

constexpr int kBudgetedMaxDepth = 6;

// One placement method's configurations, with its counts remembered across rungs.
class MethodLadder {
public:
  MethodLadder(const scene::Scene& scene, const formats::PlacementKindInfo& kind, const BakeSettings& base)
      : scene_(scene), kind_(kind), base_(base) {
    base_.placement = kind.kind;
  }

  EvalConfig rung(int budget) {
    EvalConfig c;
    c.bake = base_;
    c.asked_probes = budget;
    if (kind_.uses_grid_resolution) {
      // N^3 cells: start from the N whose cube is nearest, the walk adds what dead probes take away.
      const int guess = int(std::lround(std::cbrt(double(budget))));
      c.bake.grid_resolution =
          nearest_parameter(guess, 1, kMaxGridResolution, budget, counter(&BakeSettings::grid_resolution));
      c.budget_by = "grid resolution";
      c.label = fmt::format("{}-{}-p{}", kind_.name, c.bake.grid_resolution, budget);
    } else {
      // The octree (error rule, as `--probes` picks in the CLI) and the skeleton take the budget itself; the
      // octree's budgeted refinement needs room below the default depth (docs/results/placement.md, "Error-driven
      // refinement and a probe budget (issue #13, first bullet)", ran it at 6).
      c.bake.probe_budget = budget;
      if (kind_.uses_max_depth) {
        c.bake.split_rule = SplitRule::error;
        c.bake.max_depth = std::max(c.bake.max_depth, kBudgetedMaxDepth);
      }
      c.budget_by = "probe budget";
      c.label = fmt::format("{}-p{}", kind_.name, budget);
    }
    return c;
  }

private:
  std::function<int(int)> counter(int BakeSettings::*parameter) {
    return [this, parameter](int value) {
      const auto found = counts_.find(value);
      if (found != counts_.end()) return found->second;
      BakeSettings s = base_;
      s.*parameter = value;
      return counts_[value] = live_probes(scene_, s);
    };
  }

  const scene::Scene& scene_;
  const formats::PlacementKindInfo& kind_;
  BakeSettings base_;
  std::map<int, int> counts_; // parameter -> live probes
};

bool same_bake(const EvalConfig& a, const EvalConfig& b) {
  return a.bake.placement == b.bake.placement && a.bake.grid_resolution == b.bake.grid_resolution &&
         a.bake.max_depth == b.bake.max_depth && a.bake.probe_budget == b.bake.probe_budget;
}

} // namespace

std::vector<EvalConfig> ladder_sweep(const scene::Scene& scene, std::span<const int> probes, const BakeSettings& base) {
  std::vector<EvalConfig> out;
  for (const formats::PlacementKindInfo& kind : formats::placement_kinds()) {
    if (!kind.meets_probe_budget) continue;
    MethodLadder ladder(scene, kind, base);
    const std::size_t first = out.size();
    for (int budget : probes) {
      EvalConfig c = ladder.rung(budget);
      const bool repeat = std::any_of(out.begin() + std::ptrdiff_t(first), out.end(),
                                      [&](const EvalConfig& o) { return same_bake(o, c); });
      if (!repeat) out.push_back(std::move(c));
    }
  }
  return out;
}

} // namespace probebake::bake
