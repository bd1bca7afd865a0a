#include "probebake/streaming/cell_residency.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "probebake/formats/cells.h"

namespace probebake::streaming {

std::vector<CellFootprint> cell_footprints(const formats::ProbeVolume& volume) {
  std::vector<CellFootprint> out;
  out.reserve(volume.cells.size());
  for (std::size_t k = 0; k < volume.cells.size(); ++k) {
    const formats::Cell& cell = volume.cells[k];
    out.push_back({cell.cell_index, cell.bounds_min, cell.bounds_max, formats::cell_bytes(volume, k)});
  }
  return out;
}

std::uint64_t most_resident(std::span<const CellFootprint> cells, std::span<const std::uint64_t> counts,
                            std::uint64_t budget) {
  std::uint64_t total = 0;
  std::vector<std::size_t> paid; // cells that cost bytes, densest first
  for (std::size_t k = 0; k < cells.size(); ++k) {
    if (counts[k] == 0) continue;
    if (cells[k].bytes == 0)
      total += counts[k];
    else
      paid.push_back(k);
  }
  const auto density = [&](std::size_t k) { return double(counts[k]) / double(cells[k].bytes); };
  std::sort(paid.begin(), paid.end(), [&](std::size_t a, std::size_t b) {
    return density(a) > density(b) || (density(a) == density(b) && a < b);
  });
  std::uint64_t left = budget;
  for (std::size_t k : paid) {
    if (cells[k].bytes <= left) {
      total += counts[k];
      left -= cells[k].bytes;
      continue;
    }
    total +=
        std::uint64_t(std::ceil(double(counts[k]) * double(left) / double(cells[k].bytes))); // the fraction that fits
    break;
  }
  return total;
}

float distance_to_box(glm::vec3 point, glm::vec3 min, glm::vec3 max) {
  const glm::vec3 outside = glm::max(glm::max(min - point, point - max), glm::vec3(0.0f));
  return glm::length(outside);
}

CellResidency::CellResidency(std::vector<CellFootprint> cells)
    : cells_(std::move(cells)), resident_(cells_.size(), 0), refused_(cells_.size(), 0) {}

std::vector<std::size_t> CellResidency::wanted(glm::vec3 position, float radius) const {
  std::vector<std::pair<float, std::size_t>> near;
  const bool usable = std::isfinite(position.x) && std::isfinite(position.y) && std::isfinite(position.z) &&
                      std::isfinite(radius) && radius >= 0.0f;
  if (!usable) return {};
  for (std::size_t k = 0; k < cells_.size(); ++k) {
    const float d = distance_to_box(position, cells_[k].min, cells_[k].max);
    if (refused_[k] != 0) continue;
    if (d <= radius || (resident_[k] != 0 && d <= radius + keep_margin_)) near.emplace_back(d, k);
  }
  // Ties by record order, which is cell_index order (the format sorts records by it).
  std::sort(near.begin(), near.end());
  std::vector<std::size_t> out;
  std::uint64_t taken = 0;
  for (const auto& [distance, k] : near) {
    if (cells_[k].bytes > budget_ - taken) continue;
    taken += cells_[k].bytes;
    out.push_back(k);
  }
  return out;
}

ResidencyChanges CellResidency::update(glm::vec3 position, float radius) {
  const std::vector<std::size_t> want = wanted(position, radius);
  std::vector<std::uint8_t> is_wanted(cells_.size(), 0);
  for (std::size_t k : want) is_wanted[k] = 1;
  ResidencyChanges changes;
  for (std::size_t k = 0; k < cells_.size(); ++k) {
    if (resident_[k] == 0 || is_wanted[k] != 0) continue;
    resident_[k] = 0;
    resident_bytes_ -= cells_[k].bytes;
    --resident_count_;
    changes.drops.push_back(k);
    changes.dropped_bytes += cells_[k].bytes;
  }
  for (std::size_t k : want) {
    if (resident_[k] != 0) continue;
    const bool over =
        max_load_bytes_ != 0 && !changes.loads.empty() && changes.loaded_bytes + cells_[k].bytes > max_load_bytes_;
    if (over) {
      ++changes.waiting;
      continue;
    }
    resident_[k] = 1;
    resident_bytes_ += cells_[k].bytes;
    ++resident_count_;
    changes.loads.push_back(k);
    changes.loaded_bytes += cells_[k].bytes;
  }
  return changes;
}

void CellResidency::cancel_load(std::size_t cell) {
  if (cell >= cells_.size() || resident_[cell] == 0) return;
  resident_[cell] = 0;
  resident_bytes_ -= cells_[cell].bytes;
  --resident_count_;
}

void CellResidency::refuse(std::size_t cell) {
  if (cell >= cells_.size()) return;
  cancel_load(cell);
  refused_[cell] = 1;
}

} // namespace probebake::streaming
