// The one list of a ProbeVolume's sections: which member holds which SectionType, in type order. The
// writer and reader (probes_file.cpp), the runtime's GPU buffers (runtime/core/gpu_volume.cpp) and the bake's
// report of section sizes all walk it, so a new section is added here and nowhere else.
#pragma once

#include "probebake/formats/container.h"
#include "probebake/formats/probe_volume.h"

namespace probebake::formats {

// Calls f(type, member) for every section of `v` (const or not) in SectionType order: `member` is the
// struct of a singleton section (volume_info, leaf_queue_header), the std::optional of lighting_info, or
// the std::vector of an array section. The leaf header is a section only when leaf_entries is not empty
// (docs/FORMAT.md) and cells are CPU-side data of the file; callers decide what to do with both.
template <class Volume, class F>
void for_each_section(Volume& v, F&& f) {
  f(SectionType::volume_info, v.info);
  f(SectionType::octree, v.octree);
  f(SectionType::probes, v.probes);
  f(SectionType::surfel_batches, v.surfel_batches);
  f(SectionType::leaf_queue_header, v.leaf_header);
  f(SectionType::leaf_entries, v.leaf_entries);
  f(SectionType::probe_index, v.probe_index);
  f(SectionType::svo_nodes, v.svo_nodes);
  f(SectionType::svo_leaves, v.svo_leaves);
  f(SectionType::cells, v.cells);
  f(SectionType::lighting_info, v.lighting);
  f(SectionType::ray_directions, v.ray_directions);
  f(SectionType::bvh_nodes, v.bvh_nodes);
  f(SectionType::trace_triangles, v.trace_triangles);
  f(SectionType::punctual_lights, v.punctual_lights);
  f(SectionType::emitter_patches, v.emitter_patches);
  f(SectionType::dynamic_objects, v.dynamic_objects);
  f(SectionType::trace_trees, v.trace_trees);
  f(SectionType::trace_nodes, v.trace_nodes);
  f(SectionType::trace_faces, v.trace_faces);
  f(SectionType::trace_vertices, v.trace_vertices);
  f(SectionType::trace_materials, v.trace_materials);
  f(SectionType::cell_tracing, v.cell_tracing);
  f(SectionType::cell_checksums, v.cell_checksums);
  f(SectionType::cell_global_checksums, v.cell_global_checksums);
  f(SectionType::grid_lattice, v.grid_lattice);
  f(SectionType::sky, v.sky);
  static_assert(kSectionTypeCount == 27, "a new section type: add it above");
}

} // namespace probebake::formats
