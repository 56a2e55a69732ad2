// A small, portable pseudo-random generator for grooming (roots, per-strand variation).
//
// Why not <random>: the engines are portable but the distributions (uniform_real_distribution,
// normal_distribution, ...) are implementation-defined, so the same seed gives different roots
// with libstdc++ and libc++. Here the integer stream is fixed bit for bit on every platform; the
// doubles derived from it go through IEEE-754 arithmetic plus std::log/sqrt/cos, so they are
// identical on every platform whose libm rounds these the same way (glibc on x86-64 and arm64).
#pragma once

#include <cmath>
#include <cstdint>
#include <numbers>

namespace ringlet::groom {

/// SplitMix64 (Steele, Lea & Flood, "Fast splittable pseudorandom number generators", OOPSLA 2014;
/// constants of Vigna's public-domain reference splitmix64.c). Passes BigCrush; one 64-bit state,
/// so a generator per (seed, index) costs nothing.
class SplitMix64 {
 public:
  explicit SplitMix64(uint64_t seed) : state_(seed) {}

  /// The next 64 random bits.
  uint64_t Next() {
    state_ += 0x9E3779B97F4A7C15ull;
    return Mix(state_);
  }

  /// Uniform in [0, 1): the top 53 bits times 2^-53 (every value is a multiple of 2^-53).
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }

  /// Uniform in [lo, hi).
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }

  /// Standard normal by the Box-Muller transform (Box & Muller 1958), one value per call (the
  /// second of the pair is discarded so that the stream position does not depend on history).
  double Normal() {
    const double u1 = 1.0 - Uniform();  // (0, 1]: log is finite
    const double u2 = Uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }

  /// The SplitMix64 output function (a variant of MurmurHash3's fmix64 finalizer).
  static uint64_t Mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }

 private:
  uint64_t state_;
};

/// The seed of an independent stream number `index` derived from a user seed: hashing both makes
/// stream (seed, i) unrelated to stream (seed, i + 1) and to (seed + 1, i), so per-strand values
/// do not depend on the order in which strands are visited or on the thread count.
inline uint64_t StreamSeed(uint64_t seed, uint64_t index) {
  return SplitMix64::Mix(SplitMix64::Mix(seed ^ 0x6A09E667F3BCC909ull) +
                         0x9E3779B97F4A7C15ull * (index + 1));
}

}  // namespace ringlet::groom
