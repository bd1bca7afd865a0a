#include "streaming/cell_streaming.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <utility>

#include "core/error.h"
#include "probebake/bindings.h"
#include "probebake/formats/cells.h"
#include "probebake/memory_types.h"

namespace probebake::runtime::detail {

CellStreaming::CellStreaming(Device& device, const formats::ProbeVolume& volume, const formats::TracingView& tracing,
                             std::unique_ptr<CellSource> source, const StreamingOptions& options, std::uint32_t rings,
                             bool lists_probes)
    : tracing_(device, volume, tracing, std::move(source), options.budget_bytes,
               options.max_upload_bytes != 0 ? options.max_upload_bytes : options.budget_bytes, rings,
               options.read_in_background),
      residency_(StreamedTracing::footprints(volume)),
      lit_(volume.cells.size(), 0),
      max_joining_probes_(options.max_joining_probes),
      max_budget_(options.budget_bytes),
      lists_probes_(lists_probes) {
  residency_.set_budget(options.budget_bytes);
  residency_.set_max_load_bytes(options.max_upload_bytes);
  residency_.set_keep_margin(options.keep_margin);
  for (const formats::Cell& cell : volume.cells) probe_ranges_.push_back(cell.probes);
  // With the memory update the GPU lists the probes to light: no host list, no host-handed record slots.
  const std::size_t probes = lists_probes ? volume.probes.size() : 0;
  const std::size_t slots = options.max_lit_probes > 0 ? std::min(probes, std::size_t(options.max_lit_probes)) : probes;
  record_of_probe_.assign(probes, -1);
  if (slots >= std::size_t(gpu::RECORD_SLOT_UNRESOLVED))
    fail(StatusCode::unsupported, "streaming: more probes with light records than record slots can number");
  record_slot_count_ = std::uint32_t(slots);
  free_records_.reserve(slots);
  for (std::size_t r = slots; r-- > 0;) free_records_.push_back(std::int32_t(r)); // slot 0 handed out first
  queued_.assign(volume.cells.size(), 0);
  find_cells_within_reach(volume, options.light_reach);
}

// Grid cells dx, dy, dz apart are sqrt(sum of max(0, |d| - 1)^2) cell widths apart (box to box).
void CellStreaming::find_cells_within_reach(const formats::ProbeVolume& volume, float reach) {
  reach_.assign(volume.cells.size(), {});
  if (!(reach > 0.0f)) return;
  const int n = formats::cells_per_axis(volume.cell_depth);
  const float width = volume.info.root_size / float(n);
  const int span = int(std::min(float(n), std::ceil(reach / width)));
  std::vector<std::int32_t> record_of_cell(std::size_t(n) * std::size_t(n) * std::size_t(n), -1);
  for (std::size_t k = 0; k < volume.cells.size(); ++k)
    record_of_cell[std::size_t(volume.cells[k].cell_index)] = std::int32_t(k);
  const auto gap = [](int d) { return float(std::max(0, std::abs(d) - 1)); };
  for (std::size_t k = 0; k < volume.cells.size(); ++k) {
    const int c = volume.cells[k].cell_index, x = c % n, y = c / n % n, z = c / (n * n);
    for (int dz = -span; dz <= span; ++dz)
      for (int dy = -span; dy <= span; ++dy)
        for (int dx = -span; dx <= span; ++dx) {
          const int cx = x + dx, cy = y + dy, cz = z + dz;
          if ((dx == 0 && dy == 0 && dz == 0) || cx < 0 || cy < 0 || cz < 0 || cx >= n || cy >= n || cz >= n) continue;
          const std::int32_t other = record_of_cell[std::size_t(cx + n * (cy + n * cz))];
          if (other < 0 || residency_.cells()[std::size_t(other)].bytes == 0) continue; // nothing to trace there
          if (width * std::sqrt(gap(dx) * gap(dx) + gap(dy) * gap(dy) + gap(dz) * gap(dz)) <= reach)
            reach_[k].push_back(std::uint32_t(other));
        }
    if (!reach_[k].empty() && probe_ranges_[k].count > 0) reach_cells_.push_back(k);
  }
}

std::vector<std::uint32_t> CellStreaming::take_tree_changes() { return std::exchange(tree_changes_, {}); }

std::vector<int> CellStreaming::resident_cells() const {
  std::vector<int> out;
  for (std::size_t k = 0; k < residency_.cells().size(); ++k)
    if (residency_.resident(k)) out.push_back(residency_.cells()[k].cell_index);
  return out;
}

bool CellStreaming::lightable(std::size_t k) const {
  if (!residency_.resident(k)) return false;
  return std::all_of(reach_[k].begin(), reach_[k].end(), [&](std::uint32_t n) { return residency_.resident(n); });
}

bool CellStreaming::update_lit_cells(const streaming::ResidencyChanges& changes,
                                     std::vector<formats::CellRange>& retrace,
                                     std::vector<formats::CellRange>& reassigned, StreamStats& stats) {
  bool changed = false;
  // Cells dropped, or with a cell within light_reach dropped: their probes leave the light list. Only a drop
  // makes a lit cell unlightable (the loads that did not happen were not resident before).
  for (std::size_t k = 0; k < lit_.size() && !changes.drops.empty(); ++k) {
    if (lit_[k] == 0 || lightable(k)) continue;
    const formats::CellRange& probes = probe_ranges_[k];
    for (std::uint32_t i = 0; i < lit_[k]; ++i)
      free_records_.push_back(std::exchange(record_of_probe_[probes.first + i], -1));
    reassigned.push_back({probes.first, lit_[k], 0, 0});
    lit_[k] = 0;
    changed = true;
  }
  std::erase_if(joining_, [&](std::size_t k) { return !lightable(k) ? (queued_[k] = 0, true) : false; });
  // Cells that became lightable join: the arrived ones in arrival order, then those whose last neighbour arrived.
  const auto queue = [&](std::size_t k) {
    if (queued_[k] != 0 || lit_[k] == probe_ranges_[k].count || !lightable(k)) return;
    joining_.push_back(k);
    queued_[k] = 1;
  };
  for (std::size_t k : changes.loads) queue(k);
  if (!reach_cells_.empty() && !changes.loads.empty())
    for (std::size_t k : reach_cells_) queue(k);
  std::uint32_t left = max_joining_probes_ > 0 ? std::uint32_t(max_joining_probes_) : ~0u;
  for (std::size_t k : joining_) {
    const formats::CellRange& probes = probe_ranges_[k];
    left = std::min(left, std::uint32_t(free_records_.size()));
    if (left == 0) break;
    const std::uint32_t take = std::min(left, probes.count - lit_[k]);
    if (take == 0) continue; // a cell without probes
    const formats::CellRange joined{probes.first + lit_[k], take, 0, 0};
    for (std::uint32_t i = 0; i < take; ++i) {
      record_of_probe_[joined.first + i] = free_records_.back();
      free_records_.pop_back();
    }
    retrace.push_back(joined);
    reassigned.push_back(joined);
    lit_[k] += take, left -= take;
    stats.joined_probes += int(take);
    changed = true;
  }
  std::erase_if(joining_,
                [&](std::size_t k) { return lit_[k] == probe_ranges_[k].count ? (queued_[k] = 0, true) : false; });
  for (std::size_t k : joining_) stats.joining_probes += int(probe_ranges_[k].count - lit_[k]);
  return changed;
}

StreamStats CellStreaming::record(VkCommandBuffer cmd, PassTimer& timer, std::uint32_t slot, std::uint32_t ring,
                                  LightUpdatePass& light, bool& timed) {
  StreamStats stats;
  stats.active = true;
  if (moved_ || pending_) {
    const auto start = std::chrono::steady_clock::now();
    streaming::ResidencyChanges changes = residency_.update(camera_, radius_);
    timer.begin(cmd, slot);
    const StreamedTracing::Missed missed = tracing_.record(cmd, ring, changes);
    std::uint64_t missed_bytes = 0; // of the loads that did not happen
    for (const std::vector<std::size_t>* later : {&missed.unplaced, &missed.reading})
      for (std::size_t k : *later) residency_.cancel_load(k), missed_bytes += residency_.cells()[k].bytes;
    for (const auto& [k, reason] : missed.refused)
      residency_.refuse(k), refusals_.push_back(reason), missed_bytes += residency_.cells()[k].bytes;
    std::vector<formats::CellRange> retrace, reassigned;
    if (lists_probes_ && update_lit_cells(changes, retrace, reassigned, stats)) {
      std::vector<std::int32_t> slots;
      for (std::size_t k = 0; k < probe_ranges_.size(); ++k)
        for (std::uint32_t i = 0; i < lit_[k]; ++i) slots.push_back(std::int32_t(probe_ranges_[k].first + i));
      light.record_record_slots(cmd, reassigned, record_of_probe_);
      light.record_host_list(cmd, slots, retrace);
    }
    const int loaded =
        int(changes.loads.size() - missed.unplaced.size() - missed.reading.size() - missed.refused.size());
    if (!lists_probes_) {
      for (std::size_t k : changes.drops) tree_changes_.push_back(std::uint32_t(residency_.cells()[k].cell_index));
      for (std::size_t k : changes.loads)
        if (residency_.resident(k)) tree_changes_.push_back(std::uint32_t(k) | gpu::MEMORY_CELL_ARRIVED);
    }
    if (loaded > 0)
      light.retry_unresolved(
          std::uint32_t(std::max(0, max_joining_probes_))); // geometry arrived: retry, as many a frame as join
    timer.end(cmd, slot);
    timed = true;
    barrier(cmd, kTransferWrite, kComputeAndIndirect); // the light update dispatches by the list's sizes
    stats.loaded_cells = loaded;
    stats.dropped_cells = int(changes.drops.size());
    stats.loaded_bytes = changes.loaded_bytes - missed_bytes;
    stats.waiting_cells = int(changes.waiting);
    stats.unplaced_cells = int(missed.unplaced.size());
    stats.refused_cells = int(missed.refused.size());
    stats.reading_cells = int(missed.reading.size());
    stats.moved_cells = missed.compacted;
    stats.upload_cpu_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    pending_ = changes.waiting > 0 || !missed.unplaced.empty() || !missed.reading.empty() || !joining_.empty();
    moved_ = false;
  }
  stats.resident_cells = int(residency_.resident_count());
  stats.resident_bytes = residency_.resident_bytes();
  return stats;
}

} // namespace probebake::runtime::detail
