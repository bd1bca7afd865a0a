// Set 1 of the sampling kernels (sample_irradiance.comp, sample_grid.comp, sample_all_probes.comp): the queries and results of
// one batch, rewritten for each run (sample_pass.cpp).
#ifndef PROBEBAKE_SAMPLE_BINDINGS_H
#define PROBEBAKE_SAMPLE_BINDINGS_H

#include "probebake/bindings.h"

PB_GPU_BEGIN

// sample_irradiance.comp
PB_CONSTANT(uint, SAMPLE_BINDING_QUERIES, 0u);
PB_CONSTANT(uint, SAMPLE_BINDING_RESULTS, 1u);
// Streaming: the light update's record slots (LIGHT_BINDING_RECORD_SLOTS), so that a result can say that
// its probes are not being lit; read only with SamplePush.streaming.
PB_CONSTANT(uint, SAMPLE_BINDING_RECORD_SLOTS, 2u);
// With compact probes (SamplePush.code_bands != 0): the probe code pass's points and codes (probe_codes/).
PB_CONSTANT(uint, SAMPLE_BINDING_PROBE_POINTS, 3u);
PB_CONSTANT(uint, SAMPLE_BINDING_PROBE_CODES, 4u);
PB_CONSTANT(uint, SAMPLE_BINDING_COUNT, 5u);

// sample_grid.comp: the grid engine's lookup on a grid bake's lattice (the volume's grid_lattice section)
PB_CONSTANT(uint, SAMPLE_GRID_BINDING_QUERIES, 0u);
PB_CONSTANT(uint, SAMPLE_GRID_BINDING_RESULTS, 1u);
PB_CONSTANT(uint, SAMPLE_GRID_BINDING_LATTICE, 2u);
PB_CONSTANT(uint, SAMPLE_GRID_BINDING_PROBE_POINTS, 3u);
PB_CONSTANT(uint, SAMPLE_GRID_BINDING_PROBE_CODES, 4u);
PB_CONSTANT(uint, SAMPLE_GRID_BINDING_COUNT, 5u);

// sample_all_probes.comp
PB_CONSTANT(uint, SAMPLE_ALL_BINDING_QUERIES, 0u);
PB_CONSTANT(uint, SAMPLE_ALL_BINDING_RESULTS, 1u);
PB_CONSTANT(uint, SAMPLE_ALL_BINDING_COUNT, 2u);

PB_GPU_END
#endif // PROBEBAKE_SAMPLE_BINDINGS_H
