// The parts of the tracing sections that a validator run reads: a run without the cells (streamed files,
// validate_without_cells) leaves each cell's ranges unread; these "holes" are skipped by every check and
// the tree walk's marks (validate_tracing.cpp).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "probebake/formats/trace_mesh.h"
#include "validate_internal.h"

namespace probebake::formats::detail {

// A cell's range of one section that a run leaves unread: [begin, end), its record.
struct Hole {
  std::uint64_t begin = 0, end = 0;
  std::size_t cell = 0;
};
using Holes = std::vector<Hole>; // sorted by begin, disjoint, inside the section

// The non-empty ranges of `member` clamped to `size`, sorted; overlapping ones (an invalid file: cell_range
// reports it) are merged into the first.
Holes holes_of(const std::vector<CellTracing>& records, CellRange CellTracing::*member, std::size_t size);

// The hole holding element i, or null.
const Hole* hole_at(const Holes& holes, std::uint64_t i);

// Calls f(i) for every i in [0, size) outside the holes.
template <class F>
void for_each_outside(const Holes& holes, std::size_t size, F&& f) {
  std::uint64_t i = 0;
  for (const Hole& h : holes) {
    for (; i < h.begin; ++i) f(i);
    i = std::max(i, h.end);
  }
  for (; i < size; ++i) f(i);
}

// What a run reads of the three sections: the window, minus the holes of a run without the cells.
struct Readable {
  const TracingWindow& window;
  Holes nodes, faces, vertices;
};
Readable readable(const ProbeVolume& v, const TracingWindow& w, const DeferredCells* deferred);

// One count per element of a section outside its holes (what a walk may reach), stored without the holes.
class Marks {
public:
  Marks(std::size_t size, const Holes& holes);

  // The count of element i, which lies outside the holes: every hole that begins before it ends before it.
  std::uint8_t& at(std::uint64_t i);

  // f(base + i) for every element i outside the holes whose count is 0.
  template <class F>
  void for_each_zero(std::uint64_t base, F&& f) {
    for_each_outside(holes_, size_, [&](std::uint64_t i) {
      if (at(i) == 0) f(base + i);
    });
  }

private:
  std::size_t size_;
  const Holes& holes_;
  std::vector<std::uint64_t> skipped_through_;
  std::vector<std::uint8_t> counts_;
};

} // namespace probebake::formats::detail
