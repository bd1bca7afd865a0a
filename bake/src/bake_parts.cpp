// Parts of a split bake and their merge (probebake/bake/bake_parts.h).
#include "probebake/bake/bake_parts.h"

#include <algorithm>
#include <map>

#include <fmt/core.h>

#include "probebake/formats/cells.h"
#include "probebake/common/parallel.h"
#include "probebake/formats/error.h"
#include "probebake/placement/sealed.h"
#include "probebake/scene/ray_scene.h"

namespace probebake::bake {
namespace {

// The part grid's cell of every triangle (its centroid's, as the file's cells own triangles).
std::vector<std::int32_t> triangle_cells(const scene::Scene& scene, const BakeSettings& settings, int depth) {
  const gpu::VolumeInfo info = volume_info(scene, settings);
  std::vector<std::int32_t> cells(scene.triangles.size());
  for (std::size_t t = 0; t < scene.triangles.size(); ++t) {
    const glm::uvec3 c = scene.triangles[t];
    cells[t] = formats::cell_of_triangle(info, depth, scene.positions[c.x], scene.positions[c.y], scene.positions[c.z]);
  }
  return cells;
}

// The triangles whose cell is one of `cells` (ascending), in scene order.
std::vector<std::uint32_t> triangles_in(const std::vector<std::int32_t>& triangle_cell,
                                        std::span<const std::int32_t> cells) {
  std::vector<std::uint32_t> out;
  for (std::size_t t = 0; t < triangle_cell.size(); ++t)
    if (std::binary_search(cells.begin(), cells.end(), triangle_cell[t])) out.push_back(std::uint32_t(t));
  return out;
}

BakeSettings with_part_grid(const scene::Scene& scene, const BakeSettings& settings) {
  BakeSettings s = settings;
  s.cell_depth = part_cell_depth(scene, settings);
  s.cell_size = 0.0f; // as bake() hashes the depth it uses
  return s;
}

} // namespace

int part_cell_depth(const scene::Scene& scene, const BakeSettings& settings) {
  return cell_depth_for(settings, volume_info(scene, settings).root_size);
}

std::uint64_t part_input_hash(const scene::Scene& scene, const BakeSettings& settings) {
  return bake_input_hash(scene, with_part_grid(scene, settings));
}

formats::BakePart bake_part(const scene::Scene& scene, const BakeSettings& settings,
                            std::span<const std::int32_t> cells) {
  check_settings(settings);
  formats::BakePart part;
  part.cell_depth = part_cell_depth(scene, settings);
  part.input_hash = part_input_hash(scene, settings);
  part.scene_triangles = std::uint32_t(scene.triangles.size());
  const int grid = formats::cell_count(part.cell_depth);
  for (std::size_t k = 0; k < cells.size(); ++k) {
    if (cells[k] < 0 || cells[k] >= grid)
      throw Error(ErrorKind::usage, fmt::format("--cells: cell {} is outside the grid's {} cells ({}^3)", cells[k],
                                                grid, formats::cells_per_axis(part.cell_depth)));
    if (k > 0 && cells[k] <= cells[k - 1]) throw Error(ErrorKind::internal, "bake_part: cells not ascending");
  }
  part.cells.assign(cells.begin(), cells.end());
  const std::vector<std::uint32_t> triangles = triangles_in(triangle_cells(scene, settings, part.cell_depth), cells);
  if (triangles.empty()) return part;
  const ThreadLimit thread_limit(settings.threads);
  const scene::RayScene rays(scene); // the sealed test traces the whole scene, not only these cells
  const std::vector<char> sealed = placement::sealed_triangles(rays, triangles, settings.threads);
  part.sealed.assign(sealed.begin(), sealed.end());
  return part;
}

PrecomputedWork merge_parts(const scene::Scene& scene, const BakeSettings& settings,
                            std::span<const formats::BakePart> parts, std::span<const std::string> names) {
  const int depth = part_cell_depth(scene, settings);
  const std::uint64_t hash = part_input_hash(scene, settings);
  std::map<std::int32_t, std::size_t> baked_by; // cell -> part
  for (std::size_t p = 0; p < parts.size(); ++p) {
    const formats::BakePart& part = parts[p];
    if (part.input_hash != hash || part.cell_depth != depth || part.scene_triangles != scene.triangles.size())
      throw Error(ErrorKind::input,
                  fmt::format("{}: baked from another scene or with other settings (input hash {:016x}, this merge's "
                              "{:016x}): give merge the scene and the options the parts were baked with",
                              names[p], part.input_hash, hash));
    for (const std::int32_t cell : part.cells)
      if (const auto [at, added] = baked_by.emplace(cell, p); !added)
        throw Error(ErrorKind::input, fmt::format("{}: cell {} is also in {}", names[p], cell, names[at->second]));
  }
  const std::vector<std::int32_t> triangle_cell = triangle_cells(scene, settings, depth);
  PrecomputedWork work;
  work.sealed.assign(scene.triangles.size(), 0);
  std::vector<std::size_t> next(parts.size(), 0); // each part's flags in scene order
  for (std::size_t t = 0; t < triangle_cell.size(); ++t) {
    const auto at = baked_by.find(triangle_cell[t]);
    if (at == baked_by.end())
      throw Error(ErrorKind::input, fmt::format("no part bakes cell {} (triangle {} lies in it): bake it with --cells",
                                                triangle_cell[t], t));
    const std::size_t p = at->second;
    if (next[p] >= parts[p].sealed.size())
      throw Error(ErrorKind::input, fmt::format("{}: {} sealed flags, fewer than the triangles of its cells", names[p],
                                                parts[p].sealed.size()));
    work.sealed[t] = char(parts[p].sealed[next[p]++]);
  }
  for (std::size_t p = 0; p < parts.size(); ++p)
    if (next[p] != parts[p].sealed.size())
      throw Error(ErrorKind::input, fmt::format("{}: {} sealed flags for the {} triangles of its cells", names[p],
                                                parts[p].sealed.size(), next[p]));
  return work;
}

} // namespace probebake::bake
