// Static equilibrium of a strand by energy minimization (paper section 2.3), with a stability
// certificate and escape from unstable equilibria (../shared/DESIGN.md, "Solving").
#include "ringlet/statics.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "solve/minimizer.h"

namespace ringlet {
namespace {

// An equilibrium is stable when the smallest eigenvalue of the stiffness-scaled Hessian is above
// -kStabilityTolerance: the finite-difference Hessian is accurate to ~1e-9 in these units.
constexpr double kStabilityTolerance = 1e-7;
// Leaving an unstable equilibrium: the step along the negative-curvature mode turns the most
// turned segment by this angle (rad).
constexpr double kEscapeTurn = 0.05;
// A line-search step may turn no segment by more than this angle (rad): keeps trial shapes sane.
constexpr double kMaxTurnPerStep = 1.0;
// Hessian difference step, as a curvature change relative to 1/L.
constexpr double kHessianCurvatureStep = 1e-5;

// The energy in stiffness-scaled variables x_i = sqrt(l_i K) (Omega_i - Omega^0): the elastic
// energy becomes |x|^2 / 2 (DESIGN.md, "Solving").
class ScaledStrandObjective final : public internal::Objective {
 public:
  explicit ScaledStrandObjective(const StrandModel& model)
      : model_(model), energy_(model), natural_(model.NaturalCurvatures()) {
    const int n = model.NumSegments();
    scale_.resize(3 * n);
    const Vec3 k = model.Stiffness();
    for (int i = 0; i < n; ++i) {
      scale_.segment<3>(3 * i) = (model.segment_lengths[i] * k).cwiseSqrt();
    }
    q_.resize(3 * n);
    gq_.resize(3 * n);
  }

  int Dimension() const override { return static_cast<int>(scale_.size()); }

  VecX ToScaled(const VecX& q) const { return (q - natural_).cwiseProduct(scale_); }
  VecX ToCurvatures(const VecX& x) const { return natural_ + x.cwiseQuotient(scale_); }

  double Evaluate(const VecX& x, VecX* gradient) override {
    q_ = natural_ + x.cwiseQuotient(scale_);
    const double e = energy_.Evaluate(q_, gradient ? &gq_ : nullptr);
    if (gradient) *gradient = gq_.cwiseQuotient(scale_);  // dE/dx = dE/dq / scale
    return e;
  }

  double Residual(const VecX& x, const VecX& gradient) const override {
    return EquilibriumResidual(model_, natural_ + x.cwiseQuotient(scale_),
                               gradient.cwiseProduct(scale_));
  }

  double MaxStep(const VecX& /*x*/, const VecX& p) const override {
    double max_turn = 0.0;
    const int n = model_.NumSegments();
    for (int i = 0; i < n; ++i) {
      const Vec3 dq = p.segment<3>(3 * i).cwiseQuotient(scale_.segment<3>(3 * i));
      max_turn = std::max(max_turn, dq.norm() * model_.segment_lengths[i]);
    }
    return max_turn > 0.0 ? kMaxTurnPerStep / max_turn : 1e300;
  }

  double HessianStep(int j) const override {
    return kHessianCurvatureStep / model_.Length() * scale_(j);
  }

  const VecX& scale() const { return scale_; }

 private:
  const StrandModel& model_;
  StrandEnergy energy_;
  VecX natural_;
  VecX scale_;
  VecX q_, gq_;
};

// Smallest eigenvalue of the scaled Hessian at x, and, when it is negative, its eigenvector.
// Positive definiteness is certified by a Cholesky factorization of H - tol I (O(N^3/3), ~10x
// cheaper than an eigensolver at N = 300); the reported eigenvalue is then the Rayleigh quotient
// after a few steps of inverse iteration with that factor (an estimate from above, converging to
// lambda_min). Only when Cholesky fails is the full symmetric eigensolver run, to find the mode
// along which to leave the unstable equilibrium.
double MinEigen(ScaledStrandObjective& objective, const VecX& x, VecX* vector, int* evaluations) {
  MatX hessian;
  *evaluations += internal::FiniteDifferenceHessian(objective, x, &hessian);
  const int n = static_cast<int>(hessian.rows());
  const Eigen::LLT<MatX> llt(hessian - kStabilityTolerance * MatX::Identity(n, n));
  if (llt.info() == Eigen::Success) {
    VecX v = VecX::Ones(n) / std::sqrt(static_cast<double>(n));
    for (int k = 0; k < 8; ++k) v = llt.solve(v).normalized();
    if (vector) *vector = v;
    return v.dot(hessian * v);
  }
  Eigen::SelfAdjointEigenSolver<MatX> eig(hessian);
  if (eig.info() != Eigen::Success) return std::nan("");
  if (vector) *vector = eig.eigenvectors().col(0);
  return eig.eigenvalues()(0);
}

}  // namespace

const char* TerminationName(Termination termination) {
  switch (termination) {
    case Termination::kConverged: return "converged";
    case Termination::kMaxIterations: return "max_iterations";
    case Termination::kLineSearchFailed: return "line_search_failed";
    case Termination::kNonFinite: return "non_finite";
  }
  return "unknown";
}

bool SolveOptions::IsValid(std::string* why) const {
  if (max_iterations < 1) {
    if (why) *why = "max_iterations must be >= 1";
    return false;
  }
  if (!(std::isfinite(tolerance) && tolerance > 0.0 && tolerance < 1.0)) {
    if (why) *why = "tolerance must be a finite number in (0, 1)";
    return false;
  }
  if (max_stability_restarts < 0) {
    if (why) *why = "max_stability_restarts must be >= 0";
    return false;
  }
  return true;
}

double MinScaledHessianEigenvalue(const StrandModel& model, const VecX& curvatures,
                                  VecX* direction) {
  ScaledStrandObjective objective(model);
  int evaluations = 0;
  VecX v;
  const double lambda = MinEigen(objective, objective.ToScaled(curvatures), &v, &evaluations);
  if (direction) *direction = v.cwiseQuotient(objective.scale());
  return lambda;
}

StrandSolution SolveStrand(const StrandModel& model, const SolveOptions& options,
                           const VecX* initial_curvatures) {
  ScaledStrandObjective objective(model);
  VecX x = initial_curvatures ? objective.ToScaled(*initial_curvatures)
                              : VecX::Zero(objective.Dimension());
  internal::MinimizerOptions minimizer_options;
  minimizer_options.method = options.method;
  minimizer_options.max_iterations = options.max_iterations;
  minimizer_options.tolerance = options.tolerance;

  SolveSummary summary;
  for (;;) {
    const internal::MinimizerResult r = internal::Minimize(objective, &x, minimizer_options);
    summary.termination = r.termination;
    summary.message = r.message;
    summary.iterations += r.iterations;
    summary.evaluations += r.evaluations;
    if (r.termination != Termination::kConverged || !options.check_stability) break;

    // Stability: the smallest eigenvalue of the scaled Hessian (1 = unloaded elastic rod).
    VecX mode;
    summary.stability_checked = true;
    summary.min_eigenvalue = MinEigen(objective, x, &mode, &summary.evaluations);
    if (!(summary.min_eigenvalue < -kStabilityTolerance)) break;
    if (summary.stability_restarts >= options.max_stability_restarts) {
      summary.message = "converged to an unstable equilibrium (negative Hessian eigenvalue " +
                        std::to_string(summary.min_eigenvalue) + ") and could not leave it";
      break;
    }
    // Leave the unstable equilibrium along the negative-curvature mode (the energy decreases to
    // second order either way; the sign is fixed for determinism) and minimize again.
    ++summary.stability_restarts;
    Eigen::Index largest;
    mode.cwiseAbs().maxCoeff(&largest);
    if (mode(largest) < 0.0) mode = -mode;
    // MaxStep is the multiplier that turns the most turned segment by kMaxTurnPerStep; scale it
    // to turn that segment by kEscapeTurn instead.
    x += (objective.MaxStep(x, mode) * (kEscapeTurn / kMaxTurnPerStep)) * mode;
  }

  StrandSolution solution;
  solution.curvatures = objective.ToCurvatures(x);
  StrandEnergy energy(model);
  VecX gradient;
  energy.Evaluate(solution.curvatures, &gradient, &summary.energy);
  summary.gradient_norm = gradient.norm();
  summary.residual = EquilibriumResidual(model, solution.curvatures, gradient);
  summary.contact = MeasureContact(model, solution.curvatures);
  summary.stable = summary.Converged() && summary.stability_checked &&
                   summary.min_eigenvalue >= -kStabilityTolerance;
  if (summary.Converged() && summary.stability_checked && !summary.stable &&
      summary.message.rfind("converged to an unstable", 0) != 0) {
    summary.message = "converged, but the equilibrium is not stable";
  }
  if (!std::isfinite(summary.energy.total) || !gradient.allFinite()) {
    summary.termination = Termination::kNonFinite;
    summary.stable = false;
  }
  solution.summary = summary;
  return solution;
}

}  // namespace ringlet
