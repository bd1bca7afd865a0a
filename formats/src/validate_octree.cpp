// Validator phase for the octree buffer of the octree thesis §3.1.1: root at 0, clusters of nine
// elements whose meta element holds ~parent and whose parent points back, sign rules, every cluster
// reachable from the root exactly once, no cycles, the incomplete trailing cluster never used, depth
// within info.max_depth. Runs in passes from cheap to deep; each cluster is reported at most once.
#include <unordered_map>

#include "probebake/formats/placement_kind.h"
#include "text.h"
#include "validate_internal.h"

namespace probebake::formats::detail {
namespace {

// Traversal stops descending here even in a corrupt tree (cubes would underflow long before).
constexpr int kTraversalDepthCap = 64;

class OctreeChecker {
public:
  OctreeChecker(const ProbeVolume& volume, Reporter& out)
      : volume_(volume),
        octree_(volume.octree),
        out_(out),
        clusters_(complete_clusters(octree_.size())),
        usable_end_(static_cast<int>(1 + 9 * clusters_)) {}

  OctreeFacts run() {
    const std::size_t violations_before = out_.count();
    facts_.cubes.assign(octree_.size(), NodeCube{-1, 0, glm::vec3(0.0f), 0.0f});
    if (octree_.empty()) {
      out_.add("octree_root", "octree", -1, "the octree buffer is empty (no root node)");
      facts_.clean = false;
      return std::move(facts_);
    }
    check_incomplete_tail();
    check_grid_has_no_octree();
    check_cluster_metas();
    collect_child_links();
    check_parent_links();
    traverse_from_root();
    check_unreached_clusters();
    facts_.clean = out_.count() == violations_before;
    return std::move(facts_);
  }

private:
  int meta_of_cluster(std::size_t cluster) const { return static_cast<int>(1 + 9 * cluster); }
  std::size_t cluster_of_meta(int meta) const { return static_cast<std::size_t>(meta - 1) / 9; }
  bool is_usable_node(int index) const { return index >= 0 && index < usable_end_ && is_node_index(index); }
  bool allocated(std::size_t cluster) const { return octree_[meta_of_cluster(cluster)] < 0; }

  // A trailing incomplete cluster is never used, so all its elements are zero.
  void check_incomplete_tail() {
    for (std::size_t i = static_cast<std::size_t>(usable_end_); i < octree_.size(); ++i) {
      if (octree_[i] != 0) {
        out_.add("incomplete_cluster_used", "octree", static_cast<long long>(i),
                 "element of the incomplete trailing cluster is not zero");
        return;
      }
    }
  }

  void check_grid_has_no_octree() {
    const PlacementKindInfo* kind = placement_kind_for_code(volume_.info.placement);
    if (kind == nullptr || kind->has_octree) return;
    if (octree_[0] != 0) out_.add("grid_octree", "octree", 0, "grid placement: the root must be a leaf without probe");
    for (std::size_t cluster = 0; cluster < clusters_; ++cluster) {
      if (allocated(cluster)) {
        out_.add("grid_octree", "octree", meta_of_cluster(cluster), "grid placement: no node cluster may be allocated");
        return;
      }
    }
  }

  // Pass 1, per cluster: free clusters are all zero, metas are never positive, parents are node indices.
  void check_cluster_metas() {
    bad_parent_.assign(clusters_, false);
    for (std::size_t cluster = 0; cluster < clusters_; ++cluster) {
      const int meta = meta_of_cluster(cluster);
      const int value = octree_[meta];
      if (value == 0) {
        for (int octant = 0; octant < 8; ++octant) {
          if (octree_[child_node(meta, octant)] != 0) {
            out_.add("free_not_zeroed", "octree", child_node(meta, octant),
                     concat("node of free cluster ", meta, " is not zero"));
            break;
          }
        }
      } else if (value > 0) {
        bad_parent_[cluster] = true;
        out_.add("node_sign", "octree", meta,
                 concat("meta element is positive (", value, "); it must be 0 or ~parent"));
      } else if (!is_usable_node(~value)) {
        bad_parent_[cluster] = true;
        out_.add("meta_parent_mismatch", "octree", meta,
                 concat("meta names parent ", ~value, ", which is not a node index"));
      }
    }
  }

  // Pass 2: child links of the root and of nodes in allocated clusters; valid ones are recorded.
  void collect_child_links() {
    child_ok_.assign(octree_.size(), false);
    first_referrer_.assign(clusters_, -1);
    check_child_link(0);
    for (std::size_t cluster = 0; cluster < clusters_; ++cluster) {
      if (!allocated(cluster)) continue;
      for (int octant = 0; octant < 8; ++octant) check_child_link(child_node(meta_of_cluster(cluster), octant));
    }
  }

  void check_child_link(int node) {
    const int child = octree_[node];
    if (child <= 0) return;
    if (is_meta_index(child) && child < static_cast<int>(octree_.size()) && child >= usable_end_) {
      out_.add("incomplete_cluster_used", "octree", node,
               concat("child cluster ", child, " is the incomplete trailing cluster"));
    } else if (!is_meta_index(child) || child >= static_cast<int>(octree_.size())) {
      out_.add("octree_child_range", "octree", node,
               concat("child index ", child, " is not the meta index of a cluster"));
    } else if (octree_[child] == 0) {
      out_.add("meta_parent_mismatch", "octree", node, concat("child cluster ", child, " is free"));
    } else if (octree_[child] < 0) {
      child_ok_[node] = true;
      const std::size_t cluster = cluster_of_meta(child);
      if (first_referrer_[cluster] < 0) {
        first_referrer_[cluster] = node;
      } else {
        more_referrers_[cluster].push_back(node);
      }
    }
  }

  // Pass 3, per allocated cluster: exactly one node points at it, and it is the node its meta names.
  void check_parent_links() {
    reported_.assign(clusters_, false);
    for (std::size_t cluster = 0; cluster < clusters_; ++cluster) {
      if (!allocated(cluster) || bad_parent_[cluster]) continue;
      const int meta = meta_of_cluster(cluster);
      const int parent = ~octree_[meta];
      const int referrer = first_referrer_[cluster];
      if (const auto more = more_referrers_.find(cluster); more != more_referrers_.end()) {
        reported_[cluster] = true;
        report_shared_cluster(meta, referrer, more->second);
      } else if (referrer >= 0 && referrer != parent) {
        reported_[cluster] = true;
        out_.add("meta_parent_mismatch", "octree", meta,
                 concat("meta names parent ", parent, " but node ", referrer, " points here"));
      } else if (referrer < 0) {
        reported_[cluster] = true;
        out_.add(
            "octree_unreachable", "octree", meta,
            concat("allocated cluster: its parent ", parent, " does not point to it (value ", octree_[parent], ")"));
      }
    }
  }

  void report_shared_cluster(int meta, int referrer, const std::vector<int>& more) {
    bool cycle = is_inside_subtree(referrer, meta);
    for (int other : more) cycle = cycle || is_inside_subtree(other, meta);
    if (cycle) {
      out_.add("octree_cycle", "octree", meta, concat("cluster is a child of a node in its own subtree"));
    } else {
      out_.add("octree_two_parents", "octree", meta,
               concat("nodes ", referrer, " and ", more.front(), " both point at this cluster"));
    }
  }

  // Whether `node` lies below the cluster at `meta`, following meta -> parent links (bounded).
  bool is_inside_subtree(int node, int meta) const {
    for (std::size_t steps = 0; steps <= clusters_ && node > 0; ++steps) {
      const int node_meta = cluster_meta_of(node);
      if (node_meta == meta) return true;
      if (octree_[node_meta] >= 0) return false;
      node = ~octree_[node_meta];
      if (!is_usable_node(node)) return false;
    }
    return false;
  }

  // Pass 4: depth-first from the root over valid links, each cluster once; records every node's cube.
  void traverse_from_root() {
    visited_.assign(clusters_, false);
    std::vector<NodeCube> stack{root_cube(volume_.info)};
    while (!stack.empty()) {
      const NodeCube cube = stack.back();
      stack.pop_back();
      facts_.cubes[cube.node] = cube;
      if (!child_ok_[cube.node]) continue;
      const int meta = octree_[cube.node];
      const std::size_t cluster = cluster_of_meta(meta);
      if (visited_[cluster]) continue; // a second parent, reported in pass 3
      visited_[cluster] = true;
      if (cube.depth >= volume_.info.max_depth) {
        out_.add("octree_too_deep", "octree", cube.node,
                 concat("parent at depth ", cube.depth, ", max_depth is ", volume_.info.max_depth));
      }
      if (cube.depth >= kTraversalDepthCap) continue;
      for (int octant = 7; octant >= 0; --octant) {
        NodeCube child = child_cube(cube, octant);
        child.node = child_node(meta, octant);
        stack.push_back(child);
      }
    }
  }

  // Pass 5: allocated clusters that the traversal did not reach and no earlier pass explained: a
  // detached cycle (parents lead back to the start) or a detached chain.
  void check_unreached_clusters() {
    std::vector<std::size_t> on_path_stamp(clusters_, static_cast<std::size_t>(-1));
    for (std::size_t cluster = 0; cluster < clusters_; ++cluster) {
      if (!allocated(cluster) || visited_[cluster] || reported_[cluster] || bad_parent_[cluster]) continue;
      std::vector<std::size_t> path{cluster};
      on_path_stamp[cluster] = cluster;
      bool cycle = false;
      for (int parent = ~octree_[meta_of_cluster(cluster)]; parent > 0;) {
        const std::size_t up = cluster_of_meta(cluster_meta_of(parent));
        if (on_path_stamp[up] == cluster) {
          cycle = true;
          break;
        }
        if (!allocated(up) || visited_[up] || reported_[up] || bad_parent_[up]) break;
        on_path_stamp[up] = cluster;
        path.push_back(up);
        parent = ~octree_[meta_of_cluster(up)];
      }
      for (std::size_t on_path : path) reported_[on_path] = true;
      const int meta = meta_of_cluster(cluster);
      if (cycle) {
        out_.add("octree_cycle", "octree", meta, "parent links form a cycle that does not reach the root");
      } else {
        out_.add("octree_unreachable", "octree", meta, "allocated cluster is not reachable from the root");
      }
    }
  }

  const ProbeVolume& volume_;
  const std::vector<std::int32_t>& octree_;
  Reporter& out_;
  std::size_t clusters_;
  int usable_end_;
  OctreeFacts facts_;
  std::vector<bool> bad_parent_, child_ok_, reported_, visited_;
  std::vector<int> first_referrer_;
  std::unordered_map<std::size_t, std::vector<int>> more_referrers_;
};

} // namespace

OctreeFacts check_octree(const ProbeVolume& volume, Reporter& out) { return OctreeChecker(volume, out).run(); }

} // namespace probebake::formats::detail
