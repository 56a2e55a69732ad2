// Inverse statics: rest shapes from target configurations, certificate, verification
// (inverse.h, docs/inverse.md).
#include "ringlet/inverse.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <mutex>
#include <sstream>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <Eigen/QR>

#include "ringlet/energy.h"
#include "ringlet/helix.h"
#include "ringlet/kirchhoff.h"
#include "ringlet/strand_geometry.h"
#include "ringlet/strand_hessian.h"

namespace ringlet {
namespace {

std::string Number(double x) {
  std::ostringstream s;
  s.precision(3);
  s << x;
  return s.str();
}

}  // namespace

bool InverseOptions::IsValid(std::string* why) const {
  if (points_per_segment < 1 || points_per_segment > 1024) {
    if (why) *why = "points_per_segment: expected 1 to 1024";
    return false;
  }
  if (!(std::isfinite(support_tolerance) && support_tolerance >= 0.0)) {
    if (why) *why = "support_tolerance: expected a finite number >= 0 (units of L)";
    return false;
  }
  std::string reason;
  if (!solver.IsValid(&reason)) {
    if (why) *why = "solver: " + reason;
    return false;
  }
  return true;
}

VecX InverseRestCurvatures(const StrandModel& model, const VecX& target) {
  const int n = model.NumSegments();
  assert(target.size() == 3 * n);
  // dE_ext/dq at the target: gravity and contact in one sweep (StrandEnergy's), the elastic
  // gradient subtracted. Evaluating with the rest shape q0 = target makes the elastic gradient
  // exactly zero, so the total gradient is the external one.
  StrandModel at_target = model;
  at_target.rest_curvatures = target;
  VecX gradient;
  StrandEnergy(at_target).Evaluate(target, &gradient);
  // q0_i = q_i + (l_i K)^(-1) dE_ext/dq_i (inverse.h): the stationarity l_i K (q_i - q0_i) +
  // dE_ext/dq_i = 0 solved for q0_i, K = diag(E I1, E I2, mu J).
  const Vec3 k = model.Stiffness();
  VecX rest(3 * n);
  for (int i = 0; i < n; ++i) {
    rest.segment<3>(3 * i) = target.segment<3>(3 * i) +
                             gradient.segment<3>(3 * i).cwiseQuotient(model.segment_lengths[i] * k);
  }
  return rest;
}

VecX PointForceGradient(const StrandModel& model, const VecX& curvatures, int segment, double u,
                        const Vec3& force) {
  assert(curvatures.size() == 3 * model.NumSegments() && segment >= 0 &&
         segment < model.NumSegments());
  return PointForceGradients(model, curvatures, {PointForce{segment, u, force}}).col(0);
}

MatX PointForceGradients(const StrandModel& model, const VecX& curvatures,
                         const std::vector<PointForce>& forces) {
  const int n = model.NumSegments();
  const Eigen::Index p = static_cast<Eigen::Index>(forces.size());
  assert(curvatures.size() == 3 * n);
  MatX gradient = MatX::Zero(3 * n, p);
  if (p == 0) return gradient;
  const StrandGeometry g = ComputeGeometry(model, curvatures);
  // x = r_i + Q_i h(u): dE/dx = -F. Each force's own segment through its partial chord, then
  // the reverse sweep of energy.cpp with r_bar = dE/dr_(k+1) = -F and q_bar = dE/dQ_(k+1):
  // forces [begin, p) lie past segment k (the segment's closed forms are shared by all).
  std::vector<Mat3> q_bar(static_cast<size_t>(p));
  Eigen::Index begin = p;
  for (int k = n - 1; k >= 0; --k) {
    const Vec3 omega_k = curvatures.segment<3>(3 * k);
    const Mat3& q_k = g.frames[static_cast<size_t>(k)];
    if (begin < p) {
      const double l = model.segment_lengths[static_cast<size_t>(k)];
      const HelixSegment s = EvaluateHelixSegment(omega_k, l);
      for (Eigen::Index c = begin; c < p; ++c) {
        const Vec3 r_bar = -forces[static_cast<size_t>(c)].force;
        Mat3& qb = q_bar[static_cast<size_t>(c)];
        gradient.block<3, 1>(3 * k, c) = HelixSegmentVjp(
            omega_k, l, s.functions, q_k.transpose() * qb, q_k.transpose() * r_bar, Vec3::Zero());
        qb = qb * s.rotation.transpose() + r_bar * s.chord.transpose();
      }
    }
    // The forces inside segment k: their own partial chords.
    while (begin > 0 && forces[static_cast<size_t>(begin - 1)].segment == k) {
      --begin;
      const PointForce& f = forces[static_cast<size_t>(begin)];
      const Vec3 de_dx = -f.force;
      const HelixFunctions functions = EvaluateHelixFunctions(omega_k.norm() * f.u);
      const Vec3 h = HelixChordFromFunctions(omega_k, f.u, functions);
      gradient.block<3, 1>(3 * k, begin) =
          HelixChordVjp(omega_k, f.u, functions, q_k.transpose() * de_dx);
      q_bar[static_cast<size_t>(begin)] = de_dx * h.transpose();
    }
  }
  assert(begin == 0);  // sorted by segment, every segment in [0, n)
  return gradient;
}

namespace {

// Lawson & Hanson's active-set loop on variables y of unit-norm columns (zero columns, scale 0,
// stay out). dual(y) gives w = A^T (b - A y); solve(set) the unconstrained least squares on the
// passive columns `set` (ascending). Returns the outer iterations, -1 past max_outer.
template <class Dual, class Solve>
int LawsonHanson(const VecX& scale, double tolerance, const Dual& dual, const Solve& solve,
                 VecX* y_out) {
  const Eigen::Index cols = scale.size();
  std::vector<bool> passive(static_cast<size_t>(cols), false);
  VecX y = VecX::Zero(cols);
  const int max_outer = 3 * static_cast<int>(cols + 1);
  int outer = 0;
  std::vector<Eigen::Index> set;
  while (true) {
    // Dual vector; stop when no variable out of the passive set can decrease the residual.
    const VecX w = dual(y);
    Eigen::Index t = -1;
    double best = tolerance;
    for (Eigen::Index j = 0; j < cols; ++j) {
      if (!passive[static_cast<size_t>(j)] && scale(j) > 0.0 && w(j) > best) {
        best = w(j);
        t = j;
      }
    }
    if (t < 0) break;
    if (++outer > max_outer) {
      outer = -1;
      break;
    }
    passive[static_cast<size_t>(t)] = true;
    // Inner loop: the unconstrained least squares on the passive set, stepping back to the
    // feasible segment (and dropping the variables that reach 0) while it has components <= 0.
    while (true) {
      set.clear();
      for (Eigen::Index j = 0; j < cols; ++j) {
        if (passive[static_cast<size_t>(j)]) set.push_back(j);
      }
      const VecX zp = solve(set);
      VecX z = VecX::Zero(cols);
      bool feasible = true;
      for (size_t k = 0; k < set.size(); ++k) {
        z(set[k]) = zp(static_cast<Eigen::Index>(k));
        if (!(z(set[k]) > 0.0)) feasible = false;
      }
      if (feasible) {
        y = z;
        break;
      }
      // The largest step from y towards z that keeps every passive variable >= 0; the one
      // that limits it (and any other that reaches 0) leaves the passive set.
      double alpha = 1.0;
      Eigen::Index limiting = -1;
      for (Eigen::Index j : set) {
        if (z(j) > 0.0) continue;
        const double denominator = y(j) - z(j);  // y_j >= 0 >= z_j: the step is in [0, 1]
        const double step = denominator > 0.0 ? y(j) / denominator : 0.0;
        if (limiting < 0 || step < alpha) {
          alpha = step;
          limiting = j;
        }
      }
      y += alpha * (z - y);
      for (Eigen::Index j : set) {
        if (j == limiting || y(j) <= 0.0) {
          y(j) = 0.0;
          passive[static_cast<size_t>(j)] = false;
        }
      }
      if (std::none_of(passive.begin(), passive.end(), [](bool p) { return p; })) break;
    }
  }
  *y_out = y;
  return outer;
}

// Lawson & Hanson's tolerance on the dual vector (as scipy's nnls).
double DualTolerance(Eigen::Index rows, Eigen::Index cols, double b_norm) {
  return 10.0 * std::numeric_limits<double>::epsilon() *
         static_cast<double>(std::max(rows, cols)) * std::max(1.0, b_norm);
}

}  // namespace

int NonNegativeLeastSquares(const MatX& a, const VecX& b, VecX* x) {
  const Eigen::Index rows = a.rows(), cols = a.cols();
  assert(b.size() == rows);
  x->setZero(cols);
  if (cols == 0) return 0;
  // Unit columns (zero columns stay out): the tolerance is then relative.
  VecX scale(cols);
  MatX as = a;
  for (Eigen::Index j = 0; j < cols; ++j) {
    const double norm = a.col(j).norm();
    scale(j) = norm > 0.0 ? 1.0 / norm : 0.0;
    as.col(j) *= scale(j);
  }
  VecX y;
  const int outer = LawsonHanson(
      scale, DualTolerance(rows, cols, b.norm()),
      [&](const VecX& v) -> VecX { return as.transpose() * (b - as * v); },
      [&](const std::vector<Eigen::Index>& set) -> VecX {
        MatX ap(rows, static_cast<Eigen::Index>(set.size()));
        for (size_t k = 0; k < set.size(); ++k) {
          ap.col(static_cast<Eigen::Index>(k)) = as.col(set[k]);
        }
        return ap.colPivHouseholderQr().solve(b);
      },
      &y);
  *x = y.cwiseProduct(scale);
  return outer;
}

int NonNegativeLeastSquaresNormal(const MatX& a, const VecX& b, VecX* x) {
  const Eigen::Index rows = a.rows(), cols = a.cols();
  assert(b.size() == rows);
  x->setZero(cols);
  if (cols == 0) return 0;
  MatX gram = MatX::Zero(cols, cols);
  gram.selfadjointView<Eigen::Lower>().rankUpdate(a.transpose());
  gram.triangularView<Eigen::StrictlyUpper>() = gram.transpose();
  VecX scale(cols);
  for (Eigen::Index j = 0; j < cols; ++j) {
    scale(j) = gram(j, j) > 0.0 ? 1.0 / std::sqrt(gram(j, j)) : 0.0;
  }
  gram = scale.asDiagonal() * gram * scale.asDiagonal();
  const VecX atb = scale.cwiseProduct(a.transpose() * b);
  VecX y;
  const int outer = LawsonHanson(
      scale, DualTolerance(rows, cols, b.norm()),
      [&](const VecX& v) -> VecX { return atb - gram * v; },
      [&](const std::vector<Eigen::Index>& set) -> VecX {
        const Eigen::Index k = static_cast<Eigen::Index>(set.size());
        MatX gp(k, k);
        VecX cp(k);
        for (Eigen::Index i = 0; i < k; ++i) {
          cp(i) = atb(set[static_cast<size_t>(i)]);
          for (Eigen::Index j = 0; j < k; ++j) {
            gp(i, j) = gram(set[static_cast<size_t>(i)], set[static_cast<size_t>(j)]);
          }
        }
        return gp.ldlt().solve(cp);
      },
      &y);
  *x = y.cwiseProduct(scale);
  return outer;
}

double CentrelineDeviation(const StrandModel& model, const VecX& a, const VecX& b,
                           int points_per_segment) {
  const std::vector<Vec3> pa = SampleCentreline(model, a, points_per_segment);
  const std::vector<Vec3> pb = SampleCentreline(model, b, points_per_segment);
  double deviation = 0.0;
  for (size_t j = 0; j < pa.size(); ++j) {
    const double d = (pa[j] - pb[j]).norm();
    deviation = std::isnan(d) ? d : std::max(deviation, d);
    if (std::isnan(deviation)) break;
  }
  return deviation;
}

namespace {

// The relative weight of the support forces' ridge (ChooseSupportForces).
constexpr double kSupportRidge = 1e-5;
// How far a support left without force is moved off its surface, relative to the strand's
// length: far above the rounding of a distance (~1e-16 m), far below anything visible.
constexpr double kZeroForceGap = 1e-9;

// 1/2 sum_i l_i (q0_i - q0nat)^T K (q0_i - q0nat) (J): the elastic energy of bending the natural
// shape into the rest shape q0.
double RestEnergy(const StrandModel& model, const VecX& rest) {
  const Vec3 k = model.Stiffness();
  double energy = 0.0;
  for (int i = 0; i < model.NumSegments(); ++i) {
    const Vec3 d = rest.segment<3>(3 * i) - model.natural_curvature;
    energy += 0.5 * model.segment_lengths[static_cast<size_t>(i)] * d.dot(k.cwiseProduct(d));
  }
  return energy;
}

// Contact forces as unknowns (docs/inverse.md, after Derouet-Jourdan et al., "Inverse dynamic
// hair modeling with frictional contact", SIGGRAPH Asia 2013, without friction): the samples of
// the target within the support tolerance of the clearance surface carry normal forces f_j n_j,
// f_j >= 0. With them the closed form of InverseRestCurvatures becomes
//   q0(f) = q + (l K)^(-1) (dE_ext/dq(q) + sum_j f_j a_j),  a_j = -J_j^T n_j
// (PointForceGradient), affine in f. The forces minimize |W (q0(f) - q0nat)|^2 with W^2 =
// diag(l_i K), i.e. twice the elastic energy that bends the natural shape (the hair type's
// curvature) into the rest shape: the rest shape stays closest to the natural one in the
// energy norm (for a straight natural shape this is Menabrea's theorem: the redundant reactions
// minimize the complementary energy int M^2 / (2 E I) ds). The forward penalty reproduces f_j
// through the sample's clearance shift: x_j = f_j / (k l_i / m).
// Fills result->supports, support_offsets and the counts; returns the contact model to use.
ContactModel ChooseSupportForces(const StrandModel& model, const VecX& target,
                                 const InverseOptions& options, InverseResult* result) {
  ContactModel contact = model.contact;
  contact.support_offsets.clear();
  const Obstacle* obstacle = contact.obstacle.get();
  if (!options.contact_forces) return model.contact;
  if (!obstacle) return contact;
  const int n = model.NumSegments();
  const int m = contact.samples_per_segment;
  const double tolerance = options.support_tolerance * model.Length();
  const StrandGeometry g = ComputeGeometry(model, target);

  // The candidates: samples (those of the contact energy) within the tolerance of the surface.
  std::vector<SupportSample>& supports = result->supports;
  std::vector<double> offsets(static_cast<size_t>(n) * static_cast<size_t>(m), 0.0);
  for (int i = 0; i < n; ++i) {
    const Vec3 omega = target.segment<3>(3 * i);
    const double w = model.segment_lengths[static_cast<size_t>(i)] / m;
    for (int j = 0; j < m; ++j) {
      SupportSample p;
      p.segment = i;
      p.index = j;
      p.u = (j + 1) * w;
      p.position = g.points[static_cast<size_t>(i)] +
                   g.frames[static_cast<size_t>(i)] * HelixChord(omega, p.u);
      p.distance = obstacle->SignedDistance(p.position, &p.normal) - contact.clearance;
      if (!(std::abs(p.distance) <= tolerance)) continue;
      // Without its force the sample sits exactly on its shifted surface (x = 0).
      offsets[static_cast<size_t>(i * m + j)] = p.distance;
      supports.push_back(p);
    }
  }
  if (supports.empty()) return contact;
  contact.support_offsets = offsets;

  // q0 without support forces, and the columns (l K)^(-1) a_j per unit force.
  StrandModel free = model;
  free.contact = contact;
  const VecX rest_free = InverseRestCurvatures(free, target);
  const Vec3 k = model.Stiffness();
  VecX inverse_stiffness(3 * n), weight(3 * n);  // (l K)^(-1) and W = (l K)^(1/2)
  for (int i = 0; i < n; ++i) {
    const Vec3 lk = model.segment_lengths[static_cast<size_t>(i)] * k;
    inverse_stiffness.segment<3>(3 * i) = lk.cwiseInverse();
    weight.segment<3>(3 * i) = lk.cwiseSqrt();
  }
  const Eigen::Index p = static_cast<Eigen::Index>(supports.size());
  std::vector<PointForce> unit_forces;  // supports are in order of segment
  unit_forces.reserve(supports.size());
  for (const SupportSample& s : supports) unit_forces.push_back({s.segment, s.u, s.normal});
  MatX a = PointForceGradients(model, target, unit_forces);
  for (Eigen::Index c = 0; c < p; ++c) {
    a.col(c) = weight.cwiseProduct(inverse_stiffness.cwiseProduct(a.col(c)));
  }
  // min |W (q0_free + (lK)^(-1) A f - q0nat)|^2, f >= 0, plus a tiny ridge. With m samples per
  // segment and 3 rows per segment the columns are dependent: many force distributions give the
  // same rest shape, and the NNLS vertex leaves most supports at f = 0, where the penalty has no
  // stiffness, so the forward model can lose the stability the target had (measured: 7 of 120
  // groomed wavy masters). The ridge kSupportRidge^2 sum_j |a_j|^2 (f_j - p_j)^2
  // (column-scaled, so it has the objective's units) picks, among the (nearly) equally close
  // rest shapes, the forces closest to p_j = w k max(0, clearance - d_j), the penalty forces of
  // the forward model at the target: a groomed equilibrium gets back its own forces (and rest
  // shape), a target lying on the surface the most even distribution. It changes the objective
  // by a relative ~kSupportRidge^2.
  VecX natural(3 * n);
  for (int i = 0; i < n; ++i) natural.segment<3>(3 * i) = model.natural_curvature;
  MatX augmented = MatX::Zero(3 * n + p, p);
  augmented.topRows(3 * n) = a;
  VecX b = VecX::Zero(3 * n + p);
  b.head(3 * n) = -weight.cwiseProduct(rest_free - natural);
  const double stiffness = model.ContactStiffness();
  for (Eigen::Index c = 0; c < p; ++c) {
    const SupportSample& s = supports[static_cast<size_t>(c)];
    const double w = model.segment_lengths[static_cast<size_t>(s.segment)] / m;
    const double penalty = w * stiffness * std::max(0.0, -s.distance);
    augmented(3 * n + c, c) = kSupportRidge * a.col(c).norm();
    b(3 * n + c) = augmented(3 * n + c, c) * penalty;
  }
  VecX f;
  result->nnls_iterations = NonNegativeLeastSquaresNormal(augmented, b, &f);

  // The penalty reproduces f_j: x_j = f_j / (k w_j), so clearance + offset_j - d_j = x_j. A
  // support left at f_j = 0 would sit exactly on its shifted surface (x_j = 0 up to rounding),
  // where the penalty's second derivative jumps from 0 to w k: whether the Hessian counted that
  // stiffness would be decided by the sign of a rounding error, and counting it certifies
  // stiffness that a sample pulled away from the surface does not have (measured on 1,000
  // groomed wavy masters: ~13 such supports per strand, lowering the smallest scaled eigenvalue
  // by up to 0.015). So it is moved kZeroForceGap L off the surface: no force, no stiffness.
  for (Eigen::Index c = 0; c < p; ++c) {
    SupportSample& s = supports[static_cast<size_t>(c)];
    s.force = f(c);
    const double w = model.segment_lengths[static_cast<size_t>(s.segment)] / m;
    contact.support_offsets[static_cast<size_t>(s.segment * m + s.index)] =
        s.force > 0.0 ? s.force / (stiffness * w) + s.distance
                      : s.distance - kZeroForceGap * model.Length();
    if (s.force > 0.0) {
      ++result->supported_samples;
      result->support_force += s.force;
    }
  }
  result->support_offsets = contact.support_offsets;
  return contact;
}

}  // namespace

InverseResult InvertStrand(const StrandModel& model, const VecX& target,
                           const InverseOptions& options) {
  assert(target.size() == 3 * model.NumSegments());
  InverseResult result;
  StrandModel inverted = model;
  inverted.contact = ChooseSupportForces(model, target, options, &result);
  result.rest_curvatures = InverseRestCurvatures(inverted, target);
  inverted.rest_curvatures = result.rest_curvatures;
  result.rest_energy = RestEnergy(model, result.rest_curvatures);
  StrandModel plain = model;  // the model's own penalty forces only
  plain.contact.support_offsets.clear();
  plain.rest_curvatures = InverseRestCurvatures(plain, target);
  result.rest_energy_unsupported = RestEnergy(model, plain.rest_curvatures);

  // The certificate: the Hessian at the target (independent of q0) factored from tip to root.
  StrandHessian hessian;
  ComputeStrandHessian(inverted, target, &hessian);
  StrandHessianFactor factor;
  result.stable = factor.Factor(hessian, 0.0);
  result.failed_segment = factor.failed_segment();
  // Support forces can cost stability: a support at f = 0 has no penalty stiffness, and a normal
  // force f on a convex part of the body (radius R) has the negative tangential stiffness -f/R
  // of frictionless contact. When the target is not certified stable with the chosen forces but
  // is with the model's own penalty forces, that rest shape is kept instead (the closest stable
  // alternative, docs/inverse.md), and support_fallback says so.
  // The smallest eigenvalue is reported too (and must be > 0, as the factorization says). A
  // finite-difference Hessian is no referee here: its columns cross the penalty's kinks (samples
  // with x_j smaller than the difference step), and its symmetrized form then has spurious
  // eigenvalues down to -50 where the energy curves up along every such direction (checked
  // along the directions on 1,000 groomed wavy masters; StrandHessian matched them).
  // It is computed only for the rest shape kept: for a failed factorization it takes a dense
  // eigensolver (~3 ms at 50 segments), which a fallback does not need.
  double lambda = result.stable ? MinScaledHessianEigenvalue(inverted, hessian) : 0.0;
  bool fell_back = false;
  if (!(result.stable && lambda > 0.0) && !result.support_offsets.empty()) {
    StrandHessian plain_hessian;
    ComputeStrandHessian(plain, target, &plain_hessian);
    double plain_lambda = 0.0;
    if (factor.Factor(plain_hessian, 0.0) &&
        (plain_lambda = MinScaledHessianEigenvalue(plain, plain_hessian)) > 0.0) {
      fell_back = true;
      inverted = plain;
      result.rest_curvatures = plain.rest_curvatures;
      result.rest_energy = result.rest_energy_unsupported;
      result.support_offsets.clear();
      for (SupportSample& p : result.supports) p.force = 0.0;
      result.supported_samples = 0;
      result.support_force = 0.0;
      result.support_fallback = true;
      result.stable = true;
      result.failed_segment = -1;
      result.min_eigenvalue = plain_lambda;
    }
  }
  if (!fell_back) {
    result.min_eigenvalue =
        result.stable ? lambda : MinScaledHessianEigenvalue(inverted, std::move(hessian));
  }
  const double length = model.Length();

  if (options.verify) {
    // Kirchhoff's balance by quadrature: an independent check of the closed form's q0.
    result.kirchhoff_residual = KirchhoffResidual(inverted, target);
    StrandSolution forward = SolveStrand(inverted, options.solver, &target);
    result.deviation =
        CentrelineDeviation(model, target, forward.curvatures, options.points_per_segment);
    result.equilibrium = std::move(forward.curvatures);
    result.forward = std::move(forward.summary);
  }
  if (options.naive) {
    StrandModel naive = model;  // the artist's groom: rest = target, the body as it is
    naive.contact.support_offsets.clear();
    naive.rest_curvatures = target;
    StrandSolution sagged = SolveStrand(naive, options.solver, &target);
    result.naive_deviation =
        CentrelineDeviation(model, target, sagged.curvatures, options.points_per_segment);
    result.naive_equilibrium = std::move(sagged.curvatures);
    result.naive_forward = std::move(sagged.summary);
  }

  std::string m = result.stable ? "stable target" : "UNSTABLE target (pivot of segment " +
                                                         std::to_string(result.failed_segment) +
                                                         " not positive definite)";
  m += ", min scaled eigenvalue " + Number(result.min_eigenvalue);
  if (options.verify) m += ", Kirchhoff residual " + Number(result.kirchhoff_residual);
  if (!result.supports.empty()) {
    m += "; " + std::to_string(result.supported_samples) + " of " +
         std::to_string(result.supports.size()) + " contact samples on the body carry " +
         Number(result.support_force) + " N";
    if (result.nnls_iterations < 0) m += " (NNLS did not terminate)";
    if (result.support_fallback) m += " (the chosen forces were not stable: penalty forces kept)";
  }
  if (options.verify) {
    m += "; forward solve " + std::string(TerminationName(result.forward.termination)) +
         ", deviation " + Number(result.deviation / length) + " L";
    if (!result.stable) m += " (the closest stable equilibrium of the inverted rest shape)";
  }
  if (options.naive) {
    m += "; naive rest shape sags " + Number(result.naive_deviation / length) + " L";
  }
  result.message = m;
  return result;
}

std::vector<InverseResult> InvertStrands(const std::vector<StrandModel>& models,
                                         const std::vector<VecX>& targets,
                                         const InverseOptions& options, int threads,
                                         const ProgressCallback& progress) {
  assert(models.size() == targets.size());
  std::vector<InverseResult> results(models.size());
  const int total = static_cast<int>(models.size());
  std::mutex progress_mutex;  // progress calls are serialized (solve_strands.h)
  int finished = 0;
  // Each result depends on its strand alone, so any split gives the same results.
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] {
    // One strand per task (grain 1): strands on the body cost many times the free ones.
    tbb::parallel_for(tbb::blocked_range<int>(0, total, 1), [&](const tbb::blocked_range<int>& r) {
      for (int i = r.begin(); i < r.end(); ++i) {
        results[static_cast<size_t>(i)] =
            InvertStrand(models[static_cast<size_t>(i)], targets[static_cast<size_t>(i)], options);
        if (progress) {
          std::lock_guard<std::mutex> lock(progress_mutex);
          progress(++finished, total);
        }
      }
    });
  });
  return results;
}

}  // namespace ringlet
