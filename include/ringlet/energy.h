// Potential energy of a strand and its exact gradient (paper eqs. 2-5).
#pragma once

#include <vector>

#include "ringlet/helix.h"
#include "ringlet/math.h"
#include "ringlet/strand_model.h"

namespace ringlet {

/// The energy terms of one configuration (J).
struct EnergyTerms {
  double elastic = 0.0;  ///< E_e, eq. 3
  double gravity = 0.0;  ///< E_g, eq. 4, measured from the root: -f . int (r(s) - r(0)) ds
  double contact = 0.0;  ///< E_c, section 3.1: penalty of the body contact (ContactModel)
  double total = 0.0;    ///< E_e + E_g + E_c (eq. 2 and section 3.1)
};

/// Elastic energy (eq. 3) of piecewise-constant curvatures, exactly
///   E_e = sum_i 1/2 l_i (Omega_i - Omega^0_i)^T K (Omega_i - Omega^0_i),  K = diag(E I1, E I2, mu J),
/// with Omega^0_i = model.NaturalCurvature(i) (the rest shape, constant by default),
/// and, if gradient is not null, its gradient (J m), written (not added) into gradient (size 3n).
double ElasticEnergy(const StrandModel& model, const VecX& curvatures, VecX* gradient);

/// Reusable scratch space for the sweeps over the external loads (gravity and contact): no heap
/// allocation per evaluation once warm.
class LoadWorkspace {
 public:
  explicit LoadWorkspace(int segments = 0) { Resize(segments); }
  void Resize(int segments);

 private:
  friend struct LoadSweep;
  // One sample in contact: x = r_i + Q_i h with h = HelixChord(Omega_i, u).
  struct ContactSample {
    int segment;
    double u;      // arc length inside the segment (m)
    Vec3 h;        // chord to the sample in the segment's start frame (m)
    Vec3 dE_dx;    // gradient of E_c with respect to the sample's position (N)
    HelixFunctions functions;  // G_m(u |Omega_i|), kept for the derivative
  };
  std::vector<Mat3> frames_;            // Q_i
  std::vector<Vec3> starts_;            // r_i - r_0
  std::vector<HelixSegment> segments_;  // R_i, p_i, c_i
  std::vector<ContactSample> contacts_;
};

/// Gravity energy (eqs. 4-5) in closed form over each helical segment, with the root as origin
/// (the paper's z(0) = 0):
///   E_g = -f . int_0^L (r(s) - r(0)) ds = -f . sum_i (l_i r_i + Q_i c_i),   f = rho S g,
/// and, if gradient is not null, its exact gradient (J m), by one reverse sweep (O(n)): the
/// adjoint of r_i is -(L - s_i) f and that of Q_i accumulates the downstream moment.
/// The gradient is written (not added) into gradient (size 3n).
double GravityEnergy(const StrandModel& model, const VecX& curvatures, VecX* gradient,
                     LoadWorkspace* workspace);

/// Contact energy E_c of ContactModel (section 3.1; 0 without an obstacle), with its exact
/// gradient (J m) by the same reverse sweep: a sample at x = r_i + Q_i h(u) with dE_c/dx = F
/// adds F to the adjoint of r_i, F h^T to that of Q_i and the derivative of the partial chord
/// h(u) = HelixChord(Omega_i, u) to segment i. Samples of a segment are skipped when the segment
/// is certainly clear: every point of it lies within l_i/2 of one of its ends and d is
/// 1-Lipschitz, so min(d(r_i), d(r_(i+1))) - l_i/2 >= clearance rules contact out. Far from the
/// obstacle even those two queries are skipped where Obstacle::LipschitzBound proves the test's
/// outcome (docs/body.md, "Contact broad phase"): the same samples, the same bits.
double ContactEnergy(const StrandModel& model, const VecX& curvatures, VecX* gradient,
                     LoadWorkspace* workspace);

/// Evaluates all terms and the total gradient (J m) if gradient is not null.
class StrandEnergy {
 public:
  explicit StrandEnergy(const StrandModel& model);

  /// Total energy (J); fills terms and gradient when given.
  double Evaluate(const VecX& curvatures, VecX* gradient, EnergyTerms* terms = nullptr);

  const StrandModel& model() const { return model_; }

 private:
  const StrandModel& model_;
  LoadWorkspace workspace_;
  VecX scratch_;
};

}  // namespace ringlet
