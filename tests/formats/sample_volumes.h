// Small deterministic probe volumes for the formats tests and the golden files. Every value is an
// exact binary fraction or the result of basic float operations, so the bytes are the same on every
// IEEE-754 platform and compiler.
#pragma once

#include "probebake/formats/probe_volume.h"

namespace probebake::formats::testing {

enum class Sample {
  small,        // depth-2 octree, probes, surfel batches, leaf buffer, probe index, SVO, cells of depth 1
  static_set,   // the same without surfel batches and without a leaf buffer (static scene)
  grid,         // 2x2x2 grid placement: root-only octree, probes with node -1, SVO, cells of depth 1
  lighting,     // static_set plus the runtime lighting sections of format 1.1 (BVH of 6 triangles, 3 lights,
                // 2 emitter patches, 6 + 32 ray directions)
  double_sided, // lighting with format 1.2's flags: the wall and the emissive ceiling (and its patches)
                // double-sided
  dynamic,      // lighting plus format 1.3's dynamic_objects: a two-triangle card with its own one-leaf BVH,
                // moved by its rest pose (a translation)
  compact,      // dynamic with the double-sided flags, its tracing in format 1.4's compact sections
                // (formats::upgrade_tracing): two trees, shared vertices, a material table
  cells,        // compact with its static tree split by streaming cell (format 1.5 cell_tracing: one leaf per
                // cell of depth 1 under a top level) and so a checksum per cell (1.6 cell_checksums)
  grid_lattice, // grid with format 1.8's grid_lattice: probe i at point i, each point serving its one cell
  sky,          // lighting with format 1.9's sky: a 4 x 2 physical sky map whose sun is no light (-1)
  emitters,     // lighting with format 1.10's emitter groups: each patch its own emitter (materials 3 and 5)
};

// Every sample, for tests that loop over them.
inline constexpr Sample kAllSamples[] = {Sample::small,        Sample::static_set, Sample::grid,    Sample::lighting,
                                         Sample::double_sided, Sample::dynamic,    Sample::compact, Sample::cells,
                                         Sample::grid_lattice, Sample::sky,        Sample::emitters};

ProbeVolume make_sample(Sample sample);

// "small", "static", "grid", "lighting", "double_sided" (test parameter names).
const char* sample_name(Sample sample);

// Golden file name under tests/data/golden for a sample ("v1_0_small.probes", ..., "v1_2_double_sided.probes").
const char* golden_name(Sample sample);

} // namespace probebake::formats::testing
