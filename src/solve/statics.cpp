// Static equilibrium of a strand by energy minimization (paper section 2.3), with a stability
// certificate and escape from unstable equilibria (../shared/DESIGN.md, "Solving").
#include "ringlet/statics.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "ringlet/strand_hessian.h"
#include "solve/minimizer.h"

namespace ringlet {
namespace {

// An equilibrium is stable when the smallest eigenvalue of the stiffness-scaled Hessian is above
// -kStabilityTolerance: the exact Hessian is accurate to rounding (~1e-13 relative, measured
// against differences of the gradient to ~1e-9 in strand_hessian_test), so this only absorbs
// the rounding of neutral directions.
constexpr double kStabilityTolerance = 1e-7;
// Up to this many unknowns the negative-curvature mode of an unstable equilibrium comes from a
// dense symmetric eigensolver (O(N^2) memory: 2.9 MB at N = 600); beyond, from shifted inverse
// iteration with the O(n) factorization, which needs no dense matrix at all.
constexpr int kMaxDenseEigenUnknowns = 600;
constexpr int kShiftedInverseIterations = 60;
// Inverse-iteration steps for the smallest eigenvalue once positive definiteness is certified:
// few in SolveStrand (the estimate is informative, the certificate is the factorization), more
// in MinScaledHessianEigenvalue (asked for the value itself).
constexpr int kCertificateInverseIterations = 4;
constexpr int kReportedInverseIterations = 16;
// Newton's shift, relative to the elastic part (the identity in scaled variables): the first
// nonzero shift tried when H is not positive definite, then multiplied by 10.
constexpr double kNewtonFirstShift = 1e-4;
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
    const double e = energy_.Evaluate(q_, gradient ? &gq_ : nullptr, &last_terms_);
    if (gradient) {
      *gradient = gq_.cwiseQuotient(scale_);  // dE/dx = dE/dq / scale
      last_q_ = q_;
      last_gq_ = gq_;
    }
    return e;
  }

  // The energy terms and curvature gradient of the last evaluation with a gradient, if it was
  // at exactly these curvatures (the minimizer's last accepted point usually is): the same
  // numbers a new evaluation would give, without its cost.
  bool LastEvaluation(const VecX& q, VecX* gradient, EnergyTerms* terms) const {
    if (last_q_.size() != q.size() || last_q_ != q) return false;
    *gradient = last_gq_;
    *terms = last_terms_;
    return true;
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

  // The exact Hessian in scaled variables, diag(1/scale) H_q diag(1/scale).
  void ScaledHessian(const VecX& x, StrandHessian* hessian) {
    q_ = natural_ + x.cwiseQuotient(scale_);
    ComputeStrandHessian(model_, q_, hessian);
    hessian->Scale(scale_.cwiseInverse());
  }

  bool NewtonDirection(const VecX& x, const VecX& g, VecX* p) override {
    ScaledHessian(x, &hessian_);
    // Levenberg-style shift: the smallest of 0, 1e-4, 1e-3, ... that gives a positive definite
    // H + sigma I (in scaled variables the elastic part alone is I, so a shift of 1 is "treat
    // the loads as half the stiffness").
    for (double sigma = 0.0;; sigma = sigma == 0.0 ? kNewtonFirstShift : 10.0 * sigma) {
      if (factor_.Factor(hessian_, -sigma)) break;
      if (!(sigma < 1e12)) return false;
    }
    factor_.Solve(-g, p);
    return p->allFinite();
  }

  const VecX& scale() const { return scale_; }
  // Reused by MinEigen too (no allocation per Hessian).
  StrandHessian& hessian_scratch() { return hessian_; }
  StrandHessianFactor& factor_scratch() { return factor_; }

 private:
  const StrandModel& model_;
  StrandEnergy energy_;
  VecX natural_;
  VecX scale_;
  VecX q_, gq_;
  VecX last_q_, last_gq_;
  EnergyTerms last_terms_;
  StrandHessian hessian_;
  StrandHessianFactor factor_;
};

// Smallest eigenvalue of the scaled Hessian at x, and, when it is negative, its eigenvector, from
// the exact Hessian (strand_hessian.h). Positive definiteness of H - tol I is certified by the O(n)
// block factorization; the reported eigenvalue is then the Rayleigh quotient after a few steps
// of inverse iteration with that factor (an estimate from above, converging to lambda_min), each
// O(n). Only when the factorization fails is the mode along which to leave the unstable
// equilibrium computed: by a dense eigensolver for small strands, by shifted inverse iteration
// (a shift below lambda_min found by doubling, then the O(n) solve) for long ones.
// The same from the scaled Hessian itself (factor: scratch).
double MinEigenOf(const StrandHessian& hessian, StrandHessianFactor& factor, int inverse_iterations,
                  VecX* vector) {
  const int n = 3 * hessian.NumSegments();
  VecX v = VecX::Ones(n) / std::sqrt(static_cast<double>(n)), w;
  if (factor.Factor(hessian, kStabilityTolerance)) {
    for (int k = 0; k < inverse_iterations; ++k) {
      factor.Solve(v, &w);
      v = w.normalized();
    }
    if (vector) *vector = v;
    hessian.Multiply(v, &w);
    return v.dot(w);
  }
  if (n <= kMaxDenseEigenUnknowns) {
    Eigen::SelfAdjointEigenSolver<MatX> eig(hessian.Dense());
    if (eig.info() != Eigen::Success) return std::nan("");
    if (vector) *vector = eig.eigenvectors().col(0);
    return eig.eigenvalues()(0);
  }
  double shift = -1.0;
  while (!factor.Factor(hessian, shift)) {
    shift *= 2.0;
    if (!(shift > -1e300)) return std::nan("");
  }
  for (int k = 0; k < kShiftedInverseIterations; ++k) {
    factor.Solve(v, &w);
    v = w.normalized();
  }
  if (vector) *vector = v;
  hessian.Multiply(v, &w);
  return v.dot(w);
}

double MinEigen(ScaledStrandObjective& objective, const VecX& x, int inverse_iterations,
                VecX* vector, int* hessian_evaluations) {
  StrandHessian& hessian = objective.hessian_scratch();
  objective.ScaledHessian(x, &hessian);
  ++*hessian_evaluations;
  return MinEigenOf(hessian, objective.factor_scratch(), inverse_iterations, vector);
}

}  // namespace

Method ResolveMethod(Method method, const StrandModel& model) {
  if (method != Method::kAuto) return method;
  return model.GravityParameter() >= kAutoNewtonLoad ? Method::kNewton : Method::kLbfgs;
}

const char* TerminationName(Termination termination) {
  switch (termination) {
    case Termination::kConverged: return "converged";
    case Termination::kMaxIterations: return "max_iterations";
    case Termination::kLineSearchFailed: return "line_search_failed";
    case Termination::kNonFinite: return "non_finite";
  }
  return "unknown";
}

bool CheckMethodSegments(int segments, Method method, std::string* why) {
  const int limit = method == Method::kBfgs ? kMaxBfgsSegments : kMaxSegments;
  if (segments <= limit) return true;
  if (why) {
    *why = std::to_string(segments) + " segments exceed the limit of " + std::to_string(limit) +
           (method == Method::kBfgs
                ? " for the method \"bfgs\" (its dense inverse Hessian takes 72 n^2 bytes); use "
                  "\"lbfgs\", \"newton\" or \"auto\""
                : "");
  }
  return false;
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
  int hessians = 0;
  VecX v;
  const double lambda = MinEigen(objective, objective.ToScaled(curvatures), kReportedInverseIterations, &v, &hessians);
  if (direction) *direction = v.cwiseQuotient(objective.scale());
  return lambda;
}

double MinScaledHessianEigenvalue(const StrandModel& model, StrandHessian hessian) {
  const int n = model.NumSegments();
  assert(hessian.NumSegments() == n);
  VecX inverse_scale(3 * n);
  const Vec3 k = model.Stiffness();
  for (int i = 0; i < n; ++i) {
    inverse_scale.segment<3>(3 * i) = (model.segment_lengths[i] * k).cwiseSqrt().cwiseInverse();
  }
  hessian.Scale(inverse_scale);
  StrandHessianFactor factor;
  return MinEigenOf(hessian, factor, kReportedInverseIterations, nullptr);
}

StrandSolution SolveStrand(const StrandModel& model, const SolveOptions& options,
                           const VecX* initial_curvatures) {
  ScaledStrandObjective objective(model);
  VecX x = initial_curvatures ? objective.ToScaled(*initial_curvatures)
                              : VecX::Zero(objective.Dimension());
  internal::MinimizerOptions minimizer_options;
  minimizer_options.method = ResolveMethod(options.method, model);
  // Dense BFGS keeps a 3n x 3n inverse Hessian (72 n^2 bytes): the readers refuse it above
  // kMaxBfgsSegments (CheckMethodSegments); a caller of the library that asks for it anyway gets
  // L-BFGS, and the summary's message says so, rather than an allocation of gigabytes.
  const bool bfgs_refused =
      minimizer_options.method == Method::kBfgs && model.NumSegments() > kMaxBfgsSegments;
  if (bfgs_refused) minimizer_options.method = Method::kLbfgs;
  minimizer_options.max_iterations = options.max_iterations;
  minimizer_options.tolerance = options.tolerance;

  SolveSummary summary;
  for (;;) {
    const internal::MinimizerResult r = internal::Minimize(objective, &x, minimizer_options);
    summary.termination = r.termination;
    summary.message = r.message;
    summary.iterations += r.iterations;
    summary.evaluations += r.evaluations;
    summary.hessian_evaluations += r.hessian_evaluations;
    if (r.termination != Termination::kConverged || !options.check_stability) break;

    // Stability: the smallest eigenvalue of the scaled Hessian (1 = unloaded elastic rod).
    VecX mode;
    summary.stability_checked = true;
    summary.min_eigenvalue = MinEigen(objective, x, kCertificateInverseIterations, &mode,
                                      &summary.hessian_evaluations);
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
  VecX gradient;
  if (!objective.LastEvaluation(solution.curvatures, &gradient, &summary.energy)) {
    StrandEnergy energy(model);
    energy.Evaluate(solution.curvatures, &gradient, &summary.energy);
  }
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
  if (bfgs_refused) {
    summary.message += " (method \"bfgs\" refused above " + std::to_string(kMaxBfgsSegments) +
                       " segments, its dense inverse Hessian takes 72 n^2 bytes: solved with "
                       "\"lbfgs\")";
  }
  solution.summary = summary;
  return solution;
}

}  // namespace ringlet
