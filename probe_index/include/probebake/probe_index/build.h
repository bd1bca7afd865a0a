// The SVO probe index of the non-uniform placement paper (§4.1): a sparse octree over the root cube
// whose leaf voxels store up to four probes visible from the voxel, with weights; interior nodes carry
// no payload; voxels inside solid geometry are left out (empty).
#pragma once

#include "probebake/scene/ray_scene.h"
#include "probebake/formats/probe_volume.h"

namespace probebake::probe_index {

struct SvoStats {
  int voxels_evaluated = 0;
  int solid_voxels = 0;     // left out: inside geometry
  int uncovered_voxels = 0; // no probe visible from the voxel: left empty
};

// Fills volume.svo_nodes / svo_leaves from the probes in volume.probes (which must be final).
SvoStats build_svo(const scene::RayScene& rays, formats::ProbeVolume& volume, int svo_depth, int threads);

} // namespace probebake::probe_index
