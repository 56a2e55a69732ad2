// Fit of a target polyline by a G1 piecewise helix, segment by segment with Levenberg-Marquardt
// on the closed-form helix (inverse.h, docs/inverse.md).
#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <string>

#include "ringlet/helix.h"
#include "ringlet/inverse.h"

namespace ringlet {
namespace {

bool Fail(std::string* why, const std::string& message) {
  if (why) *why = message;
  return false;
}

// Levenberg-Marquardt's damping: initial value relative to the diagonal of J^T J, and its
// factors on success and failure (Nielsen's simple rule).
constexpr double kInitialDamping = 1e-3;
constexpr double kDampingDown = 1.0 / 3.0;
constexpr double kDampingUp = 4.0;
// Stop when a step changes no unknown by more than this, relative to its scale (the segment's
// length for lengths, 1/l for curvatures, 1 for the fractions): rounding.
constexpr double kStepTolerance = 1e-15;

// The fit of one segment: start (r0, Q0), target points in the start frame W_1..W_k (the last
// one is the segment's end). Unknowns y = (Omega (3), l, sigma_1 .. sigma_(k-1)); residuals
// p(Omega, u_j) - W_j with u_j = sigma_j l (j < k) and u_k = l.
struct SegmentFit {
  Vec3 omega = Vec3::Zero();
  double length = 0.0;
  std::vector<double> u;  // arc length of each target point inside the segment (m)
  int iterations = 0;
};

// Residuals (3k) and, if jacobian is not null, the exact Jacobian (3k x (k + 3)).
void SegmentResiduals(const VecX& y, const std::vector<Vec3>& w, VecX* residual, MatX* jacobian) {
  const int k = static_cast<int>(w.size());
  const Vec3 omega = y.head<3>();
  const double l = y(3);
  residual->resize(3 * k);
  if (jacobian) jacobian->setZero(3 * k, k + 3);
  for (int j = 0; j < k; ++j) {
    const bool end = j == k - 1;
    const double sigma = end ? 1.0 : y(4 + j);
    const double u = sigma * l;
    const HelixFunctions functions = EvaluateHelixFunctions(omega.norm() * u);
    residual->segment<3>(3 * j) = HelixChordFromFunctions(omega, u, functions) - w[j];
    if (!jacobian) continue;
    // d p / d Omega, row by row: the vector-Jacobian product with the unit vectors.
    for (int r = 0; r < 3; ++r) {
      jacobian->block<1, 3>(3 * j + r, 0) =
          HelixChordVjp(omega, u, functions, Vec3::Unit(r)).transpose();
    }
    // d p / d u = R(u) e3, the tangent at u in the start frame.
    const Vec3 tangent = HelixRotation(omega, u).col(2);
    jacobian->block<3, 1>(3 * j, 3) = sigma * tangent;
    if (!end) jacobian->block<3, 1>(3 * j, 4 + j) = l * tangent;
  }
}

// The circular arc that leaves along e3 and reaches the chord c (start frame): turning angle
// 2 alpha, alpha the angle between e3 and c, curvature 2 sin(alpha) / |c| about e3 x c.
void ArcGuess(const Vec3& c, Vec3* omega, double* length) {
  const double chord = c.norm();
  const Vec3 axis = Vec3::UnitZ().cross(c);
  const double alpha = std::atan2(axis.norm(), c.z());  // no acos of a dot product
  if (alpha < 1e-8) {
    *omega = Vec3::Zero();
    *length = chord;
    return;
  }
  // A point behind the start (alpha near pi) would need an arc of infinite radius: cap alpha.
  const double a = std::min(alpha, 0.9 * 3.14159265358979323846);
  const double kappa = 2.0 * std::sin(a) / chord;
  *omega = kappa * axis.normalized();
  *length = 2.0 * a / kappa;
}

SegmentFit FitSegment(const std::vector<Vec3>& w, const std::vector<double>& edge_fraction,
                      int max_iterations) {
  const int k = static_cast<int>(w.size());
  VecX y(k + 3);
  Vec3 omega;
  double length;
  ArcGuess(w.back(), &omega, &length);
  y.head<3>() = omega;
  y(3) = length;
  for (int j = 0; j + 1 < k; ++j) y(4 + j) = edge_fraction[static_cast<size_t>(j)];

  VecX residual, trial_residual;
  MatX jacobian;
  SegmentResiduals(y, w, &residual, &jacobian);
  double cost = residual.squaredNorm();
  double damping = -1.0;
  SegmentFit fit;
  for (int it = 0; it < max_iterations && cost > 0.0; ++it) {
    ++fit.iterations;
    const MatX a = jacobian.transpose() * jacobian;
    const VecX g = jacobian.transpose() * residual;
    if (damping < 0.0) damping = kInitialDamping;
    bool improved = false;
    bool tiny = false;
    // Raise the damping until a step lowers the cost (at most ~30 times: 4^30 ~ 1e18).
    for (int attempt = 0; attempt < 30; ++attempt) {
      MatX m = a;
      for (int d = 0; d < m.rows(); ++d) {
        m(d, d) += damping * std::max(a(d, d), 1e-30);
      }
      const VecX step = -m.ldlt().solve(g);
      const VecX trial = y + step;
      // Scale of each unknown for the stopping test.
      const double l = std::max(y(3), 1e-300);
      double relative = step.head<3>().cwiseAbs().maxCoeff() * l;
      relative = std::max(relative, std::abs(step(3)) / l);
      if (k > 1) relative = std::max(relative, step.tail(k - 1).cwiseAbs().maxCoeff());
      if (!(relative > kStepTolerance)) {
        tiny = true;
        break;
      }
      if (!(trial(3) > 0.0) || !trial.allFinite()) {
        damping *= kDampingUp;
        continue;
      }
      SegmentResiduals(trial, w, &trial_residual, nullptr);
      const double trial_cost = trial_residual.squaredNorm();
      if (trial_cost < cost) {
        y = trial;
        SegmentResiduals(y, w, &residual, &jacobian);
        cost = residual.squaredNorm();
        damping *= kDampingDown;
        improved = true;
        break;
      }
      damping *= kDampingUp;
    }
    if (tiny || !improved) break;
  }
  fit.omega = y.head<3>();
  fit.length = y(3);
  fit.u.resize(static_cast<size_t>(k));
  for (int j = 0; j < k; ++j) fit.u[static_cast<size_t>(j)] = (j == k - 1 ? 1.0 : y(4 + j)) * y(3);
  return fit;
}

// The fit with n segments (1 <= n <= edges).
void FitWithSegments(const std::vector<Vec3>& points, const Mat3& root_frame, int n,
                     int max_iterations, HelixFit* fit) {
  const int edges = static_cast<int>(points.size()) - 1;
  fit->root_position = points[0];
  fit->root_frame = root_frame;
  fit->segment_lengths.assign(static_cast<size_t>(n), 0.0);
  fit->curvatures.resize(3 * n);
  fit->arc_lengths.assign(points.size(), 0.0);
  fit->iterations = 0;
  Mat3 q = root_frame;
  Vec3 r = points[0];
  double s = 0.0;
  double max_d = 0.0, sum_d2 = 0.0;
  for (int i = 0; i < n; ++i) {
    // Segment i spans the edges [b0, b1) (b = floor(i m / n), at least one edge each).
    const int b0 = static_cast<int>(static_cast<long long>(i) * edges / n);
    const int b1 = static_cast<int>(static_cast<long long>(i + 1) * edges / n);
    std::vector<Vec3> w;
    std::vector<double> fraction;
    double total = 0.0;
    for (int e = b0; e < b1; ++e) total += (points[e + 1] - points[e]).norm();
    double acc = 0.0;
    for (int p = b0 + 1; p <= b1; ++p) {
      w.push_back(q.transpose() * (points[p] - r));
      acc += (points[p] - points[p - 1]).norm();
      fraction.push_back(acc / total);
    }
    const SegmentFit f = FitSegment(w, fraction, max_iterations);
    fit->iterations += f.iterations;
    fit->curvatures.segment<3>(3 * i) = f.omega;
    fit->segment_lengths[static_cast<size_t>(i)] = f.length;
    for (size_t j = 0; j < w.size(); ++j) {
      const double d = (HelixChord(f.omega, f.u[j]) - w[j]).norm();
      max_d = std::max(max_d, d);
      sum_d2 += d * d;
      fit->arc_lengths[static_cast<size_t>(b0) + 1 + j] = s + f.u[j];
    }
    const HelixSegment seg = EvaluateHelixSegment(f.omega, f.length);
    r += q * seg.chord;
    q = q * seg.rotation;
    s += f.length;
  }
  fit->length = s;
  fit->max_distance = max_d;
  fit->rms_distance = std::sqrt(sum_d2 / static_cast<double>(points.size()));
}

}  // namespace

Mat3 DefaultRootFrame(const Vec3& tangent, const Vec3& axis) {
  const Vec3 t = tangent.normalized();
  Vec3 a = axis;
  if (!(a.norm() > 0.0) || std::abs(a.normalized().dot(t)) > 0.9) {
    // The world axis least aligned with t: |t_k| smallest.
    int best = 0;
    for (int c = 1; c < 3; ++c) {
      if (std::abs(t(c)) < std::abs(t(best))) best = c;
    }
    a = Vec3::Unit(best);
  }
  const Vec3 n1 = (a - t * t.dot(a)).normalized();
  Mat3 frame;
  frame.col(0) = n1;
  frame.col(1) = t.cross(n1);
  frame.col(2) = t;
  return frame;
}

bool FitOptions::IsValid(std::string* why) const {
  if (segments < 0 || segments > kMaxSegments) {
    return Fail(why, "segments: expected 0 (automatic) to " + std::to_string(kMaxSegments));
  }
  if (!(std::isfinite(tolerance) && tolerance > 0.0)) {
    return Fail(why, "fit tolerance: expected a finite number > 0 (units of the strand length)");
  }
  if (max_iterations < 1) return Fail(why, "fit max_iterations: expected an integer >= 1");
  if (!n1_axis.allFinite() || !(n1_axis.norm() > 0.0)) {
    return Fail(why, "n1 axis: expected a finite non-zero vector");
  }
  return true;
}

bool FitPiecewiseHelix(const std::vector<Vec3>& points, const Mat3* root_frame,
                       const FitOptions& options, HelixFit* fit, std::string* why) {
  if (!options.IsValid(why)) return false;
  if (points.size() < 2) return Fail(why, "point 0: a strand needs at least 2 points");
  double polyline = 0.0;
  for (size_t p = 0; p < points.size(); ++p) {
    if (!points[p].allFinite()) return Fail(why, "point " + std::to_string(p) + ": not finite");
    if (p > 0) {
      const double e = (points[p] - points[p - 1]).norm();
      if (!(e > 0.0)) {
        return Fail(why, "point " + std::to_string(p) + ": repeats point " + std::to_string(p - 1) +
                             " (zero-length edge)");
      }
      polyline += e;
    }
  }
  if (!std::isfinite(polyline)) return Fail(why, "point 0: the polyline's length is not finite");
  Mat3 frame;
  if (root_frame) {
    frame = *root_frame;
    if (!frame.allFinite() || (frame.transpose() * frame - Mat3::Identity()).norm() > 1e-9 ||
        frame.determinant() < 0.0) {
      return Fail(why, "root frame: expected a proper rotation (n1, n2, t)");
    }
  } else {
    frame = DefaultRootFrame(points[1] - points[0], options.n1_axis);
  }
  const int edges = static_cast<int>(points.size()) - 1;
  if (options.segments > 0) {
    FitWithSegments(points, frame, std::min(options.segments, edges), options.max_iterations, fit);
    return true;
  }
  // The smallest n of 1, 2, 4, ... (capped at the edge count) meeting the tolerance.
  for (int n = 1;; n = std::min(2 * n, edges)) {
    FitWithSegments(points, frame, n, options.max_iterations, fit);
    if (fit->max_distance <= options.tolerance * polyline || n == edges) break;
  }
  return true;
}

}  // namespace ringlet
