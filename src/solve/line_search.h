// Line search along a descent direction satisfying the strong Wolfe conditions (Nocedal & Wright,
// Numerical Optimization, 2nd ed., algorithms 3.5 and 3.6), made robust to rounding near the
// optimum with Hager & Zhang's approximate Wolfe test (SIAM J. Optim. 16, 2005, eq. 4.1).
#pragma once

#include <functional>

namespace ringlet::internal {

/// phi(alpha) and phi'(alpha) at one trial step; finite is false if either is NaN or infinite.
struct LineSample {
  double alpha = 0.0;
  double value = 0.0;
  double slope = 0.0;
  bool finite = true;
};

struct LineSearchOptions {
  double sufficient_decrease = 1e-4;  ///< c1
  double curvature = 0.9;             ///< c2 (0.9 is the usual quasi-Newton choice)
  /// Relative size of energy rounding: below it, values are compared through slopes only.
  double value_noise = 1e-12;
  int max_evaluations = 40;
};

struct LineSearchResult {
  bool success = false;
  LineSample best;  ///< the accepted step (or the best one seen on failure)
  int evaluations = 0;
};

/// Searches alpha in (0, alpha_max] starting at alpha_init. evaluate(alpha) returns phi and phi'.
/// The caller's state after the call corresponds to the last evaluation, not necessarily best:
/// the caller re-evaluates or caches as needed.
LineSearchResult StrongWolfeSearch(const std::function<LineSample(double)>& evaluate,
                                   const LineSample& at_zero, double alpha_init, double alpha_max,
                                   const LineSearchOptions& options);

}  // namespace ringlet::internal
