// Random numbers and direction sampling for the tracer. Private to src/render.
#pragma once

#include <algorithm>
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
