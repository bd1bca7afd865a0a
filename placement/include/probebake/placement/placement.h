// Probe placement methods. A method is a function (PlacementInput, tree, bounds) -> placed probes, in its
// own folder placement/methods/<name>/, named by its row of formats/placement_methods.def; it fills the
// ProbeVolume behind `tree` through formats::Octree. The bake picks the method from formats::PlacementKind
// with placement_method().
#pragma once

#include <functional>
#include <vector>

#include "probebake/lighting/lighting.h"
#include "probebake/formats/octree.h"
#include "probebake/formats/placement_kind.h"
#include "probebake/placement/probe_tracing.h"
#include "probebake/scene/ray_scene.h"

namespace probebake::placement {

// The bake settings that placement reads (the bake copies them from BakeSettings).
struct PlacementSettings {
  int max_depth = 4;        // octree: deepest level a node may split to (root = 0)
  float split_low = 0.25f;  // octree: hit fraction below which a probe is freed
  float split_high = 0.5f;  // octree: hit fraction at or above which a node splits
  int grid_resolution = 16; // grid: N for N^3 probes
  int threads = 0;          // 0 = all cores
  int probes = 0;           // skeleton: probe budget (0 = the fewest that see every surface sample)
};

// The octree under a probe budget (refine_octree.h) instead of the hit-fraction rule, when probe_budget > 0:
// ranked by estimated interpolation error (rank_by_error: the bake's SplitRule::error) or by visible
// surface per probe (SplitRule::surface).
struct RefineSettings {
  int probe_budget = 0;
  bool rank_by_error = true;
  float uniform_share = 0.5f;          // share of the budget a uniform start may take
  lighting::LightingSettings lighting; // the estimate's light model (sky, emitters as lights)
};

struct PlacementInput {
  const scene::RayScene* rays = nullptr;
  PlacementSettings settings;
  RefineSettings refine;
  std::vector<glm::vec3> directions;             // the lattice
  float clearance = 0.0f;                        // the bake's effective clearance (a centre nearer a surface is moved)
  std::function<void(double fraction)> progress; // may be empty; called from the calling thread
};

// A placed probe and the cube it must stay in (its octree node, or its grid cell).
struct PlacedProbe {
  int probe = 0;
  Cube cube;
  ProbeRays rays;
};

// `bounds`: the scene's bounds (the octree starts from the root cube in tree.volume().info instead).
using PlacementMethod = std::vector<PlacedProbe> (*)(const PlacementInput& in, formats::Octree& tree,
                                                     const scene::Bounds& bounds);

// Every method's function, declared from its row of formats/placement_methods.def and defined and
// documented in its folder, placement/methods/<name>/ (octree: octree.cpp and refine_octree.h; grid: grid.cpp;
// skeleton: skeleton.h).
#define PROBEBAKE_PLACEMENT(name, code, function, ...)                                                                 \
  std::vector<PlacedProbe> function(const PlacementInput& in, formats::Octree& tree, const scene::Bounds& bounds);
#include "probebake/formats/placement_methods.def"

// The method of `kind` (methods.cpp), and a call of it.
PlacementMethod placement_method(formats::PlacementKind kind);
std::vector<PlacedProbe> place(formats::PlacementKind kind, const PlacementInput& in, formats::Octree& tree,
                               const scene::Bounds& bounds);

} // namespace probebake::placement
