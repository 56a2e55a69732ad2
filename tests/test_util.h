// Shared test helpers: reproducible random configurations, finite-difference checker, models.
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <random>

#include "ringlet/cross_section.h"
#include "ringlet/math.h"
#include "ringlet/strand_model.h"

namespace ringlet::testing {

/// A 3n-vector of curvatures uniform in [-amplitude, amplitude] (1/m), seeded.
inline VecX RandomCurvatures(int segments, double amplitude, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  VecX q(3 * segments);
  for (int i = 0; i < q.size(); ++i) q(i) = u(rng);
  return q;
}

/// A random proper rotation, seeded (QR of a Gaussian matrix, sign-fixed).
Mat3 RandomRotation(unsigned seed);

/// Central finite difference of f at x along coordinate i with step h.
inline double CentralDifference(const std::function<double(const VecX&)>& f, VecX x, int i,
                                double h) {
  const double x0 = x(i);
  x(i) = x0 + h;
  const double fp = f(x);
  x(i) = x0 - h;
  const double fm = f(x);
  return (fp - fm) / (2.0 * h);
}

/// A hair strand with the paper's material (E = 10 GPa, sigma = 0.3, rho = 1300 kg/m^3),
/// radius 50 um, root at the origin with the given frame, uniform segments.
StrandModel MakeStrand(double length, int segments, double eccentricity = 0.0,
                       const Vec3& natural = Vec3::Zero(), const Mat3& frame = Mat3::Identity());

/// A root frame whose tangent is horizontal (+x) with n1 pointing up (+z), so that kappa2
/// (bending about n2 = t x n1 = -y) bends the strand in the vertical x-z plane... see test_util.cpp.
Mat3 HorizontalFrame();

}  // namespace ringlet::testing
