// Small deterministic random numbers for the reference path tracer: a PCG32 stream per (seed, key), so a
// point's paths do not depend on which thread runs them.
#pragma once

#include <cstdint>

namespace probebake::bake::detail {

// SplitMix64: turns (seed, key) into well-mixed stream seeds.
inline std::uint64_t mix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

class Pcg32 {
public:
  Pcg32(std::uint64_t seed, std::uint64_t key) {
    inc_ = (mix64(key ^ 0xda3e39cb94b95bdbull) << 1u) | 1u;
    state_ = 0;
    next();
    state_ += mix64(seed);
    next();
  }

  std::uint32_t next() {
    const std::uint64_t old = state_;
    state_ = old * 6364136223846793005ull + inc_;
    const auto xorshifted = static_cast<std::uint32_t>(((old >> 18u) ^ old) >> 27u);
    const auto rot = static_cast<std::uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
  }

  // Uniform in [0, 1): 24 random bits, so the result is exactly representable and never 1.
  float uniform() { return static_cast<float>(next() >> 8) * 0x1.0p-24f; }

private:
  std::uint64_t state_ = 0;
  std::uint64_t inc_ = 1;
};

} // namespace probebake::bake::detail
