// Validator phase for the grid lattice (format 1.8, gpu_types.h GridLatticeHeader): a grid bake's only, its
// size that of its resolution, a finite frame, and points naming each allocated probe exactly once, with cell
// bits only for cells inside the lattice.
#include <cmath>
#include <cstring>

#include "probebake/formats/grid_lattice.h"
#include "probebake/formats/placement_kind.h"
#include "text.h"
#include "validate_internal.h"

namespace probebake::formats::detail {
namespace {

constexpr const char* kInvariant = "grid_lattice";
constexpr const char* kSection = "grid_lattice";

// Bits of the cells that exist around point (x, y, z) of an n^3 lattice: cell bit o lies on the +axis
// side when bit `axis` of o is set, which needs coordinate < n - 1, else on the -axis side (> 0).
std::uint32_t existing_cells(int x, int y, int z, int n) {
  std::uint32_t bits = 0;
  const int c[3] = {x, y, z};
  for (std::uint32_t o = 0; o < 8; ++o) {
    bool inside = true;
    for (int axis = 0; axis < 3; ++axis) inside = inside && (((o >> axis) & 1u) ? c[axis] < n - 1 : c[axis] > 0);
    if (inside) bits |= 1u << o;
  }
  return bits;
}

bool frame_ok(const gpu::GridLatticeHeader& h, Reporter& out) {
  if (!finite3(h.origin) || !finite3(h.spacing) || !(h.spacing.x > 0.0f && h.spacing.y > 0.0f && h.spacing.z > 0.0f)) {
    out.add(kInvariant, kSection, -1, "origin or spacing not finite, or a spacing <= 0");
    return false;
  }
  if (h.pad0 != 0) out.add(kInvariant, kSection, -1, "header padding is not zero");
  return true;
}

void check_points(const ProbeVolume& volume, const GridLatticeView& view, Reporter& out) {
  const int n = view.header.resolution;
  std::vector<int> seen(volume.probes.size(), -1);
  for (std::size_t i = 0; i < view.points.size(); ++i) {
    const gpu::GridPoint& word = view.points[i];
    const int x = int(i % std::size_t(n)), y = int(i / std::size_t(n) % std::size_t(n)),
              z = int(i / std::size_t(n * n));
    const int probe = grid_point_probe(word);
    const long long at = static_cast<long long>(i);
    if (probe < 0) {
      if (grid_point_cells(word) != 0 || word.reach != 0)
        out.add(kInvariant, kSection, at, "a point without probe serves cells or has a reach");
      continue;
    }
    if (word.reach >> (kReachDirections * gpu::GRID_REACH_BITS) != 0)
      out.add(kInvariant, kSection, at, "reach bits 30-31 are not zero");
    if (std::size_t(probe) >= volume.probes.size() || volume.probes[std::size_t(probe)].link == 0) {
      out.add(kInvariant, kSection, at, concat("probe ", probe, " is not an allocated probe"));
      continue;
    }
    if (seen[std::size_t(probe)] >= 0)
      out.add(kInvariant, kSection, at, concat("probe ", probe, " is also at point ", seen[std::size_t(probe)]));
    seen[std::size_t(probe)] = int(i);
    if ((grid_point_cells(word) & ~existing_cells(x, y, z, n)) != 0)
      out.add(kInvariant, kSection, at, "serves a cell outside the lattice");
  }
  for (std::size_t p = 0; p < volume.probes.size(); ++p)
    if (volume.probes[p].link != 0 && seen[p] < 0)
      out.add(kInvariant, "probes", static_cast<long long>(p), "an allocated probe is at no lattice point");
}

} // namespace

void check_grid_lattice(const ProbeVolume& volume, Reporter& out) {
  if (volume.grid_lattice.empty()) return;
  const PlacementKindInfo* kind = placement_kind_for_code(volume.info.placement);
  if (kind == nullptr || !kind->uses_grid_resolution) {
    out.add(kInvariant, kSection, -1, "a lattice in a volume that is not a grid");
    return;
  }
  const std::optional<GridLatticeView> view = grid_lattice_view(volume);
  if (!view) {
    out.add(kInvariant, kSection, -1,
            concat(volume.grid_lattice.size(), " words are not a header and resolution^3 points (resolution 2..",
                   gpu::GRID_MAX_RESOLUTION, ")"));
    return;
  }
  if (view->header.resolution != volume.info.grid_resolution) {
    out.add(kInvariant, kSection, -1,
            concat("resolution ", view->header.resolution, " but grid_resolution ", volume.info.grid_resolution));
    return;
  }
  if (frame_ok(view->header, out)) check_points(volume, *view, out);
}

} // namespace probebake::formats::detail
