// The grid placement's lattice section (format 1.8, gpu_types.h GridLatticeHeader and GridPoint): what a grid
// engine's lookup needs to find a cell's eight probes by arithmetic (probe_index/grid_lookup.h), and the rules
// a file's lattice must keep (validate.h "grid_lattice").
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/ext/vector_int3.hpp>

#include "probebake/formats/probe_volume.h"

namespace probebake::formats {

// The lattice of an N^3 grid over [min, max]: points at the centres of its N^3 boxes.
gpu::GridLatticeHeader grid_lattice_frame(glm::vec3 min, glm::vec3 max, int resolution);
// Lattice point (x, y, z)'s position.
glm::vec3 grid_point_position(const gpu::GridLatticeHeader& header, int x, int y, int z);
// A position in lattice coordinates (lattice point (x, y, z) at (x, y, z)), and the cell a lookup at lattice
// coordinates g reads: its lowest corner clamp(floor(g), 0, n - 2) (beyond the lattice, the border cell).
glm::vec3 grid_lattice_coordinates(const gpu::GridLatticeHeader& header, glm::vec3 position);
glm::ivec3 grid_cell_of(glm::vec3 g, int resolution);

// A point's probe_cells word: probe index (or none, -1) and the cells around the point its probe serves.
std::uint32_t grid_probe_cells(int probe, std::uint32_t cells);
inline int grid_point_probe(const gpu::GridPoint& point) {
  const std::uint32_t probe = point.probe_cells & gpu::GRID_POINT_PROBE_MASK;
  return probe == gpu::GRID_POINT_NO_PROBE ? -1 : int(probe);
}
inline std::uint32_t grid_point_cells(const gpu::GridPoint& point) {
  return point.probe_cells >> gpu::GRID_POINT_CELLS_SHIFT;
}

// The six axis directions of GridPoint::reach, in its order: +x, -x, +y, -y, +z, -z.
inline constexpr int kReachDirections = 6;
using Reach = std::array<float, kReachDirections>; // in spacings of the direction's axis
// The word of a reach in spacings (rounded down to 1/GRID_REACH_STEPS; a spacing or more: no surface), and the
// reach a word stores (infinity for GRID_REACH_STEPS).
std::uint32_t grid_reach_word(const Reach& reach);
Reach grid_point_reach(const gpu::GridPoint& point);

// The section's words: the header, then the points (resolution^3 of them).
std::vector<std::uint32_t> grid_lattice_words(const gpu::GridLatticeHeader& header,
                                              std::span<const gpu::GridPoint> points);

// A volume's lattice as read: the header and the points, or nothing when the section is absent or its size is
// not a header and resolution^3 points (validate reports why).
struct GridLatticeView {
  gpu::GridLatticeHeader header{};
  std::span<const gpu::GridPoint> points;
};
std::optional<GridLatticeView> grid_lattice_view(const ProbeVolume& volume);

// Renames the lattice's probes after a permutation of the probe buffer (cells.cpp's arrange_cells).
void remap_grid_probes(std::vector<std::uint32_t>& lattice, const std::vector<int>& new_probe);

} // namespace probebake::formats
