// Probe groups (probe_groups.h).
#include "probe_groups.h"

#include "probebake/common/parallel.h"
#include "voxel_samples.h"

namespace probebake::probe_index::detail {
namespace {

constexpr int kJoinNeighbours = 12; // the nearest probes each probe tries to see

} // namespace

ProbeGroups probe_groups(const scene::RayScene& rays, const formats::ProbeVolume& v, const ProbeBuckets& buckets,
                         int threads) {
  const std::size_t count = v.probes.size();
  std::vector<std::vector<int>> joined(count);
  parallel_for(count, threads, [&](std::size_t i) {
    if (v.probes[i].link == 0) return;
    for (int other : buckets.nearest(v.probes[i].position, kJoinNeighbours + 1))
      if (std::size_t(other) > i && sees(rays, v.probes[i].position, v.probes[std::size_t(other)].position))
        joined[i].push_back(other);
  });
  DisjointSets sets(count);
  for (std::size_t i = 0; i < count; ++i)
    for (int other : joined[i]) sets.join(int(i), other);
  ProbeGroups out{std::vector<int>(count, -1), std::vector<int>(count, 0)};
  for (std::size_t i = 0; i < count; ++i) {
    if (v.probes[i].link == 0) continue;
    out.group[i] = sets.root(int(i));
    ++out.size[std::size_t(out.group[i])];
  }
  if (!out.size.empty()) out.largest = *std::max_element(out.size.begin(), out.size.end());
  return out;
}

void GroupVotes::vote(int group, int points) {
  auto it = std::find_if(votes_.begin(), votes_.end(), [group](const auto& e) { return e.first == group; });
  if (it == votes_.end()) it = votes_.insert(votes_.end(), {group, 0.0});
  it->second += double(points) * double(groups_.size[std::size_t(group)]);
}

int GroupVotes::winner() const {
  if (votes_.empty()) return -1;
  return std::max_element(votes_.begin(), votes_.end(),
                          [](const auto& a, const auto& b) {
                            return a.second < b.second || (a.second == b.second && a.first > b.first);
                          })
      ->first;
}

} // namespace probebake::probe_index::detail
