// Random numbers and direction sampling for the tracer. Private to src/render.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "groom/random.h"
#include "ringlet/math.h"

namespace ringlet::render {

/// The random stream of one pixel sample: SplitMix64 (groom/random.h) seeded by hashing the
/// render seed, the pixel index and the sample index, so a sample's numbers depend on nothing
/// else (not the tile order, not the thread count): the image is bit-identical for any threads.
class SampleRng {
 public:
  SampleRng(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample)
      : rng_(groom::StreamSeed(groom::StreamSeed(seed, pixel), sample)) {}

  /// Uniform in [0, 1).
  double Uniform() { return rng_.Uniform(); }

 private:
  groom::SplitMix64 rng_;
};

/// Bits of x in reverse order (bit 0 <-> bit 31).
inline std::uint32_t ReverseBits(std::uint32_t x) {
  x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
  x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
  x = ((x >> 4) & 0x0F0F0F0Fu) | ((x & 0x0F0F0F0Fu) << 4);
  x = ((x >> 8) & 0x00FF00FFu) | ((x & 0x00FF00FFu) << 8);
  return (x >> 16) | (x << 16);
}

/// A Laine-Karras style permutation of 32-bit words in which output bit k depends only on input
/// bits 0..k (every step is x += c, x *= odd, or x ^= x * even): Vegdahl's improved hash
/// ("Building a better LK hash", psychopath.io, 2021) of Burley's Laine-Karras permutation.
inline std::uint32_t LaineKarrasPermutation(std::uint32_t x, std::uint32_t seed) {
  x ^= x * 0x3d20adeau;
  x += seed;
  x *= (seed >> 16) | 1u;
  x ^= x * 0x05526c56u;
  x ^= x * 0x53a22864u;
  return x;
}

/// Owen's nested uniform scrambling of the base-2 digits of x (x / 2^32 in [0, 1), most
/// significant digit first), hashed (Burley, "Practical hash-based Owen scrambling", JCGT 9(4),
/// 2020): each digit is flipped by a random function of the digits before it. Applied to a
/// sample index instead, it shuffles the sequence so that the first 2^m indices map onto an
/// aligned block of 2^m indices (Burley's section 4).
inline std::uint32_t NestedUniformScramble(std::uint32_t x, std::uint32_t seed) {
  return ReverseBits(LaineKarrasPermutation(ReverseBits(x), seed));
}

/// The first two dimensions of the Sobol sequence as 32-bit fractions: dimension 0 is van der
/// Corput's radical inverse, dimension 1 uses the direction numbers v_k = 2^31 >> k of Pascal's
/// triangle mod 2 (each v ^= v >> 1). Any aligned block of 2^m consecutive indices is a
/// (0, m, 2)-net: one point in each of the 2^m elementary intervals of every shape.
inline std::uint32_t Sobol0(std::uint32_t index) { return ReverseBits(index); }
inline std::uint32_t Sobol1(std::uint32_t index) {
  std::uint32_t x = 0;
  for (std::uint32_t v = 1u << 31; index != 0; index >>= 1, v ^= v >> 1) {
    if (index & 1u) x ^= v;
  }
  return x;
}

/// 32-bit word of a 64-bit hash of (a, b): SplitMix64's finalizer (groom/random.h's StreamSeed).
inline std::uint32_t Hash32(std::uint64_t a, std::uint64_t b) {
  return static_cast<std::uint32_t>(groom::StreamSeed(a, b) >> 32);
}

/// The numbers of one pixel sample, in pairs: every pair of dimensions (the pixel position, a
/// light sample, a BSDF sample, ...) is a shuffled, Owen-scrambled 2D Sobol sequence over the
/// pixel's samples (Burley 2020), with its own scramble and shuffle seeds per pixel and per
/// dimension ("padding"). So for every pair the samples 0..N-1 of a pixel are stratified (a
/// (0, m, 2)-net when N = 2^m: one sample in each of N strips along either axis and in each of
/// the N-cell grids in between), yet independent between pairs and between pixels, as
/// independent random numbers are. Sample s's numbers depend on (seed, pixel, s, dimension)
/// only: the image is the same whatever the threads, tiles or passes. Kind kIndependent draws
/// the same calls from SampleRng instead (the unstratified reference).
class PixelSampler {
 public:
  PixelSampler(std::uint64_t seed, std::uint64_t pixel, std::uint64_t sample, bool stratified)
      : rng_(seed, pixel, sample),
        pixel_seed_(groom::StreamSeed(seed ^ 0x5a17b0c3d2e1f4a5ull, pixel)),
        sample_(static_cast<std::uint32_t>(sample)),
        stratified_(stratified) {}

  /// Two numbers in [0, 1), the next pair of dimensions.
  std::array<double, 2> Get2D() {
    if (!stratified_) return {rng_.Uniform(), rng_.Uniform()};
    const std::uint64_t d = dimension_++;
    const std::uint32_t index = NestedUniformScramble(sample_, Hash32(pixel_seed_, 3 * d));
    const std::uint32_t x = NestedUniformScramble(Sobol0(index), Hash32(pixel_seed_, 3 * d + 1));
    const std::uint32_t y = NestedUniformScramble(Sobol1(index), Hash32(pixel_seed_, 3 * d + 2));
    return {ToUnit(x), ToUnit(y)};
  }
  /// One number in [0, 1): the first of a pair (a 1D stratified sequence).
  double Get1D() { return stratified_ ? Get2D()[0] : rng_.Uniform(); }

 private:
  // x / 2^32 plus half a step, so that 0 maps inside (0, 1) and no number is exactly 0.
  static double ToUnit(std::uint32_t x) { return (static_cast<double>(x) + 0.5) * 0x1p-32; }

  SampleRng rng_;
  std::uint64_t pixel_seed_;
  std::uint32_t sample_;
  std::uint64_t dimension_ = 0;
  bool stratified_;
};

/// An orthonormal basis (s, t, n) around the unit vector n (Duff et al., "Building an
/// orthonormal basis, revisited", JCGT 6(1), 2017): branch-free, continuous except at n.z = -1.
struct Frame {
  Vec3 s, t, n;
  explicit Frame(const Vec3& normal) : n(normal) {
    const double sign = std::copysign(1.0, n.z());
    const double a = -1.0 / (sign + n.z());
    const double b = n.x() * n.y() * a;
    s = Vec3(1.0 + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
    t = Vec3(b, sign + n.y() * n.y() * a, -n.y());
  }
  Vec3 ToWorld(double x, double y, double z) const { return x * s + y * t + z * n; }
};

/// Uniform direction on the unit sphere (Archimedes: z uniform in [-1, 1]); pdf 1/(4 pi).
inline Vec3 UniformSphere(double u1, double u2) {
  const double z = 1.0 - 2.0 * u1;
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  const double phi = 2.0 * std::numbers::pi * u2;
  return Vec3(r * std::cos(phi), r * std::sin(phi), z);
}
inline constexpr double kUniformSpherePdf = 0.25 * std::numbers::inv_pi;  // 1/sr

/// Cosine-weighted direction in the hemisphere around frame.n (Malley's method: a uniform
/// disk point lifted to the hemisphere); pdf cos(theta)/pi.
inline Vec3 CosineHemisphere(const Frame& frame, double u1, double u2) {
  const double r = std::sqrt(u1);
  const double phi = 2.0 * std::numbers::pi * u2;
  const double z = std::sqrt(std::max(0.0, 1.0 - u1));
  return frame.ToWorld(r * std::cos(phi), r * std::sin(phi), z);
}

/// Uniform direction in the cone of half-angle with cos_max = cos(half-angle) around frame.n:
/// cos(theta) uniform in [cos_max, 1]; pdf 1 / (2 pi (1 - cos_max)) (pbrt-v3, section 13.6.4).
inline Vec3 UniformCone(const Frame& frame, double cos_max, double u1, double u2) {
  const double cos_theta = 1.0 - u1 * (1.0 - cos_max);
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  const double phi = 2.0 * std::numbers::pi * u2;
  return frame.ToWorld(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
}

/// Veach's power heuristic (beta = 2) for one sample from each of two strategies (Veach &
/// Guibas, SIGGRAPH 1995): the weight of the strategy with density pdf_f.
inline double PowerHeuristic(double pdf_f, double pdf_g) {
  const double f = pdf_f * pdf_f;
  const double g = pdf_g * pdf_g;
  return f + g > 0.0 ? f / (f + g) : 0.0;
}

}  // namespace ringlet::render
