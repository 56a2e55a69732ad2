// Fit of a target polyline by a G1 piecewise helix, segment by segment with Levenberg-Marquardt
// on the closed-form helix (inverse.h, docs/inverse.md).
#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <mutex>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "ringlet/helix.h"
#include "ringlet/helix_jacobian.h"
#include "ringlet/inverse.h"

namespace ringlet {
namespace {

using Vec4 = Eigen::Matrix<double, 4, 1>;
using Mat4 = Eigen::Matrix<double, 4, 4>;

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
// The smallest damping of the global refinement (keeps the step finite where a segment of one
// edge leaves a direction free).
constexpr double kMinimumDamping = 1e-12;
// The automatic segment count's global refinement also stops when a step lowers the cost by less
// than kDecidedDecrease of it while the fit's largest distance is within the tolerance (the
// count is kept), or by less than kDecidedDecreaseFar while it is more than kFarFactor times the
// tolerance (the count is rejected): the slow final descent (a cost floor approached linearly:
// ~0.3 % per iteration for dozens of iterations on 16-segment fits of 32 float points) no longer
// changes whether the count is kept. Between the tolerance and kFarFactor times it the full
// descent (kRelativeDecrease) decides. Measured on wavy strands of the head (docs/benchmarks.md):
// 3e-3 for both gave the same segment counts as the full descent on 1,000 strands, refinement
// iterations 26 -> 12 at 16 segments; 1e-2 and 3e-2 then cut the fit's instructions by 17 %
// (100 strands) with 4 of 5,000 strands one count lower (all still within the tolerance), the
// largest distance of the same count 1.0006x the 3e-3 one (median), mean RMS distance 1.045x.
constexpr double kDecidedDecrease = 1e-2;
constexpr double kDecidedDecreaseFar = 3e-2;
constexpr double kFarFactor = 2.0;
// Segments fitted together in the root-to-tip pass (FitWithSegments).
constexpr int kWindow = 2;
// The global refinement stops after this many rejected steps in a row (damping raised 4^6 =
// 4096 times without lowering the cost: the cost is at its floor).
constexpr int kMaxAttempts = 6;
// Levenberg-Marquardt stops when a step lowers the cost by less than this fraction of it: a
// zero-residual fit converges quadratically and reaches rounding before; a polyline that is no
// piecewise helix (float points, points between the breaks) has a cost floor, which the steps
// then approach linearly, ever more slowly. Measured on 200 wavy masters of 50 segments (float
// points, no frames), against 1e-6 everywhere: the fit distances change by < 7 % (mean RMS
// 2.13e-6 L against 2.00e-6 L for 100 points; 3.0e-9 L both for 201 points) in 1/6 of the time.
//  - the global refinement (the result);
constexpr double kRelativeDecrease = 1e-3;
//  - the 2-segment windows and the single segments of the root-to-tip pass, when the global
//    refinement follows (they only give it its starting point).
constexpr double kStartRelativeDecrease = 1e-2;

// The fit of one segment: start (r0, Q0), target points in the start frame W_1..W_k (the last
// one is the segment's end). Unknowns y = (Omega (3), l, sigma_1 .. sigma_(k-1)); residuals
// p(Omega, u_j) - W_j with u_j = sigma_j l (j < k) and u_k = l.
struct SegmentFit {
  Vec3 omega = Vec3::Zero();
  double length = 0.0;
  std::vector<double> u;  // arc length of each target point inside the segment (m)
  int iterations = 0;
};

// The residuals p(Omega, u_j) - W_j (start frame) and, if jacobian is set, the blocks of the
// exact Jacobian: d/dOmega = dp/dOmega(u_j) (HelixChordJacobian), d/dl = sigma_j t_j and, for an
// inner point, d/dsigma_j = l t_j (t_j = R(u_j) e3 the tangent at u_j, sigma_k = 1 at the
// segment's end). Returns the cost, the sum of squared residuals.
struct SegmentPoint {
  Vec3 residual;
  Mat3 d_omega;
  Vec3 tangent;
};
double SegmentResiduals(const Vec3& omega, double l, const std::vector<double>& sigma,
                        const std::vector<Vec3>& w, bool jacobian,
                        std::vector<SegmentPoint>* out) {
  const int k = static_cast<int>(w.size());
  out->resize(static_cast<size_t>(k));
  const double norm = omega.norm();
  double cost = 0.0;
  for (int j = 0; j < k; ++j) {
    SegmentPoint& pt = (*out)[static_cast<size_t>(j)];
    const double u = (j == k - 1 ? 1.0 : sigma[static_cast<size_t>(j)]) * l;
    const HelixFunctions functions = EvaluateHelixFunctions(norm * u);
    pt.residual = HelixChordFromFunctions(omega, u, functions) - w[static_cast<size_t>(j)];
    cost += pt.residual.squaredNorm();
    if (!jacobian) continue;
    pt.d_omega = HelixChordJacobian(omega, u, functions);
    pt.tangent = HelixTangentFromFunctions(omega, u, functions);
  }
  return cost;
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

// Levenberg-Marquardt on y = (Omega, l, sigma_1 .. sigma_(k-1)). The normal matrix J^T J is an
// arrow: a dense 4 x 4 block for (Omega, l), a diagonal one for the sigmas (sigma_j enters
// residual j only, with the column l t_j) and their 4 x 1 couplings c_j = [D_j, sigma_j t_j]^T
// l t_j. The damped system (Marquardt: the diagonal times 1 + damping) is solved by eliminating
// the sigmas (Schur complement S = M_44 - sum c_j c_j^T / m_j), O(k) instead of the O(k^3) dense
// factorization: the same step, to rounding.
SegmentFit FitSegment(const std::vector<Vec3>& w, const std::vector<double>& edge_fraction,
                      int max_iterations, double relative_decrease) {
  const int k = static_cast<int>(w.size());
  const int inner = k - 1;
  Vec3 omega;
  double length;
  ArcGuess(w.back(), &omega, &length);
  std::vector<double> sigma(edge_fraction.begin(), edge_fraction.begin() + inner);
  std::vector<double> trial_sigma(static_cast<size_t>(inner));
  std::vector<SegmentPoint> points, trial_points;
  double cost = SegmentResiduals(omega, length, sigma, w, true, &points);
  // Per inner point: the coupling c_j, the diagonal d_j and the gradient entry.
  std::vector<Vec4> coupling(static_cast<size_t>(inner));
  std::vector<double> diagonal(static_cast<size_t>(inner)), gradient(static_cast<size_t>(inner));
  std::vector<double> step_sigma(static_cast<size_t>(inner));
  double damping = -1.0;
  SegmentFit fit;
  for (int it = 0; it < max_iterations && cost > 0.0; ++it) {
    ++fit.iterations;
    Mat4 a = Mat4::Zero();
    Vec4 g = Vec4::Zero();
    for (int j = 0; j < k; ++j) {
      const SegmentPoint& pt = points[static_cast<size_t>(j)];
      const double s = j == k - 1 ? 1.0 : sigma[static_cast<size_t>(j)];
      Eigen::Matrix<double, 3, 4> bj;
      bj.leftCols<3>() = pt.d_omega;
      bj.col(3) = s * pt.tangent;
      a.noalias() += bj.transpose().lazyProduct(bj);
      g.noalias() += bj.transpose() * pt.residual;
      if (j < inner) {
        const Vec3 column = length * pt.tangent;
        coupling[static_cast<size_t>(j)] = bj.transpose() * column;
        diagonal[static_cast<size_t>(j)] = column.squaredNorm();
        gradient[static_cast<size_t>(j)] = column.dot(pt.residual);
      }
    }
    if (damping < 0.0) damping = kInitialDamping;
    bool improved = false;
    bool tiny = false;
    // Raise the damping until a step lowers the cost (at most ~30 times: 4^30 ~ 1e18).
    for (int attempt = 0; attempt < 30; ++attempt) {
      Mat4 schur = a;
      for (int d = 0; d < 4; ++d) schur(d, d) += damping * std::max(a(d, d), 1e-30);
      Vec4 rhs = g;
      for (int j = 0; j < inner; ++j) {
        const double m = diagonal[static_cast<size_t>(j)] +
                         damping * std::max(diagonal[static_cast<size_t>(j)], 1e-30);
        const Vec4& c = coupling[static_cast<size_t>(j)];
        schur.noalias() -= (c / m) * c.transpose();
        rhs -= c * (gradient[static_cast<size_t>(j)] / m);
      }
      const Vec4 step = -schur.ldlt().solve(rhs);
      double sigma_step = 0.0;
      for (int j = 0; j < inner; ++j) {
        const double m = diagonal[static_cast<size_t>(j)] +
                         damping * std::max(diagonal[static_cast<size_t>(j)], 1e-30);
        const double ds =
            -(gradient[static_cast<size_t>(j)] + coupling[static_cast<size_t>(j)].dot(step)) / m;
        step_sigma[static_cast<size_t>(j)] = ds;
        sigma_step = std::max(sigma_step, std::abs(ds));
      }
      // Scale of each unknown for the stopping test.
      const double l = std::max(length, 1e-300);
      double relative = step.head<3>().cwiseAbs().maxCoeff() * l;
      relative = std::max(relative, std::abs(step(3)) / l);
      relative = std::max(relative, sigma_step);
      if (!(relative > kStepTolerance)) {
        tiny = true;
        break;
      }
      const Vec3 trial_omega = omega + step.head<3>();
      const double trial_length = length + step(3);
      bool finite = trial_omega.allFinite() && std::isfinite(trial_length);
      for (int j = 0; j < inner; ++j) {
        trial_sigma[static_cast<size_t>(j)] =
            sigma[static_cast<size_t>(j)] + step_sigma[static_cast<size_t>(j)];
        finite = finite && std::isfinite(trial_sigma[static_cast<size_t>(j)]);
      }
      if (!(trial_length > 0.0) || !finite) {
        damping *= kDampingUp;
        continue;
      }
      const double trial_cost =
          SegmentResiduals(trial_omega, trial_length, trial_sigma, w, false, &trial_points);
      if (trial_cost < cost) {
        if (cost - trial_cost <= relative_decrease * cost) tiny = true;
        omega = trial_omega;
        length = trial_length;
        sigma.swap(trial_sigma);
        cost = SegmentResiduals(omega, length, sigma, w, true, &points);
        damping *= kDampingDown;
        improved = true;
        break;
      }
      damping *= kDampingUp;
    }
    if (tiny || !improved) break;
  }
  fit.omega = omega;
  fit.length = length;
  fit.u.resize(static_cast<size_t>(k));
  for (int j = 0; j < k; ++j) {
    fit.u[static_cast<size_t>(j)] = (j == k - 1 ? 1.0 : sigma[static_cast<size_t>(j)]) * length;
  }
  return fit;
}

// ---------------------------------------------------------------------------------------------
// Global refinement: Levenberg-Marquardt on all segments at once, solved exactly in O(n) by the
// chain's structure (a discrete-time linear-quadratic regulator).
//
// Unknowns: the curvatures Omega_i and lengths l_i of every segment (the "controls" u_i), the
// fractions sigma_j of the inner points, and (without a given root frame) the tilt of the root
// tangent. The state x_i = (dr_i, dtheta_i) (6) is the first-order change of the start frame of
// segment i (position, and rotation in world coordinates: Q -> exp([dtheta]x) Q). Linearized,
//   x_(i+1) = A_i x_i + B_i u_i,  A_i = [I, -[c_i]x; 0, I]  (c_i = Q_i p_i, the world chord),
//   B_i = [Q_i dp/dOmega, Q_i R_i e3; Q_(i+1) J_i, Q_(i+1) Omega_i],
// with J_i = l I - l^2 G2 [Omega]x + l^3 G3 [Omega]x^2 (l times SO(3)'s right Jacobian at
// l Omega: exp(l[Omega + dOmega]x) = R exp([J_i dOmega]x)), and every residual of segment i is
//   e_j + dr_i + dtheta_i x (Q_i p(u_j)) + Q_i (dp/dOmega(u_j) dOmega + t_j (sigma_j dl + l dsigma_j))
// (t_j = R(u_j) e3 the tangent). Each sigma_j enters one residual only: eliminated in closed form
// (weight I - t t^T / (1 + mu) on that residual, Marquardt damping mu l^2 on dsigma_j). The
// damped Gauss-Newton step then minimizes a sum of stage costs of (x_i, u_i) under the linear
// chain: a backward Riccati sweep (6x6 cost-to-go matrices) and a forward sweep give the exact
// step in O(n), instead of the O(n^3) dense normal equations.
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Vec11 = Eigen::Matrix<double, 11, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat11 = Eigen::Matrix<double, 11, 11>;
using Mat64 = Eigen::Matrix<double, 6, 4>;
using Mat46 = Eigen::Matrix<double, 4, 6>;

// A piecewise helix with its point parameters: segment i spans the points (b_i, b_(i+1)].
struct Chain {
  Mat3 root = Mat3::Identity();
  std::vector<Vec3> omega;
  std::vector<double> length;
  std::vector<double> sigma;  // per point: the fraction of its segment's length (inner points)
};

// Segment boundaries b_i = floor(i m / n), i = 0..n.
std::vector<int> Boundaries(int edges, int n) {
  std::vector<int> b(static_cast<size_t>(n) + 1);
  for (int i = 0; i <= n; ++i) {
    b[static_cast<size_t>(i)] = static_cast<int>(static_cast<long long>(i) * edges / n);
  }
  return b;
}

// Sum of squared distances between the target points and the chain's points (m^2); the
// per-point distances in *distances and the largest squared one in *max_squared if given.
double ChainCost(const std::vector<Vec3>& points, const std::vector<int>& b, const Chain& c,
                 std::vector<double>* distances, double* max_squared = nullptr) {
  double worst = 0.0;
  const int n = static_cast<int>(c.omega.size());
  Mat3 q = c.root;
  Vec3 r = points[0];
  double cost = 0.0;
  if (distances) distances->assign(points.size(), 0.0);
  for (int i = 0; i < n; ++i) {
    const Vec3& omega = c.omega[static_cast<size_t>(i)];
    const double l = c.length[static_cast<size_t>(i)];
    const double norm = omega.norm();
    for (int p = b[static_cast<size_t>(i)] + 1; p < b[static_cast<size_t>(i) + 1]; ++p) {
      const double u = c.sigma[static_cast<size_t>(p)] * l;
      const Vec3 chord = HelixChordFromFunctions(omega, u, EvaluateHelixFunctions(norm * u));
      const double d2 = (r + q * chord - points[p]).squaredNorm();
      cost += d2;
      worst = std::max(worst, d2);
      if (distances) (*distances)[static_cast<size_t>(p)] = std::sqrt(d2);
    }
    const HelixSegment seg = EvaluateHelixSegment(omega, l);
    r += q * seg.chord;
    q = q * seg.rotation;
    const int end = b[static_cast<size_t>(i) + 1];
    const double d2 = (r - points[static_cast<size_t>(end)]).squaredNorm();
    cost += d2;
    worst = std::max(worst, d2);
    if (distances) (*distances)[static_cast<size_t>(end)] = std::sqrt(d2);
  }
  if (max_squared) *max_squared = worst;
  return cost;
}

// The linearization of one segment: the stage cost of (x, u, 1) is
// [x; u; 1]^T (F - T / (1 + mu)) [x; u; 1], and each inner point's g = [C D e]^T t gives its
// dsigma = -g . [x; u; 1] / (l (1 + mu)).
struct Stage {
  Mat11 f = Mat11::Zero();
  Mat11 t = Mat11::Zero();
  std::vector<Vec11> g;  // inner points, in order
  Vec3 chord = Vec3::Zero();  // c_i (world)
  Mat64 b = Mat64::Zero();
  // Riccati gains of the last backward sweep.
  Mat46 gain = Mat46::Zero();
  Vec4 offset = Vec4::Zero();
};

// Adds a residual row block J = [C (3x6) | D (3x4) | e (3x1)] to the stage. C's first 3 columns
// are the identity (a residual moves with the segment's start), so the first 3 rows of J^T J
// are J itself and only the lower right 8 x 8 block is a product: the same sums as the full
// 11 x 11 product (whose identity terms add exact zeros), in half of its multiplications.
void AddResidual(const Eigen::Matrix<double, 3, 11>& j, const Vec3* tangent, Stage* s) {
  const auto rest = j.rightCols<8>();
  s->f.topRows<3>() += j;
  s->f.bottomLeftCorner<8, 3>() += rest.transpose();
  s->f.bottomRightCorner<8, 8>().noalias() += rest.transpose().lazyProduct(rest);
  if (tangent) {
    const Vec11 g = j.transpose() * *tangent;
    s->t.noalias() += g * g.transpose();
    s->g.push_back(g);
  }
}

void Linearize(const std::vector<Vec3>& points, const std::vector<int>& b, const Chain& c,
               std::vector<Stage>* stages) {
  const int n = static_cast<int>(c.omega.size());
  stages->resize(static_cast<size_t>(n));
  Mat3 q = c.root;
  Vec3 r = points[0];
  for (int i = 0; i < n; ++i) {
    Stage& s = (*stages)[static_cast<size_t>(i)];
    s.f.setZero();
    s.t.setZero();
    s.g.clear();
    const Vec3& omega = c.omega[static_cast<size_t>(i)];
    const double l = c.length[static_cast<size_t>(i)];
    // One residual at arc length u: position r + Q p(u) - P, its derivatives.
    auto row = [&](double u, double sigma, const Vec3& target, Vec3* tangent) {
      const HelixFunctions h = EvaluateHelixFunctions(omega.norm() * u);
      const Vec3 p = HelixChordFromFunctions(omega, u, h);
      const Mat3 dp = HelixChordJacobian(omega, u, h);  // dp/dOmega (start frame)
      *tangent = q * HelixTangentFromFunctions(omega, u, h);
      Eigen::Matrix<double, 3, 11> j;
      j.block<3, 3>(0, 0).setIdentity();
      j.block<3, 3>(0, 3) = -Hat(q * p);
      j.block<3, 3>(0, 6) = q * dp;
      j.col(9) = sigma * *tangent;
      j.col(10) = r + q * p - target;
      return j;
    };
    Vec3 tangent;
    for (int p = b[static_cast<size_t>(i)] + 1; p < b[static_cast<size_t>(i) + 1]; ++p) {
      const double sigma = c.sigma[static_cast<size_t>(p)];
      const auto j = row(sigma * l, sigma, points[static_cast<size_t>(p)], &tangent);
      AddResidual(j, &tangent, &s);
    }
    AddResidual(row(l, 1.0, points[static_cast<size_t>(b[static_cast<size_t>(i) + 1])], &tangent),
                nullptr, &s);
    // The chain: B_i.
    const HelixSegment seg = EvaluateHelixSegment(omega, l);
    const Mat3 q_end = q * seg.rotation;
    const Mat3 dp_end = HelixChordJacobian(omega, l, seg.functions);
    const Mat3 w = Hat(omega);
    const Mat3 jr = l * Mat3::Identity() - (l * l * seg.functions.g[2]) * w +
                    (l * l * l * seg.functions.g[3]) * w * w;
    s.chord = q * seg.chord;
    s.b.block<3, 3>(0, 0) = q * dp_end;
    s.b.block<3, 1>(0, 3) = q_end.col(2);
    s.b.block<3, 3>(3, 0) = q_end * jr;
    s.b.block<3, 1>(3, 3) = q_end * omega;
    r += s.chord;
    q = q_end;
  }
}

// A x for A = [I, -[c]x; 0, I].
Vec6 ApplyA(const Vec3& c, const Vec6& x) {
  Vec6 y = x;
  y.head<3>() += x.tail<3>().cross(c);
  return y;
}

// The Riccati gains: gain = -huu^(-1) hux, offset = -huu^(-1) hu. huu is symmetric positive
// definite (a sum of Gauss-Newton terms and the cost-to-go, Marquardt-damped): Cholesky
// huu = L L^T written out for 4 x 4 and the 7 right-hand sides substituted in place (Eigen's
// fixed-size LDL^T with pivoting and its solves were 13 % of the fit); a pivot that rounding
// leaves non-positive falls back to that LDL^T.
void SolveGains(const Mat4& huu, const Mat46& hux, const Vec4& hu, Mat46* gain, Vec4* offset) {
  double l[4][4] = {};
  for (int j = 0; j < 4; ++j) {
    double d = huu(j, j);
    for (int k = 0; k < j; ++k) d -= l[j][k] * l[j][k];
    if (!(d > 0.0)) {
      const Eigen::LDLT<Mat4> ldlt(huu);
      for (int c = 0; c < 6; ++c) gain->col(c) = -ldlt.solve(Vec4(hux.col(c)));
      *offset = -ldlt.solve(hu);
      return;
    }
    l[j][j] = std::sqrt(d);
    for (int i = j + 1; i < 4; ++i) {
      double v = huu(i, j);
      for (int k = 0; k < j; ++k) v -= l[i][k] * l[j][k];
      l[i][j] = v / l[j][j];
    }
  }
  Eigen::Matrix<double, 4, 7> x;
  x.leftCols<6>() = hux;
  x.col(6) = hu;
  for (int c = 0; c < 7; ++c) {
    for (int i = 0; i < 4; ++i) {  // L y = b
      double v = x(i, c);
      for (int k = 0; k < i; ++k) v -= l[i][k] * x(k, c);
      x(i, c) = v / l[i][i];
    }
    for (int i = 3; i >= 0; --i) {  // L^T z = y
      double v = x(i, c);
      for (int k = i + 1; k < 4; ++k) v -= l[k][i] * x(k, c);
      x(i, c) = v / l[i][i];
    }
  }
  *gain = -x.leftCols<6>();
  *offset = -x.col(6);
}

// One damped Gauss-Newton step (mu: Marquardt's damping, relative to the diagonal). Returns the
// trial chain in *trial (its vectors reused); *step_size gets the largest relative change.
void Step(const Chain& c, const std::vector<int>& b, std::vector<Stage>* stages, bool free_root,
          double mu, Chain* trial_out, double* step_size) {
  const int n = static_cast<int>(c.omega.size());
  const double weight = 1.0 / (1.0 + mu);
  Mat6 pm = Mat6::Zero();
  Vec6 qv = Vec6::Zero();
  for (int i = n - 1; i >= 0; --i) {
    Stage& s = (*stages)[static_cast<size_t>(i)];
    const Mat11 lq = s.f - weight * s.t;
    Mat6 a = Mat6::Identity();
    a.block<3, 3>(0, 3) = -Hat(s.chord);
    const Mat6 pa = pm * a;
    const Mat6 hxx = lq.block<6, 6>(0, 0) + a.transpose() * pa;
    const Mat46 hux = lq.block<4, 6>(6, 0) + s.b.transpose() * pa;
    Mat4 huu = lq.block<4, 4>(6, 6) + s.b.transpose() * pm * s.b;
    const Vec6 hx = lq.block<6, 1>(0, 10) + a.transpose() * qv;
    const Vec4 hu = lq.block<4, 1>(6, 10) + s.b.transpose() * qv;
    for (int d = 0; d < 4; ++d) huu(d, d) += mu * std::max(huu(d, d), 1e-300);
    SolveGains(huu, hux, hu, &s.gain, &s.offset);
    pm = hxx + hux.transpose() * s.gain;
    pm = 0.5 * (pm + pm.transpose()).eval();
    qv = hx + hux.transpose() * s.offset;
  }
  Vec6 x = Vec6::Zero();
  Chain& trial = *trial_out;
  trial.root = c.root;
  trial.omega.assign(c.omega.begin(), c.omega.end());
  trial.length.assign(c.length.begin(), c.length.end());
  trial.sigma.assign(c.sigma.begin(), c.sigma.end());
  double size = 0.0;
  if (free_root) {
    // x_0 = S z: the root tilts about n1 and n2 (a turn about t is a gauge: it turns every
    // (kappa1, kappa2) with it and leaves the centreline).
    Eigen::Matrix<double, 6, 2> sm = Eigen::Matrix<double, 6, 2>::Zero();
    sm.block<3, 1>(3, 0) = c.root.col(0);
    sm.block<3, 1>(3, 1) = c.root.col(1);
    Eigen::Matrix2d hz = sm.transpose() * pm * sm;
    const Eigen::Vector2d hzv = sm.transpose() * qv;
    for (int d = 0; d < 2; ++d) hz(d, d) += mu * std::max(hz(d, d), 1e-300);
    const Eigen::Vector2d z = -hz.ldlt().solve(hzv);
    x = sm * z;
    const Vec3 theta = x.tail<3>();
    if (theta.norm() > 0.0) {
      trial.root = Eigen::AngleAxisd(theta.norm(), theta.normalized()).toRotationMatrix() * c.root;
    }
    size = theta.norm();
  }
  for (int i = 0; i < n; ++i) {
    const Stage& s = (*stages)[static_cast<size_t>(i)];
    const Vec4 u = s.gain * x + s.offset;
    const double l = c.length[static_cast<size_t>(i)];
    Vec11 xu1;
    xu1 << x, u, 1.0;
    int j = 0;
    for (int p = b[static_cast<size_t>(i)] + 1; p < b[static_cast<size_t>(i) + 1]; ++p, ++j) {
      const double ds = -s.g[static_cast<size_t>(j)].dot(xu1) * weight / l;
      trial.sigma[static_cast<size_t>(p)] += ds;
      size = std::max(size, std::abs(ds));
    }
    trial.omega[static_cast<size_t>(i)] += u.head<3>();
    trial.length[static_cast<size_t>(i)] += u(3);
    size = std::max(size, u.head<3>().cwiseAbs().maxCoeff() * l);
    size = std::max(size, std::abs(u(3)) / l);
    x = ApplyA(s.chord, x) + s.b * u;
  }
  *step_size = size;
}

// Levenberg-Marquardt on the whole chain from c; returns the iterations made. With accept > 0
// (the largest allowed distance, m, of the automatic segment count), it also stops once a step
// lowers the cost by less than kDecidedDecrease of it with the largest distance within accept
// (the fit is kept), or by less than kDecidedDecreaseFar of it with the largest distance beyond
// kFarFactor accept (the count is rejected).
int RefineChain(const std::vector<Vec3>& points, const std::vector<int>& b, bool free_root,
                int max_iterations, double relative_decrease, Chain* c, double accept = 0.0) {
  std::vector<Stage> stages;
  Chain trial;
  double cost = ChainCost(points, b, *c, nullptr);
  double mu = kInitialDamping;
  int iterations = 0;
  double scale = 0.0;
  for (double l : c->length) scale += l;
  // Rounding: the cost of distances of ~1e-15 L at every point.
  const double floor = static_cast<double>(points.size()) * (1e-15 * scale) * (1e-15 * scale);
  for (int it = 0; it < max_iterations && cost > floor; ++it) {
    ++iterations;
    Linearize(points, b, *c, &stages);
    bool improved = false, tiny = false;
    for (int attempt = 0; attempt < kMaxAttempts; ++attempt) {
      double size = 0.0;
      Step(*c, b, &stages, free_root, mu, &trial, &size);
      if (!(size > kStepTolerance)) {
        tiny = true;
        break;
      }
      bool valid = std::isfinite(size);
      for (double l : trial.length) valid = valid && l > 0.0;
      double worst = 0.0;  // the largest squared distance (m^2)
      const double trial_cost = valid ? ChainCost(points, b, trial, nullptr, &worst) : 0.0;
      if (valid && trial_cost < cost) {
        const double decrease = cost - trial_cost;
        std::swap(*c, trial);
        cost = trial_cost;
        mu = std::max(mu * kDampingDown, kMinimumDamping);
        improved = true;
        // Converged when a step no longer changes the cost (relative): the noise floor of a
        // polyline that is no piecewise helix, or rounding.
        if (decrease <= relative_decrease * (cost + decrease)) tiny = true;
        if (accept > 0.0 &&
            ((worst <= accept * accept && decrease <= kDecidedDecrease * (cost + decrease)) ||
             (worst > kFarFactor * kFarFactor * accept * accept &&
              decrease <= kDecidedDecreaseFar * (cost + decrease)))) {
          tiny = true;
        }
        break;
      }
      mu *= kDampingUp;
    }
    if (tiny || !improved) break;
  }
  return iterations;
}

// The root tangent of a polyline without a frame: the tangent at P0 of the circle through P0, P1,
// P2 (exact for a circular arc, second order in the edge length for a smooth curve, where the
// first edge's direction is only first order). An inversion about P0 maps that circle to the
// line through a / |a|^2 and b / |b|^2 (a = P1 - P0, b = P2 - P0), parallel to the tangent at P0.
// The first edge's direction when there are only 2 points or the points are degenerate.
Vec3 RootTangent(const std::vector<Vec3>& points) {
  const Vec3 a = points[1] - points[0];
  if (points.size() < 3) return a.normalized();
  const Vec3 b = points[2] - points[0];
  const Vec3 t = a / a.squaredNorm() - b / b.squaredNorm();
  if (!t.allFinite() || !(t.norm() > 0.0) || !(t.dot(a) > 0.0)) return a.normalized();
  // A tangent more than 60 degrees from the first edge is no smooth curve's: keep the edge's.
  const Vec3 u = t.normalized();
  return u.dot(a.normalized()) > 0.5 ? u : Vec3(a.normalized());
}

// The fit of one segment alone from the frame (r, q) (FitSegment on the points of segment i in
// that frame); fills the segment's unknowns in *chain.
int GreedySegment(const std::vector<Vec3>& points, const std::vector<int>& b, int i, const Vec3& r,
                  const Mat3& q, int max_iterations, double relative_decrease, Chain* chain) {
  const int b0 = b[static_cast<size_t>(i)], b1 = b[static_cast<size_t>(i) + 1];
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
  const SegmentFit f = FitSegment(w, fraction, max_iterations, relative_decrease);
  chain->omega[static_cast<size_t>(i)] = f.omega;
  chain->length[static_cast<size_t>(i)] = f.length;
  for (int p = b0 + 1; p < b1; ++p) {
    chain->sigma[static_cast<size_t>(p)] = f.u[static_cast<size_t>(p - b0 - 1)] / f.length;
  }
  return f.iterations;
}

// The fit with n segments (1 <= n <= edges), root to tip with a look-ahead window, then the
// global refinement (the root tangent free when no root frame was given; accept as in
// RefineChain, 0 for a given segment count).
void FitWithSegments(const std::vector<Vec3>& points, const Mat3& root_frame, bool free_root,
                     int n, const FitOptions& options, HelixFit* fit, double accept) {
  const int edges = static_cast<int>(points.size()) - 1;
  const std::vector<int> b = Boundaries(edges, n);
  Chain chain;
  chain.root = root_frame;
  chain.omega.resize(static_cast<size_t>(n));
  chain.length.resize(static_cast<size_t>(n));
  chain.sigma.assign(points.size(), 1.0);
  fit->iterations = 0;
  int window = kWindow;
  if (options.refine_iterations == 0) window = 1;
  // Without a refinement the single segments are the result: fitted to the end (rounding).
  const double start_decrease = options.refine_iterations == 0 ? 0.0 : kStartRelativeDecrease;
  // Segments [i, i + window) are fitted together from the frame (r, q) at the start of segment
  // i (the root's tilt free in the first window), then segment i is kept: its end tangent is
  // fitted to the following segments' points too, so that the noise of one segment's points is
  // not passed on to the next one as a wrong start tangent.
  Mat3 q = root_frame;
  Vec3 r = points[0];
  int initialized = 0;  // segments [0, initialized) have initial values
  for (int i = 0; i < n; ++i) {
    const int last = std::min(i + window, n);
    // Initial values of the segments entering the window: greedy from the window's end frame.
    Mat3 qe = q;
    Vec3 re = r;
    for (int k = i; k < last; ++k) {
      if (k >= initialized) {
        fit->iterations += GreedySegment(points, b, k, re, qe, options.max_iterations,
                                         start_decrease, &chain);
        initialized = k + 1;
      }
      const HelixSegment seg = EvaluateHelixSegment(chain.omega[static_cast<size_t>(k)],
                                                    chain.length[static_cast<size_t>(k)]);
      re += qe * seg.chord;
      qe = qe * seg.rotation;
    }
    if (window > 1) {
      const int p0 = b[static_cast<size_t>(i)];
      std::vector<Vec3> sub_points(points.begin() + p0, points.begin() + b[static_cast<size_t>(last)] + 1);
      sub_points[0] = r;
      std::vector<int> sub_b;
      Chain sub;
      sub.root = q;
      for (int k = i; k <= last; ++k) sub_b.push_back(b[static_cast<size_t>(k)] - p0);
      for (int k = i; k < last; ++k) {
        sub.omega.push_back(chain.omega[static_cast<size_t>(k)]);
        sub.length.push_back(chain.length[static_cast<size_t>(k)]);
      }
      sub.sigma.assign(chain.sigma.begin() + p0, chain.sigma.begin() + b[static_cast<size_t>(last)] + 1);
      fit->iterations +=
          RefineChain(sub_points, sub_b, free_root && i == 0, options.refine_iterations,
                      kStartRelativeDecrease, &sub);
      for (int k = i; k < last; ++k) {
        chain.omega[static_cast<size_t>(k)] = sub.omega[static_cast<size_t>(k - i)];
        chain.length[static_cast<size_t>(k)] = sub.length[static_cast<size_t>(k - i)];
      }
      std::copy(sub.sigma.begin(), sub.sigma.end(), chain.sigma.begin() + p0);
      if (i == 0) {
        chain.root = sub.root;
        q = sub.root;
      }
    }
    const HelixSegment seg = EvaluateHelixSegment(chain.omega[static_cast<size_t>(i)],
                                                  chain.length[static_cast<size_t>(i)]);
    r += q * seg.chord;
    q = q * seg.rotation;
  }
  if (options.refine_iterations > 0) {
    fit->iterations += RefineChain(points, b, free_root, options.refine_iterations,
                                   kRelativeDecrease, &chain, accept);
  }
  if (free_root) {
    // Back to the n1 rule for the refined tangent: F = Q0 Rz with Rz a turn about e3; the same
    // centreline has the frame Q Rz everywhere and the curvatures Rz^T Omega.
    const Mat3 frame = DefaultRootFrame(chain.root.col(2), options.n1_axis);
    const Mat3 rz = chain.root.transpose() * frame;
    for (Vec3& omega : chain.omega) omega = rz.transpose() * omega;
    chain.root = frame;
  }
  std::vector<double> distances;
  ChainCost(points, b, chain, &distances);
  fit->root_position = points[0];
  fit->root_frame = chain.root;
  fit->segment_lengths = chain.length;
  fit->curvatures.resize(3 * n);
  fit->arc_lengths.assign(points.size(), 0.0);
  double s = 0.0, max_d = 0.0, sum_d2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const double l = chain.length[static_cast<size_t>(i)];
    fit->curvatures.segment<3>(3 * i) = chain.omega[static_cast<size_t>(i)];
    for (int p = b[static_cast<size_t>(i)] + 1; p < b[static_cast<size_t>(i) + 1]; ++p) {
      fit->arc_lengths[static_cast<size_t>(p)] = s + chain.sigma[static_cast<size_t>(p)] * l;
    }
    s += l;
    fit->arc_lengths[static_cast<size_t>(b[static_cast<size_t>(i) + 1])] = s;
  }
  for (double d : distances) {
    max_d = std::max(max_d, d);
    sum_d2 += d * d;
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
  if (refine_iterations < 0) return Fail(why, "fit refine_iterations: expected an integer >= 0");
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
    frame = DefaultRootFrame(RootTangent(points), options.n1_axis);
  }
  const bool free_root = root_frame == nullptr;
  const int edges = static_cast<int>(points.size()) - 1;
  if (options.segments > 0) {
    FitWithSegments(points, frame, free_root, std::min(options.segments, edges), options, fit,
                    0.0);
    return true;
  }
  // The smallest n of 1, 2, 4, ... (capped at the edge count) meeting the tolerance.
  const double allowed = options.tolerance * polyline;
  std::vector<int> levels;
  for (int n = 1;; n = std::min(2 * n, edges)) {
    levels.push_back(n);
    if (n == edges) break;
  }
  const int last = static_cast<int>(levels.size()) - 1;
  auto fit_level = [&](int index, HelixFit* out) {
    FitWithSegments(points, frame, free_root, levels[static_cast<size_t>(index)], options, out,
                    allowed);
    return out->max_distance <= allowed;
  };
  // One segment first. Its largest distance e1 predicts the count: a piecewise helix's distance
  // falls by ~4x or more per doubling of n on smooth curves (the segment length squared, or
  // faster), so the search starts at the first n of the sequence with n^2 >= e1 / allowed and
  // goes down while the count still passes, or up until one does. The partitions are nested
  // (b_i = floor(i m / n): every break of n is one of 2 n), so a count that fails has every
  // smaller count failing too for the best fits, and the search finds the same smallest n as
  // trying 1, 2, 4, ... in turn without fitting the rejected small counts: a 16-segment strand
  // of the head fits 1, 8 and 16 instead of 1, 2, 4, 8 and 16. The fits are local minima: 3 of
  // the head's 50,000 strands get a larger count than in turn (a count failed while a smaller
  // one passed), all 1,000 of a subset the same (docs/benchmarks.md).
  if (fit_level(0, fit) || last == 0) return true;
  const double ratio = fit->max_distance / allowed;
  int start = 1;
  while (start < last && static_cast<double>(levels[static_cast<size_t>(start)]) *
                                 static_cast<double>(levels[static_cast<size_t>(start)]) <
                             ratio) {
    ++start;
  }
  HelixFit trial;
  if (fit_level(start, &trial)) {
    *fit = std::move(trial);
    for (int index = start - 1; index >= 1; --index) {
      if (!fit_level(index, &trial)) break;
      *fit = std::move(trial);
    }
    return true;
  }
  for (int index = start + 1;; ++index) {
    if (fit_level(index, fit) || index == last) break;
  }
  return true;
}

bool FitPiecewiseHelices(const std::vector<std::vector<Vec3>>& polylines,
                         const FitOptions& options, int threads, std::vector<HelixFit>* fits,
                         int* failed, std::string* why, const ProgressCallback& progress) {
  const int total = static_cast<int>(polylines.size());
  std::mutex progress_mutex;  // progress calls are serialized (solve_strands.h)
  int finished = 0;
  std::vector<HelixFit> out(polylines.size());
  std::vector<std::string> reasons(polylines.size());
  std::vector<char> ok(polylines.size(), 1);
  // Each fit depends on its polyline alone, so any split gives the same fits.
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, total), [&](const tbb::blocked_range<int>& r) {
      for (int i = r.begin(); i < r.end(); ++i) {
        const size_t k = static_cast<size_t>(i);
        ok[k] = FitPiecewiseHelix(polylines[k], nullptr, options, &out[k], &reasons[k]) ? 1 : 0;
        if (progress) {
          std::lock_guard<std::mutex> lock(progress_mutex);
          progress(++finished, total);
        }
      }
    });
  });
  for (size_t k = 0; k < polylines.size(); ++k) {
    if (!ok[k]) {
      if (failed) *failed = static_cast<int>(k);
      return Fail(why, reasons[k]);
    }
  }
  *fits = std::move(out);
  return true;
}

}  // namespace ringlet
