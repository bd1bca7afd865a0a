// Set 1 of the light update kernels (light_bindings.glsl): the pass's own buffers. The volume set
// (probebake/bindings.h) holds what the file gives them.
#ifndef PROBEBAKE_LIGHT_UPDATE_BINDINGS_H
#define PROBEBAKE_LIGHT_UPDATE_BINDINGS_H

#include "probebake/bindings.h"

PB_GPU_BEGIN

// The light records are split into pages of whole probes, each within maxStorageBufferRange (unused pages
// repeat page 0; LightPush.probes_per_page).
PB_CONSTANT(uint, LIGHT_BINDING_RECORDS, 0u); // page 0; pages 1-3 at 1-3
PB_CONSTANT(uint, LIGHT_RECORD_PAGES, 4u);
PB_CONSTANT(uint, LIGHT_BINDING_NEXT_IRRADIANCE, 4u); // float[PROBE_SH_FLOATS] per record slot
PB_CONSTANT(uint, LIGHT_BINDING_COUNTERS, 5u);
PB_CONSTANT(uint, LIGHT_BINDING_TRACE_FLAGS, 6u);      // uint per probe slot: TRACE_FLAG_* (runtime_types.h)
PB_CONSTANT(uint, LIGHT_BINDING_LIGHT_LIST, 7u);       // LightListHeader + int per listed probe (runtime_types.h)
PB_CONSTANT(uint, LIGHT_BINDING_RELIGHT_CHANGES, 8u);  // RelightChanges (runtime_types.h)
PB_CONSTANT(uint, LIGHT_BINDING_TRACKED_PUNCTUAL, 9u); // float[3] per record (RelightChanges.track_after)
// Streaming: int per probe slot, the slot of its records in the record pages, -1 for a probe that has none
// (not lit), RECORD_SLOT_UNRESOLVED (bindings.h) marked; read only when LightPush.indirect_records is set
// (otherwise a probe's records are its slot's).
PB_CONSTANT(uint, LIGHT_BINDING_RECORD_SLOTS, 10u);
// UploadOptions::load_focus: int[2 * probe capacity], the slots nearest the focus first, then each slot's rank
// in that order; read only when LightPush.load_ordered is set.
PB_CONSTANT(uint, LIGHT_BINDING_LOAD_ORDER, 11u);
PB_CONSTANT(uint, LIGHT_BINDING_COUNT, 12u);

PB_GPU_END
#endif // PROBEBAKE_LIGHT_UPDATE_BINDINGS_H
