// The closed forms of one helical segment (helix.h), written once for any scalar type: double
// for the energy and its gradient, forward-mode jets of Omega (Eigen's AutoDiffScalar) for the
// exact second derivatives (strand_hessian.cpp). T = double reproduces helix.cpp bit for bit: the
// same operations in the same order.
#pragma once

#include "ringlet/math.h"

namespace ringlet::internal {

template <typename T>
using Vec3T = Eigen::Matrix<T, 3, 1>;
template <typename T>
using Mat3T = Eigen::Matrix<T, 3, 3>;

/// [v]x for any scalar.
template <typename T>
Mat3T<T> HatT(const Vec3T<T>& v) {
  Mat3T<T> m;
  m << T(0.0), -v.z(), v.y(),  //
      v.z(), T(0.0), -v.x(),   //
      -v.y(), v.x(), T(0.0);
  return m;
}

/// Vee (math.h) for any scalar.
template <typename T>
Vec3T<T> VeeT(const Mat3T<T>& x) {
  return Vec3T<T>(x(2, 1) - x(1, 2), x(0, 2) - x(2, 0), x(1, 0) - x(0, 1));
}

/// R, p and c of HelixSegment from g[m] = G_m(l |Omega|), m = 1..4.
template <typename T>
void HelixSegmentFromFunctions(const Vec3T<T>& omega, double l, const T* g, Mat3T<T>* rotation,
                               Vec3T<T>* chord, Vec3T<T>* moment) {
  const Mat3T<T> w = HatT<T>(omega);
  const Mat3T<T> w2 = w * w;
  const Vec3T<T> e3(T(0.0), T(0.0), T(1.0));
  // R = I + l G1 W + l^2 G2 W^2 (Rodrigues).
  *rotation = Mat3T<T>::Identity() + (l * g[1]) * w + (l * l * g[2]) * w2;
  // p = (l I + l^2 G2 W + l^3 G3 W^2) e3, c = (l^2/2 I + l^3 G3 W + l^4 G4 W^2) e3.
  const Vec3T<T> we3 = w.col(2);
  const Vec3T<T> w2e3 = w2.col(2);
  const double l2 = l * l, l3 = l2 * l, l4 = l3 * l;
  *chord = l * e3 + (l2 * g[2]) * we3 + (l3 * g[3]) * w2e3;
  *moment = (0.5 * l2) * e3 + (l3 * g[3]) * we3 + (l4 * g[4]) * w2e3;
}

/// HelixSegmentVjp (helix.h) from g[m] = G_m(l |Omega|), m = 1..6, for any scalar; the
/// cotangents are plain doubles.
template <typename T>
Vec3T<T> HelixSegmentVjpT(const Vec3T<T>& omega, double length, const T* g, const Mat3& d_rotation,
                          const Vec3& d_chord, const Vec3& d_moment) {
  // Each of R, p, c is A e (e = I or e3) with A = a0 I + a1 W + a2 W^2, a1 = l^m G_m,
  // a2 = l^(m+1) G_(m+1) (m = 1, 2, 3 for R, p, c). With X = dE/dA:
  //   dE/dOmega = a1 Vee(X) + a2 Vee(X W^T + W^T X) + (da1 <X, W> + da2 <X, W^2>) Omega,
  // using d[e_j]x-terms <X, [e_j]x> = Vee(X)_j and d(l^m G_m)/dOmega = l^(m+2) (G_m'/x) Omega,
  // G_m'/x = m G_(m+2) - G_(m+1) (helix.h).
  const double l = length;
  const Mat3T<T> w = HatT<T>(omega);
  const Mat3T<T> w2 = w * w;
  Mat3 x_mats[3];
  x_mats[0] = d_rotation;
  x_mats[1].setZero();
  x_mats[1].col(2) = d_chord;
  x_mats[2].setZero();
  x_mats[2].col(2) = d_moment;

  double lp[8];  // powers of l
  lp[0] = 1.0;
  for (int k = 1; k < 8; ++k) lp[k] = lp[k - 1] * l;

  Mat3T<T> y1 = Mat3T<T>::Zero();
  Mat3T<T> y2 = Mat3T<T>::Zero();
  T s = T(0.0);
  for (int j = 0; j < 3; ++j) {
    const int m = j + 1;
    const T a1 = lp[m] * g[m];
    const T a2 = lp[m + 1] * g[m + 1];
    const T da1 = lp[m + 2] * (m * g[m + 2] - g[m + 1]);
    const T da2 = lp[m + 3] * ((m + 1) * g[m + 3] - g[m + 2]);
    const Mat3T<T> x = x_mats[j].template cast<T>();
    y1 += a1 * x;
    y2 += a2 * x;
    s += da1 * (x.cwiseProduct(w)).sum() + da2 * (x.cwiseProduct(w2)).sum();
  }
  // W^T = -W.
  return VeeT<T>(y1) - VeeT<T>(Mat3T<T>(y2 * w + w * y2)) + s * omega;
}

/// HelixChordFromFunctions (helix.h) for any scalar.
template <typename T>
Vec3T<T> HelixChordT(const Vec3T<T>& omega, double u, const T* g) {
  const Vec3T<T> e3(T(0.0), T(0.0), T(1.0));
  const Vec3T<T> we3 = omega.cross(e3);
  return u * e3 + (u * u * g[2]) * we3 + (u * u * u * g[3]) * omega.cross(we3);
}

/// HelixChordVjp (helix.h) for any scalar; the cotangent d is a plain double vector.
template <typename T>
Vec3T<T> HelixChordVjpT(const Vec3T<T>& omega, double u, const T* g, const Vec3& d_chord) {
  // The m = 2 term of HelixSegmentVjp with X = d e3^T.
  const double u2 = u * u, u3 = u2 * u, u4 = u3 * u, u5 = u4 * u;
  const T a1 = u2 * g[2];
  const T a2 = u3 * g[3];
  const T da1 = u4 * (2.0 * g[4] - g[3]);
  const T da2 = u5 * (3.0 * g[5] - g[4]);
  const Vec3T<T> e3(T(0.0), T(0.0), T(1.0));
  const Vec3T<T> we3 = omega.cross(e3);
  const Vec3T<T> w2e3 = omega.cross(we3);
  const Vec3T<T> d = d_chord.template cast<T>();
  Mat3T<T> x = Mat3T<T>::Zero();
  x.col(2) = d;
  const Mat3T<T> w = HatT<T>(omega);
  return a1 * e3.cross(d) - a2 * VeeT<T>(Mat3T<T>(x * w + w * x)) +
         (da1 * d.dot(we3) + da2 * d.dot(w2e3)) * omega;
}

}  // namespace ringlet::internal
