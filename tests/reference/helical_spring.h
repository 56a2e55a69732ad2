// A uniform helical equilibrium of a naturally curved and twisted rod pulled along its axis with no
// axial torque: the local state of a hanging curl when the tension changes slowly over a turn
// (docs/validation.md, "Hanging curls"). Only the standard library; no ringlet code.
//
// Rod: isotropic (circular section), bending stiffness B = E I, twisting stiffness C = mu J,
// natural material curvature and twist (kappa0, 0, tau0). Ansatz: a uniform equilibrium with
// constant material curvatures Omega = (kappa, 0, tau) (the curvature stays along the natural
// direction n1). Then the Darboux vector Omega = kappa n1 + tau t is constant in space, the
// centreline is a helix about a_hat = Omega / |Omega| of radius kappa / |Omega|^2, and the
// internal moment is m = B (kappa - kappa0) n1 + C (tau - tau0) t (the paper's eq. 3).
// Kirchhoff's equations for a rod with no distributed load (Antman, Nonlinear Problems of
// Elasticity, ch. 8; the helical spring of Love, A Treatise on the Mathematical Theory of
// Elasticity, 4th ed., chapter on thin rods):
//   n' = 0,   m' + t x n = 0,
// with a constant force n = F a_hat along the axis. m' = Omega x m (m is constant in the material
// frame), Omega x m = -n2 (kappa C (tau - tau0) - tau B (kappa - kappa0)) and t x n = F kappa /
// |Omega| n2 (n1 x t = -n2), so
//   (1)  F = |Omega| (C (tau - tau0) - (tau / kappa) B (kappa - kappa0)).
// The axial torque m . a_hat must vanish: the hanging part below any section is acted on by
// vertical weights only, whose moment has no vertical component. So
//   (2)  B kappa (kappa - kappa0) + C tau (tau - tau0) = 0,
// an ellipse in the (kappa, tau) plane through the natural state (kappa0, tau0) and the straight
// twisted state (0, tau0). Eliminating C (tau - tau0) from (1) with (2):
//   (3)  F = B (kappa0 - kappa) |Omega|^3 / (kappa tau),
// positive (a tension along the direction of travel when tau > 0) while the helix opens,
// kappa < kappa0. For tau0 > 0, F grows from 0 at the natural state to infinity at kappa -> 0
// (the strand pulled straight, keeping its natural twist). For tau0 = 0 (a naturally planar curl,
// Miller et al. 2014) F tends to the finite B^2 kappa0^2 / C as kappa -> 0: above it no uniform
// helix exists. By dimensional analysis F / (B (kappa0^2 + tau0^2)) depends only on C / B and the
// natural pitch angle, which is the F ~ E I kappa0^2 scaling of Miller et al.
//
// In a hanging strand the force at arc length s is the weight below, F(s) = w (L - s), so in the
// slowly varying ("effective column", Gomez & Lauga, arXiv:2403.02299) limit the local curvature is
// the kappa that (3) gives for F = w (L - s); the curls are tight (kappa -> kappa0) at the tip and
// opened (kappa -> 0) where w (L - s) >> B |Omega0|^2.
#pragma once

#include <cmath>

namespace ringlet::reference {

/// Material stiffnesses and natural curvatures of an isotropic rod (SI units).
struct HelicalSpring {
  double bending = 0.0;    ///< B = E I (N m^2)
  double twisting = 0.0;   ///< C = mu J (N m^2)
  double kappa0 = 0.0;     ///< natural curvature (1/m), > 0
  double tau0 = 0.0;       ///< natural twist (1/m), >= 0

  /// The twist tau on the branch of (2) through the natural state, for a curvature kappa in
  /// (0, kappa0]: the root of C tau^2 - C tau0 tau + B kappa (kappa - kappa0) = 0 that equals
  /// tau0 at kappa = kappa0 (1/m).
  double Twist(double kappa) const {
    const double discriminant = tau0 * tau0 + 4.0 * bending * kappa * (kappa0 - kappa) / twisting;
    return 0.5 * (tau0 + std::sqrt(discriminant));
  }

  /// Axial tension (3) that holds the helix at curvature kappa in (0, kappa0) (N).
  double Tension(double kappa) const {
    const double tau = Twist(kappa);
    const double omega = std::hypot(kappa, tau);
    return bending * (kappa0 - kappa) * omega * omega * omega / (kappa * tau);
  }

  /// Helix radius kappa / (kappa^2 + tau^2) on the branch (m).
  double Radius(double kappa) const {
    const double tau = Twist(kappa);
    return kappa / (kappa * kappa + tau * tau);
  }

  /// The curvature at which the tension equals force (N), by bisection on (0, kappa0) (Tension
  /// decreases from its kappa -> 0 limit to 0 at kappa0). Returns 0 if force exceeds the largest
  /// tension a helix can carry (possible only for tau0 = 0).
  double CurvatureAtTension(double force) const {
    if (force <= 0.0) return kappa0;
    double lo = 1e-12 * kappa0, hi = kappa0;  // Tension(lo) >= force > Tension(hi) = 0
    if (Tension(lo) < force) return 0.0;
    for (int i = 0; i < 200 && hi - lo > 1e-15 * kappa0; ++i) {
      const double mid = 0.5 * (lo + hi);
      (Tension(mid) > force ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  }
};

}  // namespace ringlet::reference
