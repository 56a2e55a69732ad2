// The fold of a body's components into one signed distance (Body, SplitBody; docs/body.md,
// "Union" and "Smooth union"): shared by body.cpp and split_body.cpp so that both fold the same
// way, bit for bit.
#pragma once

#include <cmath>
#include <vector>

#include "ringlet/math.h"

namespace ringlet::internal {

// The nearest sphere surface: the index of the sphere with the smallest |x - c| - r below *best
// (which it then holds), or -1. The same answer, bit for bit, as taking the square root of every
// sphere: a sphere is skipped without its root only when |x - c|^2 exceeds (best + r + margin)^2,
// margin = 1e-12 (|best| + r) (far above the rounding of best + r and of the square), so that its
// rounded distance could not have been below best either; an empty bound (below 0) skips too, as
// |x - c| >= 0. Most spheres of a body are far from most samples: ~1 root per query, not 9.
inline int NearestSphere(const std::vector<Eigen::Vector4d>& spheres, const Vec3& x,
                         double* best) {
  int nearest = -1;
  const int count = static_cast<int>(spheres.size());
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector4d& s = spheres[static_cast<size_t>(i)];
    const double dx = x.x() - s(0), dy = x.y() - s(1), dz = x.z() - s(2);
    const double d2 = dx * dx + dy * dy + dz * dz;
    const double bound = *best + s(3) + 1e-12 * (std::abs(*best) + s(3));
    if (bound < 0.0 || d2 > bound * bound) continue;  // false for best = inf and for NaN
    const double d = std::sqrt(d2) - s(3);
    if (d < *best) {
      *best = d;
      nearest = i;
    }
  }
  return nearest;
}

// Folds a component's signed distance d (gradient g) into the running smooth minimum (best,
// best_gradient) with the quadratic smooth minimum of width k (Body::Create).
inline void SmoothFold(double d, const Vec3& g, double k, double* best, Vec3* best_gradient) {
  if (d - *best >= k) return;
  if (*best - d >= k) {
    *best = d;
    *best_gradient = g;
    return;
  }
  const double h = 0.5 + 0.5 * (d - *best) / k;  // weight of the running minimum
  *best = d + h * (*best - d) - k * h * (1.0 - h);
  *best_gradient = h * *best_gradient + (1.0 - h) * g;
}

// SmoothFold with Hessians: the Hessian of the quadratic smooth minimum (Body::Create) of the
// running minimum a and the component b, h H_a + (1 - h) H_b - (g_a - g_b)(g_a - g_b)^T / (2k).
inline void SmoothFoldHessian(double d, const Vec3& g, const Mat3& hd, double k, double* best,
                              Vec3* best_gradient, Mat3* best_hessian) {
  if (d - *best >= k) return;
  if (*best - d >= k) {
    *best = d;
    *best_gradient = g;
    *best_hessian = hd;
    return;
  }
  const double h = 0.5 + 0.5 * (d - *best) / k;
  const Vec3 jump = *best_gradient - g;
  *best = d + h * (*best - d) - k * h * (1.0 - h);
  *best_hessian = h * *best_hessian + (1.0 - h) * hd - (jump * jump.transpose()) / (2.0 * k);
  *best_gradient = h * *best_gradient + (1.0 - h) * g;
}

// Hessian of |x - c| - r: (I - n n^T) / |x - c| (0 at the centre, where it is undefined).
inline Mat3 SphereHessian(const Vec3& r, double norm) {
  if (!(norm > 0.0)) return Mat3::Zero();
  const Vec3 n = r / norm;
  return (Mat3::Identity() - n * n.transpose()) / norm;
}

}  // namespace ringlet::internal
