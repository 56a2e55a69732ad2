// Static equilibrium of one strand: minimize E_e + E_g over the 3n curvatures (paper, section 2.3).
#pragma once

#include <string>

#include "ringlet/contact.h"
#include "ringlet/energy.h"
#include "ringlet/kirchhoff.h"
#include "ringlet/math.h"
#include "ringlet/strand_hessian.h"
#include "ringlet/strand_model.h"

namespace ringlet {

/// The minimization algorithm. Both work on curvatures scaled by the elastic stiffness,
/// x_i = sqrt(l_i K) (Omega_i - Omega^0), so that the elastic energy is |x|^2/2 and the
/// conditioning is set by gravity alone.
enum class Method {
  kBfgs,    ///< dense BFGS with a strong-Wolfe line search (modern form of the paper's DFP [FP63])
  kLbfgs,   ///< limited-memory BFGS (10 pairs): O(n) per iteration instead of O(n^2)
  kNewton,  ///< Newton with the exact Hessian (strand_hessian.h, O(n) per step), shifted when needed
  /// L-BFGS for light strands, Newton for heavy ones (GravityParameter >= kAutoNewtonLoad): the
  /// faster of the two on each side of the crossover measured in docs/benchmarks.md.
  kAuto,
};

/// Most segments of a strand solved with Method::kBfgs: its dense 3n x 3n inverse Hessian takes
/// 72 n^2 bytes (72 MB at 1000 segments) per strand being solved, and each iteration costs
/// O(n^2). L-BFGS, Newton and auto are O(n) in memory and per iteration (up to kMaxSegments).
inline constexpr int kMaxBfgsSegments = 1000;
/// Most segments one command solves in all (a scene's strands; a hairstyle's masters, plus its
/// children when they are solved): 10^7, about 0.1 ms each of CPU time at most for the
/// examples (~20 min on one core) and about 1 KB each while solving (docs/robustness.md).
inline constexpr long kMaxTotalSegments = 10000000;

/// Checks that a strand of `segments` segments may be solved with `method` (kMaxBfgsSegments
/// for kBfgs, kMaxSegments otherwise); false with one line naming the limit.
bool CheckMethodSegments(int segments, Method method, std::string* why);

/// Why the minimizer stopped.
enum class Termination {
  kConverged,         ///< the equilibrium residual fell below the tolerance
  kMaxIterations,     ///< the iteration budget ran out first
  kLineSearchFailed,  ///< no step decreased the energy enough (usually rounding at the optimum)
  kNonFinite,         ///< an energy or gradient was NaN or infinite
};

/// "converged", "max_iterations", "line_search_failed" or "non_finite".
const char* TerminationName(Termination termination);

/// The load w L^3 / (E I1) from which Method::kAuto uses Newton: on curly 20-60-cm strands
/// L-BFGS is 1.6x faster at 55, even at 186, and Newton 1.3x faster at 441 and 3.4x at 1488
/// (docs/benchmarks.md, "Heavy strands by method").
inline constexpr double kAutoNewtonLoad = 300.0;

/// The method kAuto resolves to for this model (kLbfgs or kNewton); other methods unchanged.
Method ResolveMethod(Method method, const StrandModel& model);

/// Options of SolveStrand.
struct SolveOptions {
  /// kAuto by default: L-BFGS (same iterations as dense BFGS on light hair, 2-6x faster) below
  /// kAutoNewtonLoad, Newton with the exact Hessian above (docs/benchmarks.md). kBfgs on a
  /// strand of more than kMaxBfgsSegments segments runs L-BFGS instead (the message says so).
  Method method = Method::kAuto;
  /// Iteration budget of one minimization (each stability restart gets its own).
  int max_iterations = 1000;
  /// Convergence tolerance on the dimensionless equilibrium residual (EquilibriumResidual).
  double tolerance = 1e-9;
  /// Check that the equilibrium is stable (positive definite Hessian) and, if it is not, leave it
  /// along the most negative curvature direction and minimize again.
  bool check_stability = true;
  /// How many times an unstable equilibrium may be left and re-minimized.
  int max_stability_restarts = 4;

  /// True when every field is in range; otherwise says which and why.
  bool IsValid(std::string* why) const;
};

/// What a solve did and where it ended. Numerical trouble is reported here, never hidden.
struct SolveSummary {
  Termination termination = Termination::kMaxIterations;
  std::string message;           ///< one human sentence
  int iterations = 0;            ///< minimizer iterations, all restarts included
  int evaluations = 0;           ///< energy+gradient evaluations
  int hessian_evaluations = 0;   ///< exact Hessians (stability check, Newton steps), O(n) each
  EnergyTerms energy;            ///< energy terms at the result (J)
  double gradient_norm = 0.0;    ///< Euclidean norm of dE/dq at the result (J m)
  double residual = 0.0;         ///< dimensionless equilibrium residual (EquilibriumResidual)
  bool stability_checked = false;  ///< whether the Hessian test ran
  bool stable = false;           ///< converged and the scaled Hessian is positive definite
  /// Smallest eigenvalue of the stiffness-scaled exact Hessian (1 = no load). When the Hessian
  /// is positive definite (certified by its O(n) block factorization, strand_hessian.h) this is
  /// an inverse-iteration estimate, slightly above the true value; when it is not, the
  /// eigenvalue of a dense eigensolver (up to 200 segments) or of shifted inverse iteration.
  double min_eigenvalue = 0.0;
  int stability_restarts = 0;    ///< unstable equilibria left along negative curvature
  /// Contact at the result (ContactMeasure; zeros without an obstacle): the largest depth below
  /// the body surface (m) and into the clearance layer (m), and the samples carrying a force.
  ContactMeasure contact;

  bool Converged() const { return termination == Termination::kConverged; }
};

/// Curvatures at equilibrium and the summary of the solve.
struct StrandSolution {
  VecX curvatures;  ///< size 3n, (kappa1, kappa2, tau) per segment (1/m)
  SolveSummary summary;
};

/// Finds a stable equilibrium of the strand by minimizing its potential energy, starting from the
/// natural (gravity-free) shape or from initial_curvatures (a warm start, size 3n) when given.
StrandSolution SolveStrand(const StrandModel& model, const SolveOptions& options = {},
                           const VecX* initial_curvatures = nullptr);

/// Smallest eigenvalue of the Hessian in the stiffness-scaled variables x (dimensionless; 1 with
/// no gravity, negative at an unstable equilibrium), from the exact Hessian (strand_hessian.h;
/// see SolveSummary::min_eigenvalue for its accuracy). If direction is not null it
/// receives the matching eigenvector in curvature space.
double MinScaledHessianEigenvalue(const StrandModel& model, const VecX& curvatures,
                                  VecX* direction = nullptr);
/// The same from the exact Hessian in curvatures already computed at that configuration
/// (ComputeStrandHessian(model, curvatures, &hessian)): the same value (up to the rounding of
/// the curvatures' round trip through the scaled variables) without computing the Hessian again.
double MinScaledHessianEigenvalue(const StrandModel& model, StrandHessian hessian);

}  // namespace ringlet
