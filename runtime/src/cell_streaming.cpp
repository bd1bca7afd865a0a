#include "cell_streaming.h"

#include <algorithm>
#include <chrono>
#include <utility>

namespace probebake::runtime::detail {

CellStreaming::CellStreaming(Device& device, const formats::ProbeVolume& volume, std::unique_ptr<CellSource> source,
                             const StreamingOptions& options, std::uint32_t rings)
    : tracing_(device, volume, std::move(source), options.budget_bytes,
               options.max_upload_bytes != 0 ? options.max_upload_bytes : options.budget_bytes, rings, options.read_in_background),
      residency_(tracing_.footprints(volume.cells)), lit_(volume.cells.size(), 0),
      max_joining_probes_(options.max_joining_probes), max_budget_(options.budget_bytes) {
  residency_.set_budget(options.budget_bytes);
  residency_.set_max_load_bytes(options.max_upload_bytes);
  residency_.set_keep_margin(options.keep_margin);
  for (const formats::Cell& cell : volume.cells) probe_ranges_.push_back(cell.probes);
  const std::size_t probes = volume.probes.size();
  const std::size_t slots = options.max_lit_probes > 0 ? std::min(probes, std::size_t(options.max_lit_probes)) : probes;
  record_of_probe_.assign(probes, -1);
  record_slot_count_ = std::uint32_t(slots);
  free_records_.reserve(slots);
  for (std::size_t r = slots; r-- > 0;) free_records_.push_back(std::int32_t(r)); // slot 0 handed out first
}

std::vector<int> CellStreaming::resident_cells() const {
  std::vector<int> out;
  for (std::size_t k = 0; k < residency_.cells().size(); ++k)
    if (residency_.resident(k)) out.push_back(residency_.cells()[k].cell_index);
  return out;
}

bool CellStreaming::update_lit_cells(const streaming::ResidencyChanges& changes, std::vector<formats::CellRange>& retrace,
                                     std::vector<formats::CellRange>& reassigned, StreamStats& stats) {
  bool changed = false;
  for (std::size_t k : changes.drops) {
    const formats::CellRange& probes = probe_ranges_[k];
    for (std::uint32_t i = 0; i < lit_[k]; ++i) free_records_.push_back(std::exchange(record_of_probe_[probes.first + i], -1));
    if (lit_[k] != 0) reassigned.push_back({probes.first, lit_[k], 0, 0}), changed = true;
    lit_[k] = 0;
  }
  for (std::size_t k : changes.loads) joining_.push_back(k);
  std::erase_if(joining_, [&](std::size_t k) { return !residency_.resident(k); }); // dropped, or not placed
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
  std::erase_if(joining_, [&](std::size_t k) { return lit_[k] == probe_ranges_[k].count; });
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
    for (std::size_t k : missed.unplaced) residency_.cancel_load(k);
    for (std::size_t k : missed.reading) residency_.cancel_load(k);
    for (const auto& [k, reason] : missed.refused) residency_.refuse(k), refusals_.push_back(reason);
    std::vector<formats::CellRange> retrace, reassigned;
    if (update_lit_cells(changes, retrace, reassigned, stats)) {
      std::vector<std::int32_t> slots;
      for (std::size_t k = 0; k < probe_ranges_.size(); ++k)
        for (std::uint32_t i = 0; i < lit_[k]; ++i) slots.push_back(std::int32_t(probe_ranges_[k].first + i));
      light.record_record_slots(cmd, reassigned, record_of_probe_);
      light.record_host_list(cmd, slots, retrace);
    }
    timer.end(cmd, slot);
    timed = true;
    barrier(cmd, kTransferWrite, kComputeAndIndirect); // the light update dispatches by the list's sizes
    stats.loaded_cells = int(changes.loads.size() - missed.unplaced.size() - missed.reading.size() - missed.refused.size());
    stats.dropped_cells = int(changes.drops.size());
    stats.loaded_bytes = changes.loaded_bytes;
    for (std::size_t k : missed.unplaced) stats.loaded_bytes -= residency_.cells()[k].bytes;
    for (std::size_t k : missed.reading) stats.loaded_bytes -= residency_.cells()[k].bytes;
    for (const auto& refused : missed.refused) stats.loaded_bytes -= residency_.cells()[refused.first].bytes;
    stats.waiting_cells = int(changes.waiting);
    stats.unplaced_cells = int(missed.unplaced.size());
    stats.refused_cells = int(missed.refused.size());
    stats.reading_cells = int(missed.reading.size());
    stats.upload_cpu_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    pending_ = changes.waiting > 0 || !missed.unplaced.empty() || !missed.reading.empty() || !joining_.empty();
    moved_ = false;
  }
  stats.resident_cells = int(residency_.resident_count());
  stats.resident_bytes = residency_.resident_bytes();
  return stats;
}

} // namespace probebake::runtime::detail
