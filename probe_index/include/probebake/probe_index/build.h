// The SVO probe index of the non-uniform placement paper (§4.1): a sparse octree over the root cube
// whose leaf voxels store up to four probes visible from the voxel, with weights; interior nodes carry
// no payload; voxels inside solid geometry are left out (empty).
#pragma once

#include <span>

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

// Fills volume.grid_lattice (format 1.8; the grid engine's lookup, grid_lookup.h) for a grid whose lattice
// point i (x fastest) holds probe lattice_probes[i] (-1 or a freed probe: none). A probe serves a cell
// around its point when it sees one of the cell's nine sample points (centre and octant centres) that lie
// in open space. Needs the final probe positions; 2 <= frame.resolution <= GRID_MAX_RESOLUTION.
void build_grid_lattice(const scene::RayScene& rays, formats::ProbeVolume& volume, const gpu::GridLatticeHeader& frame,
                        std::span<const int> lattice_probes, int threads);

} // namespace probebake::probe_index
