// Seam score (issue #39): how far an irradiance lookup jumps where it should be continuous. Along random
// lines through open space, at each sample x with local cell size s (the SVO leaf holding the lookup),
// h = 1 % of s: the jump E(x + h) - E(x), minus the jump its slope predicts (the median slope of ten steps
// of h/10 on either side, so that a seam inside those windows does not hide itself), over the local
// irradiance. A C0 lookup scores O(h) times its curvature; a step between voxels scores the step's size.
// E is the mean of the RGB channels. The score is the 99th percentile over all samples: a few percent of
// the samples straddle a cell border, so seams decide it.
#pragma once

#include <cstdint>
#include <functional>

#include <glm/vec3.hpp>

#include "probebake/formats/probe_volume.h"

namespace probebake::bake {

struct SeamSettings {
  int lines = 256;
  int samples_per_line = 64; // spaced a quarter of the local cell size apart
  std::uint64_t seed = 1;
};

struct SeamScore {
  double p99 = 0.0; // of |jump - predicted jump| / local irradiance
  double max = 0.0;
  int samples = 0;
};

// `lookup(p, n)`: irradiance at p for unit normal n; `cell_size(p, n)`: the size of the cell the lookup
// reads at p, or <= 0 where it reads nothing (outside open space). Lines start at random points of
// [lo, hi] where cell_size > 0, with a random direction and a random normal each; same settings, same score.
using SeamLookup = std::function<glm::vec3(glm::vec3, glm::vec3)>;
using SeamCellSize = std::function<float(glm::vec3, glm::vec3)>;
SeamScore seam_score(const SeamLookup& lookup, const SeamCellSize& cell_size, glm::vec3 lo, glm::vec3 hi,
                     const SeamSettings& settings = {});

// The SVO sampler (sample_irradiance) over the volume's root cube; the cell is the SVO leaf holding the
// normal-biased lookup point.
SeamScore svo_seam_score(const formats::ProbeVolume& volume, const SeamSettings& settings = {});

} // namespace probebake::bake
