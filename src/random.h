// Internal: splitmix64, for per-point reproducible randomness (RANSAC, synth). std::mt19937 costs 5
// KB of state and a slow seeding per point; splitmix64 is seeded from (seed, point index) in two
// multiplications.
#pragma once

#include <cstdint>

namespace detexture {

/// The splitmix64 output function (Steele et al. 2014): a bijective mix of x.
inline std::uint64_t splitmix64_mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

class SplitMix64 {
 public:
  SplitMix64(std::uint64_t seed, std::uint64_t stream)
      : state_(seed * 0x9E3779B97F4A7C15ull ^ (stream + 0x632BE59BD9B4E019ull)) {
    next();
  }
  std::uint64_t next() { return splitmix64_mix(state_ += kGamma); }
  /// Advances by `draws` calls of next() without computing them: the state
  /// is a counter, so this is one multiplication.
  void skip(std::uint64_t draws) { state_ += draws * kGamma; }
  /// Uniform integer in [0, n), n > 0 (Lemire's multiply-shift; the bias is
  /// below 2^-32 for the neighborhood sizes used here).
  std::uint32_t below(std::uint32_t n) {
    return static_cast<std::uint32_t>(((next() >> 32) * static_cast<std::uint64_t>(n)) >> 32);
  }

 private:
  static constexpr std::uint64_t kGamma = 0x9E3779B97F4A7C15ull;
  std::uint64_t state_;
};

}  // namespace detexture
