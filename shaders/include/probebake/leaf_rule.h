// The leaf rule of the adaptive octree: what a measured leaf (or a parent judged for merging) becomes, from
// its centre's placement-lattice measure. One definition shared by C++ (dynamic::TreeUpdate, the bake's
// placement) and GLSL (light_resolve.comp, the GPU memory update), like gpu_types.h.
//
// The rule (the bake's placement, docs/ARCHITECTURE.md): a centre that sees too little (f < split_low) or
// mostly back faces (b > dead_backface_fraction: it lies inside a solid) is blind: it cannot judge its cube.
// A blind centre refines towards geometry it does see inside its cube (f > 0) while below max depth, and
// is freed otherwise (the thesis frees every f < split_low, so a probe that lands inside an object would
// free the very cube the object fills). A centre that sees well splits at f >= split_high below max depth
// and keeps its probe otherwise.
#ifndef PROBEBAKE_LEAF_RULE_H
#define PROBEBAKE_LEAF_RULE_H

#include "probebake/gpu_types.h"

PB_GPU_BEGIN

PB_CONSTANT(int, LEAF_VERDICT_FREE, 0);  // free the probe (M2); the leaf stays without one
PB_CONSTANT(int, LEAF_VERDICT_SPLIT, 1); // split the node (M3)
PB_CONSTANT(int, LEAF_VERDICT_KEEP, 2);  // keep the probe and light it (L2)
// Default back-face fraction above which a centre counts as inside a solid (the bake's value).
PB_CONSTANT(float, LEAF_DEAD_BACKFACE_FRACTION, 0.5f);

// Whether a centre with hit fraction f and back-face fraction b cannot judge its cube.
PB_FUNCTION bool leaf_centre_blind(float hit_fraction, float backface_fraction, float split_low,
                                   float dead_backface_fraction) {
  return hit_fraction < split_low || backface_fraction > dead_backface_fraction;
}

// LEAF_VERDICT_* of a node at `depth` (root 0) measured (hit_fraction, blind), with the thresholds split_low,
// split_high and max_depth of `info`. `sees_geometry_in_cube`: the centre saw any geometry inside its cube
// (the runtime passes f > 0; the bake passes whether triangles overlap the cube). `relocates_dead`: a centre
// blind only because it is dead (inside a solid, on a double-sided surface) keeps its probe when it cannot
// refine, because a relocation step moves it out (the bake); without one (the runtime) it is freed.
PB_FUNCTION int leaf_verdict_with(float hit_fraction, bool blind, bool sees_geometry_in_cube, bool relocates_dead,
                                  int depth, VolumeInfo info) {
  const bool below_max = depth < info.max_depth;
  const bool refine_towards_geometry = blind && below_max && sees_geometry_in_cube;
  const bool unrecoverable = hit_fraction < info.split_low || (blind && !relocates_dead);
  if (unrecoverable && !refine_towards_geometry) return LEAF_VERDICT_FREE;
  if ((hit_fraction >= info.split_high && below_max) || refine_towards_geometry) return LEAF_VERDICT_SPLIT;
  return LEAF_VERDICT_KEEP;
}

// The runtime's rule (dynamic::TreeUpdate::judge, the GPU's L1 and M4): geometry in the cube = f > 0.
PB_FUNCTION int leaf_verdict(float hit_fraction, float backface_fraction, int depth, VolumeInfo info,
                             float dead_backface_fraction) {
  const bool blind = leaf_centre_blind(hit_fraction, backface_fraction, info.split_low, dead_backface_fraction);
  return leaf_verdict_with(hit_fraction, blind, hit_fraction > 0.0f, false, depth, info);
}

// Which of two states for the same node in one leaf-queue segment wins (a segment is a set keyed by node):
// M0 (a child is allocating) over M4 (free the children) over the leaf's own M3 > M2 > M1; L0 (parent
// freed) over L1 (measure again) > L2 > L3. 0 for a value that is no LEAF_* state.
PB_FUNCTION int leaf_state_priority(int state) {
  if (state == LEAF_M0_CHILD_ALLOCATING) return 5;
  if (state == LEAF_M4_FREE_CLUSTER || state == LEAF_L0_PARENT_FREED) return 4;
  if (state == LEAF_M3_SPLIT || state == LEAF_L1_PLACE_SURFELS) return 3;
  if (state == LEAF_M2_FREE_PROBE || state == LEAF_L2_LIGHT) return 2;
  if (state == LEAF_M1_ALLOCATE_PROBE || state == LEAF_L3_CHECK_BOXES) return 1;
  return 0;
}

PB_GPU_END

#endif // PROBEBAKE_LEAF_RULE_H
