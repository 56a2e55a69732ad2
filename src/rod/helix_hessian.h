// Second derivatives of the helical segment's closed forms (helix.h) in its curvatures Omega:
// the functions G_m up to G_8, the coefficients of A_m = l^(m-1)/(m-1)! I + a1 W + a2 W^2 and
// their gradients, the chord's Jacobian and a segment's own Hessian as a sum of <X, A_m> terms.
// Internal: shared by the exact Hessian of the statics (strand_hessian.cpp, which derives them)
// and the dynamics (src/dynamics/kinematics.cpp).
#pragma once

#include <cmath>

#include "ringlet/math.h"

namespace ringlet::helix_hessian {

inline constexpr double kInverseFactorial[9] = {1.0,          1.0,         0.5,
                                                1.0 / 6.0,    1.0 / 24.0,  1.0 / 120.0,
                                                1.0 / 720.0,  1.0 / 5040.0, 1.0 / 40320.0};

// G_m(x), m = 1..8 (helix.h). Below |x| = 2 the Taylor series of G7 and G8 (16 terms: the next
// one is below 1e-20 relative at x = 2) and the downward recurrence G_m = 1/m! - x^2 G_(m+2),
// which only adds; above, the closed forms of G1, G2 and G_(m+2) = (1/m! - G_m) / x^2.
inline constexpr int kTaylorTerms8 = 16;
// kTaylor8[m - 7][k] = (-1)^k / (2k + m)!, m = 7, 8.
struct Taylor8Table {
  double c[2][kTaylorTerms8];
  Taylor8Table() {
    for (int m = 7; m <= 8; ++m) {
      for (int k = 0; k < kTaylorTerms8; ++k) {
        double factorial = 1.0;
        for (int j = 2; j <= 2 * k + m; ++j) factorial *= j;
        c[m - 7][k] = (k % 2 == 0 ? 1.0 : -1.0) / factorial;
      }
    }
  }
};
inline const Taylor8Table kTaylor8;

// The two Horner chains of G7 and G8 with kTerms terms, unrolled and interleaved (the same
// operations in the same order as one loop per function: the same bits).
template <int kTerms>
inline void TaylorG7G8(double y, double g[9]) {
  double s7 = kTaylor8.c[0][kTerms - 1];
  double s8 = kTaylor8.c[1][kTerms - 1];
  for (int k = kTerms - 2; k >= 0; --k) {
    s7 = s7 * y + kTaylor8.c[0][k];
    s8 = s8 * y + kTaylor8.c[1][k];
  }
  g[7] = s7;
  g[8] = s8;
}

inline void HelixFunctions8(double x, double g[9]) {
  const double y = x * x;
  g[0] = 0.0;
  if (std::abs(x) < 2.0) {
    // Fewer terms for small x, as in helix.cpp (the next term below 1e-17 relative).
    if (y < 0.0625) {
      TaylorG7G8<6>(y, g);
    } else if (y < 0.25) {
      TaylorG7G8<7>(y, g);
    } else if (y < 1.0) {
      TaylorG7G8<9>(y, g);
    } else {
      TaylorG7G8<kTaylorTerms8>(y, g);
    }
    for (int m = 6; m >= 1; --m) g[m] = kInverseFactorial[m] - y * g[m + 2];
    return;
  }
  g[1] = std::sin(x) / x;
  g[2] = (1.0 - std::cos(x)) / y;
  for (int m = 1; m <= 6; ++m) g[m + 2] = (kInverseFactorial[m] - g[m]) / y;
}

// The coefficients of A_m = 1/(m-1)! l^(m-1) I + a1 W + a2 W^2, the matrix that gives R (m = 1,
// A_1), p (m = 2, A_2 e3) and c (m = 3, A_3 e3) of a helical segment of length l (helix.h), as
// functions of Omega: a1 = l^m G_m, a2 = l^(m+1) G_(m+1), their gradients b1 Omega, b2 Omega and
// the gradients of those, c1 Omega, c2 Omega. All from dG_k/dOmega = l^2 (k G_(k+2) - G_(k+1))
// Omega (helix.h: G_k'(x)/x = k G_(k+2) - G_(k+1), and x dx/dOmega = l^2 Omega).
struct Coefficients {
  double a1, a2, b1, b2, c1, c2;
};

inline Coefficients CoefficientsOf(int m, double l, const double g[9]) {
  // dG_k / dOmega = l^2 d_k Omega with d_k = k G_(k+2) - G_(k+1); d(d_k)/dOmega = l^2 e_k Omega
  // with e_k = k d_(k+2) - d_(k+1).
  auto d = [&](int k) { return k * g[k + 2] - g[k + 1]; };
  double lp[9];
  lp[0] = 1.0;
  for (int k = 1; k < 9; ++k) lp[k] = lp[k - 1] * l;
  Coefficients c;
  c.a1 = lp[m] * g[m];
  c.a2 = lp[m + 1] * g[m + 1];
  c.b1 = lp[m + 2] * d(m);
  c.b2 = lp[m + 3] * d(m + 1);
  c.c1 = lp[m + 4] * (m * d(m + 2) - d(m + 1));
  c.c2 = lp[m + 5] * ((m + 1) * d(m + 3) - d(m + 2));
  return c;
}

// d(A e3)/dOmega (3x3, column k for Omega_k) with A = a0 I + a1 W + a2 W^2:
//   (W e3)(b1 Omega)^T - a1 [e3]x + (W^2 e3)(b2 Omega)^T - a2 ([W e3]x + W [e3]x),
// from d(W v)/dOmega_k = e_k x v = -[v]x e_k.
// With W [e3]x = e3 Omega^T - Omega_z I this is u Omega^T + a2 Omega_z I - [a1 e3 + a2 W e3]x,
// u = b1 W e3 + b2 W^2 e3 - a2 e3: one outer product and a skew matrix, no 3 x 3 products.
inline Mat3 ChordDerivative(const Vec3& omega, const Coefficients& c) {
  const Vec3 we3(omega.y(), -omega.x(), 0.0);  // Omega x e3
  const Vec3 w2e3 = omega.cross(we3);
  const Vec3 u = c.b1 * we3 + c.b2 * w2e3 - Vec3(0.0, 0.0, c.a2);
  Mat3 d = u * omega.transpose() - Hat(c.a2 * we3 + Vec3(0.0, 0.0, c.a1));
  d.diagonal().array() += c.a2 * omega.z();
  return d;
}

// [a]x M, column by column (a x M e_k): cheaper than forming [a]x and a 3 x 3 product.
inline Mat3 CrossColumns(const Vec3& a, const Mat3& m) {
  Mat3 out;
  for (int k = 0; k < 3; ++k) out.col(k) = a.cross(m.col(k));
  return out;
}

// The Hessian in Omega of <X, A(Omega)> (X fixed), A = a0 I + a1 W + a2 W^2. With v = Vee(X),
// <X, W> = Omega . v and <X, W^2> = Omega^T M Omega, M = sym(X) - tr(X) I (W^2 = Omega Omega^T -
// |Omega|^2 I), so with rho = Omega^T M Omega:
//   b1 (Omega v^T + v Omega^T) + (Omega . v)(b1 I + c1 Omega Omega^T)
//   + rho (b2 I + c2 Omega Omega^T) + 2 b2 (Omega (M Omega)^T + (M Omega) Omega^T) + 2 a2 M.
// Its gradient, a1 v + b1 (Omega . v) Omega + 2 a2 M Omega + b2 rho Omega, is HelixSegmentVjp's.
// A segment's own Hessian is a sum of such terms (its rotation, chord, first moment and contact
// samples, each with its own coefficients and X); they are accumulated as
//   Omega t^T + t Omega^T + s Omega Omega^T + M_sum + diag I,
// t = sum (b1 v + 2 b2 M Omega), s = sum ((Omega . v) c1 + rho c2), M_sum = sum 2 a2 M,
// diag = sum ((Omega . v) b1 + rho b2), and the outer products formed once.
class OwnHessianSum {
 public:
  explicit OwnHessianSum(const Vec3& omega) : omega_(omega) {}

  // <X, A> for a general X (the rotation's term).
  void AddMatrix(const Coefficients& c, const Mat3& x) {
    const Mat3 m = 0.5 * (x + x.transpose()) - x.trace() * Mat3::Identity();
    Add(c, Vee(x), m, m * omega_);
  }
  // <X, A> for a chord, X = d e3^T: v = e3 x d, M = (d e3^T + e3 d^T)/2 - d_z I.
  void AddChord(const Coefficients& c, const Vec3& d) {
    Mat3 m = Mat3::Zero();
    m.col(2) = 0.5 * d;
    m.row(2) += 0.5 * d.transpose();
    m.diagonal().array() -= d.z();
    const Vec3 m_omega = 0.5 * (omega_.z() * d + d.dot(omega_) * Vec3::UnitZ()) - d.z() * omega_;
    Add(c, Vec3(-d.y(), d.x(), 0.0), m, m_omega);
  }

  Mat3 Hessian() const {
    Mat3 h = omega_ * t_.transpose() + t_ * omega_.transpose() +
             s_ * (omega_ * omega_.transpose()) + m_;
    h.diagonal().array() += diagonal_;
    return h;
  }

 private:
  void Add(const Coefficients& c, const Vec3& v, const Mat3& m, const Vec3& m_omega) {
    const double rho = omega_.dot(m_omega);
    const double ov = omega_.dot(v);
    t_ += c.b1 * v + (2.0 * c.b2) * m_omega;
    s_ += ov * c.c1 + rho * c.c2;
    m_ += (2.0 * c.a2) * m;
    diagonal_ += ov * c.b1 + rho * c.b2;
  }

  Vec3 omega_;
  Vec3 t_ = Vec3::Zero();
  double s_ = 0.0;
  Mat3 m_ = Mat3::Zero();
  double diagonal_ = 0.0;
};

}  // namespace ringlet::helix_hessian
