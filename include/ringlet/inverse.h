// Inverse statics (issue 13, docs/inverse.md): the rest shape that makes a target configuration
// an equilibrium under gravity and contact, its stability certificate, the forward verification,
// and the fit of target polylines by G1 piecewise helices.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "ringlet/math.h"
#include "ringlet/solve_strands.h"  // ProgressCallback
#include "ringlet/statics.h"
#include "ringlet/strand_model.h"

namespace ringlet {

/// The rest curvatures that make `target` (3n curvatures, 1/m) an equilibrium of `model` (its
/// gravity and contact; its own rest shape is ignored). The energy is
///   E(q) = sum_i 1/2 l_i (q_i - q0_i)^T K (q_i - q0_i) + E_ext(q),   E_ext = E_g + E_c
/// (paper eqs. 2-4 and section 3.1, with a rest shape q0_i per segment), so
///   dE/dq_i = l_i K (q_i - q0_i) + dE_ext/dq_i,
/// and the equilibrium dE/dq = 0 at q gives, segment by segment (K diagonal, l_i > 0),
///   q0_i = q_i + (l_i K)^(-1) dE_ext/dq_i(q)
/// (Derouet-Jourdan et al. 2010, section 4, for super-helices; Hsu et al. 2023 for discrete
/// rods). dE_ext/dq is the exact O(n) gradient of energy.h. Returns the 3n-vector q0 (1/m).
VecX InverseRestCurvatures(const StrandModel& model, const VecX& target);

/// dE/dq (3n, J m) of the potential E(q) = -F . x(q) of a constant force F (N, world) applied at
/// arc length u (m, 0 < u <= l_segment) inside segment `segment` of configuration q: minus the
/// generalized force J^T F of the sample, J = dx/dq. One reverse sweep over segments 0..segment
/// (the same closed-form derivatives as ContactEnergy's gradient, energy.h: HelixChordVjp for the
/// partial chord, HelixSegmentVjp for the upstream segments); entries after `segment` are 0.
VecX PointForceGradient(const StrandModel& model, const VecX& curvatures, int segment, double u,
                        const Vec3& force);

/// A point force on the strand: unit-free direction and place (PointForceGradients).
struct PointForce {
  int segment = 0;             ///< segment index
  double u = 0.0;              ///< arc length inside the segment (m, 0 < u <= l_segment)
  Vec3 force = Vec3::Zero();   ///< F (N, world)
};

/// The columns PointForceGradient(model, curvatures, f.segment, f.u, f.force) of every force as
/// a 3n x p matrix, in one forward and one reverse sweep: each segment's closed forms are
/// evaluated once and shared by every force downstream of it (O(n + p n) operations instead of
/// the p separate sweeps' O(p n) helix evaluations); each column is bit for bit the one of that
/// force alone. Forces must be sorted by segment.
MatX PointForceGradients(const StrandModel& model, const VecX& curvatures,
                         const std::vector<PointForce>& forces);

/// Non-negative least squares: x >= 0 minimizing |A x - b|^2, by the active-set method of
/// Lawson and Hanson ("Solving Least Squares Problems", 1974, ch. 23, algorithm NNLS), the
/// columns scaled to unit norm, the passive subproblems solved by column-pivoted QR. Columns that
/// are zero get x_j = 0. Returns the number of outer iterations (each adds one variable to the
/// passive set), or -1 when it did not terminate within 3 (columns + 1) of them (x is then the
/// last feasible iterate). On return x satisfies x >= 0 and, at termination, the KKT conditions
/// A^T (b - A x) <= tol and x_j (A^T (b - A x))_j = 0 to rounding.
int NonNegativeLeastSquares(const MatX& a, const VecX& b, VecX* x);

/// The same algorithm on the normal equations: the Gram matrix A^T A is formed once (cols^2 rows
/// operations) and every passive subproblem is an LDL^T of a principal submatrix of it, instead
/// of a QR of the passive columns. It squares the condition number, so it is for problems whose
/// columns are well conditioned or regularized: the inversion's support forces, whose ridge rows
/// bound it (ChooseSupportForces: the inversion fell from 0.26 to 0.19 ms per strand with it).
int NonNegativeLeastSquaresNormal(const MatX& a, const VecX& b, VecX* x);

/// A contact sample of the target that lies on the clearance surface of the body (within
/// InverseOptions::support_tolerance) and may carry a normal support force (N >= 0), an unknown
/// of the inversion (Derouet-Jourdan et al. 2013; docs/inverse.md).
struct SupportSample {
  int segment = 0;            ///< segment index i
  int index = 0;              ///< sample j in the segment, at arc length u = (j + 1) l_i / m
  double u = 0.0;             ///< arc length inside the segment (m)
  Vec3 position = Vec3::Zero();  ///< sample position on the target (m, world)
  Vec3 normal = Vec3::Zero();    ///< outward unit normal of the body there
  double distance = 0.0;      ///< signed distance to the body minus the clearance (m)
  double force = 0.0;         ///< normal force on the strand, f n with f >= 0 (N)
};

/// Options of InvertStrand.
struct InverseOptions {
  /// Run the forward solve from the inverted rest shape, started at the target, and measure
  /// how far the equilibrium it reaches lies from the target (the built-in verification).
  bool verify = true;
  /// Also run the forward solve with the naive rest shape q0 = target (what an artist's groom
  /// does when physics starts) and measure its sag.
  bool naive = true;
  /// Contact forces as unknowns (docs/inverse.md): the contact samples of the target that lie
  /// within support_tolerance of the clearance surface carry non-negative normal forces chosen
  /// by non-negative least squares so that the rest shape stays closest to the hair type's
  /// natural curvature, and the forward model reproduces them through
  /// ContactModel::support_offsets. Off: the penalty forces of the model at the target are used
  /// (zero unless the target penetrates the clearance layer).
  bool contact_forces = true;
  /// A contact sample is a support when |d - clearance| <= support_tolerance L, d its signed
  /// distance to the body (dimensionless, units of the strand length L; >= 0). Samples deeper
  /// inside keep the penalty force of the model.
  double support_tolerance = 1e-3;
  /// Centreline samples per segment for the deviations (>= 1).
  int points_per_segment = 4;
  /// The forward solves. Stability checking stays on: it is what moves an unstable target to
  /// the closest stable alternative (InverseResult::equilibrium). Newton with the exact Hessian
  /// (O(n) per step) rather than kAuto's L-BFGS: strands lying on a body are stiff in the
  /// contact penalty, where L-BFGS needs ~170 iterations of ~7.5 line-search evaluations for
  /// the naive solve and Newton ~9 (measured on 1,000 wavy strands on the head mesh: 0.59 against
  /// 13.6 ms of CPU per strand for inversion, verification and naive solve; docs/benchmarks.md).
  SolveOptions solver = [] {
    SolveOptions o;
    o.method = Method::kNewton;
    o.tolerance = 1e-10;
    return o;
  }();

  /// Checks the fields; says which and what was expected.
  bool IsValid(std::string* why) const;
};

/// What InvertStrand found for one strand.
struct InverseResult {
  /// The rest shape q0 (3n, 1/m): InverseRestCurvatures of the model with support_offsets.
  VecX rest_curvatures;
  /// The contact model's support offsets that go with the rest shape (ContactModel::
  /// support_offsets, m): empty when no sample is a support (or contact_forces is off).
  /// The rest shape holds the target only with these offsets in the model.
  std::vector<double> support_offsets;
  /// The support samples (all candidates, with their forces, some 0) and the count of those
  /// carrying a force > 0, with the sum of their normal forces (N).
  std::vector<SupportSample> supports;
  int supported_samples = 0;
  double support_force = 0.0;
  /// True when the target was not certified stable with the chosen support forces but was with
  /// the model's own penalty forces (contact_forces off), whose rest shape is then reported
  /// instead (no support offsets, forces 0): a support at f = 0 has no penalty stiffness, and
  /// a force f on a convex part of the body of radius R has the tangential stiffness -f/R.
  bool support_fallback = false;
  /// Lawson-Hanson iterations (-1: it did not terminate; reported in message).
  int nnls_iterations = 0;
  /// The elastic energy that bends the natural shape into the rest shape,
  /// 1/2 sum_i l_i (q0_i - q0nat)^T K (q0_i - q0nat) (J), q0nat = model.natural_curvature: what
  /// the support forces minimize; and the same without supports (their forces 0).
  double rest_energy = 0.0;
  double rest_energy_unsupported = 0.0;
  /// Stability certificate of the target with that rest shape: the exact Hessian at the target
  /// (strand_hessian.h; it does not depend on q0, whose only trace in E is the constant elastic
  /// Hessian l_i K) is positive definite, certified by its O(n) block LDL^T factorization. A
  /// target that is not a strict local minimum cannot be held stably by ANY rest shape.
  bool stable = false;
  /// The segment whose pivot failed in the factorization (-1 when stable).
  int failed_segment = -1;
  /// Smallest eigenvalue of the stiffness-scaled Hessian at the target (1 = no load, < 0
  /// unstable; see SolveSummary::min_eigenvalue for its accuracy).
  double min_eigenvalue = 0.0;
  /// Kirchhoff's balance at the target with the inverted rest shape (KirchhoffResidual, by
  /// quadrature, independent of the gradient code that gave q0): ~1e-15 when q0 is right.
  /// Part of the verification: NaN when InverseOptions::verify is off.
  double kirchhoff_residual = std::numeric_limits<double>::quiet_NaN();
  /// The forward solve from q0 started at the target (when verify): its equilibrium and summary.
  /// For a stable target it stays there; for an unstable one, the solver leaves the target along
  /// the most negative curvature direction and settles in the nearest stable equilibrium of the
  /// same rest shape: that is the closest stable alternative reported (docs/inverse.md).
  VecX equilibrium;
  SolveSummary forward;
  /// Largest distance between the centrelines of the target and of `equilibrium` (m), at
  /// points_per_segment samples per segment; 0 when not verified.
  double deviation = 0.0;
  /// The naive rest shape (q0 = target) after the forward solve from the target (when naive):
  /// its equilibrium, summary and largest distance from the target (m).
  VecX naive_equilibrium;
  SolveSummary naive_forward;
  double naive_deviation = 0.0;
  /// One human line.
  std::string message;
};

/// Inverts one strand: rest shape, certificate, verification and naive comparison. model gives
/// the segments, section, material, root, gravity and contact (its rest shape is ignored);
/// target has size 3n.
InverseResult InvertStrand(const StrandModel& model, const VecX& target,
                           const InverseOptions& options = {});

/// InvertStrand on every (models[i], targets[i]) pair, in parallel across strands (TBB) on
/// `threads` worker threads (0: all). The results do not depend on the thread count.
std::vector<InverseResult> InvertStrands(const std::vector<StrandModel>& models,
                                         const std::vector<VecX>& targets,
                                         const InverseOptions& options = {}, int threads = 0,
                                         const ProgressCallback& progress = {});

/// Largest distance (m) between the centrelines of two configurations of the same model, at the
/// root, the segment ends and points_per_segment - 1 points inside each segment.
double CentrelineDeviation(const StrandModel& model, const VecX& a, const VecX& b,
                           int points_per_segment);

// ---------------------------------------------------------------------------------------------
// Fit of a target polyline by a G1 piecewise helix.

/// The root frame when the target has none: the tangent t (normalized), and n1 the unit
/// projection of `axis` on the plane normal to t; when axis is within ~25 degrees of t
/// (|axis . t| > 0.9 |axis|), of the world axis among x, y, z least aligned with t instead.
/// n2 = t x n1. For a groom, pass the scalp normal or the head's up axis (the comb frame of
/// scalp.h has n2 away from the scalp); the fit itself does not depend on n1 (turning n1 about t
/// turns (kappa1, kappa2) with it), only the soft bending axis of an elliptic section does.
Mat3 DefaultRootFrame(const Vec3& tangent, const Vec3& axis);

/// Options of FitPiecewiseHelix.
struct FitOptions {
  /// Segment count n (1 to the number of polyline edges); 0 chooses it: the smallest n of the
  /// sequence 1, 2, 4, ... (capped at the edge count) whose fit has a largest distance of at
  /// most tolerance, searched from the count that the 1-segment fit's distance predicts
  /// (docs/inverse.md, "Fit of polylines").
  int segments = 0;
  /// Largest allowed distance from a target point to the fitted curve, in units of the
  /// polyline's length (dimensionless, > 0), when segments = 0.
  double tolerance = 1e-3;
  /// Levenberg-Marquardt iterations per segment of the greedy initialization (>= 1).
  int max_iterations = 100;
  /// Levenberg-Marquardt iterations of the global refinement of all segments (and of the root
  /// tangent when no root frame is given) after the greedy initialization (>= 0; 0: greedy only).
  int refine_iterations = 100;
  /// The axis of DefaultRootFrame's n1 rule when no root frame is given (world, non-zero).
  Vec3 n1_axis = Vec3::UnitZ();

  bool IsValid(std::string* why) const;
};

/// A fitted strand: a clamped piecewise helix (root position and frame, segment lengths,
/// curvatures), and its distance to the target points.
struct HelixFit {
  Vec3 root_position = Vec3::Zero();   ///< the first target point (m)
  Mat3 root_frame = Mat3::Identity();  ///< (n1, n2, t) at the root, world_from_material
  std::vector<double> segment_lengths; ///< (m)
  VecX curvatures;                     ///< 3n (1/m)
  /// For each target point, the arc length of its matching curve point (m), 0 for the root.
  std::vector<double> arc_lengths;
  double max_distance = 0.0;  ///< largest |r(s_j) - P_j| over the target points (m)
  double rms_distance = 0.0;  ///< root mean square of the same (m)
  double length = 0.0;        ///< fitted length L, the sum of the segment lengths (m)
  int iterations = 0;         ///< Levenberg-Marquardt iterations, all segments

  int NumSegments() const { return static_cast<int>(segment_lengths.size()); }
};

/// Fits a G1 piecewise helix to the polyline `points` (m, root first, >= 2 points, consecutive
/// points distinct). The root is clamped at points[0]. With root_frame (ringlet's own files) the
/// root frame is that one, fixed; without, the root tangent starts as the tangent at points[0] of
/// the circle through the first three points and is refined with the curve (its tilt is an
/// unknown of the global refinement), and n1 follows DefaultRootFrame's rule for the final
/// tangent.
///
/// Method: segment boundaries lie at target points (segment i spans edges [b_i, b_(i+1)) with
/// b_i = floor(i m / n), m edges). Unknowns: every segment's curvatures Omega_i (3) and length
/// l_i, the arc length sigma_j l_i of every inner target point of its segment, and the root
/// tangent's tilt (2) when free; residuals: r(s_j) - P_j for every target point (a segment's end
/// at u = l_i). (1) Greedy initialization root to tip: each segment fitted alone from the end
/// frame of the previous one by Levenberg-Marquardt with the exact Jacobian of the closed-form
/// helix (chord derivative HelixChordVjp, tangent R(u) e3), from the circular arc that leaves
/// with the start tangent and reaches the end point. (2) Global refinement: Levenberg-Marquardt
/// on all unknowns at once, each damped Gauss-Newton step solved exactly in O(n) as a
/// linear-quadratic regulator along the chain (backward Riccati sweep of 6x6 matrices; the
/// inner points' arc lengths eliminated in closed form). The curve is G1 by construction. A
/// target that is itself a G1 piecewise helix with breaks at its points is recovered to
/// rounding, with or without its root frame. Returns false with a one-line reason for bad input.
bool FitPiecewiseHelix(const std::vector<Vec3>& points, const Mat3* root_frame,
                       const FitOptions& options, HelixFit* fit, std::string* why);

/// FitPiecewiseHelix on every polyline (no root frames), in parallel across strands (TBB) on
/// `threads` worker threads (0: all); the fits do not depend on the thread count. fits gets one
/// HelixFit per polyline. Returns false for bad input: *failed (if given) is the index of the
/// first polyline that failed and *why its reason (FitPiecewiseHelix's "point I: ...").
bool FitPiecewiseHelices(const std::vector<std::vector<Vec3>>& polylines,
                         const FitOptions& options, int threads, std::vector<HelixFit>* fits,
                         int* failed, std::string* why, const ProgressCallback& progress = {});

}  // namespace ringlet
