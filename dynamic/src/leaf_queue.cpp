#include "probebake/dynamic/leaf_queue.h"

#include <string>

#include "probebake/formats/error.h"
#include "probebake/leaf_rule.h"

namespace probebake::dynamic {
namespace {

[[noreturn]] void malformed(const std::string& reason) { throw Error(ErrorKind::input, "leaf queue: " + reason); }

} // namespace

bool is_memory_state(int state) { return state >= gpu::LEAF_M0_CHILD_ALLOCATING && state <= gpu::LEAF_M4_FREE_CLUSTER; }

int state_priority(int state) { return gpu::leaf_state_priority(state); }

LeafQueue::LeafQueue(formats::ProbeVolume& volume, int segment_capacity) : volume_(&volume) {
  if (volume.leaf_entries.empty()) formats::init_leaf_queue(volume, segment_capacity);
  const gpu::LeafQueueHeader& header = volume.leaf_header;
  if (header.pull_origin < 0 || header.pull_origin > 2) malformed("pull origin not in {0, 1, 2}");
  if (volume.leaf_entries.size() != 3 * static_cast<std::size_t>(header.segment_capacity))
    malformed("entries are not three segments");
  for (int s = 0; s < 3; ++s) {
    if (header.count[s] < 0 || header.count[s] > header.segment_capacity) malformed("segment count out of range");
    for (int e = 0; e < header.count[s]; ++e) {
      const gpu::LeafEntry& entry = volume.leaf_entries[static_cast<std::size_t>(s * header.segment_capacity + e)];
      if (state_priority(entry.state) == 0)
        malformed("entry state " + std::to_string(entry.state) + " is not a LEAF_* state");
      if (!slot_[s].emplace(entry.node, e).second)
        malformed("node " + std::to_string(entry.node) + " twice in one segment");
    }
  }
}

void LeafQueue::begin_frame() { volume_->leaf_header.pull_origin = (volume_->leaf_header.pull_origin + 2) % 3; }

int LeafQueue::pull_segment(int pull_offset) const { return (volume_->leaf_header.pull_origin + pull_offset) % 3; }

int LeafQueue::count(int segment) const { return volume_->leaf_header.count[segment]; }

int LeafQueue::capacity() const { return volume_->leaf_header.segment_capacity; }

std::vector<gpu::LeafEntry> LeafQueue::entries(int segment) const {
  const auto first = volume_->leaf_entries.begin() + std::ptrdiff_t(segment) * capacity();
  return {first, first + count(segment)};
}

std::vector<gpu::LeafEntry> LeafQueue::take(int segment) {
  std::vector<gpu::LeafEntry> taken = entries(segment);
  // Entries past the count are scratch, but zeroing them keeps read-backs comparable bit for bit.
  std::fill_n(volume_->leaf_entries.begin() + std::ptrdiff_t(segment) * capacity(), count(segment), gpu::LeafEntry{});
  volume_->leaf_header.count[segment] = 0;
  slot_[segment].clear();
  return taken;
}

bool LeafQueue::push(int segment, int node, int state) {
  const auto base = std::size_t(segment) * std::size_t(capacity());
  if (const auto found = slot_[segment].find(node); found != slot_[segment].end()) {
    gpu::LeafEntry& entry = volume_->leaf_entries[base + std::size_t(found->second)];
    if (state_priority(state) > state_priority(entry.state)) entry.state = state;
    return true;
  }
  int& used = volume_->leaf_header.count[segment];
  if (used >= capacity()) return false;
  volume_->leaf_entries[base + std::size_t(used)] = gpu::LeafEntry{node, state};
  slot_[segment].emplace(node, used++);
  return true;
}

} // namespace probebake::dynamic
