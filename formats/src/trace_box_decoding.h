// How the shaders decode a quantised box bound (gpu_types.h "Compact tracing"): lower + q * scale, which a
// compiler may fuse into one fma. Shared by the builder, which quantises against both roundings
// (trace_mesh.cpp), and the readers that decode boxes as the shaders do (trace_mesh_read.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace probebake::formats {

inline float decoded(float lower, float scale, std::uint32_t q) { return lower + float(q) * scale; }
inline float decoded_fused(float lower, float scale, std::uint32_t q) { return std::fma(float(q), scale, lower); }
inline float lowest_decoding(float lower, float scale, std::uint32_t q) {
  return std::min(decoded(lower, scale, q), decoded_fused(lower, scale, q));
}
inline float highest_decoding(float lower, float scale, std::uint32_t q) {
  return std::max(decoded(lower, scale, q), decoded_fused(lower, scale, q));
}

} // namespace probebake::formats
