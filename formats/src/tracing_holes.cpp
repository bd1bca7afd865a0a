// The holes of a run without the cells (tracing_holes.h).
#include "tracing_holes.h"

#include <algorithm>

namespace probebake::formats::detail {

Holes holes_of(const std::vector<CellTracing>& records, CellRange CellTracing::*member, std::size_t size) {
  Holes holes;
  for (std::size_t k = 0; k < records.size(); ++k) {
    const CellRange& r = records[k].*member;
    const std::uint64_t begin = std::min<std::uint64_t>(r.first, size),
                        end = std::min<std::uint64_t>(std::uint64_t(r.first) + r.count, size);
    if (begin < end) holes.push_back({begin, end, k});
  }
  std::sort(holes.begin(), holes.end(), [](const Hole& a, const Hole& b) { return a.begin < b.begin; });
  Holes merged;
  for (const Hole& h : holes) {
    if (!merged.empty() && h.begin < merged.back().end)
      merged.back().end = std::max(merged.back().end, h.end);
    else
      merged.push_back(h);
  }
  return merged;
}

const Hole* hole_at(const Holes& holes, std::uint64_t i) {
  if (holes.empty()) return nullptr; // a whole volume's or a cell's run
  auto it = std::upper_bound(holes.begin(), holes.end(), i, [](std::uint64_t x, const Hole& h) { return x < h.begin; });
  if (it == holes.begin()) return nullptr;
  --it;
  return i < it->end ? &*it : nullptr;
}

Readable readable(const ProbeVolume& v, const TracingWindow& w, const DeferredCells* deferred) {
  if (!deferred) return {w, {}, {}, {}};
  return {w, holes_of(v.cell_tracing, &CellTracing::trace_nodes, w.view.nodes.size()),
          holes_of(v.cell_tracing, &CellTracing::trace_faces, w.view.faces.size()),
          holes_of(v.cell_tracing, &CellTracing::trace_vertices, w.view.vertices.size())};
}

Marks::Marks(std::size_t size, const Holes& holes) : size_(size), holes_(holes) {
  std::uint64_t skipped = 0;
  for (const Hole& h : holes_) skipped_through_.push_back(skipped += h.end - h.begin);
  counts_.assign(std::size_t(size - skipped), 0);
}
std::uint8_t& Marks::at(std::uint64_t i) {
  if (holes_.empty()) return counts_[std::size_t(i)];
  const auto after =
      std::upper_bound(holes_.begin(), holes_.end(), i, [](std::uint64_t x, const Hole& h) { return x < h.begin; });
  const std::size_t before = std::size_t(after - holes_.begin());
  return counts_[std::size_t(i - (before == 0 ? 0 : skipped_through_[before - 1]))];
}
} // namespace probebake::formats::detail
