// Validator phase for the SVO probe index (non-uniform placement paper §4.1): a tree of int32 nodes
// (children in blocks of eight that follow their parent), payload indices in range and unshared,
// payloads naming live probes with finite, non-negative weights that sum to one over the used slots.
#include <cmath>

#include "text.h"
#include "validate_internal.h"

namespace probebake::formats::detail {
namespace {

constexpr int kTraversalDepthCap = 30;

struct SvoVisit {
  int node;
  int depth;
};

class SvoChecker {
public:
  SvoChecker(const ProbeVolume& volume, Reporter& out) : volume_(volume), nodes_(volume.svo_nodes), out_(out) {}

  void run() {
    referenced_.assign(volume_.svo_leaves.size(), false);
    reached_.assign(nodes_.size(), false);
    if (!nodes_.empty()) traverse();
    for (std::size_t node = 1; node < nodes_.size(); ++node) {
      if (!reached_[node] && nodes_[node] != 0) {
        out_.add("svo_tree", "svo_nodes", static_cast<long long>(node),
                 "non-empty node is not reachable from the root");
      }
    }
    for (std::size_t leaf = 0; leaf < volume_.svo_leaves.size(); ++leaf) {
      if (referenced_[leaf]) {
        check_payload(static_cast<long long>(leaf));
      } else {
        check_free_payload(static_cast<long long>(leaf));
      }
    }
  }

private:
  void traverse() {
    std::vector<SvoVisit> stack{SvoVisit{0, 0}};
    reached_[0] = true;
    while (!stack.empty()) {
      const SvoVisit visit = stack.back();
      stack.pop_back();
      const int value = nodes_[visit.node];
      if (value < 0) {
        visit_leaf(visit.node, ~value);
      } else if (value > 0) {
        visit_children(visit, value, stack);
      }
    }
  }

  void visit_leaf(int node, int leaf) {
    if (static_cast<std::size_t>(leaf) >= referenced_.size()) {
      out_.add("svo_index_range", "svo_nodes", node, concat("leaf payload index ", leaf, " out of range"));
    } else if (referenced_[leaf]) {
      out_.add("svo_leaf_shared", "svo_nodes", node, concat("leaf payload ", leaf, " is used by two voxels"));
    } else {
      referenced_[leaf] = true;
    }
  }

  void visit_children(const SvoVisit& visit, int first, std::vector<SvoVisit>& stack) {
    if (static_cast<std::size_t>(first) + 8 > nodes_.size()) {
      out_.add("svo_index_range", "svo_nodes", visit.node,
               concat("children ", first, "..", static_cast<long long>(first) + 7, " out of range"));
      return;
    }
    if (first <= visit.node) {
      out_.add("svo_tree", "svo_nodes", visit.node, concat("children at ", first, " do not follow their parent"));
      return;
    }
    for (int octant = 0; octant < 8; ++octant) {
      if (reached_[first + octant]) {
        out_.add("svo_tree", "svo_nodes", visit.node, concat("child block ", first, " is shared with another node"));
        return;
      }
    }
    if (visit.depth + 1 > volume_.info.svo_depth) { // reported, and still walked to check the rest
      out_.add("svo_depth", "svo_nodes", visit.node, concat("children deeper than svo_depth ", volume_.info.svo_depth));
    }
    if (visit.depth >= kTraversalDepthCap) return;
    for (int octant = 7; octant >= 0; --octant) {
      reached_[first + octant] = true;
      stack.push_back(SvoVisit{first + octant, visit.depth + 1});
    }
  }

  void check_payload(long long index) {
    const gpu::SvoLeaf& leaf = volume_.svo_leaves[static_cast<std::size_t>(index)];
    int used = 0;
    bool seen_unused = false;
    float sum = 0.0f;
    for (int slot = 0; slot < gpu::SVO_PROBES_PER_LEAF; ++slot) {
      const int probe = leaf.probes[slot];
      const float weight = leaf.weights[slot];
      if (probe == -1) {
        seen_unused = true;
        if (weight != 0.0f)
          out_.add("svo_weights", "svo_leaves", index, concat("unused slot ", slot, " has weight ", weight));
        continue;
      }
      if (probe < -1 || static_cast<std::size_t>(probe) >= volume_.probes.size()) {
        out_.add("svo_index_range", "svo_leaves", index,
                 concat("slot ", slot, " names probe ", probe, ", out of range"));
      } else if (volume_.probes[probe].link == 0) {
        out_.add("svo_freed_probe", "svo_leaves", index,
                 concat("slot ", slot, " names probe ", probe, ", which is free"));
      }
      if (seen_unused)
        out_.add("svo_weights", "svo_leaves", index, concat("used slot ", slot, " follows an unused one"));
      if (!(weight >= 0.0f))
        out_.add("svo_weights", "svo_leaves", index, concat("slot ", slot, " has negative weight ", weight));
      ++used;
      sum += weight;
    }
    if (!std::isfinite(sum)) return; // non_finite reported earlier
    if (used == 0) {
      out_.add("svo_weights", "svo_leaves", index, "leaf voxel with no probe (empty voxels are 0 nodes)");
    } else if (std::fabs(sum - 1.0f) > out_.options().weight_tolerance) {
      out_.add("svo_weights", "svo_leaves", index, concat("weights sum to ", sum, ", not 1"));
    }
  }

  void check_free_payload(long long index) {
    const gpu::SvoLeaf& leaf = volume_.svo_leaves[static_cast<std::size_t>(index)];
    for (int slot = 0; slot < gpu::SVO_PROBES_PER_LEAF; ++slot) {
      if (leaf.probes[slot] != -1 || leaf.weights[slot] != 0.0f) {
        out_.add("free_not_zeroed", "svo_leaves", index, "payload no voxel uses is not empty (probes -1, weights 0)");
        return;
      }
    }
  }

  const ProbeVolume& volume_;
  const std::vector<std::int32_t>& nodes_;
  Reporter& out_;
  std::vector<bool> referenced_, reached_;
};

} // namespace

void check_svo(const ProbeVolume& volume, Reporter& out) { SvoChecker(volume, out).run(); }

} // namespace probebake::formats::detail
