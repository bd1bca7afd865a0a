// The dynamic octree's CPU reference (dynamic/) on a real scene in motion: the octree thesis's animated
// test (§4.1.3: 600 frames, the objects turn 45° about their vertical axes from frame 200 to 350), its
// Appendix B test (a full turn over 150 frames, then 50 still, three times), and a soak of random turns
// that ends where it began. Leaves are measured with the bake's own lattice tracing through Embree,
// rebuilt each frame in the current pose. Prints a summary; --csv writes one row per frame.
//
// Usage: probebake-bench-animated-tree SCENE --move NAME[,NAME...] [--motion thesis|revolution|soak]
//          [--frames N] [--max-depth D] [--surfels N] [--csv FILE]
// Instances whose node name starts with one of the NAMEs turn, each group about its own vertical axis.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <glm/gtc/matrix_transform.hpp>

#include "probebake/placement/probe_tracing.h"
#include "probebake/bake/bake.h"
#include "probebake/common/lattice.h"
#include "probebake/scene/ray_scene.h"
#include "probebake/dynamic/tree_update.h"
#include "probebake/formats/validate.h"

namespace {

using namespace probebake;

struct Options {
  std::string scene, csv, motion = "thesis";
  std::vector<std::string> move;
  int frames = 0, max_depth = 3, surfels = 64;
};

// One group of instances that turns about the vertical axis through its bounds' centre.
struct Group {
  std::vector<std::uint32_t> vertices;
  glm::vec3 pivot{0.0f};
  float angle = 0.0f; // radians, current
};

std::vector<Group> find_groups(const scene::Scene& s, const std::vector<std::string>& names) {
  std::vector<Group> groups;
  for (const std::string& name : names) {
    Group g;
    scene::Bounds b;
    for (const scene::Instance& inst : s.instances) {
      if (inst.node_name.rfind(name, 0) != 0) continue;
      for (std::uint32_t t = inst.first_triangle; t < inst.first_triangle + inst.triangle_count; ++t) {
        for (int k = 0; k < 3; ++k) g.vertices.push_back(s.triangles[t][k]);
      }
      b.extend(inst.bounds.min);
      b.extend(inst.bounds.max);
    }
    std::sort(g.vertices.begin(), g.vertices.end());
    g.vertices.erase(std::unique(g.vertices.begin(), g.vertices.end()), g.vertices.end());
    if (g.vertices.empty()) throw std::runtime_error("no instance named " + name + "*");
    g.pivot = 0.5f * (b.min + b.max);
    groups.push_back(std::move(g));
  }
  return groups;
}

dynamic::Box bounds_of(const scene::Scene& s, const Group& g) {
  dynamic::Box box{glm::vec3(3e38f), glm::vec3(-3e38f)};
  for (const std::uint32_t v : g.vertices) {
    box.min = glm::min(box.min, s.positions[v]);
    box.max = glm::max(box.max, s.positions[v]);
  }
  return box;
}

// Sets the group's angle: positions rotated about the pivot from the rest pose.
void pose(scene::Scene& s, const scene::Scene& rest, Group& g, float angle) {
  const glm::mat4 m =
      glm::translate(glm::rotate(glm::translate(glm::mat4(1.0f), g.pivot), angle, glm::vec3(0, 1, 0)), -g.pivot);
  for (const std::uint32_t v : g.vertices) s.positions[v] = glm::vec3(m * glm::vec4(rest.positions[v], 1.0f));
  g.angle = angle;
}

// Angle of every group at `frame` for the scripted motions; the soak draws its own.
float scripted_angle(const std::string& motion, int frame) {
  constexpr float quarter_pi = 0.785398163f, two_pi = 6.28318531f;
  if (motion == "thesis") return quarter_pi * std::clamp(float(frame - 200) / 150.0f, 0.0f, 1.0f);
  const int cycle = frame % 200; // revolution: 150 frames turning, 50 still
  return cycle < 150 ? two_pi * float(cycle) / 150.0f : 0.0f;
}

struct Counts {
  int live = 0;
  int by_state[gpu::LEAF_STATE_COUNT] = {};
};

Counts count(const formats::ProbeVolume& v) {
  Counts c;
  for (const gpu::Probe& p : v.probes) c.live += p.link != 0 ? 1 : 0;
  for (int s = 0; s < 3; ++s) {
    for (int e = 0; e < v.leaf_header.count[s]; ++e)
      ++c.by_state[v.leaf_entries[std::size_t(s * v.leaf_header.segment_capacity + e)].state];
  }
  return c;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&] {
      if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
      return std::string(argv[++i]);
    };
    if (a == "--move") {
      std::string list = next();
      for (std::size_t at = 0; at <= list.size();) {
        const std::size_t comma = std::min(list.find(',', at), list.size());
        o.move.push_back(list.substr(at, comma - at));
        at = comma + 1;
      }
    } else if (a == "--motion")
      o.motion = next();
    else if (a == "--frames")
      o.frames = std::stoi(next());
    else if (a == "--max-depth")
      o.max_depth = std::stoi(next());
    else if (a == "--surfels")
      o.surfels = std::stoi(next());
    else if (a == "--csv")
      o.csv = next();
    else
      o.scene = a;
  }
  if (o.scene.empty() || o.move.empty())
    throw std::runtime_error("usage: probebake-bench-animated-tree SCENE --move NAME[,NAME] [--motion "
                             "thesis|revolution|soak] [--frames N] [--max-depth D] [--surfels N] [--csv FILE]");
  if (o.frames == 0) o.frames = o.motion == "thesis" ? 600 : o.motion == "revolution" ? 600 : 10000;
  return o;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

} // namespace

int main(int argc, char** argv) try {
  const Options o = parse(argc, argv);
  const scene::Scene rest = scene::load_scene(o.scene, {.require_triangles = true});
  scene::Scene moving = rest;
  std::vector<Group> groups = find_groups(rest, o.move);
  const std::vector<glm::vec3> lattice = lattice_directions(Lattice::fibonacci, o.surfels);

  bake::BakeSettings settings; // the bake's root cube and thresholds
  settings.max_depth = o.max_depth;
  settings.surfels_per_probe = o.surfels;
  formats::ProbeVolume volume = formats::make_empty_volume(bake::volume_info(rest, settings));
  volume.surfel_batches.resize(1);
  {
    formats::Octree grow(volume);
    grow.reserve_clusters(20000);
    grow.reserve_probes(60000);
    grow.reserve_batches(60000 * ((o.surfels + gpu::SURFELS_PER_BATCH - 1) / gpu::SURFELS_PER_BATCH));
  }
  formats::Octree tree(volume, formats::Octree::Growth::fixed);
  dynamic::TreeUpdate update(tree);
  const int start_clusters = tree.free_clusters(), start_probes = tree.free_probes(),
            start_batches = tree.free_batches();

  std::ofstream csv;
  if (!o.csv.empty()) {
    csv.open(o.csv);
    csv << "frame,cpu_ms,tree_ms,live_probes,placed,freed,splits,collapses,failed,deferred";
    for (const char* s : {"M0", "M1", "M2", "M3", "M4", "L0", "L1", "L2", "L3"}) csv << ",queued_" << s;
    csv << "\n";
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> turn(-0.3f, 0.3f);
  std::vector<double> tree_ms;
  int violations = 0, max_live = 0, probes_at[3] = {0, 0, 0}; // before, at the end of, after the motion
  std::array<int, 3> pools_at_start{}; // free clusters, probes, batches at frame 49 (settled, before any motion)
  for (int frame = 0; frame < o.frames; ++frame) {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<dynamic::Box> changed;
    if (frame == 0)
      changed.push_back({volume.info.root_min, volume.info.root_min + volume.info.root_size}); // grow from the root
    const bool last = frame == o.frames - 1;
    for (Group& g : groups) {
      // The soak holds still for 50 frames at each end, in the rest pose at the end, to compare the pools.
      const bool soak_moves = frame >= 50 && frame < o.frames - 50;
      const float angle =
          o.motion == "soak" ? (soak_moves ? g.angle + turn(rng) : 0.0f) : scripted_angle(o.motion, frame);
      if (angle == g.angle) continue;
      const dynamic::Box before = bounds_of(moving, g);
      pose(moving, rest, g, angle);
      const dynamic::Box after = bounds_of(moving, g);
      changed.push_back({glm::min(before.min, after.min), glm::max(before.max, after.max)});
    }
    const scene::RayScene rays(moving);
    const auto t1 = std::chrono::steady_clock::now();
    const dynamic::TreeFrameStats st = update.run_frame(changed, [&](const formats::NodeCube& c, glm::vec3 p) {
      const placement::ProbeRays r = placement::trace_probe(rays, p, {c.min, c.size}, lattice);
      return dynamic::LeafTrace{r.hit_fraction(), r.backface_fraction()};
    });
    const auto t2 = std::chrono::steady_clock::now();
    const double ms_tree = std::chrono::duration<double, std::milli>(t2 - t1).count();
    tree_ms.push_back(ms_tree);
    const Counts c = count(volume);
    max_live = std::max(max_live, c.live);
    if (frame == 49) pools_at_start = {tree.free_clusters(), tree.free_probes(), tree.free_batches()};
    if (frame == 199) probes_at[0] = c.live;
    if (frame == 349) probes_at[1] = c.live;
    if (last) probes_at[2] = c.live;
    if (frame % 100 == 0 || last) {
      formats::rebuild_probe_index(volume);
      violations +=
          int(formats::validate(volume).violations.size()) + int(dynamic::check_queue_covers_tree(volume).size());
    }
    violations += st.lost_entries + st.stale_entries;
    if (csv.is_open()) {
      csv << frame << ',' << std::chrono::duration<double, std::milli>(t2 - t0).count() << ',' << ms_tree << ','
          << c.live << ',' << st.probes_placed << ',' << st.probes_freed << ',' << st.splits << ',' << st.collapses
          << ',' << st.failed_allocations << ',' << st.deferred;
      for (const int n : c.by_state) csv << ',' << n;
      csv << "\n";
    }
  }
  // The soak ends in the rest pose: let the tree settle and compare the pools with the first settled state.
  fmt::print("| scene | motion | frames | max depth | surfels | probes f199 | probes f349 | probes last | max live | "
             "tree ms median | tree ms worst | violations |\n");
  fmt::print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  fmt::print("| {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.3f} | {:.3f} | {} |\n",
             std::filesystem::path(o.scene).filename().string(), o.motion, o.frames, o.max_depth, o.surfels,
             probes_at[0], probes_at[1], probes_at[2], max_live, median(tree_ms),
             *std::max_element(tree_ms.begin(), tree_ms.end()), violations);
  fmt::print("pool use at the end: clusters {}, probes {}, batches {} (of {}, {}, {})\n",
             start_clusters - tree.free_clusters(), start_probes - tree.free_probes(),
             start_batches - tree.free_batches(), start_clusters, start_probes, start_batches);
  const std::array<int, 3> pools_at_end{tree.free_clusters(), tree.free_probes(), tree.free_batches()};
  if (o.motion == "soak")
    fmt::print("pools after returning to the rest pose: {} the settled start (free clusters/probes/batches {}/{}/{} vs "
               "{}/{}/{})\n",
               pools_at_end == pools_at_start ? "equal to" : "DIFFERENT from", pools_at_end[0], pools_at_end[1],
               pools_at_end[2], pools_at_start[0], pools_at_start[1], pools_at_start[2]);
  return violations == 0 && (o.motion != "soak" || pools_at_end == pools_at_start) ? 0 : 1;
} catch (const std::exception& e) {
  fmt::print(stderr, "probebake-bench-animated-tree: error: {}\n", e.what());
  return 2;
}
