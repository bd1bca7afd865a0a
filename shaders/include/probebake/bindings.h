// Descriptor binding numbers of every runtime pass: the one definition, shared by C++ (runtime/src/pipelines.h
// and the passes that write the descriptor sets) and GLSL (the shaders' layout(binding = ...)), like
// gpu_types.h. Every pass uses descriptor set 0, storage buffers only, bindings 0 .. *_BINDING_COUNT - 1.
// tests/runtime/layout_test.cpp checks each shader's Binding decorations against these values.
#ifndef PROBEBAKE_BINDINGS_H
#define PROBEBAKE_BINDINGS_H

#ifdef __cplusplus
#include <cstdint>

namespace probebake::gpu {
using uint = std::uint32_t;
#define PB_CONSTANT(type, name, value) inline constexpr type name = value
#else
#define PB_CONSTANT(type, name, value) const type name = value
#endif

// ---- Sampling (sample_irradiance.glsl, sample_irradiance.comp) ------------------------------------------
// 0-3 are the defaults of sample_irradiance.glsl's PROBEBAKE_BINDING_* (what a game binds unless it moves them).
PB_CONSTANT(uint, SAMPLE_BINDING_VOLUME_INFO, 0u);
PB_CONSTANT(uint, SAMPLE_BINDING_PROBES, 1u);
PB_CONSTANT(uint, SAMPLE_BINDING_SVO_NODES, 2u);
PB_CONSTANT(uint, SAMPLE_BINDING_SVO_LEAVES, 3u);
PB_CONSTANT(uint, SAMPLE_BINDING_QUERIES, 4u);
PB_CONSTANT(uint, SAMPLE_BINDING_RESULTS, 5u);
// Streaming: the light update's record slots (LIGHT_BINDING_RECORD_SLOTS), so that a result can say that
// its probes are not being lit; read only with SamplePush.streaming.
PB_CONSTANT(uint, SAMPLE_BINDING_RECORD_SLOTS, 6u);
PB_CONSTANT(uint, SAMPLE_BINDING_COUNT, 7u);

// ---- All-probe baseline sampler (sample_all_probes.comp) --------------------------------------------------
PB_CONSTANT(uint, SAMPLE_ALL_BINDING_VOLUME_INFO, 0u);
PB_CONSTANT(uint, SAMPLE_ALL_BINDING_PROBES, 1u);
PB_CONSTANT(uint, SAMPLE_ALL_BINDING_SVO_NODES, 2u);
PB_CONSTANT(uint, SAMPLE_ALL_BINDING_SVO_LEAVES, 3u);
PB_CONSTANT(uint, SAMPLE_ALL_BINDING_PROBE_INDEX, 4u);
PB_CONSTANT(uint, SAMPLE_ALL_BINDING_LIGHTING_INFO, 5u);
PB_CONSTANT(uint, SAMPLE_ALL_BINDING_TRACE_NODES, 6u);
PB_CONSTANT(uint, SAMPLE_ALL_BINDING_TRACE_FACES, 7u);
PB_CONSTANT(uint, SAMPLE_ALL_BINDING_QUERIES, 8u);
PB_CONSTANT(uint, SAMPLE_ALL_BINDING_RESULTS, 9u);
PB_CONSTANT(uint, SAMPLE_ALL_BINDING_DYNAMIC_OBJECTS, 10u);  // the dynamic_objects section (or the placeholder)
PB_CONSTANT(uint, SAMPLE_ALL_BINDING_OBJECT_INSTANCES, 11u); // ObjectInstance per dynamic object (or the placeholder)
PB_CONSTANT(uint, SAMPLE_ALL_BINDING_TRACE_TREES, 12u);      // the compact tracing sections (format 1.4),
PB_CONSTANT(uint, SAMPLE_ALL_BINDING_TRACE_VERTICES, 13u);   // with TRACE_NODES and TRACE_FACES above
PB_CONSTANT(uint, SAMPLE_ALL_BINDING_TRACE_MATERIALS, 14u);
PB_CONSTANT(uint, SAMPLE_ALL_BINDING_COUNT, 15u);

// ---- Probe index build (probe_index.glsl: probe_index_count, _scan, _scatter) ------------------------------
PB_CONSTANT(uint, PROBE_INDEX_BINDING_PROBES, 0u);
PB_CONSTANT(uint, PROBE_INDEX_BINDING_LIST, 1u);
PB_CONSTANT(uint, PROBE_INDEX_BINDING_BLOCK_SUMS, 2u);
PB_CONSTANT(uint, PROBE_INDEX_BINDING_COUNTERS, 3u);
PB_CONSTANT(uint, PROBE_INDEX_BINDING_COUNT, 4u);

// ---- Light update (light_bindings.glsl: light_trace, light_gather, light_resolve) --------------------------
// 0-3 equal the sampling bindings, so the gather samples the probes through sample_irradiance.glsl's names.
PB_CONSTANT(uint, LIGHT_BINDING_VOLUME_INFO, 0u);
PB_CONSTANT(uint, LIGHT_BINDING_PROBES, 1u);
PB_CONSTANT(uint, LIGHT_BINDING_SVO_NODES, 2u);
PB_CONSTANT(uint, LIGHT_BINDING_SVO_LEAVES, 3u);
PB_CONSTANT(uint, LIGHT_BINDING_OCTREE, 4u);
PB_CONSTANT(uint, LIGHT_BINDING_LIGHTING_INFO, 5u);
PB_CONSTANT(uint, LIGHT_BINDING_RAY_DIRECTIONS, 6u);
PB_CONSTANT(uint, LIGHT_BINDING_TRACE_NODES, 7u);
PB_CONSTANT(uint, LIGHT_BINDING_TRACE_FACES, 8u);
PB_CONSTANT(uint, LIGHT_BINDING_PUNCTUAL_LIGHTS, 9u);
PB_CONSTANT(uint, LIGHT_BINDING_EMITTER_PATCHES, 10u);
PB_CONSTANT(uint, LIGHT_BINDING_RECORDS, 11u);
PB_CONSTANT(uint, LIGHT_BINDING_NEXT_IRRADIANCE, 12u);
PB_CONSTANT(uint, LIGHT_BINDING_COUNTERS, 13u);
PB_CONSTANT(uint, LIGHT_BINDING_TRACE_FLAGS, 14u);      // uint per probe slot: TRACE_FLAG_* (runtime_types.h)
PB_CONSTANT(uint, LIGHT_BINDING_LIGHT_LIST, 15u);       // LightListHeader + int per listed probe (runtime_types.h)
PB_CONSTANT(uint, LIGHT_BINDING_DYNAMIC_OBJECTS, 16u);  // as SAMPLE_ALL_BINDING_DYNAMIC_OBJECTS
PB_CONSTANT(uint, LIGHT_BINDING_OBJECT_INSTANCES, 17u); // as SAMPLE_ALL_BINDING_OBJECT_INSTANCES
PB_CONSTANT(uint, LIGHT_BINDING_RELIGHT_CHANGES, 18u);  // RelightChanges (runtime_types.h)
// The light records are split into pages of whole probes, each within maxStorageBufferRange: page 0 at
// LIGHT_BINDING_RECORDS, pages 1-3 here (unused pages repeat page 0; LightPush.probes_per_page).
PB_CONSTANT(uint, LIGHT_BINDING_RECORDS_PAGE_1, 19u);
PB_CONSTANT(uint, LIGHT_BINDING_RECORDS_PAGE_2, 20u);
PB_CONSTANT(uint, LIGHT_BINDING_RECORDS_PAGE_3, 21u);
PB_CONSTANT(uint, LIGHT_RECORD_PAGES, 4u);
PB_CONSTANT(uint, LIGHT_BINDING_TRACKED_PUNCTUAL, 22u); // float[3] per record (RelightChanges.track_after)
PB_CONSTANT(uint, LIGHT_BINDING_TRACE_TREES, 23u);      // the compact tracing sections (format 1.4),
PB_CONSTANT(uint, LIGHT_BINDING_TRACE_VERTICES, 24u);   // with TRACE_NODES and TRACE_FACES above
PB_CONSTANT(uint, LIGHT_BINDING_TRACE_MATERIALS, 25u);
// Streaming: int per probe slot, the slot of its records in the record pages, -1 for a probe that has none
// (not lit); read only when LightPush.indirect_records is set (otherwise a probe's records are its slot's).
PB_CONSTANT(uint, LIGHT_BINDING_RECORD_SLOTS, 26u);
// A record slot with this bit set belongs to a probe left unresolved: its last trace or relight had a ray
// cross a cell that is out (light_trace.comp). It keeps its irradiance, and a lookup says it is not lit
// (sample_irradiance.glsl). Record slots stay below it.
PB_CONSTANT(int, RECORD_SLOT_UNRESOLVED, 0x40000000);
PB_CONSTANT(uint, LIGHT_BINDING_COUNT, 27u);

// ---- Memory update and light transitions (memory_bindings.glsl: memory_*.comp) -----------------------------
// 0-3 equal the sampling bindings (sample_irradiance.glsl's SVO lookup gives new probes their start).
PB_CONSTANT(uint, MEMORY_BINDING_VOLUME_INFO, 0u);
PB_CONSTANT(uint, MEMORY_BINDING_PROBES, 1u);
PB_CONSTANT(uint, MEMORY_BINDING_SVO_NODES, 2u);
PB_CONSTANT(uint, MEMORY_BINDING_SVO_LEAVES, 3u);
PB_CONSTANT(uint, MEMORY_BINDING_OCTREE, 4u);
PB_CONSTANT(uint, MEMORY_BINDING_LIGHTING_INFO, 5u);
PB_CONSTANT(uint, MEMORY_BINDING_RAY_DIRECTIONS, 6u);
PB_CONSTANT(uint, MEMORY_BINDING_TRACE_NODES, 7u);
PB_CONSTANT(uint, MEMORY_BINDING_TRACE_FACES, 8u);
PB_CONSTANT(uint, MEMORY_BINDING_SURFEL_BATCHES, 9u);
PB_CONSTANT(uint, MEMORY_BINDING_LEAF_HEADER, 10u);
PB_CONSTANT(uint, MEMORY_BINDING_LEAF_ENTRIES, 11u);
PB_CONSTANT(uint, MEMORY_BINDING_KEYS,
            12u); // int[3 * segment_capacity]: key of node n in segment s at s * capacity + n
PB_CONSTANT(uint, MEMORY_BINDING_STATE, 13u);             // MemoryState
PB_CONSTANT(uint, MEMORY_BINDING_CLUSTER_STACK, 14u);     // int: free cluster meta indices
PB_CONSTANT(uint, MEMORY_BINDING_PROBE_STACK, 15u);       // int: free probe slots
PB_CONSTANT(uint, MEMORY_BINDING_BATCH_STACK, 16u);       // int: free surfel batches
PB_CONSTANT(uint, MEMORY_BINDING_WORK, 17u);              // MemoryWork per pulled memory entry
PB_CONSTANT(uint, MEMORY_BINDING_MERGE_SH, 18u);          // float[PROBE_SH_FLOATS] per pulled memory entry
PB_CONSTANT(uint, MEMORY_BINDING_MARKS, 19u);             // int per octree element: MEMORY_MARK_*
PB_CONSTANT(uint, MEMORY_BINDING_FRAME, 20u);             // MemoryFrame
PB_CONSTANT(uint, MEMORY_BINDING_COUNTERS, 21u);          // MemoryCounters
PB_CONSTANT(uint, MEMORY_BINDING_TRACE_FLAGS, 22u);       // = LIGHT_BINDING_TRACE_FLAGS' buffer
PB_CONSTANT(uint, MEMORY_BINDING_PROBE_GENERATIONS, 23u); // uint per probe slot: +1 each time it is freed
PB_CONSTANT(uint, MEMORY_BINDING_SVO_GENERATIONS, 24u);   // ivec4 per SVO leaf: generation of each stencil probe
PB_CONSTANT(uint, MEMORY_BINDING_SVO_BAKE, 25u); // 16 B per SVO leaf (float bits): voxel centre, w = its SVO node; with
                                                 //   streaming, then the bake stencils (SEAT_STENCIL_VEC4S) (static)
PB_CONSTANT(uint, MEMORY_BINDING_LIGHT_LIST, 26u);       // = LIGHT_BINDING_LIGHT_LIST's buffer
PB_CONSTANT(uint, MEMORY_BINDING_DYNAMIC_OBJECTS, 27u);  // as SAMPLE_ALL_BINDING_DYNAMIC_OBJECTS
PB_CONSTANT(uint, MEMORY_BINDING_OBJECT_INSTANCES, 28u); // as SAMPLE_ALL_BINDING_OBJECT_INSTANCES
PB_CONSTANT(uint, MEMORY_BINDING_TRACE_TREES, 29u);      // the compact tracing sections (format 1.4),
PB_CONSTANT(uint, MEMORY_BINDING_TRACE_VERTICES, 30u);   // with TRACE_NODES and TRACE_FACES above
PB_CONSTANT(uint, MEMORY_BINDING_TRACE_MATERIALS, 31u);
PB_CONSTANT(uint, MEMORY_BINDING_COUNT, 32u);

// ---- Dynamic objects' poses (object_refit.comp) -------------------------------------------------------------
PB_CONSTANT(uint, OBJECT_BINDING_DYNAMIC_OBJECTS, 0u); // the dynamic_objects section
PB_CONSTANT(uint, OBJECT_BINDING_INSTANCES, 1u);       // ObjectInstance per object: the host writes world_from_object
PB_CONSTANT(uint, OBJECT_BINDING_COUNT, 2u);

// ---- Streamed tracing arena compaction (stream_relocate.comp) -----------------------------------------------
PB_CONSTANT(uint, STREAM_BINDING_ARENA, 0u);   // the streamed tracing arena (uint words)
PB_CONSTANT(uint, STREAM_BINDING_SCRATCH, 1u); // a copy of the block being moved, from word 0
PB_CONSTANT(uint, STREAM_BINDING_COUNT, 2u);

#ifdef __cplusplus
static_assert(LIGHT_BINDING_VOLUME_INFO == SAMPLE_BINDING_VOLUME_INFO &&
              LIGHT_BINDING_PROBES == SAMPLE_BINDING_PROBES && LIGHT_BINDING_SVO_NODES == SAMPLE_BINDING_SVO_NODES &&
              LIGHT_BINDING_SVO_LEAVES == SAMPLE_BINDING_SVO_LEAVES);
static_assert(MEMORY_BINDING_VOLUME_INFO == SAMPLE_BINDING_VOLUME_INFO &&
              MEMORY_BINDING_PROBES == SAMPLE_BINDING_PROBES && MEMORY_BINDING_SVO_NODES == SAMPLE_BINDING_SVO_NODES &&
              MEMORY_BINDING_SVO_LEAVES == SAMPLE_BINDING_SVO_LEAVES);
} // namespace probebake::gpu
#endif

#undef PB_CONSTANT
#endif // PROBEBAKE_BINDINGS_H
