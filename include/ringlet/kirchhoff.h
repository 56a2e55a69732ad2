// Kirchhoff's balance of a discretized strand: the equilibrium certificate of any solution.
#pragma once

#include <vector>

#include "ringlet/math.h"
#include "ringlet/strand_geometry.h"
#include "ringlet/strand_model.h"

namespace ringlet {

/// The dimensionless equilibrium residual of a configuration. The gradient of the energy with
/// respect to segment i's curvatures is g_i = l_i K (Omega_i - Omega^0_i) - m_i, where m_i is the
/// external moment integrated over the segment: g_i = 0 is Kirchhoff's moment balance averaged
/// over the segment (with the moment-free tip built in). The residual is
///   max_i |g_i| / (l_i M_ref),   M_ref = |f| L^2 / 2 + max_i |K (Omega_i - Omega^0_i)| + E I1 / L,
/// with Omega^0_i = model.NaturalCurvature(i) (the rest shape): the internal-moment mismatch
/// relative to the largest moment in play (N m / N m).
double EquilibriumResidual(const StrandModel& model, const VecX& curvatures,
                           const VecX& gradient);

/// Kirchhoff's moment balance averaged over each segment, evaluated directly from the geometry
/// and independently of the energy gradient code: for segment i,
///   b_i = l_i K (Omega_i - Omega^0_i) - int_segment Q(u)^T M(u) du   (J m, material coordinates),
/// where M(u) = int_u^L (r(s) - r(u)) x f ds = (T(u) - (L - u) r(u)) x f is the moment of the weight
/// hanging below r(u) (internal force n(u) = (L - u) f balances the weight, n' + f = 0, and the
/// free tip carries no force or moment, M(L) = 0). The integral uses 6-point Gauss-Legendre
/// quadrature on sub-intervals turning at most 1 rad (relative error about 7.7e-13 at most,
/// kirchhoff.cpp); positions and T(u) come from the closed-form helix (the chord and first
/// moment of helix.h at length u, in the segment's start frame). With a contact model, the penalty
/// forces (ComputeContactForces) are point loads at their samples and add their moments
/// sum (x_k - r(u)) x F_k about r(u) to M(u); the quadrature then breaks at the samples. At an
/// exact equilibrium of the discrete energy b equals the energy gradient, which is zero. Size 3n.
VecX KirchhoffImbalance(const StrandModel& model, const VecX& curvatures);

/// The same from the strand's geometry and segment first moments as ComputeGeometry(model,
/// curvatures, &segment_moments) returns them (strand_geometry.h), for callers that need the
/// geometry too (MakeStrandResult): the helix is then evaluated once per segment, not twice.
VecX KirchhoffImbalance(const StrandModel& model, const VecX& curvatures,
                        const StrandGeometry& geometry, const std::vector<Vec3>& segment_moments);

/// EquilibriumResidual of KirchhoffImbalance: the dimensionless certificate written as
/// `kirchhoff_residual` in result files and checked by `ringlet solve --check`.
double KirchhoffResidual(const StrandModel& model, const VecX& curvatures);
double KirchhoffResidual(const StrandModel& model, const VecX& curvatures,
                         const StrandGeometry& geometry, const std::vector<Vec3>& segment_moments);

}  // namespace ringlet
