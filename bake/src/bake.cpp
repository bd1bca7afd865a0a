// The bake pipeline: settings check, placement, dead-probe relocation, SVO probe index, lighting, the
// runtime lighting sections (gpu_scene), streaming cells.
#include "probebake/bake/bake.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <utility>

#include <fmt/core.h>
#include <glm/geometric.hpp>
#include <xxhash.h>

#include "probebake/common/parallel.h"
#include "probebake/placement/placement.h"
#include "probebake/placement/refine_root.h"
#include "probebake/placement/sealed.h"
#include "probebake/placement/relocation.h"
#include "bake_checks.h"
#include "probebake/probe_index/build.h"
#include "probebake/bake/gpu_scene.h"
#include "probebake/scene/ray_scene.h"
#include "probebake/placement/scene_sdf.h"
#include "probebake/formats/cells.h"
#include "probebake/formats/error.h"
#include "probebake/formats/grid_lattice.h"
#include "probebake/formats/octree.h"
#include "probebake/formats/validate.h"

namespace probebake::bake {
namespace {

class StageTimer {
public:
  explicit StageTimer(BakeReport& report) : report_(report) {}
  void stage(const std::string& name) {
    if (!current_.empty()) report_.stages.push_back(clock_.stop(current_));
    current_ = name;
    clock_ = StageClock();
  }

private:
  BakeReport& report_;
  std::string current_;
  StageClock clock_;
};

float effective_clearance(const scene::Scene& scene, const BakeSettings& s) {
  return s.clearance > 0.0f ? s.clearance : placement::default_clearance(scene);
}

// Moves or frees every dead probe; grid probes without a valid position are freed too.
void relocate_dead_probes(const placement::RelocationContext& ctx, std::vector<placement::PlacedProbe>& placed,
                          formats::Octree& tree, int threads, BakeReport& report) {
  std::vector<std::size_t> dead;
  for (std::size_t i = 0; i < placed.size(); ++i)
    if (placement::is_dead(placed[i].rays, ctx.clearance)) dead.push_back(i);
  std::vector<std::optional<glm::vec3>> moved(dead.size());
  parallel_for(dead.size(), threads, [&](std::size_t k) {
    const auto& p = placed[dead[k]];
    moved[k] = placement::relocate_probe(ctx, tree.volume().probes[std::size_t(p.probe)].position, p.rays, p.cube);
  });
  report.dead_probes = int(dead.size());
  for (std::size_t k = 0; k < dead.size(); ++k) {
    const int probe = placed[dead[k]].probe;
    if (moved[k]) {
      tree.volume().probes[std::size_t(probe)].position = *moved[k];
      ++report.moved_probes;
    } else {
      tree.free_probe(probe);
      ++report.freed_probes;
    }
  }
}

// Traces the final probe positions once more and stores their surfels in batch chains (for runtimes that
// update lighting or placement of dynamic scenes).
void store_surfels(const scene::RayScene& rays, const std::vector<glm::vec3>& directions,
                   const std::vector<placement::PlacedProbe>& placed, formats::Octree& tree, int threads) {
  std::vector<std::vector<gpu::Surfel>> surfels(placed.size());
  parallel_for(placed.size(), threads, [&](std::size_t i) {
    const gpu::Probe& p = tree.volume().probes[std::size_t(placed[i].probe)];
    if (p.link != 0) placement::trace_probe(rays, p.position, placed[i].cube, directions, &surfels[i]);
  });
  for (std::size_t i = 0; i < placed.size(); ++i) {
    const int probe = placed[i].probe;
    if (tree.volume().probes[std::size_t(probe)].link == 0) continue; // freed as dead
    for (std::size_t first = 0; first < surfels[i].size(); first += gpu::SURFELS_PER_BATCH) {
      const int batch = tree.append_surfel_batch(probe);
      gpu::SurfelBatch& b = tree.volume().surfel_batches[std::size_t(batch)];
      b.first = int(first);
      b.count = int(std::min<std::size_t>(gpu::SURFELS_PER_BATCH, surfels[i].size() - first));
      for (int k = 0; k < b.count; ++k) b.surfels[k] = surfels[i][first + std::size_t(k)];
    }
  }
}

// A grid bake's lattice (format 1.8, grid_lattice.h): a method that uses the grid resolution places lattice
// point i as placed[i]. Left out where the grid's box is flat (a spacing of 0: a lone triangle's bounds) or N is
// outside the section's 2..255.
void add_grid_lattice(const scene::RayScene& rays, const BakeSettings& s, const scene::Bounds& bounds,
                      const std::vector<placement::PlacedProbe>& placed, formats::ProbeVolume& volume,
                      StageTimer& timer) {
  if (!formats::placement_kind_info(s.placement).uses_grid_resolution || s.grid_resolution < 2 ||
      s.grid_resolution > gpu::GRID_MAX_RESOLUTION)
    return;
  const gpu::GridLatticeHeader frame = formats::grid_lattice_frame(bounds.min, bounds.max, s.grid_resolution);
  if (!(frame.spacing.x > 0.0f && frame.spacing.y > 0.0f && frame.spacing.z > 0.0f)) return;
  timer.stage("lattice");
  std::vector<int> lattice_probes(placed.size());
  for (std::size_t i = 0; i < placed.size(); ++i) lattice_probes[i] = placed[i].probe;
  probe_index::build_grid_lattice(rays, volume, frame, lattice_probes, s.threads);
}

// What the placement methods read of the settings (placement/placement.h), with the bake's progress as "place".
placement::PlacementInput placement_input(const scene::RayScene& rays, const BakeSettings& s, float clearance,
                                          const ProgressCallback& progress) {
  placement::PlacementInput in;
  in.rays = &rays;
  in.settings = {s.max_depth, s.split_low, s.split_high, s.grid_resolution, s.threads, s.probe_budget};
  in.refine = {.probe_budget = s.split_rule == SplitRule::hit_fraction ? 0 : s.probe_budget,
               .rank_by_error = s.split_rule == SplitRule::error,
               .uniform_share = s.uniform_share,
               .lighting = s.lighting};
  in.directions = lattice_directions(s.lattice, s.surfels_per_probe);
  in.clearance = clearance;
  if (progress) in.progress = [&progress](double fraction) { progress("place", fraction); };
  return in;
}

// The narrow band must reach past the clearance the relocation asks for (1.5x), or push_out cannot
// confirm it.
placement::SdfSettings sdf_settings(const scene::Scene& scene, float clearance) {
  const float voxel = glm::length(scene.bounds.max - scene.bounds.min) / 256.0f;
  placement::SdfSettings settings;
  if (voxel > 0.0f) settings.band_voxels = std::max(3.0f, std::ceil(1.5f * clearance / voxel) + 1.0f);
  return settings;
}

// The octree's buffers grow by doubling while placing; the file keeps no unused capacity (the runtime
// allocates its own). arrange_cells has moved free probes and batches behind every cell's elements.
void trim_trailing_free(formats::ProbeVolume& v) {
  while (!v.probes.empty() && v.probes.back().link == 0) v.probes.pop_back();
  while (!v.surfel_batches.empty() && v.surfel_batches.back().link == 0) v.surfel_batches.pop_back();
  const auto free_cluster_at_end = [&] {
    if (v.octree.size() < 10 || (v.octree.size() - 1) % 9 != 0) return false;
    return std::all_of(v.octree.end() - 9, v.octree.end(), [](std::int32_t e) { return e == 0; });
  };
  while (free_cluster_at_end()) v.octree.resize(v.octree.size() - 9);
  formats::sync_info_counts(v);
  formats::rebuild_probe_index(v);
}

void fill_report(const formats::ProbeVolume& v, BakeReport& report) {
  report.depth_histogram.assign(std::size_t(std::max(v.info.max_depth, 0) + 1), 0);
  for (const gpu::Probe& p : v.probes) {
    if (p.link == 0) continue;
    ++report.probes;
    if (p.depth >= 0 && std::size_t(p.depth) < report.depth_histogram.size())
      ++report.depth_histogram[std::size_t(p.depth)];
  }
  formats::for_each_leaf(v, [&](const formats::NodeCube&) { ++report.leaves; });
  report.svo_nodes = int(v.svo_nodes.size());
  report.svo_leaves = int(v.svo_leaves.size());
}

} // namespace

StageClock::StageClock() : wall_(std::chrono::steady_clock::now()), cpu_(std::clock()) {}

StageTime StageClock::stop(std::string stage) const {
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_).count();
  const double cpu = double(std::clock() - cpu_) / CLOCKS_PER_SEC;
  return {std::move(stage), wall, cpu};
}

// The root cube is the scene bounds' bounding cube, padded so that surfaces on the bounds are inside, and
// by the method's root_pad_clearances.
gpu::VolumeInfo volume_info(const scene::Scene& scene, const BakeSettings& s) {
  gpu::VolumeInfo info{};
  const formats::PlacementKindInfo& kind = formats::placement_kind_info(s.placement);
  const float largest = scene.bounds.largest_extent();
  const float pad = kind.root_pad_clearances > 0.0f && largest > 0.0f
                        ? 2.0f * kind.root_pad_clearances * effective_clearance(scene, s)
                        : 0.0f;
  const float size = largest > 0.0f ? largest * 1.002f + pad : 1.0f;
  info.root_min = 0.5f * (scene.bounds.min + scene.bounds.max) - glm::vec3(0.5f * size);
  info.root_size = size;
  info.placement = kind.file_code;
  info.max_depth = kind.uses_max_depth ? s.max_depth : 0;
  info.svo_depth = s.svo_depth;
  info.lattice = int(s.lattice);
  info.surfels_per_probe = s.surfels_per_probe;
  info.split_low = s.split_low;
  info.split_high = s.split_high;
  info.grid_resolution = kind.uses_grid_resolution ? s.grid_resolution : 0;
  return info;
}

std::uint64_t bake_input_hash(const scene::Scene& scene, const BakeSettings& s) {
  XXH3_state_t* state = XXH3_createState();
  XXH3_64bits_reset(state);
  auto add = [&](const void* data, std::size_t size) { XXH3_64bits_update(state, data, size); };
  add(scene.positions.data(), scene.positions.size() * sizeof(glm::vec3));
  add(scene.triangles.data(), scene.triangles.size() * sizeof(glm::uvec3));
  add(scene.triangle_albedo.data(), scene.triangle_albedo.size() * sizeof(glm::vec3));
  add(scene.triangle_emission.data(), scene.triangle_emission.size() * sizeof(glm::vec3));
  for (const auto& l : scene.lights) {
    const float values[] = {float(int(l.type)), l.color.x,    l.color.y,          l.color.z,         l.intensity,
                            l.position.x,       l.position.y, l.position.z,       l.direction.x,     l.direction.y,
                            l.direction.z,      l.range,      l.inner_cone_angle, l.outer_cone_angle};
    add(values, sizeof(values));
  }
  const std::int32_t ints[] = {int(s.placement),           s.max_depth,       s.surfels_per_probe,     int(s.lattice),
                               s.grid_resolution,          s.svo_depth,       s.store_surfels ? 1 : 0, s.cell_depth,
                               s.runtime_lighting ? 1 : 0, int(s.split_rule), s.probe_budget};
  const float floats[] = {s.split_low, s.split_high, s.clearance, s.uniform_share, s.trace_leaf_cost};
  add(ints, sizeof(ints));
  add(floats, sizeof(floats));
  const auto& l = s.lighting;
  const std::int32_t lighting_ints[] = {
      l.enabled ? 1 : 0, l.rays, l.max_iterations, l.accelerate ? 1 : 0, l.emissive_as_lights ? 1 : 0,
      l.emitter_samples};
  add(lighting_ints, sizeof(lighting_ints));
  add(&l.tolerance, sizeof(l.tolerance));
  add(&scene.sky.colour, sizeof(scene.sky.colour)); // the sky lights the probes like the lights above
  add(&scene.sky.kind, sizeof(scene.sky.kind));
  add(scene.sky.map.texels.data(), scene.sky.map.texels.size() * sizeof(glm::vec3));
  const std::uint64_t hash = XXH3_64bits_digest(state);
  XXH3_freeState(state);
  return hash;
}

int cell_depth_for(const BakeSettings& s, float root_size) {
  if (!(s.cell_size > 0.0f)) return s.cell_depth;
  for (int depth = 0; depth <= formats::kMaxCellDepth; ++depth)
    if (root_size / float(formats::cells_per_axis(depth)) <= s.cell_size) return depth;
  throw Error(ErrorKind::usage,
              fmt::format("--cell-size {:g}: the root cube is {:g} m wide and at most {} cells per axis are supported "
                          "(cells of {:g} m); give a larger size",
                          s.cell_size, root_size, formats::cells_per_axis(formats::kMaxCellDepth),
                          root_size / float(formats::cells_per_axis(formats::kMaxCellDepth))));
}

BakeResult bake(const scene::Scene& scene, const BakeSettings& requested, const ProgressCallback& progress,
                const PrecomputedWork* precomputed) {
  BakeSettings settings = requested; // the cell depth is resolved once the root cube is known
  check_settings(settings);
  detail::check_scene(scene);
  detail::check_clearance(scene, settings);
  const ThreadLimit thread_limit(settings.threads);
  BakeResult result;
  BakeReport& report = result.report;
  StageTimer timer(report);

  // Placement, relocation, the SVO and lighting see only what open space can see (placement/sealed.h); the
  // runtime lighting sections keep every triangle. The sealed test needs the whole scene's BVH, which the
  // later stages need only when nothing is sealed.
  std::optional<scene::RayScene> full_rays;
  std::vector<char> tested; // the flags this bake computes itself, without parts
  if (precomputed && precomputed->sealed.size() != scene.triangles.size())
    throw Error(ErrorKind::internal, "bake: precomputed sealed flags for another triangle count");
  if (!precomputed) {
    timer.stage("bvh");
    full_rays.emplace(scene);
    timer.stage("sealed");
    tested = placement::sealed_triangles(*full_rays, settings.threads);
  }
  const std::vector<char>& sealed = precomputed ? precomputed->sealed : tested;
  const std::optional<scene::Scene> culled = placement::without_sealed(scene, sealed);
  const scene::Scene& visible = culled ? *culled : scene;
  if (precomputed) timer.stage("bvh");
  std::optional<scene::RayScene> culled_rays;
  if (culled) {
    culled_rays.emplace(*culled);
    full_rays.reset(); // only the sealed test traced it: its memory goes before the stages that need the most
  } else if (!full_rays) {
    full_rays.emplace(scene);
  }
  const scene::RayScene& rays = culled_rays ? *culled_rays : *full_rays;
  report.sealed_triangles = int(scene.triangles.size() - visible.triangles.size());
  report.clearance = effective_clearance(scene, settings);
  formats::ProbeVolume& volume = result.volume;
  volume = formats::make_empty_volume(volume_info(scene, settings));
  const placement::PlacementInput input = placement_input(rays, settings, report.clearance, progress);
  // A closed object seen from outside has no open space inside its bounds (placement/refine_root.h): every
  // method then places its probes in the larger root cube around it (the grid over that cube, not the bounds).
  scene::Bounds placement_bounds = scene.bounds;
  if (!placement::open_space_inside(rays, volume.info, scene.bounds, report.clearance, input.directions,
                                    settings.threads)) {
    placement::surround_root(volume.info);
    report.surrounded_root = true;
    placement_bounds = {volume.info.root_min, volume.info.root_min + glm::vec3(volume.info.root_size)};
  }
  settings.cell_depth = cell_depth_for(settings, volume.info.root_size);
  settings.cell_size = 0.0f; // the input hash sees the depth used, whichever way it was asked for
  report.cell_depth = settings.cell_depth;
  report.cell_size = volume.info.root_size / float(formats::cells_per_axis(settings.cell_depth));
  formats::Octree tree(volume);

  timer.stage("place");
  std::vector<placement::PlacedProbe> placed = placement::place(settings.placement, input, tree, placement_bounds);

  report.placed_probes = int(placed.size());
  // The SDF is built only when some probe needs relocating: most clean scenes never pay for it.
  const bool any_dead = std::any_of(placed.begin(), placed.end(), [&](const placement::PlacedProbe& p) {
    return placement::is_dead(p.rays, report.clearance);
  });
  if (any_dead) {
    timer.stage("sdf");
    const placement::SceneSdf sdf(visible, sdf_settings(scene, report.clearance));
    timer.stage("relocate");
    if (progress) progress("relocate", 0.0);
    const placement::RelocationContext ctx{&rays, &sdf, input.directions, report.clearance};
    relocate_dead_probes(ctx, placed, tree, settings.threads, report);
  }
  if (settings.store_surfels) {
    timer.stage("surfels");
    store_surfels(rays, input.directions, placed, tree, settings.threads);
  }

  timer.stage("svo");
  if (progress) progress("svo", 0.0);
  const probe_index::SvoStats svo = probe_index::build_svo(rays, volume, settings.svo_depth, settings.threads);
  report.svo_solid_voxels = svo.solid_voxels;
  report.svo_uncovered_voxels = svo.uncovered_voxels;
  add_grid_lattice(rays, settings, placement_bounds, placed, volume, timer);

  if (settings.lighting.enabled) {
    timer.stage("lighting");
    if (progress) progress("lighting", 0.0);
    lighting::LightingSettings light_settings = settings.lighting;
    light_settings.threads = settings.threads;
    report.lighting = lighting::bake_lighting(visible, rays, volume, light_settings);
  }

  if (settings.runtime_lighting) {
    timer.stage("gpu_scene");
    if (progress) progress("gpu_scene", 0.0);
    report.runtime_lighting = add_runtime_lighting(scene, settings, volume);
  }

  timer.stage("cells");
  formats::sync_info_counts(volume);
  formats::rebuild_probe_index(volume);
  formats::arrange_cells(volume, settings.cell_depth);
  trim_trailing_free(volume);
  formats::arrange_cells(volume, settings.cell_depth); // byte ranges of the trimmed sections
  volume.input_hash = bake_input_hash(scene, settings);
  timer.stage("");
  fill_report(volume, report);
  if (report.probes == 0)
    detail::bake_fail(
        fmt::format("no probes placed: all {} candidates were inside geometry or could not be moved {:.3g} m "
                    "clear of it; try a smaller --clearance, a deeper --max-depth or --placement grid",
                    report.placed_probes, report.clearance));
  return result;
}

} // namespace probebake::bake
