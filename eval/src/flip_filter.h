// FLIP's spatial filters (HPG 2020, colour and feature pipelines) as separable 1D kernels, and the planes
// they filter. Every 2D kernel FLIP uses is a sum of products g(x) h(y), so each is applied as a row pass and a
// column pass; the borders repeat the edge pixel (as the reference implementations do).
#pragma once

#include <array>
#include <vector>

namespace probebake::bake::flip {

// One channel of a row-major image.
struct Plane {
  int width = 0;
  int height = 0;
  std::vector<float> v;
  Plane() = default;
  Plane(int w, int h) : width(w), height(h), v(std::size_t(w) * std::size_t(h), 0.0f) {}
  float& at(int x, int y) { return v[std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
  float at(int x, int y) const { return v[std::size_t(y) * std::size_t(width) + std::size_t(x)]; }
};

using Kernel = std::vector<float>; // odd length 2r + 1, centre in the middle

// weight * (g outer g): one Gaussian of a contrast sensitivity filter.
struct CsfTerm {
  float weight = 0.0f;
  Kernel g;
};

struct Kernels {
  std::array<std::vector<CsfTerm>, 3> csf; // achromatic, red-green, blue-yellow
  Kernel smooth;                           // Gaussian of the feature detectors, sum 1
  Kernel edge;                             // its first derivative, positive weights sum 1, negative -1
  Kernel point;                            // its second derivative, likewise
};

// Throws Error(usage) unless pixels_per_degree is positive and finite.
Kernels make_kernels(double pixels_per_degree);

// sum over the channel's terms of weight * (g outer g) applied to `in`.
Plane filter_csf(const Plane& in, const std::vector<CsfTerm>& terms, int threads);
// `in` filtered along x by `along_x`, then along y by `along_y`.
Plane filter_separable(const Plane& in, const Kernel& along_x, const Kernel& along_y, int threads);

// Edge and point strength of a luminance plane: the norms of the (x, y) responses of the edge and point
// detectors.
struct Features {
  Plane edges;
  Plane points;
};
Features detect_features(const Plane& luminance, const Kernels& kernels, int threads);

} // namespace probebake::bake::flip
