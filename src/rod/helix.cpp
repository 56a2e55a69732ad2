// Closed-form helical segments and their exact reverse-mode derivative (../shared/DESIGN.md,
// "A helical segment in closed form"; the paper's eq. 1 with constant Omega on a segment).
#include "ringlet/helix.h"
#include "ringlet/helix_jacobian.h"
#include "rod/helix_hessian.h"

#include <cmath>

namespace ringlet {
namespace {

// Below this turning angle the G_m use their Taylor series. At x = 2 the series (alternating,
// terms decreasing from the first) converges to rounding in kTaylorTerms terms, and the closed
// forms above it lose at most about one digit to cancellation (G6 at x = 2).
constexpr double kTaylorSwitch = 2.0;
constexpr int kTaylorTerms = 12;

// kCoefficients[m][k] = (-1)^k / (2k+m)!.
struct TaylorTable {
  double c[7][kTaylorTerms];
  TaylorTable() {
    for (int m = 1; m <= 6; ++m) {
      for (int k = 0; k < kTaylorTerms; ++k) {
        double factorial = 1.0;
        for (int j = 2; j <= 2 * k + m; ++j) factorial *= j;
        c[m][k] = (k % 2 == 0 ? 1.0 : -1.0) / factorial;
      }
    }
  }
};
const TaylorTable kTaylor;

// The Taylor series of G5 and G6 by Horner in y with kTerms terms: the loop of
// EvaluateHelixFunctions with a constant trip count (unrolled) and the two chains interleaved;
// the same operations in the same order, so the same bits.
template <int kTerms>
inline void TaylorG5G6(double y, double* g5, double* g6) {
  double s5 = kTaylor.c[5][kTerms - 1];
  double s6 = kTaylor.c[6][kTerms - 1];
  for (int k = kTerms - 2; k >= 0; --k) {
    s5 = s5 * y + kTaylor.c[5][k];
    s6 = s6 * y + kTaylor.c[6][k];
  }
  *g5 = s5;
  *g6 = s6;
}

}  // namespace

HelixFunctions EvaluateHelixFunctions(double x) {
  HelixFunctions h;
  h.g[0] = 0.0;
  const double y = x * x;
  if (std::abs(x) < kTaylorSwitch) {
    // Taylor series of G5 and G6 only (Horner in y = x^2, truncated where the next term is below
    // 1e-17 relative), then the upward recurrence G_m = 1/m! - x^2 G_(m+2), which only adds
    // (x^2 G_(m+2) < 1/m! here) and so keeps full precision while costing one FMA per function.
    if (y < 0.0625) {
      TaylorG5G6<6>(y, &h.g[5], &h.g[6]);
    } else if (y < 0.25) {
      TaylorG5G6<7>(y, &h.g[5], &h.g[6]);
    } else if (y < 1.0) {
      TaylorG5G6<9>(y, &h.g[5], &h.g[6]);
    } else {
      TaylorG5G6<kTaylorTerms>(y, &h.g[5], &h.g[6]);
    }
    h.g[4] = 1.0 / 24.0 - y * h.g[6];
    h.g[3] = 1.0 / 6.0 - y * h.g[5];
    h.g[2] = 0.5 - y * h.g[4];
    h.g[1] = 1.0 - y * h.g[3];
    return h;
  }
  // Closed forms, then the downward recurrence G_(m+2) = (1/m! - G_m) / x^2.
  h.g[1] = std::sin(x) / x;
  h.g[2] = (1.0 - std::cos(x)) / y;
  const double inv_factorial[5] = {1.0, 1.0, 0.5, 1.0 / 6.0, 1.0 / 24.0};
  for (int m = 1; m <= 4; ++m) h.g[m + 2] = (inv_factorial[m] - h.g[m]) / y;
  return h;
}

HelixSegment EvaluateHelixSegment(const Vec3& omega, double length) {
  const double l = length;
  const HelixFunctions h = EvaluateHelixFunctions(l * omega.norm());
  HelixSegment s;
  s.functions = h;
  const Mat3 w = Hat(omega);
  const Mat3 w2 = w * w;
  const Vec3 e3(0.0, 0.0, 1.0);
  // R = I + l G1 W + l^2 G2 W^2 (Rodrigues).
  s.rotation = Mat3::Identity() + (l * h.g[1]) * w + (l * l * h.g[2]) * w2;
  // p = (l I + l^2 G2 W + l^3 G3 W^2) e3, c = (l^2/2 I + l^3 G3 W + l^4 G4 W^2) e3.
  const Vec3 we3 = w.col(2);
  const Vec3 w2e3 = w2.col(2);
  const double l2 = l * l, l3 = l2 * l, l4 = l3 * l;
  s.chord = l * e3 + (l2 * h.g[2]) * we3 + (l3 * h.g[3]) * w2e3;
  s.moment = (0.5 * l2) * e3 + (l3 * h.g[3]) * we3 + (l4 * h.g[4]) * w2e3;
  return s;
}

Vec3 HelixSegmentVjp(const Vec3& omega, double length, const HelixFunctions& h,
                     const Mat3& d_rotation, const Vec3& d_chord, const Vec3& d_moment) {
  // Each of R, p, c is A e (e = I or e3) with A = a0 I + a1 W + a2 W^2, a1 = l^m G_m,
  // a2 = l^(m+1) G_(m+1) (m = 1, 2, 3 for R, p, c). With X = dE/dA:
  //   dE/dOmega = a1 Vee(X) + a2 Vee(X W^T + W^T X) + (da1 <X, W> + da2 <X, W^2>) Omega,
  // using d[e_j]x-terms <X, [e_j]x> = Vee(X)_j and d(l^m G_m)/dOmega = l^(m+2) (G_m'/x) Omega,
  // G_m'/x = m G_(m+2) - G_(m+1) (helix.h).
  // X is dE/dR for R and d e3^T for p and c (d = dE/dp, dE/dc): only their third columns are
  // non-zero, and the sums below skip the zeros, in the order of the full 3 x 3 sums; each starts
  // from +0 as those do, so that even the signs of exact zeros are the same (same bits).
  const double l = length;
  const Mat3 w = Hat(omega);
  const Mat3 w2 = w * w;
  double lp[8];  // powers of l
  lp[0] = 1.0;
  for (int k = 1; k < 8; ++k) lp[k] = lp[k - 1] * l;
  double a1[3], a2[3], da1[3], da2[3];
  for (int j = 0; j < 3; ++j) {
    const int m = j + 1;
    a1[j] = lp[m] * h.g[m];
    a2[j] = lp[m + 1] * h.g[m + 1];
    da1[j] = lp[m + 2] * (m * h.g[m + 2] - h.g[m + 1]);
    da2[j] = lp[m + 3] * ((m + 1) * h.g[m + 3] - h.g[m + 2]);
  }
  // Y1 = sum a1_j X_j, Y2 = sum a2_j X_j: columns 0 and 1 from dE/dR alone.
  Mat3 y1, y2;
  const Eigen::Array<double, 3, 2> zero2 = Eigen::Array<double, 3, 2>::Zero();
  const Eigen::Array3d zero3 = Eigen::Array3d::Zero();
  y1.leftCols<2>() = (zero2 + a1[0] * d_rotation.leftCols<2>().array()).matrix();
  y2.leftCols<2>() = (zero2 + a2[0] * d_rotation.leftCols<2>().array()).matrix();
  y1.col(2) = (((zero3 + a1[0] * d_rotation.col(2).array()) + a1[1] * d_chord.array()) +
               a1[2] * d_moment.array())
                  .matrix();
  y2.col(2) = (((zero3 + a2[0] * d_rotation.col(2).array()) + a2[1] * d_chord.array()) +
               a2[2] * d_moment.array())
                  .matrix();
  // <d e3^T, M> = d . M e3.
  const auto third = [](const Vec3& d, const Mat3& m) {
    return ((0.0 + d(0) * m(0, 2)) + d(1) * m(1, 2)) + d(2) * m(2, 2);
  };
  double s = 0.0;
  s += da1[0] * (d_rotation.cwiseProduct(w)).sum() + da2[0] * (d_rotation.cwiseProduct(w2)).sum();
  s += da1[1] * third(d_chord, w) + da2[1] * third(d_chord, w2);
  s += da1[2] * third(d_moment, w) + da2[2] * third(d_moment, w2);
  // W^T = -W.
  return Vee(y1) - Vee(y2 * w + w * y2) + s * omega;
}

Vec3 HelixChordFromFunctions(const Vec3& omega, double u, const HelixFunctions& h) {
  const Vec3 e3(0.0, 0.0, 1.0);
  const Vec3 we3 = omega.cross(e3);
  return u * e3 + (u * u * h.g[2]) * we3 + (u * u * u * h.g[3]) * omega.cross(we3);
}

Vec3 HelixChordVjp(const Vec3& omega, double u, const HelixFunctions& h, const Vec3& d) {
  // The m = 2 term of HelixSegmentVjp with X = d e3^T.
  const double u2 = u * u, u3 = u2 * u, u4 = u3 * u, u5 = u4 * u;
  const double a1 = u2 * h.g[2];
  const double a2 = u3 * h.g[3];
  const double da1 = u4 * (2.0 * h.g[4] - h.g[3]);
  const double da2 = u5 * (3.0 * h.g[5] - h.g[4]);
  const Vec3 e3(0.0, 0.0, 1.0);
  const Vec3 we3 = omega.cross(e3);
  const Vec3 w2e3 = omega.cross(we3);
  Mat3 x = Mat3::Zero();
  x.col(2) = d;
  const Mat3 w = Hat(omega);
  return a1 * e3.cross(d) - a2 * Vee(x * w + w * x) + (da1 * d.dot(we3) + da2 * d.dot(w2e3)) * omega;
}

Mat3 HelixChordJacobian(const Vec3& omega, double u, const HelixFunctions& h) {
  // The chord's derivative of the exact Hessian's machinery (helix_hessian.h, m = 2: the chord
  // u e3 + u^2 G2 W e3 + u^3 G3 W^2 e3), shared with strand_hessian.cpp and the dynamics.
  // Its coefficients from the G_m here (HelixFunctions has G_1..G_6: CoefficientsOf would read
  // G_7 for c2, which ChordDerivative does not use): a1 = u^2 G2, a2 = u^3 G3, b1 = u^4 (2 G4 - G3),
  // b2 = u^5 (3 G5 - G4).
  const double u2 = u * u, u3 = u2 * u, u4 = u3 * u, u5 = u4 * u;
  const helix_hessian::Coefficients c{u2 * h.g[2], u3 * h.g[3], u4 * (2.0 * h.g[4] - h.g[3]),
                                      u5 * (3.0 * h.g[5] - h.g[4]), 0.0, 0.0};
  return helix_hessian::ChordDerivative(omega, c);
}

Vec3 HelixTangentFromFunctions(const Vec3& omega, double u, const HelixFunctions& h) {
  const Vec3 e3(0.0, 0.0, 1.0);
  const Vec3 we3 = omega.cross(e3);
  return e3 + (u * h.g[1]) * we3 + (u * u * h.g[2]) * omega.cross(we3);
}

Vec3 HelixChord(const Vec3& omega, double u) { return EvaluateHelixSegment(omega, u).chord; }

Mat3 HelixRotation(const Vec3& omega, double u) {
  return EvaluateHelixSegment(omega, u).rotation;
}

}  // namespace ringlet
