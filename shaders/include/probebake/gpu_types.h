// probebake GPU data model: the one definition of every struct that the GPU reads, shared by C++ and GLSL.
//
// The layout is the octree thesis's (octree-probe-surfel-placement-ddgi-thesis, §3.1.1-3.1.5) with the
// SVO probe index of the non-uniform placement paper (§4.1). The same bytes are used in memory, in the
// .probes file (little-endian) and in GPU storage buffers (std430), so loading is a copy.
//
// Rules for this file: std430 layout, explicit padding, every size and offset checked by static_assert
// below (C++ side); no bool, no vec3 arrays; GLSL sees the same names without the namespace.
#ifndef PROBEBAKE_GPU_TYPES_H
#define PROBEBAKE_GPU_TYPES_H

#ifdef __cplusplus
#include <cstddef>
#include <cstdint>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <glm/ext/vector_int4.hpp>

#endif

#include "probebake/gpu_shared.h"

PB_GPU_BEGIN
#ifdef __cplusplus
using vec3 = glm::vec3;
using vec4 = glm::vec4;
using ivec4 = glm::ivec4;
#endif

// ---- Octree buffer (thesis §3.1.1): int32 elements ------------------------------------------------
// Element 0 is the root node. Then node clusters of nine elements: one meta element + eight nodes.
// Meta element:  0 = cluster free; < 0 = allocated, ~value = index of the parent node.
// Node element:  0 = leaf without probe; < 0 = leaf with probe ~value; > 0 = parent, value = meta index
//                of the child cluster. A trailing incomplete cluster (element count != 1 + 9k) is never
//                used as a child cluster.
PB_CONSTANT(int, OCTREE_ROOT, 0);
PB_CONSTANT(int, OCTREE_CLUSTER_SIZE, 9);
PB_CONSTANT(int, OCTREE_MAX_DEPTH, 12);

// ---- Probes (thesis §3.1.2, extended) ----------------------------------------------------------------
// link: 0 = free; < 0 = allocated, ~link = first surfel batch of the probe's chain, or ~link ==
// PROBE_NO_SURFELS when the file carries no surfel batches (static scenes).
PB_CONSTANT(int, PROBE_NO_SURFELS, 0x7fffffff);
// Irradiance is stored as L2 spherical harmonics of the irradiance (cosine lobe already convolved in),
// 9 coefficients x RGB, interleaved by coefficient: sh[3*k + channel].
PB_CONSTANT(int, PROBE_SH_COEFFS, 9);
PB_CONSTANT(int, PROBE_SH_FLOATS, 3 * PROBE_SH_COEFFS); // floats of one probe's RGB coefficients (27)
// The SH basis (real SH, coefficient k = l^2 + l + m; probe_index/include/probebake/probe_index/lookup.h
// spells it out): Y00 = SH_Y0; Y1m = SH_Y1 * (y, z, x); Y2-2, Y2-1, Y21 = SH_Y2 * (xy, yz, xz);
// Y20 = SH_Y20 * (3z^2 - 1); Y22 = SH_Y22 * (x^2 - y^2). One definition for the bake (lookup.h's kShY*)
// and the shaders (sh.glsl).
PB_CONSTANT(float, SH_Y0, 0.282094792f);  // 1 / (2 sqrt(pi))
PB_CONSTANT(float, SH_Y1, 0.488602512f);  // sqrt(3 / (4 pi))
PB_CONSTANT(float, SH_Y2, 1.092548431f);  // sqrt(15 / (4 pi))
PB_CONSTANT(float, SH_Y20, 0.315391565f); // sqrt(5 / (16 pi))
PB_CONSTANT(float, SH_Y22, 0.546274215f); // sqrt(15 / (16 pi))
// Clamped-cosine convolution factors A_l per band l (Ramamoorthi & Hanrahan 2001): irradiance coefficient
// = A_l * radiance coefficient (lookup.h's kShBand*, light_gather.comp).
PB_CONSTANT(float, SH_BAND0, 3.14159265f);  // pi
PB_CONSTANT(float, SH_BAND1, 2.09439510f);  // 2 pi / 3
PB_CONSTANT(float, SH_BAND2, 0.785398163f); // pi / 4

struct Probe {
  vec3 position;                        // offset   0: world space, metres (glTF units)
  int link;                             // offset  12: see above
  int node;                             // offset  16: octree node holding this probe (back link, -1 for grid probes)
  int depth;                            // offset  20: depth of that node (root = 0)
  float hit_fraction;                   // offset  24: surfel hits inside the node cube / surfels placed
  float backface_fraction;              // offset  28: back-face hits / hits (dead-probe test)
  float irradiance_sh[PROBE_SH_FLOATS]; // offset  32: L2 SH irradiance, RGB, W/m^2 per unit of emission
  float pad0;                           // offset 140
};                                      // size 144

// ---- Surfels and surfel batches (thesis §3.1.3, extended) ----------------------------------------------
PB_CONSTANT(int, SURFELS_PER_BATCH, 16);
PB_CONSTANT(uint, SURFEL_FLAG_HIT, 1u);      // the probe ray hit geometry inside the node cube
PB_CONSTANT(uint, SURFEL_FLAG_BACKFACE, 2u); // ... and the hit surface faces away from the probe

struct Surfel {
  vec3 position;  // offset  0: world space
  float distance; // offset 12: distance from the probe along the lattice ray
  vec3 normal;    // offset 16: unit normal of the surface facing the probe
  uint flags;     // offset 28: SURFEL_FLAG_*
  vec3 albedo;    // offset 32: diffuse reflectance
  float pad0;     // offset 44
  vec3 radiance;  // offset 48: outgoing radiance of the lit surfel ("color_lit")
  float pad1;     // offset 60
};                // size 64

// link: 0 = free; < 0 = allocated, ~link = next batch in the chain; > 0 = allocated, last batch of its
// chain, and link - 1 is the owning probe (makes ownership checkable from the chain's end).
struct SurfelBatch {
  int link;  // offset  0
  int probe; // offset  4: owning probe index
  int count; // offset  8: surfels in use in this batch, 1..SURFELS_PER_BATCH
  int first; // offset 12: lattice index of surfels[0] (the probe's k-th surfel is lattice point k)
  Surfel surfels[SURFELS_PER_BATCH]; // offset 16
};                                   // size 16 + 64 * SURFELS_PER_BATCH

// ---- Leaf buffer (thesis §3.1.4) ---------------------------------------------------------------------
// Three equal segments of (leaf node, state) entries used as a ring: pull origin p <- p + 2 mod 3 each
// frame; memory update pulls segment (p + 0) mod 3, light update pulls (p + 1) mod 3.
PB_CONSTANT(int, LEAF_M0_CHILD_ALLOCATING, 0);
PB_CONSTANT(int, LEAF_M1_ALLOCATE_PROBE, 1);
PB_CONSTANT(int, LEAF_M2_FREE_PROBE, 2);
PB_CONSTANT(int, LEAF_M3_SPLIT, 3);
PB_CONSTANT(int, LEAF_M4_FREE_CLUSTER, 4);
PB_CONSTANT(int, LEAF_L0_PARENT_FREED, 5);
PB_CONSTANT(int, LEAF_L1_PLACE_SURFELS, 6);
PB_CONSTANT(int, LEAF_L2_LIGHT, 7);
PB_CONSTANT(int, LEAF_L3_CHECK_BOXES, 8);
PB_CONSTANT(int, LEAF_STATE_COUNT, 9);

struct LeafEntry {
  int node;  // offset 0: octree node index
  int state; // offset 4: LEAF_*
};           // size 8

struct LeafQueueHeader {
  int pull_origin;      // offset  0: p in {0, 1, 2}
  int segment_capacity; // offset  4: entries per segment
  int count[3];         // offset  8: entries in use per segment
  int pad0;             // offset 20
  int pad1;             // offset 24
  int pad2;             // offset 28
};                      // size 32

// ---- Probe index list (thesis §3.1.5) ------------------------------------------------------------------
// int32[probe_capacity + 1]: indices of allocated probes in ascending order, then PROBE_INDEX_END (< 0).
PB_CONSTANT(int, PROBE_INDEX_END, -1);

// ---- SVO probe index (non-uniform placement paper §4.1) ---------------------------------------------------
// Node buffer: int32, root at 0. 0 = empty voxel (outside the scene's reach or inside solid geometry);
// > 0 = interior node, value = index of the first of 8 consecutive children (child i covers octant i,
// bit 0 = +x, bit 1 = +y, bit 2 = +z); < 0 = leaf voxel, ~value = index into the leaf payload buffer.
// Interior nodes carry no payload.
PB_CONSTANT(int, SVO_PROBES_PER_LEAF, 4);

struct SvoLeaf {
  ivec4 probes; // offset  0: probe indices, -1 = unused slot (used slots first)
  vec4 weights; // offset 16: normalised weights of the used slots, 0 for unused
};              // size 32

// ---- Volume description (one per file / runtime instance) -------------------------------------------------
PB_CONSTANT(int, PLACEMENT_OCTREE, 0);
PB_CONSTANT(int, PLACEMENT_GRID, 1);
PB_CONSTANT(int, PLACEMENT_SKELETON, 2); // probes on the SDF skeleton: node -1 like grid probes, no grid resolution
PB_CONSTANT(int, LATTICE_FIBONACCI, 0);
PB_CONSTANT(int, LATTICE_LATLONG, 1);
PB_CONSTANT(int, LATTICE_EQUAL_AREA, 2);

struct VolumeInfo {
  vec3 root_min;         // offset  0: minimum corner of the octree root cube (also the SVO cube)
  float root_size;       // offset 12: edge length of the root cube
  int placement;         // offset 16: PLACEMENT_*
  int max_depth;         // offset 20: octree max depth (octree placement)
  int svo_depth;         // offset 24: SVO leaf depth
  int lattice;           // offset 28: LATTICE_*
  int surfels_per_probe; // offset 32
  float split_low;       // offset 36: f < split_low frees a probe
  float split_high;      // offset 40: f >= split_high splits a node below max depth
  int grid_resolution;   // offset 44: N for an N^3 grid (grid placement), else 0
  int probe_capacity;    // offset 48: elements in the probe buffer
  int batch_capacity;    // offset 52: elements in the surfel batch buffer (0 when not stored)
  int octree_elements;   // offset 56: int32 elements in the octree buffer
  int svo_nodes;         // offset 60: int32 elements in the SVO node buffer
  int svo_leaves;        // offset 64: SvoLeaf elements
  int pad0;              // offset 68
  int pad1;              // offset 72
  int pad2;              // offset 76
};                       // size 80

// ---- Grid lattice (format 1.8, optional): the grid placement looked up as grid engines do -----------------
// uint32[GRID_LATTICE_HEADER_WORDS + GRID_POINT_WORDS * resolution^3]: a GridLatticeHeader, then a GridPoint
// per lattice point i = x + n (y + n z), x fastest. The grid's box [origin, origin + n spacing] is cut into
// n^3 boxes and lattice point i sits at the centre of box (x, y, z), origin + ((x, y, z) + 0.5) spacing; its
// probe is the one placed there (since moved out of geometry, perhaps). A lookup blends the eight corners of
// the lattice cell around the point trilinearly (probe_index/grid_lookup.h).
PB_CONSTANT(int, GRID_LATTICE_HEADER_WORDS, 8);
PB_CONSTANT(int, GRID_POINT_WORDS, 2);
PB_CONSTANT(int, GRID_MAX_RESOLUTION, 255); // resolution^3 probe indices fit in 24 bits
// GridPoint::probe_cells: the probe index in bits 0-23 (GRID_POINT_NO_PROBE: freed, no probe) and in bits
// 24-31 which of the eight lattice cells around the point its probe serves: bit o for the cell on the +x
// side when o & 1, else -x (likewise y with 2, z with 4).
PB_CONSTANT(uint, GRID_POINT_PROBE_MASK, 0x00FFFFFFu);
PB_CONSTANT(uint, GRID_POINT_NO_PROBE, 0x00FFFFFFu);
PB_CONSTANT(uint, GRID_POINT_CELLS_SHIFT, 24u);
// GridPoint::reach: how far the probe sees along +x, -x, +y, -y, +z, -z (five bits each from bit 0), in 1/31 of
// the axis's spacing, rounded down; GRID_REACH_STEPS: no surface within a spacing. Bits 30-31 are zero.
PB_CONSTANT(uint, GRID_REACH_BITS, 5u);
PB_CONSTANT(uint, GRID_REACH_STEPS, 31u);

struct GridLatticeHeader {
  vec3 origin;    // offset  0: minimum corner of the grid's box, world space
  int resolution; // offset 12: n, points per axis (2..GRID_MAX_RESOLUTION)
  vec3 spacing;   // offset 16: distance between neighbouring points per axis (> 0)
  int pad0;       // offset 28
};                // size 32 = GRID_LATTICE_HEADER_WORDS words

struct GridPoint {
  uint probe_cells; // offset 0: see above
  uint reach;       // offset 4: see above
};                  // size 8 = GRID_POINT_WORDS words

// ---- Runtime lighting (format 1.1, optional sections) ------------------------------------------------------
// What the runtime's light update (thesis §3.2.2) needs to reproduce the bake's lighting on any Vulkan
// device without ray-tracing extensions: the static triangles in a BVH of our own layout (built with
// Embree's rtcBuildBVH), the punctual lights, the emitter patches, the ray directions and the settings.
// docs/LIGHTING.md defines the lighting, docs/FORMAT.md the sections.
PB_CONSTANT(int, BVH_MAX_LEAF_TRIANGLES, 4);
PB_CONSTANT(int, BVH_MAX_DEPTH, 48); // traversal stack size in the shaders; the builder stays below it

// Binary BVH, root at 0. Inner node (count == 0): children at first and first + 1, first > this node's
// index. Leaf (count > 0): trace_triangles[first, first + count).
struct BvhNode {
  vec3 lower; // offset  0: bounding box minimum
  int first;  // offset 12
  vec3 upper; // offset 16: bounding box maximum
  int count;  // offset 28: 0 = inner node, 1..BVH_MAX_LEAF_TRIANGLES = leaf
};            // size 32

// TraceTriangle::flags and EmitterPatch::flags (format 1.2; other bits are zero). A double-sided
// triangle (glTF doubleSided) reflects and emits from both sides, its back shaded with the reversed
// normal; only the back of a single-sided triangle is the inside of a solid (docs/LIGHTING.md).
PB_CONSTANT(uint, TRIANGLE_DOUBLE_SIDED, 1u);
// A double-sided emitter patch lights shading points on both sides of its plane.
PB_CONSTANT(uint, EMITTER_DOUBLE_SIDED, 1u);

// A scene triangle as the shaders trace it, in BVH leaf order (Moller-Trumbore on v0, edge1, edge2).
struct TraceTriangle {
  vec3 v0;       // offset  0
  int source;    // offset 12: index of the triangle in the bake's flattened scene (diagnostics)
  vec3 edge1;    // offset 16: v1 - v0
  uint flags;    // offset 28: TRIANGLE_DOUBLE_SIDED
  vec3 edge2;    // offset 32: v2 - v0
  float pad1;    // offset 44
  vec3 normal;   // offset 48: unit geometric normal of the counter-clockwise front face
  float pad2;    // offset 60
  vec3 albedo;   // offset 64: diffuse albedo (texture averaged over the triangle)
  float pad3;    // offset 76
  vec3 emission; // offset 80: emitted radiance, W/(m^2 sr)
  float pad4;    // offset 92
};               // size 96

// ---- Compact tracing (format 1.4): what the shaders trace -----------------------------------------------
// 1.1-1.3 files stored BvhNode and TraceTriangle above (96 B per triangle plus 32 B per node); the runtime
// upgrades them on load (formats/trace_mesh.h). From 1.4 the bake writes the scene as shared vertices,
// 16 B faces, a material table and a tree whose child boxes are quantised to 16 bits in the tree's frame,
// rounded outwards so that no box ever culls its contents. Positions stay exact floats: hits are the
// same as with the float layout.
PB_CONSTANT(int, TRACE_MAX_LEAF_FACES, 8);
PB_CONSTANT(uint, TRACE_BOX_STEPS, 65535u); // quantised coordinate q: frame lower + q * frame scale
// A child word (TraceNode::child, TraceTree::root): an inner node's index (bit 31 clear), or a leaf of
// faces [first, first + count) with bit 31 set, count - 1 in bits 27-30 and first in bits 0-26.
PB_CONSTANT(uint, TRACE_CHILD_LEAF, 0x80000000u);
PB_CONSTANT(uint, TRACE_LEAF_COUNT_SHIFT, 27u);
PB_CONSTANT(uint, TRACE_LEAF_FIRST_MASK, 0x07FFFFFFu);
PB_CONSTANT(uint, TRACE_NO_ROOT, 0xFFFFFFFFu);           // TraceTree::root of a tree without faces
PB_CONSTANT(uint, TRACE_FACE_DOUBLE_SIDED, 0x80000000u); // TraceFace::material bit 31 (glTF doubleSided)
PB_CONSTANT(uint, TRACE_MATERIAL_MASK, 0x7FFFFFFFu);

// One BVH: tree 0 is the static geometry (root TRACE_NO_ROOT without static faces), tree 1 + o dynamic
// object o, in its own frame. Every box of the tree is quantised in this frame; the root's box is
// [lower, lower + TRACE_BOX_STEPS * scale].
struct TraceTree {
  vec3 lower;     // offset  0: frame origin, the minimum corner of the tree's faces
  uint root;      // offset 12: child word of the root
  vec3 scale;     // offset 16: frame step per axis (0 on an axis where the tree is flat)
  int node_count; // offset 28: its nodes are trace_nodes[root, root + node_count) (0 when the root is a leaf)
};                // size 32

// An inner node: its two children's boxes and child words. lower[axis] holds child 0's quantised minimum
// in bits 0-15 and child 1's in bits 16-31; upper likewise. Children that are nodes have larger indices.
struct TraceNode {
  uint lower[3]; // offset  0
  uint upper[3]; // offset 12
  uint child[2]; // offset 24
};               // size 32

// A triangle: three indices into trace_vertices (counter-clockwise front face) and its material word
// (index into trace_materials | TRACE_FACE_DOUBLE_SIDED).
struct TraceFace {
  uint vertex[3]; // offset  0
  uint material;  // offset 12
};                // size 16

// A vertex, shared by the faces of a tree (std430 array stride 12).
struct TraceVertex {
  float x, y, z;
};

// A face's surface: the triangle's diffuse albedo (its texture averaged over it) and emission.
struct TraceMaterial {
  vec3 albedo;   // offset  0
  float pad0;    // offset 12
  vec3 emission; // offset 16: emitted radiance, W/(m^2 sr)
  float pad1;    // offset 28
};               // size 32

PB_CONSTANT(int, LIGHT_POINT, 0);
PB_CONSTANT(int, LIGHT_SPOT, 1);
PB_CONSTANT(int, LIGHT_DIRECTIONAL, 2);

// A KHR_lights_punctual light (docs/LIGHTING.md: range window, spot falloff, radiometric units).
struct PunctualLight {
  vec3 position;    // offset  0: world space (point, spot)
  int type;         // offset 12: LIGHT_*
  vec3 direction;   // offset 16: unit direction the light travels (spot, directional)
  float range;      // offset 28: 0 = infinite
  vec3 intensity;   // offset 32: colour * intensity, W/sr (point, spot) or W/m^2 (directional)
  float cos_outer;  // offset 44: cos(outer cone angle) (spot)
  float spot_scale; // offset 48: 1 / max(0.001, cos(inner) - cos(outer)) (spot)
  float pad0;       // offset 52
  float pad1;       // offset 56
  float pad2;       // offset 60
};                  // size 64

// A sub-triangle of an emissive triangle, lit as an area light at shading points (docs/LIGHTING.md).
struct EmitterPatch {
  vec3 a;        // offset  0: vertices, counter-clockwise seen from the (front) emitting side
  uint flags;    // offset 12: EMITTER_DOUBLE_SIDED (emits from the back too)
  vec3 b;        // offset 16
  uint emitter;  // offset 28: the emitter it belongs to, numbered by first patch (1.10; FrameInputs::emitters)
  vec3 c;        // offset 32
  int material;  // offset 44: that emitter's glTF material (1.10)
  vec3 normal;   // offset 48: unit normal of the front (emitting) side
  float pad3;    // offset 60
  vec3 radiance; // offset 64: W/(m^2 sr)
  float pad4;    // offset 76
};               // size 80

// The bake's lighting settings and the counts of the lighting sections.
struct LightingInfo {
  vec3 sky_radiance;      // offset  0: radiance of rays that leave the scene
  int rays;               // offset 12: lighting rays per probe = ray_directions[0, rays) (Fibonacci)
  float shadow_offset;    // offset 16: shadow-ray origin offset along the normal (1e-4 x scene extent)
  int emissive_as_lights; // offset 20: 1 = emitters lit through emitter_patches, probes leave out L_e
  int bvh_nodes;          // offset 24: BvhNode elements
  int triangles;          // offset 28: TraceTriangle elements
  int lights;             // offset 32: PunctualLight elements
  int emitter_patches;    // offset 36: EmitterPatch elements
  int placement_rays;     // offset 40: = surfels_per_probe: ray_directions[rays, rays + placement_rays)
  int dynamic_objects;    // offset 44: DynamicObject elements (format 1.3; 0 = every triangle is static)
};                        // size 48

// ---- Dynamic objects (format 1.3, optional section) ----------------------------------------------------------
// A glTF node marked dynamic (node extras {"probebake": {"dynamic": true}}, or `probebake bake --dynamic NAME`)
// moves at run time with a transform the host gives every frame (runtime.h FrameInputs::object_poses). Its
// subtree's triangles are stored in its own frame (object space: the node's world transform at rest, which
// the bake used for placement and lighting), with a BVH of their own, after the static ones: bvh_nodes =
// static nodes, then each object's nodes; trace_triangles likewise. The static BVH is
// bvh_nodes[0, static_bvh_nodes) with static_bvh_nodes = dynamic_objects ? objects[0].bvh_root : bvh_nodes.
// An object's BvhNode::first indices are absolute (into the whole arrays), like the static ones.
struct DynamicObject {
  vec3 lower;         // offset  0: object-space bounding box of its triangles
  int bvh_root;       // offset 12: its root in bvh_nodes; its nodes are [bvh_root, bvh_root + bvh_node_count)
  vec3 upper;         // offset 16
  int bvh_node_count; // offset 28
  int first_triangle; // offset 32: its triangles are trace_triangles[first_triangle, + triangle_count)
  int triangle_count; // offset 36
  int gltf_node;      // offset 40: index of the dynamic node in the glTF's nodes (how a host finds it)
  int pad0;           // offset 44
  vec4 rest_rows[3];  // offset 48: world_from_object at rest, the rows of an affine 3x4 matrix
};                    // size 96

#ifdef __cplusplus
static_assert(sizeof(Probe) == 144 && alignof(Probe) == 4);
static_assert(offsetof(Probe, link) == 12 && offsetof(Probe, node) == 16 && offsetof(Probe, depth) == 20);
static_assert(offsetof(Probe, hit_fraction) == 24 && offsetof(Probe, irradiance_sh) == 32);
static_assert(sizeof(Surfel) == 64 && offsetof(Surfel, normal) == 16 && offsetof(Surfel, flags) == 28);
static_assert(offsetof(Surfel, albedo) == 32 && offsetof(Surfel, radiance) == 48);
static_assert(sizeof(SurfelBatch) == 16 + 64 * SURFELS_PER_BATCH && offsetof(SurfelBatch, surfels) == 16);
static_assert(sizeof(LeafEntry) == 8 && sizeof(LeafQueueHeader) == 32);
static_assert(sizeof(SvoLeaf) == 32 && offsetof(SvoLeaf, weights) == 16);
static_assert(sizeof(VolumeInfo) == 80 && offsetof(VolumeInfo, placement) == 16);
static_assert(sizeof(GridLatticeHeader) == 4 * GRID_LATTICE_HEADER_WORDS && offsetof(GridLatticeHeader, spacing) == 16);
static_assert(sizeof(GridPoint) == 4 * GRID_POINT_WORDS && offsetof(GridPoint, reach) == 4);
static_assert(offsetof(VolumeInfo, probe_capacity) == 48 && offsetof(VolumeInfo, svo_leaves) == 64);
static_assert(sizeof(BvhNode) == 32 && offsetof(BvhNode, upper) == 16 && offsetof(BvhNode, count) == 28);
static_assert(sizeof(TraceTriangle) == 96 && offsetof(TraceTriangle, normal) == 48 &&
              offsetof(TraceTriangle, emission) == 80);
static_assert(offsetof(TraceTriangle, flags) == 28 && offsetof(EmitterPatch, flags) == 12);
static_assert(sizeof(TraceTree) == 32 && offsetof(TraceTree, root) == 12 && offsetof(TraceTree, node_count) == 28);
static_assert(sizeof(TraceNode) == 32 && offsetof(TraceNode, upper) == 12 && offsetof(TraceNode, child) == 24);
static_assert(sizeof(TraceFace) == 16 && offsetof(TraceFace, material) == 12 && sizeof(TraceVertex) == 12);
static_assert(sizeof(TraceMaterial) == 32 && offsetof(TraceMaterial, emission) == 16);
static_assert(sizeof(PunctualLight) == 64 && offsetof(PunctualLight, intensity) == 32 &&
              offsetof(PunctualLight, spot_scale) == 48);
static_assert(sizeof(EmitterPatch) == 80 && offsetof(EmitterPatch, normal) == 48 &&
              offsetof(EmitterPatch, radiance) == 64);
static_assert(sizeof(LightingInfo) == 48 && offsetof(LightingInfo, shadow_offset) == 16 &&
              offsetof(LightingInfo, placement_rays) == 40);
static_assert(offsetof(LightingInfo, dynamic_objects) == 44);
static_assert(sizeof(DynamicObject) == 96 && offsetof(DynamicObject, first_triangle) == 32 &&
              offsetof(DynamicObject, rest_rows) == 48);
#endif
PB_GPU_END

#endif // PROBEBAKE_GPU_TYPES_H
