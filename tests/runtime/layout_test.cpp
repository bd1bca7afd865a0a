// The GPU structs as the shaders see them: member offsets and array strides read from the embedded SPIR-V
// (OpMemberDecorate Offset, OpDecorate ArrayStride) must equal the C++ offsets of gpu_types.h and
// runtime_types.h, so that the buffers the runtime uploads mean the same thing on both sides; and every
// buffer's Binding and DescriptorSet decorations must equal the volume set's (bindings.h) or its pass's
// (runtime/<concept>/*_bindings.h), which the C++ side binds by, for every kernel of the pass table.
#include <cstddef>
#include <cstdint>
#include <map>
#include <iterator>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "core/shader_library.h"
#include "pass_bindings.h"
#include "probebake/bindings.h"
#include "probebake/memory_types.h"
#include "probebake/runtime_types.h"

namespace probebake::test {
namespace {

// Offsets per member name of every struct type named `name` in a SPIR-V module (several types may carry
// the name; each is returned).
struct SpirvStructs {
  std::map<std::uint32_t, std::string> names;                                 // id -> OpName
  std::map<std::uint32_t, std::map<std::uint32_t, std::string>> member_names; // id -> member -> name
  std::map<std::uint32_t, std::map<std::uint32_t, std::uint32_t>> offsets;    // id -> member -> Offset
  std::map<std::uint32_t, std::uint32_t> array_strides;                       // type id -> ArrayStride
  std::map<std::uint32_t, std::vector<std::uint32_t>> struct_members;         // struct id -> member type ids
  std::map<std::uint32_t, std::uint32_t> bindings, sets;                      // variable id -> Binding, DescriptorSet
  std::map<std::uint32_t, std::uint32_t> pointees;                            // pointer type id -> pointee type id
  std::map<std::uint32_t, std::uint32_t> variable_types;                      // variable id -> (pointer) type id
};

std::string literal_string(std::span<const std::uint32_t> words) {
  std::string s;
  for (std::uint32_t w : words)
    for (int b = 0; b < 4; ++b) {
      const char c = static_cast<char>((w >> (8 * b)) & 0xffu);
      if (c == '\0') return s;
      s += c;
    }
  return s;
}

SpirvStructs reflect(std::span<const std::uint32_t> module) {
  constexpr std::uint32_t kOpName = 5, kOpMemberName = 6, kOpTypeStruct = 30, kOpTypePointer = 32, kOpVariable = 59,
                          kOpDecorate = 71, kOpMemberDecorate = 72;
  constexpr std::uint32_t kArrayStride = 6, kOffset = 35, kBinding = 33, kDescriptorSet = 34;
  SpirvStructs out;
  for (std::size_t i = 5; i < module.size();) {
    const std::uint32_t op = module[i] & 0xffffu, count = module[i] >> 16;
    if (count == 0 || i + count > module.size()) break;
    const std::span<const std::uint32_t> w = module.subspan(i, count);
    if (op == kOpName) out.names[w[1]] = literal_string(w.subspan(2));
    if (op == kOpMemberName) out.member_names[w[1]][w[2]] = literal_string(w.subspan(3));
    if (op == kOpMemberDecorate && w[3] == kOffset) out.offsets[w[1]][w[2]] = w[4];
    if (op == kOpDecorate && w[2] == kArrayStride) out.array_strides[w[1]] = w[3];
    if (op == kOpTypeStruct) out.struct_members[w[1]] = std::vector<std::uint32_t>(w.begin() + 2, w.end());
    if (op == kOpDecorate && w[2] == kBinding) out.bindings[w[1]] = w[3];
    if (op == kOpDecorate && w[2] == kDescriptorSet) out.sets[w[1]] = w[3];
    if (op == kOpTypePointer) out.pointees[w[1]] = w[3];
    if (op == kOpVariable) out.variable_types[w[2]] = w[1];
    i += count;
  }
  return out;
}

struct Member {
  const char* name;
  std::size_t offset;
};

// Checks every struct named `type` in `shader`; returns how many it found.
int expect_layout(const char* shader, const char* type, const std::vector<Member>& members) {
  const SpirvStructs s = reflect(shaders::spirv(shader));
  int found = 0;
  for (const auto& [id, name] : s.names) {
    if (name != type || !s.offsets.count(id)) continue;
    ++found;
    for (const Member& m : members) {
      bool seen = false;
      for (const auto& [index, member_name] : s.member_names.at(id)) {
        if (member_name != m.name) continue;
        seen = true;
        EXPECT_EQ(s.offsets.at(id).at(index), m.offset) << shader << ": " << type << "." << m.name;
      }
      EXPECT_TRUE(seen) << shader << ": " << type << " has no member " << m.name;
    }
  }
  return found;
}

// Buffer block name -> binding number, in one descriptor set.
using BindingTable = std::map<std::string, std::uint32_t>;

// Set 0 of every kernel: the volume set (bindings.h; the names of volume_bindings.glsl).
const BindingTable& volume_table() {
  using namespace gpu;
  static const BindingTable table{{"VolumeInfoBuffer", VOLUME_BINDING_VOLUME_INFO},
                                  {"ProbeBuffer", VOLUME_BINDING_PROBES},
                                  {"SvoNodeBuffer", VOLUME_BINDING_SVO_NODES},
                                  {"SvoLeafBuffer", VOLUME_BINDING_SVO_LEAVES},
                                  {"OctreeBuffer", VOLUME_BINDING_OCTREE},
                                  {"ProbeIndexBuffer", VOLUME_BINDING_PROBE_INDEX},
                                  {"SurfelBatchBuffer", VOLUME_BINDING_SURFEL_BATCHES},
                                  {"LeafHeaderBuffer", VOLUME_BINDING_LEAF_HEADER},
                                  {"LeafEntryBuffer", VOLUME_BINDING_LEAF_ENTRIES},
                                  {"LightingInfoBuffer", VOLUME_BINDING_LIGHTING_INFO},
                                  {"RayDirectionBuffer", VOLUME_BINDING_RAY_DIRECTIONS},
                                  {"LightBuffer", VOLUME_BINDING_PUNCTUAL_LIGHTS},
                                  {"PatchBuffer", VOLUME_BINDING_EMITTER_PATCHES},
                                  {"TraceTreeBuffer", VOLUME_BINDING_TRACE_TREES},
                                  {"TraceNodeBuffer", VOLUME_BINDING_TRACE_NODES},
                                  {"TraceFaceBuffer", VOLUME_BINDING_TRACE_FACES},
                                  {"TraceVertexBuffer", VOLUME_BINDING_TRACE_VERTICES},
                                  {"TraceMaterialBuffer", VOLUME_BINDING_TRACE_MATERIALS},
                                  {"DynamicObjectBuffer", VOLUME_BINDING_DYNAMIC_OBJECTS},
                                  {"ObjectInstanceBuffer", VOLUME_BINDING_OBJECT_INSTANCES}};
  return table;
}

// Set 1 of each layout of the pass table: the names of its concept folder's GLSL, numbered by its
// *_bindings.h.
const BindingTable& pass_table(std::string_view layout) {
  using namespace gpu;
  static const std::map<std::string_view, BindingTable> tables{
      {"probe_index", {{"BlockSums", PROBE_INDEX_BINDING_BLOCK_SUMS}, {"Counters", PROBE_INDEX_BINDING_COUNTERS}}},
      {"sample",
       {{"Queries", SAMPLE_BINDING_QUERIES},
        {"Results", SAMPLE_BINDING_RESULTS},
        {"RecordSlots", SAMPLE_BINDING_RECORD_SLOTS},
        {"ProbePoints", SAMPLE_BINDING_PROBE_POINTS},
        {"ProbeCodes", SAMPLE_BINDING_PROBE_CODES}}},
      {"sample_grid",
       {{"Queries", SAMPLE_GRID_BINDING_QUERIES},
        {"Results", SAMPLE_GRID_BINDING_RESULTS},
        {"ProbebakeGridLattice", SAMPLE_GRID_BINDING_LATTICE},
        {"ProbePoints", SAMPLE_GRID_BINDING_PROBE_POINTS},
        {"ProbeCodes", SAMPLE_GRID_BINDING_PROBE_CODES}}},
      {"probe_codes", {{"Points", PROBE_CODES_BINDING_POINTS}, {"Codes", PROBE_CODES_BINDING_CODES}}},
      {"sample_all", {{"Queries", SAMPLE_ALL_BINDING_QUERIES}, {"Results", SAMPLE_ALL_BINDING_RESULTS}}},
      {"light",
       {{"RecordPage0", LIGHT_BINDING_RECORDS},
        {"RecordPage1", LIGHT_BINDING_RECORDS + 1},
        {"RecordPage2", LIGHT_BINDING_RECORDS + 2},
        {"RecordPage3", LIGHT_BINDING_RECORDS + 3},
        {"NextIrradianceBuffer", LIGHT_BINDING_NEXT_IRRADIANCE},
        {"CounterBuffer", LIGHT_BINDING_COUNTERS},
        {"TraceFlagBuffer", LIGHT_BINDING_TRACE_FLAGS},
        {"LightListBuffer", LIGHT_BINDING_LIGHT_LIST},
        {"RelightChangeBuffer", LIGHT_BINDING_RELIGHT_CHANGES},
        {"TrackedPunctualBuffer", LIGHT_BINDING_TRACKED_PUNCTUAL},
        {"RecordSlotBuffer", LIGHT_BINDING_RECORD_SLOTS},
        {"LoadOrderBuffer", LIGHT_BINDING_LOAD_ORDER}}},
      {"memory",
       {{"StateBuffer", MEMORY_BINDING_STATE},
        {"FreeStackBuffer", MEMORY_BINDING_FREE_STACKS},
        {"WorkBuffer", MEMORY_BINDING_WORK},
        {"MergeShBuffer", MEMORY_BINDING_MERGE_SH},
        {"MarkBuffer", MEMORY_BINDING_MARKS},
        {"FrameBuffer", MEMORY_BINDING_FRAME},
        {"CounterBuffer", MEMORY_BINDING_COUNTERS},
        {"TraceFlagBuffer", MEMORY_BINDING_TRACE_FLAGS},
        {"ProbeGenerationBuffer", MEMORY_BINDING_PROBE_GENERATIONS},
        {"SvoGenerationBuffer", MEMORY_BINDING_SVO_GENERATIONS},
        {"SvoBakeBuffer", MEMORY_BINDING_SVO_BAKE},
        {"LightListBuffer", MEMORY_BINDING_LIGHT_LIST}}},
      {"object", {}},
      {"stream", {{"ArenaBuffer", STREAM_BINDING_ARENA}, {"ScratchBuffer", STREAM_BINDING_SCRATCH}}}};
  return tables.at(layout);
}

struct KernelRow {
  const char* name;
  const char* layout;
};
constexpr KernelRow kKernels[] = {
#define PROBEBAKE_KERNEL(folder, name, layout) {#name, #layout},
#include "probebake/runtime/passes.def"
};

// Every buffer of `kernel` must be a block of the volume set in set 0, or of its layout's table in set 1,
// at that binding. (Unused buffers may be left out of the SPIR-V, so not every entry must appear.)
void expect_bindings(const KernelRow& kernel) {
  const SpirvStructs s = reflect(shaders::spirv(kernel.name));
  EXPECT_FALSE(s.bindings.empty()) << kernel.name;
  for (const auto& [variable, binding] : s.bindings) {
    const std::uint32_t block = s.pointees.at(s.variable_types.at(variable));
    const std::string name = s.names.count(block) ? s.names.at(block) : "";
    const std::uint32_t set = s.sets.count(variable) ? s.sets.at(variable) : 0u;
    ASSERT_TRUE(set == gpu::VOLUME_SET || set == gpu::PASS_SET) << kernel.name << ": " << name << " in set " << set;
    const BindingTable& table = set == gpu::VOLUME_SET ? volume_table() : pass_table(kernel.layout);
    const auto want = table.find(name);
    if (want == table.end()) {
      ADD_FAILURE() << kernel.name << ": buffer " << name << " at set " << set << ", binding " << binding
                    << " is not in the " << (set == gpu::VOLUME_SET ? "volume set" : kernel.layout) << " table";
      continue;
    }
    EXPECT_EQ(binding, want->second) << kernel.name << ": " << name;
  }
}

TEST(GpuLayout, ShaderBindingsMatchBindingsHeaders) {
  for (const KernelRow& kernel : kKernels) expect_bindings(kernel);
}

TEST(GpuLayout, ShaderLibraryHoldsEveryKernelOfThePassTable) {
  EXPECT_EQ(std::size(kKernels), 29u); // the table itself: a row lost from passes.def fails here
  for (const KernelRow& kernel : kKernels) {
    const auto words = shaders::spirv(kernel.name);
    ASSERT_GT(words.size(), 5u) << kernel.name;
    EXPECT_EQ(words[0], 0x07230203u) << kernel.name; // SPIR-V magic
  }
  EXPECT_TRUE(shaders::spirv("no_such_shader").empty());
}

TEST(GpuLayout, ProbeMatchesGpuTypes) {
  using gpu::Probe;
  const std::vector<Member> members{{"position", offsetof(Probe, position)},
                                    {"link", offsetof(Probe, link)},
                                    {"node", offsetof(Probe, node)},
                                    {"depth", offsetof(Probe, depth)},
                                    {"hit_fraction", offsetof(Probe, hit_fraction)},
                                    {"backface_fraction", offsetof(Probe, backface_fraction)},
                                    {"irradiance_sh", offsetof(Probe, irradiance_sh)},
                                    {"pad0", offsetof(Probe, pad0)}};
  EXPECT_GE(expect_layout("sample_irradiance", "Probe", members), 1);
  EXPECT_GE(expect_layout("probe_index_count", "Probe", members), 1);
  // The probe buffer's runtime array has the C++ stride.
  const SpirvStructs s = reflect(shaders::spirv("sample_irradiance"));
  bool stride_checked = false;
  for (const auto& [id, name] : s.names) {
    if (name != "ProbeBuffer") continue;
    const std::uint32_t array_type = s.struct_members.at(id).at(0);
    EXPECT_EQ(s.array_strides.at(array_type), sizeof(Probe));
    stride_checked = true;
  }
  EXPECT_TRUE(stride_checked);
}

TEST(GpuLayout, VolumeInfoAndSvoLeafMatchGpuTypes) {
  using gpu::SvoLeaf;
  using gpu::VolumeInfo;
  EXPECT_EQ(expect_layout("sample_irradiance", "VolumeInfo",
                          {{"root_min", offsetof(VolumeInfo, root_min)},
                           {"root_size", offsetof(VolumeInfo, root_size)},
                           {"svo_depth", offsetof(VolumeInfo, svo_depth)},
                           {"probe_capacity", offsetof(VolumeInfo, probe_capacity)},
                           {"svo_nodes", offsetof(VolumeInfo, svo_nodes)},
                           {"svo_leaves", offsetof(VolumeInfo, svo_leaves)},
                           {"pad2", offsetof(VolumeInfo, pad2)}}),
            1);
  EXPECT_EQ(expect_layout("sample_irradiance", "SvoLeaf",
                          {{"probes", offsetof(SvoLeaf, probes)}, {"weights", offsetof(SvoLeaf, weights)}}),
            1);
}

TEST(GpuLayout, RuntimeTypesMatch) {
  EXPECT_EQ(expect_layout("sample_irradiance", "SampleQuery",
                          {{"position", offsetof(gpu::SampleQuery, position)},
                           {"normal", offsetof(gpu::SampleQuery, normal)},
                           {"pad1", offsetof(gpu::SampleQuery, pad1)}}),
            1);
  EXPECT_EQ(expect_layout("sample_irradiance", "SampleResult",
                          {{"irradiance", offsetof(gpu::SampleResult, irradiance)},
                           {"probes_used", offsetof(gpu::SampleResult, probes_used)}}),
            1);
  EXPECT_EQ(expect_layout("probe_index_scan", "RuntimeCounters",
                          {{"live_probes", offsetof(gpu::RuntimeCounters, live_probes)}}),
            1);
  EXPECT_EQ(expect_layout("probe_encode", "ProbeCodePush",
                          {{"probe_capacity", offsetof(gpu::ProbeCodePush, probe_capacity)},
                           {"code_bands", offsetof(gpu::ProbeCodePush, code_bands)}}),
            1);
  EXPECT_EQ(expect_layout(
                "sample_grid", "SamplePush",
                {{"count", offsetof(gpu::SamplePush, count)}, {"code_bands", offsetof(gpu::SamplePush, code_bands)}}),
            1);
  EXPECT_EQ(expect_layout("probe_index_scatter", "ProbeIndexPush",
                          {{"probe_capacity", offsetof(gpu::ProbeIndexPush, probe_capacity)},
                           {"block_count", offsetof(gpu::ProbeIndexPush, block_count)}}),
            1);
}

TEST(GpuLayout, LightingSectionsMatchGpuTypes) {
  using namespace gpu;
  EXPECT_GE(expect_layout("light_trace", "TraceTree",
                          {{"lower", offsetof(TraceTree, lower)},
                           {"root", offsetof(TraceTree, root)},
                           {"scale", offsetof(TraceTree, scale)},
                           {"node_count", offsetof(TraceTree, node_count)}}),
            1);
  EXPECT_GE(expect_layout("light_trace", "TraceNode",
                          {{"lower", offsetof(TraceNode, lower)},
                           {"upper", offsetof(TraceNode, upper)},
                           {"child", offsetof(TraceNode, child)}}),
            1);
  EXPECT_GE(expect_layout("light_trace", "TraceFace",
                          {{"vertex", offsetof(TraceFace, vertex)}, {"material", offsetof(TraceFace, material)}}),
            1);
  EXPECT_GE(expect_layout(
                "light_trace", "TraceVertex",
                {{"x", offsetof(TraceVertex, x)}, {"y", offsetof(TraceVertex, y)}, {"z", offsetof(TraceVertex, z)}}),
            1);
  EXPECT_GE(
      expect_layout("light_trace", "TraceMaterial",
                    {{"albedo", offsetof(TraceMaterial, albedo)}, {"emission", offsetof(TraceMaterial, emission)}}),
      1);
  EXPECT_GE(expect_layout("light_gather", "PunctualLight",
                          {{"position", offsetof(PunctualLight, position)},
                           {"type", offsetof(PunctualLight, type)},
                           {"direction", offsetof(PunctualLight, direction)},
                           {"range", offsetof(PunctualLight, range)},
                           {"intensity", offsetof(PunctualLight, intensity)},
                           {"cos_outer", offsetof(PunctualLight, cos_outer)},
                           {"spot_scale", offsetof(PunctualLight, spot_scale)}}),
            1);
  EXPECT_GE(expect_layout("light_trace", "EmitterPatch",
                          {{"a", offsetof(EmitterPatch, a)},
                           {"flags", offsetof(EmitterPatch, flags)},
                           {"b", offsetof(EmitterPatch, b)},
                           {"emitter", offsetof(EmitterPatch, emitter)},
                           {"c", offsetof(EmitterPatch, c)},
                           {"normal", offsetof(EmitterPatch, normal)},
                           {"radiance", offsetof(EmitterPatch, radiance)}}),
            1);
  EXPECT_GE(expect_layout("light_emitters", "EmitterScale", {{"scale", offsetof(EmitterScale, scale)}}), 1);
  EXPECT_GE(expect_layout("light_trace", "LightingInfo",
                          {{"sky_radiance", offsetof(LightingInfo, sky_radiance)},
                           {"rays", offsetof(LightingInfo, rays)},
                           {"shadow_offset", offsetof(LightingInfo, shadow_offset)},
                           {"emissive_as_lights", offsetof(LightingInfo, emissive_as_lights)},
                           {"bvh_nodes", offsetof(LightingInfo, bvh_nodes)},
                           {"emitter_patches", offsetof(LightingInfo, emitter_patches)},
                           {"placement_rays", offsetof(LightingInfo, placement_rays)}}),
            1);
}

TEST(GpuLayout, DynamicObjectTypesMatch) {
  using namespace gpu;
  for (const char* shader : {"object_refit", "light_trace", "memory_light", "sample_all_probes"}) {
    EXPECT_GE(expect_layout(shader, "DynamicObject",
                            {{"lower", offsetof(DynamicObject, lower)},
                             {"bvh_root", offsetof(DynamicObject, bvh_root)},
                             {"upper", offsetof(DynamicObject, upper)},
                             {"bvh_node_count", offsetof(DynamicObject, bvh_node_count)},
                             {"first_triangle", offsetof(DynamicObject, first_triangle)},
                             {"triangle_count", offsetof(DynamicObject, triangle_count)},
                             {"gltf_node", offsetof(DynamicObject, gltf_node)},
                             {"rest_rows", offsetof(DynamicObject, rest_rows)}}),
              1)
        << shader;
    EXPECT_GE(expect_layout(shader, "ObjectInstance",
                            {{"world_from_object", offsetof(ObjectInstance, world_from_object)},
                             {"object_from_world", offsetof(ObjectInstance, object_from_world)},
                             {"world_lower", offsetof(ObjectInstance, world_lower)},
                             {"world_upper", offsetof(ObjectInstance, world_upper)}}),
              1)
        << shader;
  }
  EXPECT_GE(
      expect_layout("light_trace", "LightingInfo", {{"dynamic_objects", offsetof(LightingInfo, dynamic_objects)}}), 1);
  EXPECT_GE(expect_layout("object_refit", "ObjectRefitPush", {{"objects", offsetof(ObjectRefitPush, objects)}}), 1);
  EXPECT_GE(expect_layout("stream_relocate", "StreamRelocatePush",
                          {{"from_byte", offsetof(StreamRelocatePush, from_byte)},
                           {"to_byte", offsetof(StreamRelocatePush, to_byte)},
                           {"nodes", offsetof(StreamRelocatePush, nodes)},
                           {"faces", offsetof(StreamRelocatePush, faces)}}),
            1);
}

TEST(GpuLayout, LightUpdateTypesMatch) {
  using namespace gpu;
  EXPECT_GE(expect_layout("light_gather", "LightRecord",
                          {{"position", offsetof(LightRecord, position)},
                           {"kind", offsetof(LightRecord, kind)},
                           {"normal", offsetof(LightRecord, normal)},
                           {"base", offsetof(LightRecord, base)},
                           {"reflect", offsetof(LightRecord, reflect)},
                           {"punctual_r", offsetof(LightRecord, punctual_r)},
                           {"punctual_g", offsetof(LightRecord, punctual_g)},
                           {"punctual_b", offsetof(LightRecord, punctual_b)}}),
            1);
  EXPECT_GE(expect_layout("light_relight", "RelightChanges",
                          {{"count", offsetof(RelightChanges, count)},
                           {"everything", offsetof(RelightChanges, everything)},
                           {"reuse_before", offsetof(RelightChanges, reuse_before)},
                           {"track_after", offsetof(RelightChanges, track_after)},
                           {"changes", offsetof(RelightChanges, changes)},
                           {"moved_boxes", offsetof(RelightChanges, moved_boxes)},
                           {"shadows_only", offsetof(RelightChanges, shadows_only)},
                           {"shadow_pairs", offsetof(RelightChanges, shadow_pairs)},
                           {"boxes", offsetof(RelightChanges, boxes)},
                           {"pairs", offsetof(RelightChanges, pairs)}}),
            1);
  EXPECT_GE(expect_layout("light_relight", "LightChange",
                          {{"before", offsetof(LightChange, before)}, {"after", offsetof(LightChange, after)}}),
            1);
  EXPECT_GE(expect_layout("light_gather", "LightPush",
                          {{"probe_capacity", offsetof(LightPush, probe_capacity)},
                           {"hysteresis", offsetof(LightPush, hysteresis)},
                           {"first_slot", offsetof(LightPush, first_slot)},
                           {"slot_count", offsetof(LightPush, slot_count)},
                           {"indirect_records", offsetof(LightPush, indirect_records)}}),
            1);
  EXPECT_GE(expect_layout("light_resolve", "LightCounters",
                          {{"traced_probes", offsetof(LightCounters, traced_probes)},
                           {"lit_probes", offsetof(LightCounters, lit_probes)},
                           {"non_finite", offsetof(LightCounters, non_finite)},
                           {"want_split", offsetof(LightCounters, want_split)},
                           {"want_free", offsetof(LightCounters, want_free)}}),
            1);
  EXPECT_GE(expect_layout("light_relight", "LightCounters",
                          {{"relit_records", offsetof(LightCounters, relit_records)},
                           {"reused_records", offsetof(LightCounters, reused_records)}}),
            1);
  EXPECT_GE(expect_layout("light_trace", "LightPush",
                          {{"tracked_light", offsetof(LightPush, tracked_light)},
                           {"probes_per_page", offsetof(LightPush, probes_per_page)}}),
            1);
}

TEST(GpuLayout, MemoryUpdateTypesMatch) {
  using namespace gpu;
  EXPECT_GE(expect_layout("memory_grant", "MemoryWork",
                          {{"node", offsetof(MemoryWork, node)},
                           {"state", offsetof(MemoryWork, state)},
                           {"action", offsetof(MemoryWork, action)},
                           {"verdict", offsetof(MemoryWork, verdict)},
                           {"reuse_probe", offsetof(MemoryWork, reuse_probe)},
                           {"cluster_first", offsetof(MemoryWork, cluster_first)},
                           {"probe_first", offsetof(MemoryWork, probe_first)},
                           {"batch_first", offsetof(MemoryWork, batch_first)},
                           {"merged", offsetof(MemoryWork, merged)}}),
            1);
  EXPECT_GE(expect_layout("memory_grant", "MemoryState",
                          {{"cluster_top", offsetof(MemoryState, cluster_top)},
                           {"probe_top", offsetof(MemoryState, probe_top)},
                           {"batch_top", offsetof(MemoryState, batch_top)},
                           {"traced", offsetof(MemoryState, traced)},
                           {"memory_pulled", offsetof(MemoryState, memory_pulled)},
                           {"memory_segment", offsetof(MemoryState, memory_segment)},
                           {"light_pulled", offsetof(MemoryState, light_pulled)},
                           {"light_segment", offsetof(MemoryState, light_segment)},
                           {"entry_groups", offsetof(MemoryState, entry_groups)},
                           {"entry_thread_groups", offsetof(MemoryState, entry_thread_groups)},
                           {"light_groups", offsetof(MemoryState, light_groups)},
                           {"probe_stack_base", offsetof(MemoryState, probe_stack_base)},
                           {"batch_stack_base", offsetof(MemoryState, batch_stack_base)}}),
            1);
  EXPECT_GE(expect_layout("memory_light", "MemoryFrame",
                          {{"box_count", offsetof(MemoryFrame, box_count)},
                           {"max_memory_entries", offsetof(MemoryFrame, max_memory_entries)},
                           {"max_light_entries", offsetof(MemoryFrame, max_light_entries)},
                           {"dead_backface_fraction", offsetof(MemoryFrame, dead_backface_fraction)},
                           {"batches_per_probe", offsetof(MemoryFrame, batches_per_probe)},
                           {"boxes", offsetof(MemoryFrame, boxes)}}),
            1);
  EXPECT_GE(expect_layout("memory_light", "MemoryBox",
                          {{"lower", offsetof(MemoryBox, lower)}, {"upper", offsetof(MemoryBox, upper)}}),
            1);
  EXPECT_GE(expect_layout("memory_sync", "MemoryCounters",
                          {{"processed", offsetof(MemoryCounters, processed)},
                           {"deferred", offsetof(MemoryCounters, deferred)},
                           {"probes_placed", offsetof(MemoryCounters, probes_placed)},
                           {"probes_freed", offsetof(MemoryCounters, probes_freed)},
                           {"splits", offsetof(MemoryCounters, splits)},
                           {"collapses", offsetof(MemoryCounters, collapses)},
                           {"failed_allocations", offsetof(MemoryCounters, failed_allocations)},
                           {"lost_entries", offsetof(MemoryCounters, lost_entries)},
                           {"stale_entries", offsetof(MemoryCounters, stale_entries)},
                           {"svo_slots_dropped", offsetof(MemoryCounters, svo_slots_dropped)},
                           {"svo_leaves_refilled", offsetof(MemoryCounters, svo_leaves_refilled)},
                           {"free_clusters", offsetof(MemoryCounters, free_clusters)},
                           {"free_probes", offsetof(MemoryCounters, free_probes)},
                           {"free_batches", offsetof(MemoryCounters, free_batches)}}),
            1);
  EXPECT_GE(expect_layout("memory_allocate", "SurfelBatch",
                          {{"link", offsetof(SurfelBatch, link)},
                           {"probe", offsetof(SurfelBatch, probe)},
                           {"count", offsetof(SurfelBatch, count)},
                           {"first", offsetof(SurfelBatch, first)},
                           {"surfels", offsetof(SurfelBatch, surfels)}}),
            1);
  EXPECT_GE(expect_layout("memory_allocate", "LeafQueueHeader",
                          {{"pull_origin", offsetof(LeafQueueHeader, pull_origin)},
                           {"segment_capacity", offsetof(LeafQueueHeader, segment_capacity)},
                           {"count", offsetof(LeafQueueHeader, count)}}),
            1);
  EXPECT_GE(expect_layout("memory_begin", "MemoryPush", {{"phase", offsetof(MemoryPush, phase)}}), 1);
  EXPECT_GE(expect_layout("light_trace_list", "LightPush",
                          {{"trace_mode", offsetof(LightPush, trace_mode)},
                           {"listed", offsetof(LightPush, listed)},
                           {"untraced_from", offsetof(LightPush, untraced_from)},
                           {"load_ordered", offsetof(LightPush, load_ordered)}}),
            1);
  const std::vector<Member> list{
      {"groups_x", offsetof(LightListHeader, groups_x)},   {"count", offsetof(LightListHeader, count)},
      {"resolve_x", offsetof(LightListHeader, resolve_x)}, {"resolve_z", offsetof(LightListHeader, resolve_z)},
      {"trace_x", offsetof(LightListHeader, trace_x)},     {"trace_z", offsetof(LightListHeader, trace_z)}};
  EXPECT_GE(expect_layout("memory_begin", "LightListHeader", list), 1);
  EXPECT_GE(expect_layout("light_resolve", "LightListHeader", list), 1);
}

} // namespace
} // namespace probebake::test
