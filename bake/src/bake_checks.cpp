// What the bake refuses before any work: settings out of range (usage errors) and scenes it cannot resolve
// in 32-bit floats (input errors).
#include "bake_checks.h"

#include <cmath>

#include <fmt/core.h>
#include <glm/geometric.hpp>

#include "probebake/formats/cells.h"
#include "probebake/formats/error.h"
#include "probebake/formats/octree.h"
#include "probebake/formats/validate.h"

namespace probebake::bake {
namespace {

void require(bool ok, const std::string& message) {
  if (!ok) throw Error(ErrorKind::usage, message);
}

// --probes: far above what the optimisation can afford (docs/results/placement.md).
constexpr int kMaxProbeBudget = 1 << 20;
// Measured (docs/results/bake-scale.md, "Scale range (issue #11)"): the generated Cornell box bakes the same
// probes from 1e-5 to 1e10 times its size and 1e4 of its size from the origin; beyond that 32-bit positions,
// Embree's ray epsilons and the SDF lose it. The limits keep a factor of ten from where it breaks.
constexpr float kMinSceneSize = 1e-4f;    // metres across (0.1 mm)
constexpr float kMaxSceneSize = 1e8f;     // metres across (100,000 km)
constexpr float kMaxOffsetPerSize = 1e4f; // distance of the bounds from the origin / size across

} // namespace

namespace detail {

void bake_fail(const std::string& reason) { throw Error(ErrorKind::input, "bake: " + reason); }

void check_scene(const scene::Scene& scene) {
  bool any_area = false;
  for (std::size_t t = 0; t < scene.triangles.size() && !any_area; ++t)
    any_area = scene::triangle_normal(scene, t) != glm::vec3(0.0f);
  if (!any_area)
    bake_fail("no triangle has a non-zero area (degenerate geometry): there is nothing to place probes around");
  const float size = scene.bounds.largest_extent();
  if (size < kMinSceneSize)
    bake_fail(fmt::format("the scene is {:.3g} m across, below the {:.0e} m the bake resolves in 32-bit floats; scale "
                          "it up (a glTF node scale)",
                          size, kMinSceneSize));
  if (size > kMaxSceneSize)
    bake_fail(fmt::format("the scene is {:.3g} m across, above the {:.0e} m the bake resolves in 32-bit floats; scale "
                          "it down (a glTF node scale)",
                          size, kMaxSceneSize));
  const float offset = std::max(glm::length(scene.bounds.min), glm::length(scene.bounds.max));
  if (offset > kMaxOffsetPerSize * size)
    bake_fail(fmt::format("the scene is {:.3g} m across but {:.3g} m from the origin: 32-bit positions cannot resolve "
                          "it there; move it nearer the origin (a glTF node translation)",
                          size, offset));
}

// No probe can be farther than half the scene's size from every surface; a larger clearance would also
// make the SDF band (1.5 x clearance) cover the scene many times over.
void check_clearance(const scene::Scene& scene, const BakeSettings& s) {
  const float half_size = 0.5f * scene.bounds.largest_extent();
  require(s.clearance <= half_size, fmt::format("--clearance {:.3g} m is more than half the scene's size ({:.3g} m)",
                                                s.clearance, 2.0f * half_size));
}

} // namespace detail

void check_settings(const BakeSettings& s) {
  require(s.max_depth >= 0 && s.max_depth <= gpu::OCTREE_MAX_DEPTH,
          fmt::format("--max-depth must be in [0, {}]", gpu::OCTREE_MAX_DEPTH));
  require(s.surfels_per_probe >= 1 && s.surfels_per_probe <= formats::kMaxSurfelsPerProbe,
          fmt::format("--surfels must be in [1, {}]", formats::kMaxSurfelsPerProbe)); // what the validator accepts
  require(std::isfinite(s.split_low) && std::isfinite(s.split_high) && s.split_low >= 0.0f &&
              s.split_low <= s.split_high && s.split_high <= 1.0f,
          "--split-range LOW,HIGH needs 0 <= LOW <= HIGH <= 1");
  // The octree meets a budget only with the error and surface rules; the skeleton takes one or picks the fewest
  // probes that see every surface sample; the grid's count is its resolution.
  const bool octree = s.placement == Placement::octree;
  const bool budgeted = octree && s.split_rule != SplitRule::hit_fraction;
  require(!budgeted || s.probe_budget >= 1, "--split-rule error|surface needs a probe budget: --probes N with N >= 1");
  require(budgeted || s.placement == Placement::skeleton || s.probe_budget == 0,
          "--probes N needs --placement skeleton, or the octree with --split-rule error or surface");
  require(std::isfinite(s.uniform_share) && s.uniform_share >= 0.0f && s.uniform_share <= 1.0f,
          "--uniform-share must be in [0, 1]");
  require(s.grid_resolution >= 1 && s.grid_resolution <= formats::kMaxGridResolution,
          fmt::format("--grid must be in [1, {}]", formats::kMaxGridResolution));
  require(s.svo_depth >= 0 && s.svo_depth <= 8, "--svo-depth must be in [0, 8]");
  require(std::isfinite(s.clearance) && s.clearance >= 0.0f, "--clearance must be a finite distance >= 0");
  require(s.threads >= 0, "--threads must be >= 0");
  require(s.probe_budget >= 0 && s.probe_budget <= kMaxProbeBudget,
          fmt::format("--probes must be in [0, {}]", kMaxProbeBudget));
  require(s.cell_depth >= 0 && s.cell_depth <= formats::kMaxCellDepth,
          fmt::format("cell depth must be in [0, {}]", formats::kMaxCellDepth));
  require(std::isfinite(s.cell_size) && s.cell_size >= 0.0f, "--cell-size must be a finite width >= 0");
  require(std::isfinite(s.trace_leaf_cost) && s.trace_leaf_cost >= 0.05f && s.trace_leaf_cost <= 10.0f,
          "--trace-leaf-cost must be in [0.05, 10]");
  lighting::check_lighting_settings(s.lighting);
}

} // namespace probebake::bake
