// Room in the streamed tracing arena (streamed_tracing.h): the size classes of cell blocks (slot_bytes) and
// the best-fit allocator of their runs (BlockAllocator).
#include "streaming/streamed_tracing.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <map>
#include <vector>

namespace probebake::runtime::detail {

std::vector<std::uint64_t> slot_bytes(const std::vector<std::uint64_t>& blocks) {
  std::vector<std::uint64_t> sorted(blocks);
  std::sort(sorted.begin(), sorted.end());
  std::map<std::uint64_t, std::uint64_t> slot_of; // block bytes -> its class's largest
  for (std::size_t first = 0; first < sorted.size();) {
    std::size_t end = first;
    while (end < sorted.size() && sorted[end] <= sorted[first] + sorted[first] / kSlotClassWidth) ++end;
    for (std::size_t i = first; i < end; ++i) slot_of[sorted[i]] = sorted[end - 1];
    first = end;
  }
  std::vector<std::uint64_t> slots;
  for (std::uint64_t bytes : blocks) slots.push_back(slot_of[bytes]);
  return slots;
}

BlockAllocator::BlockAllocator(std::uint64_t bytes, std::uint64_t unit) : unit_(unit), units_(bytes / unit) {
  if (units_ > 0) free_[0] = units_;
}

std::uint64_t BlockAllocator::free_bytes() const {
  std::uint64_t units = 0;
  for (const auto& [at, run] : free_) units += run;
  return units * unit_;
}

void BlockAllocator::compacted(std::uint64_t used_bytes) {
  const std::uint64_t used = (used_bytes + unit_ - 1) / unit_;
  free_.clear();
  if (used < units_) free_[used] = units_ - used;
}

std::int64_t BlockAllocator::allocate(std::uint64_t bytes) {
  const std::uint64_t units = (bytes + unit_ - 1) / unit_;
  auto best = free_.end();
  for (auto it = free_.begin(); it != free_.end(); ++it)
    if (it->second >= units && (best == free_.end() || it->second < best->second)) best = it;
  if (best == free_.end()) return -1;
  const std::uint64_t at = best->first, left = best->second - units;
  free_.erase(best);
  if (left > 0) free_[at + units] = left;
  return std::int64_t(at * unit_);
}

void BlockAllocator::release(std::uint64_t offset, std::uint64_t bytes) {
  std::uint64_t at = offset / unit_, units = (bytes + unit_ - 1) / unit_;
  auto next = free_.lower_bound(at);
  if (next != free_.end() && next->first == at + units) units += next->second, next = free_.erase(next);
  if (next != free_.begin()) {
    auto before = std::prev(next);
    if (before->first + before->second == at) at = before->first, units += before->second, free_.erase(before);
  }
  free_[at] = units;
}

} // namespace probebake::runtime::detail
