// FLIP, a perceptual difference evaluator for rendered images (issue #39: eval's camera views), written
// from the papers:
//   LDR-FLIP: Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström, Fairchild, "FLIP: A Difference
//     Evaluator for Alternating Images", HPG 2020.
//   HDR-FLIP: Andersson, Nilsson, Shirley, Akenine-Möller, "Visualizing Errors in Rendered High Dynamic
//     Range Images", Eurographics 2021 (short paper).
// LDR-FLIP compares two pictures as an observer flipping between them would: a colour difference (YCxCz
// filtered by the contrast sensitivity functions, then HyAB in Hunt-adjusted L*a*b*) raised to a power
// that edges and points which differ push towards 1. HDR-FLIP tone maps both HDR images (ACES) at a range
// of exposures that the reference's luminance chooses and keeps each pixel's largest LDR-FLIP. Per-pixel
// errors lie in [0, 1]; 0 where the pictures agree. Constants and their sources: flip.cpp, flip_color.h.
#pragma once

#include <numbers>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "probebake/eval/reference.h"

namespace probebake::bake {

// The FLIP papers' observer: 0.7 m from a 0.7 m wide monitor 3840 pixels across, pixels per degree of
// visual angle = distance * (pixels / width) * pi / 180 (the FLIP papers' default observer; about 67.02).
constexpr double kFlipPixelsPerDegree = 0.7 * (3840.0 / 0.7) * std::numbers::pi / 180.0;

struct FlipSettings {
  double pixels_per_degree = kFlipPixelsPerDegree; // > 0 and finite
  int threads = 0;                                 // 0 = all cores; the result is the same for any count
};

// Not in the paper: a bound on the cost, reached only by references spanning more than 64 stops between
// their median and largest luminance (the exposures then lie further apart).
constexpr int kMaxFlipExposures = 64;

// The exposures (log2 of the scale applied before tone mapping) HDR-FLIP visits: `count` of them evenly
// from `start` to `stop`.
struct FlipExposures {
  double start = 0.0;
  double stop = 0.0;
  int count = 1;
};

// LDR-FLIP of two linear RGB images of the same size (channels clamped to [0, 1]; NaN reads as 0). An
// sRGB-encoded picture must be decoded to linear first. One error per pixel, row-major, in [0, 1].
// Throws Error(usage) when the sizes differ or the settings are out of range.
std::vector<float> ldr_flip(const Image& reference, const Image& test, const FlipSettings& settings = {});

// HDR-FLIP's exposure range (EG 2021) from the reference's linear RGB pixels: the shortest
// exposure maps the largest luminance, the longest the median luminance, to 0.85 after the tone mapper;
// one exposure per stop between them, at least two (one when they coincide), at most kMaxFlipExposures.
// When over half the pixels are black the median is that of the others (the paper's would be 0). Negative,
// NaN and infinite values are read as 0 / the largest float; an all-black reference gives the exposure 0.
FlipExposures flip_exposures(std::span<const glm::vec3> reference);

// The ACES fit HDR-FLIP tone maps with, at exposure `exposure` (pixel * 2^exposure), clamped to [0, 1].
glm::vec3 flip_tone_map(glm::vec3 linear, double exposure);

// HDR-FLIP of two linear HDR RGB images: per pixel, the largest LDR-FLIP over `exposures` of the tone-mapped
// pair. Throws Error(usage) for non-finite exposures or a count outside [1, kMaxFlipExposures]. Without
// `exposures`, flip_exposures of every reference pixel.
std::vector<float> hdr_flip(const Image& reference, const Image& test, const FlipExposures& exposures,
                            const FlipSettings& settings = {});
std::vector<float> hdr_flip(const Image& reference, const Image& test, const FlipSettings& settings = {});

} // namespace probebake::bake
