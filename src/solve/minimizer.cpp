// BFGS (Nocedal & Wright algorithm 6.1) and modified Newton (their section 3.4, eigenvalue
// modification) with a strong-Wolfe line search. The paper used Davidon-Fletcher-Powell [FP63];
// BFGS is the same family with the dual update, known to be more robust to inexact line searches.
#include "solve/minimizer.h"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "solve/line_search.h"

namespace ringlet::internal {
namespace {

// Newton falls back to a dense finite-difference Hessian only up to this many unknowns (200
// segments: 2.9 MB and 600 gradients per step); longer strands take a steepest-descent step
// instead, so that no input makes Newton allocate O(n^2) (docs/robustness.md).
constexpr int kMaxDenseNewtonUnknowns = 600;

// Newton: eigenvalues of the Hessian are raised to at least this (relative to 1, the elastic
// part in scaled variables) so that the step is a descent direction (N&W eq. 3.41).
constexpr double kNewtonMinEigenvalue = 1e-6;

// The m most recent (s, y) pairs of L-BFGS and the two-loop recursion (N&W algorithm 7.4) with
// H_0 = I: in stiffness-scaled variables the elastic Hessian is exactly I, so no gamma scaling.
class LbfgsMemory {
 public:
  static constexpr int kPairs = 10;
  explicit LbfgsMemory(int n) : s_(n, kPairs), y_(n, kPairs), rho_(kPairs), alpha_(kPairs) {}
  void Clear() { count_ = 0; }
  void Push(const VecX& s, const VecX& y) {
    const double sy = s.dot(y);
    if (!(sy > 1e-16 * s.norm() * y.norm())) return;  // curvature condition failed: skip
    const int slot = (head_ + count_) % kPairs;
    if (count_ < kPairs) {
      ++count_;
    } else {
      head_ = (head_ + 1) % kPairs;
    }
    s_.col(slot) = s;
    y_.col(slot) = y;
    rho_(slot) = 1.0 / sy;
  }
  // out = H g.
  void ApplyInverse(const VecX& g, VecX* out) {
    VecX& q = *out;
    q = g;
    for (int k = count_ - 1; k >= 0; --k) {
      const int j = (head_ + k) % kPairs;
      alpha_(j) = rho_(j) * s_.col(j).dot(q);
      q -= alpha_(j) * y_.col(j);
    }
    for (int k = 0; k < count_; ++k) {
      const int j = (head_ + k) % kPairs;
      const double beta = rho_(j) * y_.col(j).dot(q);
      q += (alpha_(j) - beta) * s_.col(j);
    }
  }

 private:
  MatX s_, y_;
  VecX rho_, alpha_;
  int head_ = 0, count_ = 0;
};

}  // namespace

MinimizerResult Minimize(Objective& objective, VecX* x, const MinimizerOptions& options) {
  const int n = objective.Dimension();
  MinimizerResult result;
  VecX g(n), trial_x(n), trial_g(n), p(n), hy(n), step(n), y(n);
  double f = objective.Evaluate(*x, &g);
  result.evaluations = 1;
  result.value = f;
  if (!std::isfinite(f) || !g.allFinite()) {
    result.termination = Termination::kNonFinite;
    result.message = "energy or gradient is not finite at the starting point";
    return result;
  }
  result.residual = objective.Residual(*x, g);

  const bool dense = options.method == Method::kBfgs;
  const bool limited = options.method == Method::kLbfgs;
  MatX inverse_hessian;  // dense BFGS: H_0 = I in stiffness-scaled variables
  if (dense) inverse_hessian.setIdentity(n, n);
  LbfgsMemory memory(limited ? n : 0);
  bool fresh = true;                            // H is the identity
  MatX hessian;
  LineSearchOptions ls_options;

  for (result.iterations = 0;; ++result.iterations) {
    if (result.residual <= options.tolerance) {
      result.termination = Termination::kConverged;
      result.message = "converged: equilibrium residual below tolerance";
      return result;
    }
    if (result.iterations >= options.max_iterations) {
      result.termination = Termination::kMaxIterations;
      result.message = "stopped after the maximum number of iterations, not converged";
      return result;
    }

    // Search direction.
    if (options.method == Method::kNewton) {
      if (objective.NewtonDirection(*x, g, &p)) {
        ++result.hessian_evaluations;
      } else if (n > kMaxDenseNewtonUnknowns) {
        // No dense matrix for a long strand (its n^2 doubles and n gradients per step):
        // steepest descent for this step; the line search and the next step carry on.
        p = -g;
      } else {
        result.evaluations += FiniteDifferenceHessian(objective, *x, &hessian);
        Eigen::SelfAdjointEigenSolver<MatX> eig(hessian);
        VecX lambda = eig.eigenvalues().cwiseMax(kNewtonMinEigenvalue);
        p = -eig.eigenvectors() * ((eig.eigenvectors().transpose() * g).cwiseQuotient(lambda));
      }
    } else if (limited) {
      memory.ApplyInverse(g, &p);
      p = -p;
    } else {
      p.noalias() = -inverse_hessian * g;
    }
    double slope = g.dot(p);
    if (!(slope < 0.0)) {  // not a descent direction (rounding): fall back to steepest descent
      p = -g;
      slope = -g.squaredNorm();
      if (dense) inverse_hessian.setIdentity();
      memory.Clear();
      fresh = true;
    }

    // Line search on phi(alpha) = f(x + alpha p).
    double last_alpha = 0.0;
    auto evaluate = [&](double alpha) {
      last_alpha = alpha;
      trial_x = *x + alpha * p;
      LineSample s;
      s.alpha = alpha;
      s.value = objective.Evaluate(trial_x, &trial_g);
      s.slope = trial_g.dot(p);
      s.finite = std::isfinite(s.value) && std::isfinite(s.slope);
      return s;
    };
    LineSample at_zero{0.0, f, slope, true};
    const double alpha_max = objective.MaxStep(*x, p);
    LineSearchResult ls =
        StrongWolfeSearch(evaluate, at_zero, std::min(1.0, alpha_max), alpha_max, ls_options);
    result.evaluations += ls.evaluations;
    if (!ls.success) {
      if (!fresh && options.method != Method::kNewton) {
        // Restart once from steepest descent before giving up.
        if (dense) inverse_hessian.setIdentity();
        memory.Clear();
        fresh = true;
        --result.iterations;
        continue;
      }
      result.termination = Termination::kLineSearchFailed;
      result.message = "line search found no acceptable step (residual " +
                       std::to_string(result.residual) + ")";
      return result;
    }
    // Re-evaluate at the accepted step if the last trial was another one.
    if (last_alpha != ls.best.alpha) {
      trial_x = *x + ls.best.alpha * p;
      objective.Evaluate(trial_x, &trial_g);
      ++result.evaluations;
    }
    const double f_new = ls.best.value;
    if (!std::isfinite(f_new) || !trial_g.allFinite()) {
      result.termination = Termination::kNonFinite;
      result.message = "energy or gradient became non-finite";
      return result;
    }

    // BFGS update of the inverse Hessian (N&W eq. 6.17); the Wolfe conditions give s.y > 0.
    if (limited) {
      memory.Push(trial_x - *x, trial_g - g);
      fresh = false;
    } else if (dense) {
      step = trial_x - *x;
      y = trial_g - g;
      const double sy = step.dot(y);
      if (sy > 1e-16 * step.norm() * y.norm()) {
        const double rho = 1.0 / sy;
        hy.noalias() = inverse_hessian * y;
        const double yhy = y.dot(hy);
        // H += -rho (s hy^T + hy s^T) + (rho^2 y.Hy + rho) s s^T, in place: no N x N temporaries
        // (which cost a page-faulting allocation each at N = 360).
        const double c = rho * rho * yhy + rho;
        for (int j = 0; j < n; ++j) {
          const double sj = step(j), hyj = hy(j);
          inverse_hessian.col(j) += (c * sj - rho * hyj) * step - (rho * sj) * hy;
        }
        fresh = false;
      }
    }
    *x = trial_x;
    g = trial_g;
    f = f_new;
    result.value = f;
    result.residual = objective.Residual(*x, g);
  }
}

}  // namespace ringlet::internal
