#include "probebake/formats/grid_lattice.h"

#include <cmath>
#include <cstring>
#include <limits>

#include <glm/common.hpp>

namespace probebake::formats {

gpu::GridLatticeHeader grid_lattice_frame(glm::vec3 min, glm::vec3 max, int resolution) {
  gpu::GridLatticeHeader header{};
  header.spacing = (max - min) / float(resolution);
  header.origin = min;
  header.resolution = resolution;
  return header;
}

glm::vec3 grid_point_position(const gpu::GridLatticeHeader& header, int x, int y, int z) {
  return header.origin + (glm::vec3(float(x), float(y), float(z)) + 0.5f) * header.spacing;
}

glm::vec3 grid_lattice_coordinates(const gpu::GridLatticeHeader& header, glm::vec3 position) {
  return (position - header.origin) / header.spacing - 0.5f;
}

glm::ivec3 grid_cell_of(glm::vec3 g, int resolution) {
  const glm::vec3 inside = glm::clamp(g, glm::vec3(0.0f), glm::vec3(float(resolution - 1))); // no int overflow
  return glm::clamp(glm::ivec3(glm::floor(inside)), glm::ivec3(0), glm::ivec3(resolution - 2));
}

std::uint32_t grid_probe_cells(int probe, std::uint32_t cells) {
  const std::uint32_t index = probe < 0 ? gpu::GRID_POINT_NO_PROBE : std::uint32_t(probe) & gpu::GRID_POINT_PROBE_MASK;
  return index | (cells << gpu::GRID_POINT_CELLS_SHIFT);
}

std::uint32_t grid_reach_word(const Reach& reach) {
  std::uint32_t word = 0;
  for (int a = 0; a < kReachDirections; ++a) {
    const float steps = reach[std::size_t(a)] * float(gpu::GRID_REACH_STEPS); // NaN and negatives: 0
    const std::uint32_t q = steps >= float(gpu::GRID_REACH_STEPS) ? gpu::GRID_REACH_STEPS
                            : steps > 0.0f                        ? std::uint32_t(steps)
                                                                  : 0u;
    word |= q << (gpu::GRID_REACH_BITS * std::uint32_t(a));
  }
  return word;
}

Reach grid_point_reach(const gpu::GridPoint& point) {
  Reach reach{};
  for (int a = 0; a < kReachDirections; ++a) {
    const std::uint32_t q = (point.reach >> (gpu::GRID_REACH_BITS * std::uint32_t(a))) & gpu::GRID_REACH_STEPS;
    reach[std::size_t(a)] =
        q == gpu::GRID_REACH_STEPS ? std::numeric_limits<float>::infinity() : float(q) / float(gpu::GRID_REACH_STEPS);
  }
  return reach;
}

std::vector<std::uint32_t> grid_lattice_words(const gpu::GridLatticeHeader& header,
                                              std::span<const gpu::GridPoint> points) {
  std::vector<std::uint32_t> words(std::size_t(gpu::GRID_LATTICE_HEADER_WORDS) + points.size_bytes() / 4);
  std::memcpy(words.data(), &header, sizeof(header));
  std::memcpy(words.data() + gpu::GRID_LATTICE_HEADER_WORDS, points.data(), points.size_bytes());
  return words;
}

std::optional<GridLatticeView> grid_lattice_view(const ProbeVolume& volume) {
  const std::vector<std::uint32_t>& words = volume.grid_lattice;
  if (words.size() < std::size_t(gpu::GRID_LATTICE_HEADER_WORDS)) return std::nullopt;
  GridLatticeView view;
  std::memcpy(&view.header, words.data(), sizeof(view.header));
  const int n = view.header.resolution;
  if (n < 2 || n > gpu::GRID_MAX_RESOLUTION) return std::nullopt;
  const std::size_t points = std::size_t(n) * std::size_t(n) * std::size_t(n);
  if (words.size() - std::size_t(gpu::GRID_LATTICE_HEADER_WORDS) != points * std::size_t(gpu::GRID_POINT_WORDS))
    return std::nullopt;
  static_assert(alignof(gpu::GridPoint) == alignof(std::uint32_t));
  view.points = {reinterpret_cast<const gpu::GridPoint*>(words.data() + gpu::GRID_LATTICE_HEADER_WORDS), points};
  return view;
}

void remap_grid_probes(std::vector<std::uint32_t>& lattice, const std::vector<int>& new_probe) {
  for (std::size_t i = std::size_t(gpu::GRID_LATTICE_HEADER_WORDS); i + 1 < lattice.size();
       i += std::size_t(gpu::GRID_POINT_WORDS)) {
    const gpu::GridPoint point{lattice[i], lattice[i + 1]};
    const int probe = grid_point_probe(point);
    if (probe >= 0) lattice[i] = grid_probe_cells(new_probe.at(std::size_t(probe)), grid_point_cells(point));
  }
}

} // namespace probebake::formats
