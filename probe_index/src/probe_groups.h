// Probe groups for the SVO builder (build.cpp): probes joined by unoccluded segments to any of their nearest
// neighbours share a group, so that a voxel cut by a wall serves one side's probes only (issue #39).
#pragma once

#include <algorithm>
#include <utility>
#include <vector>

#include "probebake/formats/probe_volume.h"
#include "probebake/scene/ray_scene.h"
#include "probe_buckets.h"

namespace probebake::probe_index::detail {

// Disjoint sets over 0..n-1 whose lowest member names each set (so the result is independent of join order
// within a set).
class DisjointSets {
public:
  explicit DisjointSets(std::size_t n) : parent_(n) {
    for (std::size_t i = 0; i < n; ++i) parent_[i] = int(i);
  }
  int root(int i) {
    while (parent_[std::size_t(i)] != i) i = parent_[std::size_t(i)] = parent_[std::size_t(parent_[std::size_t(i)])];
    return i;
  }
  void join(int a, int b) {
    a = root(a);
    b = root(b);
    parent_[std::size_t(std::max(a, b))] = std::min(a, b);
  }

private:
  std::vector<int> parent_;
};

// Probes joined by unoccluded segments to any of their nearest neighbours form a group: the open space
// players move in is one large group, a sealed cavity (the inside of a double-sided light box) a small one.
struct ProbeGroups {
  std::vector<int> group; // per probe: its group's id (the lowest probe index in it), -1 for free slots
  std::vector<int> size;  // per group id: live probes in it
  int largest = 0;        // the largest group's size
  // A group of at most a quarter of the largest one's probes: a cavity's, like the light box's inside.
  bool minor(int g) const { return g >= 0 && 4 * size[std::size_t(g)] <= largest; }
};

// The vote for the one group that serves a voxel: each of its regions (or octants) votes for a group it sees
// with its open points times the group's probes, so that a sealed cavity's dozen probes lose to the room's
// thousands while two rooms either side of a wall compete by volume. The most votes win, ties the lower id.
class GroupVotes {
public:
  explicit GroupVotes(const ProbeGroups& groups) : groups_(groups) {}
  void vote(int group, int points);
  std::size_t groups_voted() const { return votes_.size(); }
  int winner() const; // -1 without votes

private:
  const ProbeGroups& groups_;
  std::vector<std::pair<int, double>> votes_; // (group, votes), in first-vote order
};

// The probes' groups: probes joined by unoccluded segments to any of their nearest 12 neighbours
// share one. Visibility in parallel, the joins in probe order (deterministic).
ProbeGroups probe_groups(const scene::RayScene& rays, const formats::ProbeVolume& v, const ProbeBuckets& buckets,
                         int threads);

} // namespace probebake::probe_index::detail
