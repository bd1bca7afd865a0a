// The sweeps of `probebake eval` and the validation of its settings.
#include <string>
#include <utility>

#include <fmt/core.h>

#include "probebake/eval/eval.h"
#include "probebake/formats/error.h"

namespace probebake::bake {
namespace {

// A row of a sweep: `placement` with the default settings, named `label`.
EvalConfig config(Placement placement, std::string label) {
  EvalConfig c;
  c.bake.placement = placement;
  c.label = std::move(label);
  return c;
}

EvalConfig octree(int depth, int surfels = 128, Lattice lattice = Lattice::fibonacci) {
  EvalConfig c = config(Placement::octree, fmt::format("octree-d{}", depth));
  c.bake.max_depth = depth;
  c.bake.surfels_per_probe = surfels;
  c.bake.lattice = lattice;
  if (surfels != 128) c.label += fmt::format("-s{}", surfels);
  if (lattice != Lattice::fibonacci) c.label += fmt::format("-{}", lattice_name(lattice));
  return c;
}

EvalConfig grid(int n) {
  EvalConfig c = config(Placement::grid, fmt::format("grid-{}", n));
  c.bake.grid_resolution = n;
  return c;
}

// Skeleton placement with a budget of n probes; the budgets match the octree and grid rows' counts
// (octree-d2 29, d3 69, d4 139; grid-5 124, grid-8 498) and the 92 (1 % of grid-21).
EvalConfig skeleton(int n) {
  EvalConfig c = config(Placement::skeleton, fmt::format("skeleton-p{}", n));
  c.bake.probe_budget = n;
  return c;
}

void check_ladder(const EvalSettings& s) {
  if (s.probe_ladder.empty()) return;
  if (!s.configs.empty()) throw Error(ErrorKind::usage, "--probes replaces the sweep: it cannot be combined with one");
  if (s.probe_ladder.size() > kMaxLadderRungs)
    throw Error(ErrorKind::usage,
                fmt::format("--probes takes at most {} rungs (got {})", kMaxLadderRungs, s.probe_ladder.size()));
  for (std::size_t i = 0; i < s.probe_ladder.size(); ++i) {
    const int n = s.probe_ladder[i];
    if (n < 1 || n > kMaxLadderProbes)
      throw Error(ErrorKind::usage, fmt::format("--probes: {} is not in 1..{}", n, kMaxLadderProbes));
    if (i > 0 && n <= s.probe_ladder[i - 1])
      throw Error(ErrorKind::usage, fmt::format("--probes must increase ({} after {})", n, s.probe_ladder[i - 1]));
  }
  check_settings(s.ladder_base);
}

} // namespace

std::vector<EvalConfig> default_sweep() {
  return {octree(2),
          octree(3),
          octree(4),
          octree(5),
          grid(5),
          grid(8),
          grid(12),
          grid(16),
          grid(21),
          skeleton(29),
          skeleton(64),
          skeleton(92),
          skeleton(124),
          skeleton(498),
          octree(4, 64),
          octree(4, 256),
          octree(4, 128, Lattice::latlong),
          octree(4, 128, Lattice::equal_area)};
}

BakeSettings quick_bake_settings() {
  BakeSettings s;
  s.surfels_per_probe = 64;
  s.svo_depth = 4;
  s.lighting.rays = 64;
  return s;
}

std::vector<EvalConfig> quick_sweep() {
  std::vector<EvalConfig> sweep = {octree(2, 64), octree(3, 64), grid(4)};
  for (EvalConfig& c : sweep) {
    c.bake.svo_depth = quick_bake_settings().svo_depth;
    c.bake.lighting.rays = quick_bake_settings().lighting.rays;
  }
  return sweep;
}

void check_eval_settings(const EvalSettings& s) {
  auto require = [](bool ok, const std::string& message) {
    if (!ok) throw Error(ErrorKind::usage, message);
  };
  require(s.points >= 1 && s.points <= 10'000'000, fmt::format("--points must be in 1..10000000 (got {})", s.points));
  require(s.paths >= 2, fmt::format("--samples must be at least 2 (got {})", s.paths));
  require(s.threads >= 0, "--threads must be >= 0");
  require(s.image_paths >= 2, "--image-samples must be at least 2");
  require(s.error_map_dir.empty() || s.camera.has_value(), "--error-map needs --camera and --look-at");
  require(parse_receiver_mode(receiver_mode_name(s.receivers)) == s.receivers,
          "--receivers must be visible, volume or area");
  if (s.camera) check_camera(*s.camera);
  for (const EvalConfig& c : s.configs) check_settings(c.bake);
  check_ladder(s);
}

} // namespace probebake::bake
