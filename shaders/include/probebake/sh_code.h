// Compact probe irradiance: a probe's 27 float L2 SH coefficients (108 bytes) in 16 bytes (L1) or 32 bytes
// (L2). One definition of the encoder and the decoder, shared by C++ (formats/sh_codec.h) and GLSL (the
// lookups, runtime/probe_codes/probe_encode.comp), like leaf_rule.h.
//
// Block 0 (128 bits, all an L1 code holds), bit ranges:
//   0-47    L0 of R, G, B as half floats, scaled by 2^-(e - SH_CODE_EXPONENT_BIAS) so that the brightest
//           channel lies in [0.5, 1): any float range fits, no half overflow;
//   48-55   e;
//   56-63   b1 in 1..255: band 1's step is b1 * SH_CODE_L1_STEP_UNIT (63 steps of the largest b1 span
//           SH_CODE_L1_RANGE), the smallest b1 whose 63 steps reach the probe's largest band-1 ratio;
//   64-126  band 1 (coefficients 3..11, sh[3k + c]) as the ratio to its channel's L0, 7 bits each:
//           q in 1..127 is (q - 64) steps;
// Block 1 (128 more bits for L2):
//   0-119   band 2 (coefficients 12..26) the same way, 8 bits each: q in 1..255 is (q - 128) steps;
//   120-127 b2: band 2's step is b2 * SH_CODE_L2_STEP_UNIT (127 steps of the largest span SH_CODE_L2_RANGE).
// A ratio of 0 is exact (a uniform probe stays uniform). The ranges are the largest ratios that irradiance
// from non-negative radiance can have (a single direction): band 1 |A1 L1m / A0 L00| <= (2/3) sqrt(3), band 2
// <= (1/4) sqrt(5). APV normalises its higher bands by L0 the same way over a fixed range; the per-probe
// scales (a nearly uniform probe keeps its small gradient) and the exponent are ours.
// The encoder decides each integer by comparing correctly rounded products (a division only guesses) and
// pre-rounds L0 to half precision, so that a GPU's code equals the CPU's bit for bit whatever its division's
// precision or packHalf2x16's rounding. (Probes dimmer than about 2^-110 W/m^2 may decode to 0 on a GPU that
// flushes denormals.)
#ifndef PROBEBAKE_SH_CODE_H
#define PROBEBAKE_SH_CODE_H

#include "probebake/gpu_types.h"

#ifdef __cplusplus
#include <cmath>

#include <glm/common.hpp>
#include <glm/packing.hpp>
#include <glm/ext/vector_uint4.hpp>
#endif

PB_GPU_BEGIN
#ifdef __cplusplus
using uvec4 = glm::uvec4;
using vec2 = glm::vec2;
// The GLSL built-ins the functions below use, for C++.
using glm::clamp;
using glm::floatBitsToUint;
using glm::packHalf2x16;
using glm::uintBitsToFloat;
using glm::unpackHalf2x16;
using std::abs;
using std::ceil;
using std::floor;
using std::ldexp;
using std::max;
using std::min;
#endif

PB_CONSTANT(int, SH_CODE_L1_BYTES, 16);
PB_CONSTANT(int, SH_CODE_L2_BYTES, 32);
PB_CONSTANT(int, SH_CODE_EXPONENT_BIAS, 127);              // frexp exponents -125..128 -> 2..255
PB_CONSTANT(float, SH_CODE_L1_RANGE, 1.15470054f);         // 2 / sqrt(3)
PB_CONSTANT(float, SH_CODE_L2_RANGE, 0.559016994f);        // sqrt(5) / 4
PB_CONSTANT(int, SH_CODE_L1_BITS, 7);                      // per band-1 ratio
PB_CONSTANT(int, SH_CODE_L2_BITS, 8);                      // per band-2 ratio
PB_CONSTANT(float, SH_CODE_L1_STEP_UNIT, 7.18767842e-05f); // float(float(L1_RANGE / 255) / 63)
PB_CONSTANT(float, SH_CODE_L2_STEP_UNIT, 1.72616019e-05f); // float(float(L2_RANGE / 255) / 127)
PB_CONSTANT(float, SH_CODE_HALF_BELOW_ONE, 0.99951172f);   // the largest half float below 1
PB_CONSTANT(float, SH_CODE_SMALLEST_L0, 1.17549435e-38f);  // a brightest L0 below it codes as black
PB_CONSTANT(float, SH_CODE_LARGEST_FLOAT, 3.40282347e38f);

struct ShCode {
  uvec4 band01; // offset  0: block 0
  uvec4 band2;  // offset 16: block 1 (zero in an L1 code)
};              // size 32

// `count` bits (1..31) of a block from bit `first`; a field may straddle two words.
PB_FUNCTION uint sh_code_bits(uvec4 block, int first, int count) {
  const int word = first >> 5, shift = first & 31;
  uint v = block[word] >> uint(shift);
  if (shift + count > 32) v |= block[word + 1] << uint(32 - shift);
  return v & ((1u << uint(count)) - 1u);
}

// The block with `value` (< 2^count, the field still zero) written at bit `first`.
PB_FUNCTION uvec4 sh_code_with_bits(uvec4 block, int first, int count, uint value) {
  const int word = first >> 5, shift = first & 31;
  block[word] |= value << uint(shift);
  if (shift + count > 32) block[word + 1] |= value >> uint(32 - shift);
  return block;
}

// Where coefficient j's ratio sits (3 <= j < 27), its width, and how many steps each side of 0 it has.
PB_FUNCTION int sh_code_ratio_bit(int j) {
  return j < 12 ? 64 + SH_CODE_L1_BITS * (j - 3) : SH_CODE_L2_BITS * (j - 12);
}
PB_FUNCTION int sh_code_ratio_bits(int j) { return j < 12 ? SH_CODE_L1_BITS : SH_CODE_L2_BITS; }
PB_FUNCTION int sh_code_steps(int j) { return (1 << (sh_code_ratio_bits(j) - 1)) - 1; } // 63 or 127

// One step of coefficient j's band, as a ratio, for scale byte b.
PB_FUNCTION float sh_code_step(uint b, int j) {
  return float(b) * (j < 12 ? SH_CODE_L1_STEP_UNIT : SH_CODE_L2_STEP_UNIT);
}

// L0 of R, G, B.
PB_FUNCTION vec3 sh_code_l0(uvec4 band01) {
  const vec2 rg = unpackHalf2x16(band01.x);
  const float b = unpackHalf2x16(band01.y & 0xFFFFu).x;
  const int e = int(sh_code_bits(band01, 48, 8)) - SH_CODE_EXPONENT_BIAS;
  return vec3(ldexp(rg.x, e), ldexp(rg.y, e), ldexp(b, e));
}

// Ratio to its channel's L0 of coefficient j = 3k + c, 3 <= j < 27 (band 2 reads 0 from an L1 code's zero
// block: its scale byte is 0).
PB_FUNCTION float sh_code_ratio(ShCode code, int j) {
  const bool band1 = j < 12;
  const uvec4 block = band1 ? code.band01 : code.band2;
  const uint b = sh_code_bits(block, band1 ? 56 : 120, 8);
  const int q = int(sh_code_bits(block, sh_code_ratio_bit(j), sh_code_ratio_bits(j)));
  return float(q - sh_code_steps(j) - 1) * sh_code_step(b, j);
}

// Coefficient j of the decoded probe, l0 = sh_code_l0(code.band01).
PB_FUNCTION float sh_code_coefficient(ShCode code, vec3 l0, int j) {
  const float channel_l0 = l0[j % 3];
  return j < 3 ? channel_l0 : sh_code_ratio(code, j) * channel_l0;
}

// The coefficient the encoder codes: NaN and infinities as 0.
PB_FUNCTION float sh_code_input(const float sh[27], int j) {
  return abs(sh[j]) <= SH_CODE_LARGEST_FLOAT ? sh[j] : 0.0f;
}

// Whether scale byte b's steps reach x >= 0 (coefficient j, its channel's L0 l0c): x rounds to at most
// sh_code_steps(j) steps. Products only (correctly rounded), monotonic in b.
PB_FUNCTION bool sh_code_reaches(float x, uint b, int j, float l0c) {
  return x <= (float(sh_code_steps(j)) + 0.5f) * (sh_code_step(b, j) * l0c);
}

// The scale byte (1..255): the smallest whose steps reach every ratio of the band of coefficients
// [first, last), or 255. A division guesses it, the comparisons decide.
PB_FUNCTION uint sh_code_scale_byte(const float sh[27], vec3 l0, int first, int last) {
  uint b = 1u;
  for (int j = first; j < last; ++j) {
    const float x = abs(sh_code_input(sh, j)), l0c = l0[j % 3];
    const float unit = (float(sh_code_steps(j)) + 0.5f) * (sh_code_step(1u, j) * l0c);
    if (!(unit > 0.0f) || sh_code_reaches(x, b, j, l0c)) continue;
    uint g = uint(clamp(ceil(x / unit), float(b), 255.0f));
    for (int i = 0; i < 4; ++i) {
      if (g > b && sh_code_reaches(x, g - 1u, j, l0c))
        g -= 1u;
      else if (g < 255u && !sh_code_reaches(x, g, j, l0c))
        g += 1u;
    }
    b = g;
  }
  return b;
}

// q for coefficient x with step `unit` (in units of the coefficient): k = the nearest number of steps (the
// smallest k >= 0 with |x| <= (k + 0.5) * unit), clamped to the band's steps, offset to be positive.
PB_FUNCTION uint sh_code_quantise(float x, float unit, int j) {
  const int steps = sh_code_steps(j);
  const float a = abs(x);
  float k = 0.0f;
  if (unit > 0.0f && a > 0.5f * unit) {
    k = clamp(ceil(a / unit - 0.5f), 1.0f, float(steps)); // a guess
    for (int i = 0; i < 4; ++i) {
      if (k > 1.0f && a <= (k - 0.5f) * unit)
        k -= 1.0f;
      else if (k < float(steps) && a > (k + 0.5f) * unit)
        k += 1.0f;
    }
  }
  return uint(int(x < 0.0f ? -k : k) + steps + 1);
}

// The ratios of coefficients [first, last) and their scale byte (at bit scale_bit) written into a block.
PB_FUNCTION uvec4 sh_code_encode_band(uvec4 block, const float sh[27], vec3 l0, int first, int last, int scale_bit) {
  const uint b = sh_code_scale_byte(sh, l0, first, last);
  block = sh_code_with_bits(block, scale_bit, 8, b);
  for (int j = first; j < last; ++j) {
    const uint q = sh_code_quantise(sh_code_input(sh, j), sh_code_step(b, j) * l0[j % 3], j);
    block = sh_code_with_bits(block, sh_code_ratio_bit(j), sh_code_ratio_bits(j), q);
  }
  return block;
}

// v in [0, 1) rounded to the nearest half float (ties away from zero), exactly representable, so that
// packHalf2x16 need not round.
PB_FUNCTION float sh_code_half(float v) {
  if (v < 6.10351562e-05f) return floor(v * 16777216.0f + 0.5f) * 5.96046448e-08f; // subnormal halves: 2^-24 steps
  return uintBitsToFloat((floatBitsToUint(v) + 0x1000u) & 0xFFFFE000u);            // 10 mantissa bits of 23
}

// The 27 coefficients sh[3k + c] in a code; `l2` false leaves block 1 zero (an L1 code).
PB_FUNCTION ShCode sh_code_encode(const float sh[27], bool l2) {
  // Member by member: C++ compilers before P0960 (clang 14) cannot construct an aggregate with parentheses.
  ShCode code;
  code.band01 = uvec4(0u);
  code.band2 = uvec4(0u);
  // A channel's L0 that is negative, NaN or infinite codes as black (comparisons with NaN are false).
  vec3 usable = vec3(0.0f);
  for (int c = 0; c < 3; ++c) usable[c] = sh[c] > 0.0f && sh[c] <= SH_CODE_LARGEST_FLOAT ? sh[c] : 0.0f;
  const float brightest = max(max(usable.x, usable.y), usable.z);
  if (!(brightest >= SH_CODE_SMALLEST_L0)) return code;
  // frexp's exponent of the brightest channel: brightest = f * 2^e, f in [0.5, 1).
  const int e = int((floatBitsToUint(brightest) >> 23u) & 0xFFu) - 126;
  vec3 l0 = vec3(0.0f);
  for (int c = 0; c < 3; ++c) l0[c] = min(sh_code_half(ldexp(usable[c], -e)), SH_CODE_HALF_BELOW_ONE);
  code.band01.x = packHalf2x16(vec2(l0.x, l0.y));
  code.band01.y = packHalf2x16(vec2(l0.z, 0.0f)) | (uint(e + SH_CODE_EXPONENT_BIAS) << 16u);
  // Ratios to the L0 the decoder sees, so that the code's rounding of L0 does not scale the bands.
  const vec3 decoded = sh_code_l0(code.band01);
  code.band01 = sh_code_encode_band(code.band01, sh, decoded, 3, 12, 56);
  if (l2) code.band2 = sh_code_encode_band(code.band2, sh, decoded, 12, 27, 120);
  return code;
}

PB_GPU_END

#ifdef __cplusplus
static_assert(sizeof(probebake::gpu::ShCode) == probebake::gpu::SH_CODE_L2_BYTES);
#endif

#endif // PROBEBAKE_SH_CODE_H
