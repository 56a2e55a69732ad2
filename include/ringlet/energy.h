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
  double total = 0.0;    ///< E_e + E_g (eq. 2)
};

/// Elastic energy (eq. 3) of piecewise-constant curvatures, exactly
///   E_e = sum_i 1/2 l_i (Omega_i - Omega^0)^T K (Omega_i - Omega^0),  K = diag(E I1, E I2, mu J),
/// and, if gradient is not null, its gradient (J m), written (not added) into gradient (size 3n).
double ElasticEnergy(const StrandModel& model, const VecX& curvatures, VecX* gradient);

/// Reusable scratch space for the gravity sweeps: no heap allocation per evaluation.
class GravityWorkspace {
 public:
  explicit GravityWorkspace(int segments = 0) { Resize(segments); }
  void Resize(int segments);

 private:
  friend double GravityEnergy(const StrandModel&, const VecX&, VecX*, GravityWorkspace*);
  std::vector<Mat3> frames_;            // Q_i relative to the root frame
  std::vector<HelixSegment> segments_;  // R_i, p_i, c_i
};

/// Gravity energy (eqs. 4-5) in closed form over each helical segment, with the root as origin
/// (the paper's z(0) = 0):
///   E_g = -f . int_0^L (r(s) - r(0)) ds = -f . sum_i (l_i r_i + Q_i c_i),   f = rho S g,
/// and, if gradient is not null, its exact gradient (J m), by one reverse sweep (O(n)): the
/// adjoint of r_i is -(L - s_i) f and that of Q_i accumulates the downstream moment.
/// The gradient is written (not added) into gradient (size 3n).
double GravityEnergy(const StrandModel& model, const VecX& curvatures, VecX* gradient,
                     GravityWorkspace* workspace);

/// Evaluates all terms and the total gradient (J m) if gradient is not null.
class StrandEnergy {
 public:
  explicit StrandEnergy(const StrandModel& model);

  /// Total energy (J); fills terms and gradient when given.
  double Evaluate(const VecX& curvatures, VecX* gradient, EnergyTerms* terms = nullptr);

  const StrandModel& model() const { return model_; }

 private:
  const StrandModel& model_;
  GravityWorkspace workspace_;
  VecX scratch_;
};

}  // namespace ringlet
