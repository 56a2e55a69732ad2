// Hessian by central differences of the exact analytic gradient.
#include "solve/minimizer.h"

namespace ringlet::internal {

int FiniteDifferenceHessian(Objective& objective, const VecX& x, MatX* hessian) {
  const int n = objective.Dimension();
  hessian->resize(n, n);
  VecX xp = x, gp(n), gm(n);
  for (int j = 0; j < n; ++j) {
    // Central difference: O(h^2) truncation; h is chosen by the objective so that the
    // perturbation is a small rotation (solve/statics.cpp).
    const double h = objective.HessianStep(j);
    xp(j) = x(j) + h;
    objective.Evaluate(xp, &gp);
    xp(j) = x(j) - h;
    objective.Evaluate(xp, &gm);
    xp(j) = x(j);
    hessian->col(j) = (gp - gm) / (2.0 * h);
  }
  // Symmetrize: the exact Hessian is symmetric; this halves the truncation noise.
  *hessian = 0.5 * (*hessian + hessian->transpose()).eval();
  return 2 * n;
}

}  // namespace ringlet::internal
