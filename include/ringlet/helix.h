// One segment of constant curvature and twist: an exact helix in closed form (../shared/DESIGN.md).
#pragma once

#include "ringlet/math.h"

namespace ringlet {

/// The smooth even functions G_m(x) = sum_k (-1)^k x^(2k) / (2k+m)!, m = 1..6:
///   G1 = sin x / x, G2 = (1 - cos x)/x^2, G3 = (x - sin x)/x^3, G4 = (x^2/2 - 1 + cos x)/x^4, ...
/// They satisfy G_m = 1/m! - x^2 G_(m+2) and d/dx (x^m G_m) = x^(m-1) G_(m-1) (G_0 = cos), so
/// G_m'(x)/x = m G_(m+2) - G_(m+1). Small x uses the Taylor series (no cancellation), larger x the
/// closed forms; both branches agree to rounding at the switch.
struct HelixFunctions {
  double g[7];  ///< g[m] = G_m(x) for m = 1..6 (g[0] unused)
};
HelixFunctions EvaluateHelixFunctions(double x);

/// Closed-form kinematics of one helical segment of length l and constant curvature vector Omega
/// (material coordinates, 1/m), all expressed in the segment's start material frame:
///   rotation  R = exp(l [Omega]x) = I + l G1 W + l^2 G2 W^2                    (Rodrigues)
///   chord     p = int_0^l exp(u W) e3 du = (l I + l^2 G2 W + l^3 G3 W^2) e3
///   moment    c = int_0^l (l - u) exp(u W) e3 du = (l^2/2 I + l^3 G3 W + l^4 G4 W^2) e3
/// with W = [Omega]x, x = l |Omega| and e3 = (0,0,1) the tangent. Then Q_end = Q R,
/// r_end = r + Q p and int_segment r ds = l r + Q c.
struct HelixSegment {
  Mat3 rotation;  ///< R (dimensionless)
  Vec3 chord;     ///< p (m)
  Vec3 moment;    ///< c (m^2)
  HelixFunctions functions;  ///< G_m(l |Omega|), kept for the derivative
};
HelixSegment EvaluateHelixSegment(const Vec3& omega, double length);

/// Reverse-mode derivative (vector-Jacobian product) of EvaluateHelixSegment: given the
/// sensitivities of a scalar E to R, p and c (dE/dR as a 3x3 matrix, dE/dp, dE/dc), returns
/// dE/dOmega (3-vector). Exact differentiation of the closed forms above, O(1). functions are
/// the segment's G_m (HelixSegment::functions).
Vec3 HelixSegmentVjp(const Vec3& omega, double length, const HelixFunctions& functions,
                     const Mat3& d_rotation, const Vec3& d_chord, const Vec3& d_moment);

/// The chord p(u) = (u I + u^2 G2 W + u^3 G3 W^2) e3 from precomputed functions = G_m(u |Omega|):
///   p = u e3 + u^2 G2 (Omega x e3) + u^3 G3 Omega x (Omega x e3)   (m).
Vec3 HelixChordFromFunctions(const Vec3& omega, double u, const HelixFunctions& functions);

/// dE/dOmega of the chord alone, given dE/dp (HelixSegmentVjp with d_rotation = d_moment = 0,
/// in a few dozen flops): with X = d e3^T, a1 = u^2 G2, a2 = u^3 G3, da1 = u^4 (2 G4 - G3),
/// da2 = u^5 (3 G5 - G4),
///   dE/dOmega = a1 e3 x d - a2 Vee(X W + W X) + (da1 d . (Omega x e3) + da2 d . W^2 e3) Omega.
Vec3 HelixChordVjp(const Vec3& omega, double u, const HelixFunctions& functions,
                   const Vec3& d_chord);

/// Chord of a partial segment: the displacement after arc length u in [0, l] along the helix,
/// in the segment's start frame (m). Same formula as HelixSegment::chord with l -> u.
Vec3 HelixChord(const Vec3& omega, double u);

/// Rotation after arc length u along the helix (start frame to frame at u).
Mat3 HelixRotation(const Vec3& omega, double u);

}  // namespace ringlet
