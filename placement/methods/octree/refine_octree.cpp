#include "refine_octree.h"

#include <algorithm>
#include <queue>

#include <glm/common.hpp>
#include <glm/vector_relational.hpp>

#include "probebake/common/parallel.h"
#include "probebake/formats/error.h"
#include "method_util.h"
#include "refine_sample.h"

namespace probebake::placement {
namespace {

// Leaves split per round of the greedy phase: their children's children are sampled in one parallel
// loop. Small against any useful budget, so the order is nearly that of a one-at-a-time greedy.
constexpr std::size_t kRoundSize = 8;
// Cubes (edge / clearance) from which a centre inside a solid is worth a probe for the relocation.
constexpr float kRelocationRoom = 2.0f;

using TriangleList = std::vector<std::uint32_t>;

struct Leaf {
  formats::NodeCube cube; // .node is valid once in_tree
  TriangleList triangles;
  CandidateSample sample;
  bool in_tree = false;
  bool split = false;
  int first_child = -1; // index of its eight sampled children in the pool, -1 while unsampled

  bool holds_geometry() const { return !triangles.empty(); }
  // A probe where there is surface to light: the centre sees some inside the cube (or lies inside a
  // solid, which sees none). A dead centre (is_dead) is moved by the relocation only when its cube
  // leaves room beyond the clearance; in smaller cubes it was mostly freed (30 of 150 probes in
  // refine_test's cluttered corner), so those leaves get none and spend no budget.
  bool has_probe(float clearance) const {
    if (!holds_geometry() || (sample.rays.hits_in_cube == 0 && !sample.inside())) return false;
    return !is_dead(sample.rays, clearance) || cube.size >= kRelocationRoom * clearance;
  }
};

struct Ranked {
  double score = 0.0;
  int node = 0;
  int leaf = 0;
  bool operator<(const Ranked& o) const { return score != o.score ? score < o.score : node > o.node; }
};

class Refiner {
public:
  Refiner(const PlacementInput& in, formats::Octree& tree)
      : in_(in),
        tree_(tree),
        by_error_(in.refine.rank_by_error),
        sampler_(in, by_error_),
        budget_(in.refine.probe_budget),
        max_depth_(in.settings.max_depth) {}

  std::vector<PlacedProbe> run() {
    add_root();
    const std::vector<int> base = uniform_start();
    refine(base);
    return place_probes();
  }

private:
  void add_root() {
    Leaf root;
    root.cube = formats::root_cube(tree_.volume().info);
    root.triangles.resize(in_.rays->scene().triangles.size());
    for (std::size_t t = 0; t < root.triangles.size(); ++t) root.triangles[t] = std::uint32_t(t);
    root.sample = sampler_.sample(root.cube.centre(), to_cube(root.cube));
    root.in_tree = true;
    leaves_.push_back(std::move(root));
    probes_ = leaves_[0].has_probe(in_.clearance) ? 1 : 0;
  }

  static Cube to_cube(const formats::NodeCube& c) { return {c.min, c.size}; }

  bool splittable(int i) const {
    return leaves_[std::size_t(i)].holds_geometry() && leaves_[std::size_t(i)].cube.depth < max_depth_;
  }

  // Creates and samples the eight children of every leaf in `parents` (one parallel loop).
  void sample_children(const std::vector<int>& parents) {
    const scene::Scene& scene = in_.rays->scene();
    const std::size_t first = leaves_.size();
    for (int p : parents) {
      leaves_[std::size_t(p)].first_child = int(leaves_.size());
      for (int octant = 0; octant < 8; ++octant) {
        Leaf child;
        child.cube = formats::child_cube(leaves_[std::size_t(p)].cube, octant);
        for (std::uint32_t t : leaves_[std::size_t(p)].triangles)
          if (detail::box_overlaps_cube(scene, t, child.cube)) child.triangles.push_back(t);
        leaves_.push_back(std::move(child));
      }
    }
    parallel_for(leaves_.size() - first, in_.settings.threads, [&](std::size_t k) {
      Leaf& leaf = leaves_[first + k];
      if (leaf.holds_geometry()) leaf.sample = sampler_.sample(leaf.cube.centre(), to_cube(leaf.cube));
    });
  }

  int probe_children(int i) const {
    const Leaf& leaf = leaves_[std::size_t(i)];
    int children = 0;
    for (int c = 0; c < 8; ++c) children += leaves_[std::size_t(leaf.first_child + c)].has_probe(in_.clearance) ? 1 : 0;
    return children;
  }

  // Probes a split of leaf i adds (negative or zero when its children hold fewer than it does).
  int split_cost(int i) const { return probe_children(i) - (leaves_[std::size_t(i)].has_probe(in_.clearance) ? 1 : 0); }

  void split(int i) {
    Leaf& leaf = leaves_[std::size_t(i)];
    const int meta = tree_.split(leaf.cube.node);
    if (meta == formats::kNoIndex) throw Error(ErrorKind::internal, "refine: split refused below max depth");
    probes_ += split_cost(i);
    leaf.split = true;
    for (int octant = 0; octant < 8; ++octant) {
      Leaf& child = leaves_[std::size_t(leaf.first_child + octant)];
      child.cube.node = formats::child_node(meta, octant);
      child.in_tree = true;
    }
  }

  std::vector<int> children_of(int i) const {
    std::vector<int> out;
    for (int c = 0; c < 8; ++c) out.push_back(leaves_[std::size_t(i)].first_child + c);
    return out;
  }

  // Splits every leaf holding geometry, level by level, while the next level's probes stay within the
  // uniform share of the budget. Returns the leaves of the last level reached.
  std::vector<int> uniform_start() {
    const long long limit = (long long)(double(in_.refine.uniform_share) * double(budget_));
    std::vector<int> level = {0};
    for (;;) {
      std::vector<int> parents;
      for (int i : level)
        if (splittable(i)) parents.push_back(i);
      if (parents.empty()) return level;
      sample_children(parents);
      long long next = probes_;
      for (int p : parents) next += split_cost(p);
      if (next > limit) return level;
      std::vector<int> next_level;
      for (int i : level) {
        if (!splittable(i)) continue;
        split(i);
        for (int c : children_of(i)) next_level.push_back(c);
      }
      level = std::move(next_level);
      report_progress();
    }
  }

  // Error a split of leaf i removes, per probe it costs.
  double split_score(int i) const {
    const Leaf& leaf = leaves_[std::size_t(i)];
    double error = 0.0;
    for (int c = 0; c < 8; ++c) {
      const Leaf& child = leaves_[std::size_t(leaf.first_child + c)];
      if (!child.has_probe(in_.clearance) || child.sample.inside()) continue;
      // Surface rule, or an unlit scene (nothing to estimate): where a probe serves the most surface.
      const double difference =
          by_error_ && sampler_.lit() ? double(sh_distance2(child.sample.sh, leaf.sample.sh)) : 1.0;
      error += double(child.sample.visible_area) * difference;
    }
    return error / double(std::max(split_cost(i), 1));
  }

  void push_scored(const std::vector<int>& candidates, std::priority_queue<Ranked>& heap) {
    std::vector<int> unsampled;
    for (int i : candidates)
      if (leaves_[std::size_t(i)].first_child < 0) unsampled.push_back(i);
    sample_children(unsampled);
    for (int i : candidates) {
      // A split that removes no estimated error, or leaves the cube without probes, is never made.
      const double score = split_score(i);
      if (score > 0.0 && probe_children(i) > 0) heap.push({score, leaves_[std::size_t(i)].cube.node, i});
    }
  }

  void refine(const std::vector<int>& base) {
    std::priority_queue<Ranked> heap;
    std::vector<int> candidates;
    for (int i : base)
      if (splittable(i)) candidates.push_back(i);
    push_scored(candidates, heap);
    while (!heap.empty()) {
      std::vector<int> fresh;
      for (std::size_t n = 0; n < kRoundSize && !heap.empty(); ++n) {
        const int i = heap.top().leaf;
        heap.pop();
        if (probes_ + split_cost(i) > budget_) continue;
        split(i);
        for (int c : children_of(i))
          if (splittable(c)) fresh.push_back(c);
      }
      push_scored(fresh, heap);
      report_progress();
    }
  }

  std::vector<PlacedProbe> place_probes() {
    std::vector<int> order;
    for (std::size_t i = 0; i < leaves_.size(); ++i)
      if (leaves_[i].in_tree && !leaves_[i].split && leaves_[i].has_probe(in_.clearance)) order.push_back(int(i));
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return leaves_[std::size_t(a)].cube.node < leaves_[std::size_t(b)].cube.node; });
    std::vector<PlacedProbe> placed;
    for (int i : order) {
      const Leaf& leaf = leaves_[std::size_t(i)];
      const int probe = tree_.place_probe(leaf.cube.node);
      gpu::Probe& record = tree_.volume().probes[std::size_t(probe)];
      record.hit_fraction = leaf.sample.rays.hit_fraction();
      record.backface_fraction = leaf.sample.rays.backface_fraction();
      placed.push_back({probe, to_cube(leaf.cube), leaf.sample.rays});
    }
    return placed;
  }

  void report_progress() const {
    if (in_.progress) in_.progress(std::min(1.0, double(probes_) / double(std::max(budget_, 1))));
  }

  const PlacementInput& in_;
  formats::Octree& tree_;
  bool by_error_; // SplitRule::error: rank by estimated error, else (surface) by visible surface
  CandidateSampler sampler_;
  int budget_;
  int max_depth_;
  std::vector<Leaf> leaves_; // every sampled cube: in the tree or a not (yet) created child
  long long probes_ = 0;     // probe leaves in the tree
};

} // namespace

std::vector<PlacedProbe> place_octree_by_error(const PlacementInput& in, formats::Octree& tree) {
  return Refiner(in, tree).run();
}

} // namespace probebake::placement
