// Error against run time: bakes a scene with a sweep of settings and compares each volume's irradiance
// (punctual direct light + the probe lookup, lookup.h) with the path-traced reference (reference.h) at
// fixed, seeded surface points.
//
// The reference is computed once and cached beside the scene as `<scene>.reference.<hash>.csv` (the same
// columns as `probebake reference --csv`), keyed by a hash of the scene's geometry, materials and lights,
// the point count, seed and paths per point; a cache that cannot be written only costs the next run time.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "probebake/bake/bake.h"
#include "probebake/eval/flip.h"
#include "probebake/eval/reference.h"

namespace probebake::bake {

// ---- Receivers: where eval measures -------------------------------------------------------------------
// visible (default): first hits of uniformly random rays from viewpoints in the open space of the scene
//   bounds (cell centres where a probe would not be dead at the bake's clearance), restricted to the
//   player's open regions (README "Receivers"); front faces only, with open space in front of them.
// volume: points in that open space with random normals (where dynamic objects sample probes).
// area: the old points spread over every front face by area, minus points inside geometry.
enum class ReceiverMode { visible, volume, area };
std::string_view receiver_mode_name(ReceiverMode mode);
std::optional<ReceiverMode> parse_receiver_mode(std::string_view name);

struct ReceiverSettings {
  ReceiverMode mode = ReceiverMode::visible;
  int count = 1000;
  std::uint64_t seed = 1;
  float clearance = 0.0f;              // viewpoints' distance from surfaces; 0 = the bake's default (2% of the size)
  int cells = 32;                      // viewpoint cells along the largest axis of the scene bounds
  std::vector<glm::vec3> anchors = {}; // camera positions: the open regions holding them are the player's
  int threads = 0;
};

struct Receivers {
  std::vector<SamplePoint> points; // fewer than asked only when the open space sees almost nothing
  int viewpoints = 0;              // open cells in the kept regions (0 for area receivers)
  int regions = 0;                 // open regions kept, of open_regions
  int open_regions = 0;
};

// Same (scene, settings) -> same receivers, for any thread count.
Receivers make_receivers(const scene::Scene& scene, const scene::RayScene& rays, const ReceiverSettings& settings);

struct EvalConfig {
  std::string label; // unique, file-name safe (error maps are named after it)
  BakeSettings bake;
  int asked_probes = 0;  // the ladder rung this configuration was chosen for (0: not from a ladder)
  std::string budget_by; // how it meets the rung: "grid resolution" or "probe budget" (empty: not from a ladder)
};

// Octree max depth 2..5; grid 5, 8, 12, 16, 21; 64 and 256 surfels at depth 4; latlong and equal-area
// lattices at depth 4 (the depth-4 / 128 / fibonacci configuration appears once).
std::vector<EvalConfig> default_sweep();
// Three small configurations, for tests.
std::vector<EvalConfig> quick_sweep();
// The settings of quick_sweep's bakes (small SVO and lighting), for ladders in tests.
BakeSettings quick_bake_settings();

// The probe ladder (`--probes 64,128,...`): for each rung and each placement method whose kinds-table row
// says meets_probe_budget, one configuration of `base` baked to about that many live probes (after dead
// probes are freed). Methods with a grid resolution take the resolution whose live count is nearest the
// rung (counted by placement-only bakes, no lighting, no SVO, walking the resolution one step at a time from
// a guess until the count crosses the rung; ties go to fewer probes); the others (the octree with the error
// rule at max depth >= 6, the skeleton) take the rung as BakeSettings::probe_budget. A rung whose configuration equals a lower rung's of the same
// method is left out (it would be the same bake). Deterministic, as the bakes are.
std::vector<EvalConfig> ladder_sweep(const scene::Scene& scene, std::span<const int> probes, const BakeSettings& base);

struct EvalSettings {
  int points = 1000;
  int paths = 4096;                // reference paths per point (about 1.5% noise per point on the Cornell box)
  std::uint64_t seed = 1;          // sample points and reference
  int threads = 0;                 // bakes and reference; 0 = all cores (sampling is timed on one thread)
  std::vector<EvalConfig> configs; // empty: default_sweep(), or the ladder when probe_ladder is set
  std::vector<int> probe_ladder;   // --probes: rungs in 1..kMaxLadderProbes, increasing; needs empty configs
  BakeSettings ladder_base;        // what every ladder configuration starts from
  std::string baseline;            // label of the configuration also sampled with all probes; empty: "octree-d4"
                                   // when swept, else the first octree configuration
  ReceiverMode receivers = ReceiverMode::visible;
  bool use_cache = true;
  std::optional<Camera> camera; // adds image receivers (its visible pixels) and anchors the player's region;
                                // with error_map_dir also per-configuration error images
  std::filesystem::path error_map_dir;
  int image_paths = 64;                            // reference paths per pixel of the error maps
  scene::LoadOptions scene_input = {};             // confinement and memory budget of the scene load
  std::vector<std::filesystem::path> outputs = {}; // checked against every file the load read
};

constexpr int kMaxLadderProbes = 1'000'000;
constexpr std::size_t kMaxLadderRungs = 16;

// Throws Error(usage) naming the option when a setting is out of range.
void check_eval_settings(const EvalSettings& settings);

struct EvalRow {
  std::string label;
  std::string sampler; // "svo" (probe_index::sample_irradiance), "grid" (a grid bake's lattice looked up as grid
                       // engines do, probe_index::sample_irradiance_grid) or "all-probes" (the baseline)
  BakeSettings bake;
  int asked_probes = 0; // EvalConfig::asked_probes and budget_by
  std::string budget_by;
  int probes = 0;
  std::uint64_t file_bytes = 0;   // the .probes file as written by write_probes
  std::uint64_t lookup_bytes = 0; // what the row's lookup keeps on the GPU (formats::lookup_bytes)
  std::uint64_t l2_lookup_bytes = 0, l1_lookup_bytes = 0; // the same with compact probes (0: all-probe loop)
  double bake_seconds = 0.0;
  double sample_ns = 0.0;     // per point, one thread, lookup only (direct light is the same for all rows)
  double rmse = 0.0;          // over points of the RGB RMS error, W/m^2
  double relative_rmse = 0.0; // rmse / mean reference irradiance
  double bias = 0.0;          // (mean estimate - mean reference) / mean reference
  double p95 = 0.0;           // 95th percentile of the per-point RGB RMS error
  double max_error = 0.0;
  double leak_rmse = 0.0; // rmse over points darker than 1% of the mean reference (0 when none)
  int leak_points = 0;
  std::size_t misses = 0;       // lookups that found no probe: scored as what a runtime shows (direct light only)
  double coverage = 0.0;        // fraction of receivers whose lookup found probes
  double relative_median = 0.0; // median and 95th percentile of the per-receiver relative error
  double relative_p95 = 0.0;    //   |error| / max(|reference|, 1% of the mean reference)
  // What a game takes from probes: the lookup alone (probe_index::sample_irradiance) against the reference's indirect
  // part (reference - its direct part, reference.h), relative to the mean indirect reference.
  double indirect_rmse = 0.0;
  double indirect_relative_rmse = 0.0;
  double image_mean_error = 0.0;    // camera receivers: mean over pixels and channels of |error| (the error map's mean)
  double image_relative_rmse = 0.0; // camera receivers: RMSE / their mean reference
  // camera receivers: mean over them of HDR-FLIP (flip.h) between the picture of the estimate and the
  // reference's, black elsewhere; 0 = alike, 1 = as different as green and blue (DIR/<label>.flip.exr's mean)
  double image_flip_mean = 0.0;
  // svo rows: the lookup's seam score (seams.h), 99th percentile of the unexplained jump over the local
  // irradiance along random lines through open space (-1 for the all-probe loop, not measured)
  double seam_p99 = -1.0;
  // The compact probe codes (formats/sh_codec.h), apart from placement: how far the lookup moves when the
  // probes go through the code (RMS over receivers, relative to the mean reference), and the coded lookup's
  // relative RMSE against the reference. -1 where not measured (the all-probe loop).
  double l2_codec_error = -1.0, l1_codec_error = -1.0;
  double l2_relative_rmse = -1.0, l1_relative_rmse = -1.0;
};

struct EvalResult {
  std::filesystem::path scene;
  std::string receivers; // receiver_mode_name
  int viewpoints = 0;    // 0 when the receivers came from the cache or by area
  int points = 0;        // may be below the requested count when most surfaces are hidden
  int image_pixels = 0;  // camera receivers (0 without --camera)
  double image_mean_reference = 0.0;
  FlipExposures image_flip_exposures; // what HDR-FLIP tone maps the camera views at (from the reference)
  int paths = 0;
  std::uint64_t seed = 0;
  double mean_reference = 0.0;          // W/m^2, mean over points and channels
  double reference_noise = 0.0;         // RMS standard error of the reference / mean_reference
  double mean_indirect_reference = 0.0; // W/m^2: the reference minus its direct part, mean over points and channels
  double indirect_noise = 0.0;          // RMS standard error of the indirect part / mean_indirect_reference
  // lighting::direct_irradiance (what a renderer adds per pixel) against the path tracer's direct part, relative to
  // the mean traced direct light: RMSE (holds the traced direct part's noise too) and bias.
  double direct_relative_rmse = 0.0;
  double direct_bias = 0.0;
  double reference_seconds = 0.0; // 0 when read from the cache
  bool reference_from_cache = false;
  std::filesystem::path cache_file;
  bool cache_written = false;
  std::vector<EvalRow> rows; // one per configuration; the all-probes baseline follows its own
  std::vector<std::filesystem::path> error_maps;
};

// Progress messages ("reference", "bake octree-d3", ...), called from the calling thread.
using EvalProgress = std::function<void(const std::string& message)>;

// Throws Error(input) for an unreadable scene, Error(output) when an error map cannot be written.
EvalResult evaluate(const std::filesystem::path& scene, const EvalSettings& settings,
                    const EvalProgress& progress = {});

// Reports.
std::string eval_markdown_table(const EvalResult& result);
void write_eval_csv(const std::filesystem::path& path, const EvalResult& result);
// Relative RMSE against bake time (log axis), the Pareto front of the probe configurations marked; for a
// ladder (rows with asked_probes), relative RMSE against probe count instead: one curve per method, total
// solid and indirect dashed.
std::string eval_svg_plot(const EvalResult& result);
// Quality per byte (issue #41): relative RMSE with the l2 probe code against the lookup's bytes with it (log
// axis), one colour per method (the grid engine one of them), every row a point and each method's Pareto
// front a line.
std::string eval_bytes_svg_plot(const EvalResult& result);
void write_text_file(const std::filesystem::path& path, const std::string& text); // Error(output) on failure

// The cache key: scene geometry, materials and lights, point count, seed, paths per point, receiver mode
// and the anchors that chose the player's region.
std::uint64_t reference_hash(const scene::Scene& scene, int points, std::uint64_t seed, int paths,
                             ReceiverMode mode = ReceiverMode::visible, std::span<const glm::vec3> anchors = {});

} // namespace probebake::bake
