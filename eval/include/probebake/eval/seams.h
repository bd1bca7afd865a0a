// Seam score (issue #39): how far an irradiance lookup jumps where it should be continuous. Along random
// lines through open space, wherever the line passes from one cell of the lookup into another (an SVO leaf
// into the next), the border is found by bisection and the step of h = 1 % of the local cell size across
// it is scored: the jump E(b + h/2) - E(b - h/2), minus the jump its slope predicts (the median slope of
// ten steps of h/10 on either side, so that a seam inside those windows does not hide itself), over the
// local irradiance. A C0 lookup scores O(h) times its curvature; a step between cells scores the step's
// size. E is the mean of the RGB channels. Scored at borders only: samples at random places along the
// line straddle a border about 1 % of the time, and their 99th percentile would hide what a player sees.
#pragma once

#include <cstdint>
#include <functional>

#include <glm/vec3.hpp>

#include "probebake/formats/probe_volume.h"
#include "probebake/scene/ray_scene.h"

namespace probebake::bake {

struct SeamSettings {
  int lines = 256;
  int steps_per_line = 64; // a quarter of the local cell size each
  std::uint64_t seed = 1;
};

struct SeamScore {
  double p99 = 0.0; // of |jump - predicted jump| / local irradiance, over the borders crossed
  double max = 0.0;
  int borders = 0;
};

// What the lookup reads at a point: the cell's size (<= 0: nothing, outside open space) and an id that
// differs between cells whose lookups may disagree.
struct SeamCell {
  float size = 0.0f;
  std::int64_t id = -1;
};

// `lookup(p, n)`: irradiance at p for unit normal n; `cell(p, n)`: the cell it reads there; `open(a, b, n)`:
// whether the lookups from a to b with normal n read open space without crossing a surface (a line ends
// there: light may jump across a wall, and that is no seam). Lines start at random points of [lo, hi] inside a cell, with a random
// direction and a random normal each; same settings, same score.
using SeamLookup = std::function<glm::vec3(glm::vec3, glm::vec3)>;
using SeamCellAt = std::function<SeamCell(glm::vec3, glm::vec3)>;
using SeamOpen = std::function<bool(glm::vec3, glm::vec3, glm::vec3)>;
SeamScore seam_score(const SeamLookup& lookup, const SeamCellAt& cell, const SeamOpen& open, glm::vec3 lo, glm::vec3 hi,
                     const SeamSettings& settings = {});

// The SVO sampler (probe_index::sample_irradiance) over the volume's root cube; the cell is the SVO leaf holding the
// normal-biased lookup point (merged leaves are one cell: their voxels share a stencil). A step is open
// when the biased points' segment and each point's bias cross no surface: a shading point's bias never
// passes through a wall, so lookups that would are not a game's.
SeamScore svo_seam_score(const formats::ProbeVolume& volume, const scene::RayScene& rays,
                         const SeamSettings& settings = {});
// The same for another lookup over the volume, e.g. one leaf's stencil alone (probe_index::svo_stencil), which the
// blend replaced: its borders are steps.
SeamScore svo_seam_score(const formats::ProbeVolume& volume, const scene::RayScene& rays, const SeamLookup& lookup,
                         const SeamSettings& settings = {});
// The grid engine's lookup (probe_index::sample_irradiance_grid) of a grid bake with a lattice; the cell is
// the lattice cell around the biased point, its size the smallest spacing, where the SVO lookup's point has a
// leaf (the same open space as svo_seam_score's lines). Without a lattice: no borders.
SeamScore grid_seam_score(const formats::ProbeVolume& volume, const scene::RayScene& rays,
                          const SeamSettings& settings = {});

} // namespace probebake::bake
