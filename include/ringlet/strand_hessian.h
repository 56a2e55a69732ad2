// Exact second derivatives of the strand energy E_e + E_g + E_c in the curvature coordinates, in
// O(n) storage, and their O(n) block factorization: the stability certificate and Newton steps.
#pragma once

#include <vector>

#include "ringlet/math.h"
#include "ringlet/strand_model.h"

namespace ringlet {

using Mat63 = Eigen::Matrix<double, 6, 3>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

/// The exact Hessian d^2E/dq^2 of E_e + E_g + E_c (J m^2; q the 3n curvatures in 1/m) at one
/// configuration, as a block-semiseparable matrix of 3x3 blocks:
///   H_ab = S_a^T B_b  (a < b),   H_ba = H_ab^T,   H_aa = D_a.
/// S_a (6x3) maps a curvature change of segment a to the infinitesimal rigid motion it gives
/// everything downstream of the segment: a world rotation vector (rows 0-2) and the velocity it
/// gives the point at the root (rows 3-5), so that a downstream point y moves by
/// omega x (y - r(0)) + v. B_b (6x3) is the change, caused by a curvature change of segment b, of
/// the load that the part of the strand downstream of b's start exerts on the rotations upstream
/// (the gravity and contact moments, plus the contact stiffness of the samples downstream).
/// Why this form: a curvature change of segment a only moves the strand downstream of a as a
/// rigid body, so the second derivative in (a, b), a < b, factors through that motion (the
/// product-of-exponentials structure of serial chains). Storage and every operation below are
/// O(n), against O(n^2) storage and O(n^3) work for a dense Hessian.
struct StrandHessian {
  std::vector<Mat3> diagonal;  ///< D_a (J m^2), symmetric
  std::vector<Mat63> twist;    ///< S_a (rows 0-2: rad per 1/m = m; rows 3-5: m^2)
  std::vector<Mat63> load;     ///< B_b (rows 0-2: J m; rows 3-5: J)
  /// Whether some B has non-zero bottom rows (contact samples carry a force); when false they
  /// are all zero and the factorization works on the 3x3 top blocks alone (without an obstacle
  /// the twists' bottom rows are then left zero too: they only ever meet those zero rows).
  bool translational = false;

  /// Number of segments n (the matrix is 3n x 3n).
  int NumSegments() const { return static_cast<int>(diagonal.size()); }
  /// out = H v (O(n)).
  void Multiply(const VecX& v, VecX* out) const;
  /// The dense 3n x 3n matrix (O(n^2): for tests and small eigenproblems only).
  MatX Dense() const;
  /// H <- diag(s) H diag(s) (a change of variables q = s x).
  void Scale(const VecX& s);
};

/// Computes the exact Hessian of StrandEnergy at curvatures (size 3n): elastic (eq. 3, l_i K on
/// the diagonal), gravity (eqs. 4-5) and the contact penalty (section 3.1) with the same samples
/// and the same broad phase as ContactEnergy, including the obstacle's curvature
/// (Obstacle::SignedDistanceHessian). Second derivatives of each helical segment are in closed
/// form (the derivatives of its coefficient functions G_m, helix.h), exact to rounding; the chain
/// is summed in one forward and one reverse sweep, O(n + samples).
void ComputeStrandHessian(const StrandModel& model, const VecX& curvatures, StrandHessian* hessian);

struct EnergyTerms;

/// ComputeStrandHessian that also returns StrandEnergy's value (J), its terms and its gradient
/// (J m, size 3n, written) from the same sweeps: the loads' adjoints of the Hessian's reverse
/// sweep are the gradient's (the same chain rule as StrandEnergy::Evaluate, through the segments'
/// derivative matrices instead of HelixSegmentVjp: equal to rounding). One pass over the
/// segments and one body query per sample instead of two of each where both are needed (the
/// implicit step's Newton point).
double ComputeStrandEnergyAndHessian(const StrandModel& model, const VecX& curvatures,
                                     StrandHessian* hessian, VecX* gradient, EnergyTerms* terms);

/// Block LDL^T factorization of H - shift I from the tip to the root, H - shift I = U D U^T with U
/// block unit upper triangular, in O(n) using the semiseparable form. Positive definiteness of a
/// symmetric matrix is equivalent to every pivot block D_k being positive definite (Sylvester's
/// law of inertia applied to the block congruence), so a successful Factor is a certificate that
/// H - shift I is positive definite, up to rounding in the 3x3 pivots.
class StrandHessianFactor {
 public:
  /// Factors H - shift I; returns false, with failed_segment() set to the segment whose pivot
  /// block is not positive definite, when H - shift I is not positive definite.
  bool Factor(const StrandHessian& hessian, double shift);
  /// x = (H - shift I)^(-1) b after a successful Factor (O(n)).
  void Solve(const VecX& b, VecX* x) const;
  /// The segment whose pivot failed (-1 after a success).
  int failed_segment() const { return failed_; }

 private:
  const StrandHessian* hessian_ = nullptr;
  std::vector<Mat3> inverses_;            // D'_k^(-1)
  std::vector<Mat63> reduced_load_;       // B'_k = B_k - C S_k
  int failed_ = -1;
};

}  // namespace ringlet
