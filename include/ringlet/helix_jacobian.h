// First derivatives of a helical segment's chord and tangent in matrix form (helix.h gives the
// closed forms and their vector-Jacobian products): for the fit of piecewise helices
// (src/inverse/fit.cpp), whose Gauss-Newton steps need whole Jacobian blocks.
#pragma once

#include "ringlet/helix.h"
#include "ringlet/math.h"

namespace ringlet {

/// The full Jacobian dp/dOmega (3x3, m^2) of the chord p(u) = u e3 + a1 Omega x e3 +
/// a2 Omega x (Omega x e3) (a1 = u^2 G2, a2 = u^3 G3) in one pass, instead of three
/// HelixChordVjp calls: differentiating each term (Omega x (Omega x e3) = Omega Omega_3 - e3
/// |Omega|^2, and d a_m / dOmega = da_m Omega with da1, da2 as in HelixChordVjp),
///   dp/dOmega = -a1 [e3]x + a2 (Omega_3 I + Omega e3^T - 2 e3 Omega^T)
///               + (da1 Omega x e3 + da2 Omega x (Omega x e3)) Omega^T.
/// Its transpose times d is HelixChordVjp(omega, u, functions, d) to rounding.
Mat3 HelixChordJacobian(const Vec3& omega, double u, const HelixFunctions& functions);

/// The tangent R(u) e3 = e3 + u G1 Omega x e3 + u^2 G2 Omega x (Omega x e3) after arc length u
/// (start frame; Rodrigues as in HelixSegment::rotation), from precomputed functions =
/// G_m(u |Omega|).
Vec3 HelixTangentFromFunctions(const Vec3& omega, double u, const HelixFunctions& functions);

}  // namespace ringlet
