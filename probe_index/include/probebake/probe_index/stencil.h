// Step 4 of the sampler (lookup.h) over any probe SH storage: sample_irradiance applies it to the
// volume's probes in float (as the GPU does), the bake's iteration to its double-precision state.
#pragma once

#include <array>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

#include "probebake/probe_index/lookup.h"

namespace probebake::probe_index::detail {

// Irradiance of 27 interleaved coefficients for precomputed basis values `y`, per channel, unclamped,
// computed in T (float: the sampler and the GPU; double: the bake's iteration state).
template <class T>
glm::vec<3, T> evaluate_sh(const T* sh, const std::array<float, 9>& y) {
  glm::vec<3, T> e(0);
  for (int k = 0; k < 9; ++k) e += T(y[std::size_t(k)]) * glm::vec<3, T>(sh[3 * k], sh[3 * k + 1], sh[3 * k + 2]);
  return e;
}

// sum_k weight_k * max(0, E_k(n)); sh_of(probe) returns the probe's 27 coefficients (const T*).
template <class T, class ShOf>
glm::vec<3, T> apply_stencil(const ProbeStencil& s, glm::vec3 normal, const ShOf& sh_of) {
  glm::vec<3, T> e(0);
  if (s.empty()) return e;
  const std::array<float, 9> y = sh_basis(normal);
  for (int k = 0; k < 4; ++k) {
    if (s.probes[k] < 0) continue;
    e += T(s.weights[k]) * glm::max(evaluate_sh<T>(sh_of(s.probes[k]), y), glm::vec<3, T>(0));
  }
  return e;
}

} // namespace probebake::probe_index::detail
