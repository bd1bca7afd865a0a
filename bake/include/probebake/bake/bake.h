// The bake: probe placement (adaptive octree or uniform grid), dead-probe relocation and the SVO probe
// index, producing the canonical ProbeVolume that the .probes writer stores.
//
// Units: metres (glTF). Deterministic: the same scene and settings give the same volume for any thread
// count (work is split per probe / per voxel and results are combined in index order).
#pragma once

#include <chrono>
#include <cstdint>
#include <ctime>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "probebake/common/lattice.h"
#include "probebake/lighting/lighting.h"
#include "probebake/scene/scene.h"
#include "probebake/formats/placement_kind.h"
#include "probebake/formats/probe_volume.h"

namespace probebake::bake {

// The placement methods and their properties: formats/placement_kind.h (one table for bake, CLI, info).
using Placement = formats::PlacementKind;

// When an octree leaf splits: the thesis's hit fraction of its centre probe (split_low/split_high); or,
// under a probe budget (refine_octree.h), where a split removes the most estimated interpolation error
// (error) or gives each new probe the most visible surface (surface).
enum class SplitRule { hit_fraction, error, surface };

struct BakeSettings {
  Placement placement = Placement::octree;
  int max_depth = 4;           // octree: deepest level a node may split to (root = 0), at most 12
  int surfels_per_probe = 128; // lattice points traced per probe
  Lattice lattice = Lattice::fibonacci;
  float split_low = 0.25f; // hit fraction below which a probe is freed
  float split_high = 0.5f; // hit fraction at or above which a node splits
  SplitRule split_rule = SplitRule::hit_fraction;
  int probe_budget = 0;       // probes at most (placed, before dead ones are freed): the octree's error/surface
                              // rule (>= 1), the skeleton (0 = the fewest that see every surface sample)
  float uniform_share = 0.5f; // error/surface rule: share of the budget a uniform start may take, in [0, 1]
  int grid_resolution = 16;   // grid: N for N^3 probes
  int svo_depth = 5;          // SVO leaf depth (voxels of root_size / 2^svo_depth)
  float clearance = 0.0f;     // minimum probe-to-surface distance; 0 = 2% of the scene's largest extent
  int threads = 0;            // 0 = all cores
  bool store_surfels = false; // write the surfel batches (for runtime updates of dynamic scenes)
  int cell_depth = 1;         // streaming cells: (2^cell_depth)^3
  float cell_size = 0.0f;     // > 0: cells at most this wide (metres), the shallowest such depth
                              // replaces cell_depth once the root cube is known
  lighting::LightingSettings lighting; // probe irradiance (lighting.h); its `threads` is replaced by `threads`
  // Write the runtime lighting sections (format 1.1: BVH, trace triangles, lights, emitter patches, ray
  // directions, LightingInfo) so that a GPU runtime can reproduce `lighting` without ray-tracing
  // extensions. Also when lighting.enabled is false (the runtime can then light from zero).
  bool runtime_lighting = true;
  // SAH cost of a triangle test relative to a node visit in the runtime's trees: lower makes fewer, larger
  // leaves (smaller files, slower GPU traces). 0.35: 28 B per triangle on the generated rooms, 1: 38 B and
  // 20 % faster light_trace on an H100 (docs/results/tracing.md "Compact tracing data: bytes per triangle and
  // trace time (issue #14)").
  float trace_leaf_cost = 0.35f;
};

// Throws Error(usage) with a message naming the option when a setting is out of range.
void check_settings(const BakeSettings& settings);

// The cell depth a bake uses in a root cube of `root_size` metres: settings.cell_depth, or with cell_size > 0
// the shallowest depth whose cells are at most cell_size wide. Throws Error(usage) when even the deepest
// grid (kMaxCellDepth) has wider cells.
int cell_depth_for(const BakeSettings& settings, float root_size);

// The VolumeInfo a bake of `scene` with `settings` starts from: the root cube and the placement settings
// (counts zero). The runtime's tree update and its benchmark start from the same root.
gpu::VolumeInfo volume_info(const scene::Scene& scene, const BakeSettings& settings);

struct StageTime {
  std::string stage;
  double seconds = 0.0;     // wall clock
  double cpu_seconds = 0.0; // process CPU time, all threads: what the stage costs whatever else runs on the machine
};

// Wall and process CPU time from construction to stop(): the bake's stages, and the CLI's load and write.
class StageClock {
public:
  StageClock();
  StageTime stop(std::string stage) const;

private:
  std::chrono::steady_clock::time_point wall_;
  std::clock_t cpu_;
};

// The runtime lighting sections of a bake (stage "gpu_scene"), when settings.runtime_lighting.
struct RuntimeLightingReport {
  bool written = false;
  int bvh_nodes = 0;          // inner nodes of the compact trees
  int bvh_depth = 0;          // deepest BVH node (root = 0), below gpu::BVH_MAX_DEPTH
  int triangles = 0;          // trace faces
  int left_out_triangles = 0; // zero-area triangles (never hit) left out of the BVH
  int lights = 0;
  int emitter_patches = 0;
  int dynamic_objects = 0;       // format 1.3: objects moved by the host, each with its own BVH
  int vertices = 0;              // shared trace vertices (format 1.4)
  int materials = 0;             // distinct (albedo, emission) pairs
  std::size_t bytes = 0;         // payload bytes of the lighting sections
  std::size_t tracing_bytes = 0; // of which the tracing sections (trees, nodes, faces, vertices, materials)
  double bvh_seconds = 0.0;      // rtcBuildBVH, flattening and compaction
};

struct BakeReport {
  int probes = 0;                   // live probes in the file
  int placed_probes = 0;            // probes placed before dead ones were freed
  std::vector<int> depth_histogram; // probes per octree depth (grid: all at depth 0)
  int leaves = 0;
  int sealed_triangles = 0; // inside solids, unseen from open space: ignored by placement and lighting
  int dead_probes = 0;      // probes found inside geometry or closer than the clearance
  int moved_probes = 0;
  int freed_probes = 0; // dead probes that could not be moved out
  int svo_nodes = 0;
  int svo_leaves = 0;
  int svo_solid_voxels = 0;     // leaf-depth voxels left out: inside geometry
  int svo_uncovered_voxels = 0; // leaf-depth voxels from which no probe is visible (left empty)
  float clearance = 0.0f;       // the clearance actually used
  int cell_depth = 0;           // the streaming cell grid used: (2^cell_depth)^3 cells of cell_size
  float cell_size = 0.0f;
  bool surrounded_root = false;      // no open space inside the scene bounds: root cube tripled around them
                                     // (the grid covers that cube)
  lighting::LightingReport lighting; // when settings.lighting.enabled
  RuntimeLightingReport runtime_lighting;
  std::vector<StageTime> stages;
};

struct BakeResult {
  formats::ProbeVolume volume;
  BakeReport report;
};

// Progress: stage name and fraction done in [0, 1]; called from the calling thread only.
using ProgressCallback = std::function<void(const std::string& stage, double fraction)>;

// Work that parts of a split bake did beforehand (bake_parts.h merge_parts): the bake takes it instead of
// doing it, and the result is the same bytes.
struct PrecomputedWork {
  std::vector<char> sealed; // placement/sealed.h sealed_triangles of every scene triangle
};

BakeResult bake(const scene::Scene& scene, const BakeSettings& settings, const ProgressCallback& progress = {},
                const PrecomputedWork* precomputed = nullptr);

// Hash of everything that determines the bake's output: the scene's geometry and materials and the
// settings (not the thread count).
std::uint64_t bake_input_hash(const scene::Scene& scene, const BakeSettings& settings);

} // namespace probebake::bake
