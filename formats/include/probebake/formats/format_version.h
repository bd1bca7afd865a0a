// The .probes format version, defined here and nowhere else. Major: incompatible layout changes (a reader
// refuses other majors). Minor: compatible additions (new optional sections).
#pragma once

#include <cstdint>

namespace probebake::formats {
inline constexpr std::uint16_t kFormatVersionMajor = 1;
inline constexpr std::uint16_t kFormatVersionMinor = 10;
// 1.1 added the optional runtime lighting sections. The writer stamps the lowest minor whose sections a
// file uses (1.0 without lighting sections), so that files without them stay byte-identical to 1.0.
inline constexpr std::uint16_t kLightingSectionsMinor = 1;
// 1.2 gave trace triangles and emitter patches a flags word (bit 0: double-sided) in what was padding.
// A file stamps 1.2 only when a flag is set; a 1.1 validator (and the runtime, which validates on load)
// refuses such a file ("padding is not zero") instead of tracing double-sided surfaces as single-sided.
inline constexpr std::uint16_t kDoubleSidedFlagsMinor = 2;
// 1.3 added the optional dynamic_objects section (objects the host moves at run time) and gave
// LightingInfo's last padding word the count of its elements.
inline constexpr std::uint16_t kDynamicObjectsMinor = 3;
// 1.4 replaced the float tracing sections (bvh_nodes, trace_triangles: 96 B per triangle plus nodes) with
// the compact ones (trace_trees ... trace_materials), marked REQUIRED so that a 1.3 reader refuses the
// file. 1.1-1.3 files still read; the runtime upgrades their tracing sections on load.
inline constexpr std::uint16_t kCompactTracingMinor = 4;
// 1.5 split the static tracing tree by streaming cell (a top level over one subtree per cell) and added the
// optional cell_tracing section naming each cell's nodes, faces and vertices. The tree is an ordinary 1.4
// tree, so a 1.4 reader that skips the section traces the same hits.
inline constexpr std::uint16_t kCellTracingMinor = 5;
// 1.6 added the optional cell_checksums section: an XXH3-64 per cell over its byte ranges, so that a reader
// that loads one cell (or a patcher that replaces one) checks it without reading the whole sections.
inline constexpr std::uint16_t kCellChecksumsMinor = 6;
// 1.7 added the optional cell_global_checksums section: an XXH3-64 of each cell-split section's bytes outside
// every cell's range, so that a streaming load reads and checks only the global part of a file and each cell
// when it arrives (docs/FORMAT.md section 6.2).
inline constexpr std::uint16_t kCellGlobalChecksumsMinor = 7;
// 1.8 added the optional grid_lattice section: a grid bake's lattice (origin, spacing, the probe at each
// point and the cells it serves), so that a lookup finds a grid cell's eight probes by arithmetic.
inline constexpr std::uint16_t kGridLatticeMinor = 8;
// 1.9 added the optional sky section: the radiance map of the rays that leave the scene (an environment or the
// physical sky with its sun), which LightingInfo::sky_radiance scales.
inline constexpr std::uint16_t kSkyMinor = 9;
// 1.10 gave emitter patches the emitter they belong to and its glTF material, in what was padding, so that the
// runtime scales each emissive material's light (FrameInputs::emitters). Stamped only when one is not zero; an
// older file reads as one emitter of material 0.
inline constexpr std::uint16_t kEmitterGroupsMinor = 10;
} // namespace probebake::formats
