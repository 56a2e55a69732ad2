// Unconstrained minimization of a smooth energy: dense BFGS or finite-difference Newton, both with
// the strong-Wolfe line search. Knows nothing of rods: the statics driver supplies the objective.
#pragma once

#include <string>

#include "ringlet/math.h"
#include "ringlet/statics.h"

namespace ringlet::internal {

/// A smooth function of x in R^N with its exact gradient.
class Objective {
 public:
  virtual ~Objective() = default;
  virtual int Dimension() const = 0;
  /// f(x); writes the gradient into gradient when not null. May return NaN or infinity.
  virtual double Evaluate(const VecX& x, VecX* gradient) = 0;
  /// Dimensionless stationarity measure at (x, gradient); converged when <= the tolerance.
  virtual double Residual(const VecX& x, const VecX& gradient) const = 0;
  /// Largest step multiplier alpha allowed along direction p from x (a trust cap).
  virtual double MaxStep(const VecX& x, const VecX& p) const = 0;
  /// Finite-difference step of coordinate j for Hessians (in units of x).
  virtual double HessianStep(int j) const = 0;
  /// A Newton direction p = -(H + sigma I)^(-1) g from an exact Hessian H at x, with the
  /// smallest shift sigma >= 0 tried that makes H + sigma I positive definite. Returns false when
  /// the objective has no exact Hessian (Newton then differences the gradient).
  virtual bool NewtonDirection(const VecX& /*x*/, const VecX& /*g*/, VecX* /*p*/) { return false; }
};

struct MinimizerOptions {
  Method method = Method::kLbfgs;
  int max_iterations = 1000;
  double tolerance = 1e-9;
};

struct MinimizerResult {
  Termination termination = Termination::kMaxIterations;
  std::string message;
  int iterations = 0;
  int evaluations = 0;
  int hessian_evaluations = 0;  ///< exact Hessians (NewtonDirection)
  double value = 0.0;
  double residual = 0.0;
};

/// Minimizes from *x (overwritten with the result). Never reports convergence unless the residual
/// is at or below the tolerance.
MinimizerResult Minimize(Objective& objective, VecX* x, const MinimizerOptions& options);

/// Symmetric Hessian by central differences of the exact gradient, column j with step
/// objective.HessianStep(j): 2N gradient evaluations. Returns the evaluations used.
int FiniteDifferenceHessian(Objective& objective, const VecX& x, MatX* hessian);

}  // namespace ringlet::internal
