// Receivers of `probebake eval`: what a player can see, found from viewpoints in open space.
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numeric>
#include <optional>

#include <fmt/core.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vector_relational.hpp>

#include "probebake/common/parallel.h"
#include "probebake/placement/probe_tracing.h"
#include "probebake/eval/eval.h"
#include "probebake/common/enum_names.h"
#include "probebake/common/lattice.h"
#include "probebake/formats/error.h"
#include "rng.h"
#include "sampling.h"

namespace probebake::bake {
namespace {

constexpr int kOpenRays = 64;    // directions of the open-space test (the bake's dead-probe test)
constexpr int kMaxRounds = 64;   // rounds of `count` candidates before giving up on rare hits
constexpr int kKeepFraction = 4; // open regions of at least 1/4 of the largest one are the player's

// The viewpoint grid over the scene bounds; a flat axis is widened to 10% of the largest extent so
// that a single plane still has open space above it.
struct Grid {
  glm::vec3 min{0.0f}, step{1.0f};
  glm::ivec3 n{1};
  std::size_t size() const { return std::size_t(n.x) * std::size_t(n.y) * std::size_t(n.z); }
  glm::ivec3 cell(std::size_t i) const {
    return {int(i % std::size_t(n.x)), int((i / std::size_t(n.x)) % std::size_t(n.y)),
            int(i / (std::size_t(n.x) * std::size_t(n.y)))};
  }
  std::size_t index(glm::ivec3 c) const {
    return (std::size_t(c.z) * std::size_t(n.y) + std::size_t(c.y)) * std::size_t(n.x) + std::size_t(c.x);
  }
  glm::vec3 centre(std::size_t i) const { return min + (glm::vec3(cell(i)) + 0.5f) * step; }
};

Grid make_grid(const scene::Bounds& bounds, int cells) {
  const glm::vec3 extent = bounds.max - bounds.min;
  const float largest = std::max({extent.x, extent.y, extent.z, 1e-6f});
  const glm::vec3 size = glm::max(extent, glm::vec3(0.1f * largest));
  const float cell = largest / float(cells);
  Grid g;
  g.min = 0.5f * (bounds.min + bounds.max) - 0.5f * size;
  for (int a = 0; a < 3; ++a) {
    g.n[a] = std::max(1, int(std::lround(size[a] / cell)));
    g.step[a] = size[a] / float(g.n[a]);
  }
  return g;
}

// Union-find over cells, smallest index as root (so the result does not depend on the union order).
std::size_t find_root(std::vector<std::size_t>& parent, std::size_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

void unite(std::vector<std::size_t>& parent, std::size_t a, std::size_t b) {
  a = find_root(parent, a);
  b = find_root(parent, b);
  if (a != b) parent[std::max(a, b)] = std::min(a, b);
}

struct OpenSpace {
  std::vector<glm::vec3> viewpoints;
  int regions = 0, open_regions = 0;
  glm::vec3 step{0.0f};
};

// Open cells joined to their +x/+y/+z neighbours when the segment between the centres is clear.
std::vector<std::size_t> open_regions(const scene::RayScene& rays, const Grid& g, const std::vector<char>& open,
                                      int threads) {
  std::vector<std::array<char, 3>> link(g.size(), {0, 0, 0});
  parallel_for(g.size(), threads, [&](std::size_t i) {
    if (open[i] == 0) return;
    const glm::ivec3 c = g.cell(i);
    for (int a = 0; a < 3; ++a) {
      glm::ivec3 d = c;
      if (++d[a] >= g.n[a] || open[g.index(d)] == 0) continue;
      glm::vec3 dir(0.0f);
      dir[a] = 1.0f;
      link[i][std::size_t(a)] = rays.occluded(g.centre(i), dir, 0.0f, g.step[a]) ? 0 : 1;
    }
  });
  std::vector<std::size_t> parent(g.size());
  std::iota(parent.begin(), parent.end(), std::size_t(0));
  for (std::size_t i = 0; i < g.size(); ++i)
    for (int a = 0; a < 3; ++a) {
      if (link[i][std::size_t(a)] == 0) continue;
      glm::ivec3 d = g.cell(i);
      ++d[a];
      unite(parent, i, g.index(d));
    }
  for (std::size_t i = 0; i < g.size(); ++i) parent[i] = find_root(parent, i);
  return parent;
}

// The player's regions: those holding an anchor (a camera) in open space; else every region of at least
// a quarter of the largest one's volume (sealed cavities and pockets inside solids are small).
std::vector<char> player_regions(const Grid& g, const std::vector<char>& open, const std::vector<std::size_t>& root,
                                 const std::vector<glm::vec3>& anchors) {
  std::vector<char> keep(g.size(), 0);
  for (const glm::vec3& a : anchors) {
    const glm::ivec3 c = glm::ivec3(glm::floor((a - g.min) / g.step));
    if (glm::any(glm::lessThan(c, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(c, g.n))) continue;
    const std::size_t i = g.index(c);
    if (open[i] != 0) keep[root[i]] = 1;
  }
  if (std::find(keep.begin(), keep.end(), 1) != keep.end()) return keep;
  std::vector<std::size_t> volume(g.size(), 0);
  for (std::size_t i = 0; i < g.size(); ++i) volume[root[i]] += open[i] != 0 ? 1 : 0;
  const std::size_t largest = *std::max_element(volume.begin(), volume.end());
  for (std::size_t i = 0; i < g.size(); ++i) keep[i] = largest > 0 && kKeepFraction * volume[i] >= largest ? 1 : 0;
  return keep;
}

OpenSpace open_space(const scene::Scene& scene, const scene::RayScene& rays, const ReceiverSettings& s,
                     float clearance) {
  const Grid g = make_grid(scene.bounds, s.cells);
  const std::vector<glm::vec3> dirs = lattice_directions(Lattice::fibonacci, kOpenRays);
  std::vector<char> open(g.size(), 0);
  parallel_for(g.size(), s.threads,
               [&](std::size_t i) { open[i] = placement::is_open(rays, g.centre(i), clearance, dirs) ? 1 : 0; });
  const std::vector<std::size_t> root = open_regions(rays, g, open, s.threads);
  const std::vector<char> keep = player_regions(g, open, root, s.anchors);
  OpenSpace space;
  space.step = g.step;
  for (std::size_t i = 0; i < g.size(); ++i) {
    if (open[i] != 0 && root[i] == i) {
      ++space.open_regions;
      space.regions += keep[i] != 0 ? 1 : 0;
    }
    if (open[i] != 0 && keep[root[i]] != 0) space.viewpoints.push_back(g.centre(i));
  }
  return space;
}

glm::vec3 uniform_sphere(detail::Pcg32& rng) {
  const float z = 1.0f - 2.0f * rng.uniform();
  const float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const float phi = 2.0f * detail::kPi * rng.uniform();
  return {r * std::cos(phi), r * std::sin(phi), z};
}

// One candidate: a seeded viewpoint and what it yields, or nothing.
using Candidate = std::function<std::optional<SamplePoint>(detail::Pcg32& rng, const glm::vec3& viewpoint)>;

// Rounds of `count` candidates (candidate j draws from its own stream, so any thread count gives the same
// set) until `count` are accepted; the first `count` in candidate order are kept.
std::vector<SamplePoint> collect(const OpenSpace& space, const ReceiverSettings& s, std::uint64_t key,
                                 const Candidate& make) {
  std::vector<SamplePoint> points;
  for (int round = 0; round < kMaxRounds && int(points.size()) < s.count && !space.viewpoints.empty(); ++round) {
    std::vector<std::optional<SamplePoint>> found(std::size_t(s.count));
    parallel_for(found.size(), s.threads, [&](std::size_t i) {
      detail::Pcg32 rng(s.seed, key + std::uint64_t(round) * std::uint64_t(s.count) + i);
      const auto v = std::min(std::size_t(rng.uniform() * float(space.viewpoints.size())), space.viewpoints.size() - 1);
      found[i] = make(rng, space.viewpoints[v]);
    });
    for (const auto& p : found)
      if (p && int(points.size()) < s.count) points.push_back(*p);
  }
  return points;
}

std::vector<SamplePoint> visible_points(const scene::Scene& scene, const scene::RayScene& rays, const OpenSpace& space,
                                        const ReceiverSettings& s, float clearance) {
  const float epsilon = scene::ray_epsilon(scene);
  // Open space in front of a receiver: nothing within a quarter of the clearance along its normal, which
  // drops sub-millimetre gaps (a light fixture just below a ceiling) that a grazing ray can still enter.
  const float gap = 0.25f * clearance;
  return collect(
      space, s, 0x7669736900000000ull,
      [&](detail::Pcg32& rng, const glm::vec3& viewpoint) -> std::optional<SamplePoint> {
        const auto hit = rays.intersect(viewpoint, uniform_sphere(rng));
        if (!hit || hit->inside()) return std::nullopt; // the sky, or the back of a single-sided surface
        // The side the viewpoint sees: either side of a double-sided surface is a receiver with its own normal.
        const SamplePoint p{detail::triangle_point(scene, hit->triangle, hit->u, hit->v), hit->facing_normal()};
        if (rays.occluded(p.position + epsilon * p.normal, p.normal, 0.0f, gap)) return std::nullopt;
        return p;
      });
}

std::vector<SamplePoint> volume_points(const scene::RayScene& rays, const OpenSpace& space, const ReceiverSettings& s,
                                       float clearance) {
  const std::vector<glm::vec3> dirs = lattice_directions(Lattice::fibonacci, kOpenRays);
  return collect(space, s, 0x766f6c7500000000ull,
                 [&](detail::Pcg32& rng, const glm::vec3& viewpoint) -> std::optional<SamplePoint> {
                   const glm::vec3 jitter(rng.uniform() - 0.5f, rng.uniform() - 0.5f, rng.uniform() - 0.5f);
                   const glm::vec3 p = viewpoint + jitter * space.step;
                   if (!placement::is_open(rays, p, clearance, dirs)) return std::nullopt;
                   return SamplePoint{p, uniform_sphere(rng)};
                 });
}

} // namespace

constexpr EnumName<ReceiverMode> kReceiverModeNames[] = {
    {ReceiverMode::visible, "visible"},
    {ReceiverMode::volume, "volume"},
    {ReceiverMode::area, "area"},
};

std::string_view receiver_mode_name(ReceiverMode mode) { return name_in(kReceiverModeNames, mode, "visible"); }

std::optional<ReceiverMode> parse_receiver_mode(std::string_view name) {
  return parse_name_in(kReceiverModeNames, name);
}

Receivers make_receivers(const scene::Scene& scene, const scene::RayScene& rays, const ReceiverSettings& s) {
  if (s.count < 1) throw Error(ErrorKind::usage, fmt::format("--points must be at least 1 (got {})", s.count));
  if (s.cells < 1 || s.cells > 1024)
    throw Error(ErrorKind::usage, fmt::format("receiver cells must be in 1..1024 (got {})", s.cells));
  Receivers r;
  if (s.mode == ReceiverMode::area) {
    r.points = surface_sample_points(scene, rays, s.count, s.seed);
    return r;
  }
  const float clearance = s.clearance > 0.0f ? s.clearance : placement::default_clearance(scene);
  const OpenSpace space = open_space(scene, rays, s, clearance);
  r.viewpoints = int(space.viewpoints.size());
  r.regions = space.regions;
  r.open_regions = space.open_regions;
  r.points = s.mode == ReceiverMode::visible ? visible_points(scene, rays, space, s, clearance)
                                             : volume_points(rays, space, s, clearance);
  return r;
}

} // namespace probebake::bake
