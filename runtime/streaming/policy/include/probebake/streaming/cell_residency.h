// Which streaming cells of a .probes file (docs/FORMAT.md section 6) should be resident around a camera
// within a byte budget, and what changes from one update to the next: the policy of cell streaming
// (issue #15), without I/O or GPU work, so that the runtime, the CLI's stream plan and an engine with its
// own I/O decide alike. Depends on formats and glm only.
//
// Policy: the cells whose cube lies within `radius` of the camera (distance from the point to the cube),
// nearest first (ties by cell index), each taken when its bytes still fit the budget beside the nearer ones
// taken, skipped otherwise: a nearer cell always has the room before a farther one, and one cell larger than
// the budget blocks nothing behind it. Updates drop first, then load nearest first, at most
// max_load_bytes per update (at least one cell, so a cell larger than that limit still loads); the rest wait
// for the next update. A resident cell stays while it lies within radius + keep margin (after the cells within
// the radius, nearest first, as the budget allows): a camera moving back and forth across the radius does not
// drop and reload the same cells every frame. Resident bytes never exceed the budget. Deterministic.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "probebake/formats/probe_volume.h"

namespace probebake::streaming {

// One cell as the policy sees it: where it is and what loading it costs.
struct CellFootprint {
  int cell_index = 0; // Cell::cell_index
  glm::vec3 min{0.0f}, max{0.0f};
  std::uint64_t bytes = 0; // formats::cell_bytes
};

// The footprint of every Cell record of a volume, in record order.
std::vector<CellFootprint> cell_footprints(const formats::ProbeVolume& volume);

// The most of a per-cell quantity (`counts[k]` for cell k: probes, node clusters) that the cells resident at
// once can hold, whatever the camera does: resident bytes never exceed `budget`, so every cell of zero bytes
// and, of the others, the fractional knapsack by count per byte (an upper bound of any whole-cell choice),
// rounded up. Sizes what a GPU pool needs for the resident cells. counts.size() == cells.size().
std::uint64_t most_resident(std::span<const CellFootprint> cells, std::span<const std::uint64_t> counts,
                            std::uint64_t budget);

// Distance from `point` to the box (0 inside).
float distance_to_box(glm::vec3 point, glm::vec3 min, glm::vec3 max);

// Cells (indices into the footprints) that one update drops and loads; loads in the order to upload them.
struct ResidencyChanges {
  std::vector<std::size_t> drops;
  std::vector<std::size_t> loads;
  std::uint64_t dropped_bytes = 0;
  std::uint64_t loaded_bytes = 0;
  std::size_t waiting = 0; // wanted cells left for later updates by max_load_bytes
};

class CellResidency {
public:
  explicit CellResidency(std::vector<CellFootprint> cells);

  // Takes effect at the next update (which drops what no longer fits). 0 keeps nothing resident.
  void set_budget(std::uint64_t bytes) { budget_ = bytes; }
  // Bytes loaded per update at most (0 = no limit); one cell is always allowed.
  void set_max_load_bytes(std::uint64_t bytes) { max_load_bytes_ = bytes; }
  // Metres beyond the radius within which resident cells are kept (>= 0; 0 = none, the default).
  void set_keep_margin(float metres) { keep_margin_ = metres >= 0.0f && metres < 3.0e38f ? metres : 0.0f; }

  // Moves the camera. `radius` >= 0 and `position` finite (a non-finite value or a negative radius wants
  // no cell). The caller applies the drops and then the loads.
  ResidencyChanges update(glm::vec3 position, float radius);

  // A load the caller could not carry out (no room left in a fragmented store): the cell is not resident
  // and the next update wants it again.
  void cancel_load(std::size_t cell);
  // A load whose cell cannot be used (its bytes could not be read, or differ from those validated): the cell
  // is not resident and no later update wants it.
  void refuse(std::size_t cell);
  bool refused(std::size_t cell) const { return refused_[cell] != 0; }

  // The cells the policy wants resident around `position`, nearest first, ignoring max_load_bytes (the
  // kept ones depend on what is resident now).
  std::vector<std::size_t> wanted(glm::vec3 position, float radius) const;

  std::span<const CellFootprint> cells() const { return cells_; }
  bool resident(std::size_t cell) const { return resident_[cell] != 0; }
  std::uint64_t resident_bytes() const { return resident_bytes_; }
  std::size_t resident_count() const { return resident_count_; }
  std::uint64_t budget() const { return budget_; }

private:
  std::vector<CellFootprint> cells_;
  std::vector<std::uint8_t> resident_;
  std::vector<std::uint8_t> refused_;
  std::uint64_t budget_ = 0;
  std::uint64_t max_load_bytes_ = 0;
  float keep_margin_ = 0.0f;
  std::uint64_t resident_bytes_ = 0;
  std::size_t resident_count_ = 0;
};

} // namespace probebake::streaming
