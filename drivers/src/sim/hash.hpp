// Counter-based hashing and random numbers for the simulator (deterministic
// per seed, independent of threading).
#pragma once

#include <cmath>
#include <cstdint>

namespace gvs::drivers::sim::detail {

/// SplitMix64 finaliser: a bijective 64-bit mix.
inline std::uint64_t mix64(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

/// Hash of (seed, salt, 64-bit cell indices): the texture never repeats.
inline std::uint64_t hash_cell(std::uint64_t seed, std::uint64_t salt, std::int64_t ix,
                               std::int64_t iy) {
  std::uint64_t h = mix64(seed + 0x9E3779B97F4A7C15ULL * (salt + 1));
  h = mix64(h ^ static_cast<std::uint64_t>(ix));
  h = mix64(h ^ (static_cast<std::uint64_t>(iy) * 0xD6E8FEB86659FD93ULL));
  return h;
}

/// Small counter-based generator: a stream of uniform and normal numbers.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(mix64(seed)) {}
  std::uint64_t next() {
    state_ += 0x9E3779B97F4A7C15ULL;
    return mix64(state_);
  }
  /// Uniform in [0, 1).
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  /// Uniform in [0, 1) as float.
  float uniformf() { return static_cast<float>(next() >> 40) * 0x1.0p-24f; }
  /// Standard normal (Box-Muller, both values used).
  float normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    const float u1 = (static_cast<float>(next() >> 40) + 0.5f) * 0x1.0p-24f;
    const float u2 = static_cast<float>(next() >> 40) * 0x1.0p-24f;
    const float r = std::sqrt(-2.0f * std::log(u1));
    const float a = 6.28318530718f * u2;
    spare_ = r * std::sin(a);
    has_spare_ = true;
    return r * std::cos(a);
  }

 private:
  std::uint64_t state_;
  float spare_ = 0.0f;
  bool has_spare_ = false;
};

}  // namespace gvs::drivers::sim::detail
