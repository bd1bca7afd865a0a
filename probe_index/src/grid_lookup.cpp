// The grid engine's lookup (algorithm in grid_lookup.h).
#include "probebake/probe_index/grid_lookup.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "probebake/probe_index/stencil.h"

namespace probebake::probe_index {
namespace {

constexpr float kWeightFloor = 0.001f;
constexpr float kFloorFade = 0.01f;

bool finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// Step 3's reach weight: per axis, 1 until the point comes within kReachRamp / 2 of the first surface the probe
// sees along it, 0 from kReachRamp / 2 past it (offsets and reach in spacings).
constexpr float kReachRamp = 0.125f;
float reach_weight(const formats::Reach& reach, glm::vec3 offset) {
  float w = 1.0f;
  for (int axis = 0; axis < 3; ++axis) {
    const float r = reach[std::size_t(2 * axis + (offset[axis] < 0.0f ? 1 : 0))];
    const float ramp = (r - std::abs(offset[axis])) / kReachRamp + 0.5f;
    w *= ramp > 0.0f ? std::min(ramp, 1.0f) : 0.0f; // NaN: 0
  }
  return w;
}

// Step 3's serve weight of the probe at lattice point q for the point at lattice coordinates g: its cell bits
// blended trilinearly over the centres of the eight cells around q (at q +- 0.5), so that it changes smoothly
// where the point crosses from one of q's cells into the next. On the lattice's border the missing side takes
// the present side's bits.
float serve_weight(std::uint32_t cells, glm::vec3 g, glm::ivec3 q, int n) {
  glm::vec3 o = g - glm::vec3(q);
  for (int axis = 0; axis < 3; ++axis) {
    if (q[axis] == 0) o[axis] = std::max(o[axis], 0.5f);
    if (q[axis] == n - 1) o[axis] = std::min(o[axis], -0.5f);
  }
  const glm::vec3 plus = glm::clamp(o + 0.5f, glm::vec3(0.0f), glm::vec3(1.0f));
  float serve = 0.0f;
  for (int octant = 0; octant < 8; ++octant) {
    if (((cells >> octant) & 1u) == 0) continue;
    const glm::vec3 side(octant & 1, (octant >> 1) & 1, (octant >> 2) & 1);
    const glm::vec3 w = glm::mix(glm::vec3(1.0f) - plus, plus, side);
    serve += w.x * w.y * w.z;
  }
  return serve;
}

struct Corner {
  int probe = -1;
  float trilinear = 0.0f; // times the reach weight
  float serve = 0.0f;
  float side = 0.0f;
  float weight() const { return trilinear * serve * side; }
  float floored() const { return serve * (trilinear + kWeightFloor) * (side + kWeightFloor); }
};

// Step 3's corners that serve the cell, with their trilinear and side weights.
int serving_corners(const formats::ProbeVolume& volume, const formats::GridLatticeView& lattice, glm::vec3 position,
                    glm::vec3 normal, std::array<Corner, 8>& corners) {
  const gpu::GridLatticeHeader& h = lattice.header;
  const int n = h.resolution;
  const bool volumetric = glm::dot(normal, normal) == 0.0f;
  const float bias = volumetric ? 0.0f : grid_normal_bias(h);
  const glm::vec3 g = formats::grid_lattice_coordinates(h, position + normal * bias);
  const glm::ivec3 c = formats::grid_cell_of(g, n);
  const glm::vec3 f = glm::clamp(g - glm::vec3(c), glm::vec3(0.0f), glm::vec3(1.0f));
  int count = 0;
  for (int k = 0; k < 8; ++k) {
    const glm::ivec3 b(k & 1, (k >> 1) & 1, (k >> 2) & 1);
    const glm::ivec3 q = c + b;
    const gpu::GridPoint& point = lattice.points[std::size_t(q.x + n * (q.y + n * q.z))];
    const int probe = formats::grid_point_probe(point);
    if (probe < 0 || std::size_t(probe) >= volume.probes.size() || volume.probes[std::size_t(probe)].link == 0)
      continue;
    const float serve = serve_weight(formats::grid_point_cells(point), g, q, n);
    if (!(serve > 0.0f)) continue;
    const glm::vec3 at = volume.probes[std::size_t(probe)].position;
    const glm::vec3 t = glm::mix(glm::vec3(1.0f) - f, f, glm::vec3(b));
    const float side = volumetric ? 1.0f : glm::dot(at - position, normal) / bias;
    const float reach = reach_weight(formats::grid_point_reach(point), (position + normal * bias - at) / h.spacing);
    corners[std::size_t(count++)] = {probe, t.x * t.y * t.z * reach, serve,
                                     side > 0.0f ? std::min(side, 1.0f) : 0.0f}; // NaN: 0
  }
  return count;
}

} // namespace

float grid_normal_bias(const gpu::GridLatticeHeader& header) {
  return 0.25f * std::min({header.spacing.x, header.spacing.y, header.spacing.z});
}

GridCorners grid_corners(const formats::ProbeVolume& volume, glm::vec3 position, glm::vec3 normal) {
  GridCorners out;
  const std::optional<formats::GridLatticeView> lattice = formats::grid_lattice_view(volume);
  if (!lattice || !finite(position) || !finite(normal)) return out;
  std::array<Corner, 8> corners;
  const int count = serving_corners(volume, *lattice, position, normal, corners);
  float primary = 0.0f;
  for (int i = 0; i < count; ++i) primary += corners[std::size_t(i)].weight();
  // The floor fades in as the weights vanish (below kFloorFade), so the lookup stays continuous.
  const float fade = std::max(0.0f, 1.0f - primary / kFloorFade);
  float sum = 0.0f;
  for (int i = 0; i < count; ++i) sum += corners[std::size_t(i)].weight() + fade * corners[std::size_t(i)].floored();
  if (!(sum > 0.0f)) return out;
  for (int i = 0; i < count; ++i) {
    const Corner& k = corners[std::size_t(i)];
    const float w = k.weight() + fade * k.floored();
    if (!(w > 0.0f)) continue;
    out.probes[std::size_t(out.count)] = k.probe;
    out.weights[std::size_t(out.count++)] = w / sum;
  }
  return out;
}

glm::vec3 sample_irradiance_grid(const formats::ProbeVolume& volume, glm::vec3 position, glm::vec3 normal,
                                 SamplerStats* stats) {
  const GridCorners corners = grid_corners(volume, position, normal);
  if (stats) {
    ++stats->samples;
    stats->misses += corners.count == 0 ? 1 : 0;
  }
  const std::array<float, 9> basis = sh_basis(normal); // once for the eight probes
  glm::vec3 e(0.0f);
  for (int i = 0; i < corners.count; ++i) {
    const gpu::Probe& probe = volume.probes[std::size_t(corners.probes[std::size_t(i)])];
    e += corners.weights[std::size_t(i)] *
         glm::max(detail::evaluate_sh<float>(probe.irradiance_sh, basis), glm::vec3(0.0f));
  }
  return e;
}

} // namespace probebake::probe_index
