// Inverse statics (inverse.h): the rest shape against the closed form of a straight cantilever,
// round trips through the forward solver (gravity, contact), the sag of the naive rest shape,
// Greenhill's column below and above its critical load, and the piecewise-helix fit against
// known piecewise helices, circles and helices in closed form.
#include "ringlet/inverse.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "reference/greenhill.h"
#include "ringlet/kirchhoff.h"
#include "ringlet/obstacle.h"
#include "ringlet/strand_geometry.h"
#include "test_util.h"

namespace ringlet {
namespace {

using testing::HorizontalFrame;
using testing::MakeStrand;
using testing::RandomCurvatures;
using testing::RandomRotation;

constexpr double kPi = 3.14159265358979323846;

// A sphere with its exact signed distance (independent of src/body).
class SphereObstacle final : public Obstacle {
 public:
  SphereObstacle(const Vec3& c, double r) : c_(c), r_(r) {}
  double SignedDistance(const Vec3& x, Vec3* gradient) const override {
    const Vec3 d = x - c_;
    const double n = d.norm();
    if (gradient) *gradient = n > 0.0 ? Vec3(d / n) : Vec3(0, 0, 1);
    return n - r_;
  }

 private:
  Vec3 c_;
  double r_;
};

// Root frame with the tangent straight down (t = -z, n1 = +x, n2 = t x n1 = -y).
Mat3 DownFrame() {
  Mat3 q;
  q.col(0) = Vec3(1, 0, 0);
  q.col(1) = Vec3(0, -1, 0);
  q.col(2) = Vec3(0, 0, -1);
  return q;
}

// A straight horizontal target (q = 0) of a circular strand: the bending moment of the weight w
// per length hanging beyond s is M(s) = w (L - s)^2 / 2, so the rest curvature that holds it
// straight, averaged over segment i, is (1 / (l_i EI)) int_segment M ds
//   = w ((L - s_i)^3 - (L - s_(i+1))^3) / (6 EI l_i),
// curling up (kappa2 > 0 with HorizontalFrame: n2 = -y, dt/ds = kappa2 n2 x t = kappa2 z), and
// nothing about the other axes.
TEST(InverseRestCurvatures, StraightCantileverMatchesTheBendingMoment) {
  StrandModel m = MakeStrand(0.15, 9, 0.0, Vec3(30.0, 0.0, 5.0), HorizontalFrame());
  m.segment_lengths = GradedSegments(0.15, 9, 2.5);
  const VecX rest = InverseRestCurvatures(m, VecX::Zero(27));
  const double w = m.WeightPerLength().norm();
  const double ei = m.Stiffness()(1);
  const double length = m.Length();
  double s = 0.0;
  for (int i = 0; i < 9; ++i) {
    const double l = m.segment_lengths[i];
    const double expected =
        w * (std::pow(length - s, 3) - std::pow(length - s - l, 3)) / (6.0 * ei * l);
    EXPECT_NEAR(rest(3 * i + 1), expected, 1e-12 * std::abs(expected)) << i;
    EXPECT_NEAR(rest(3 * i), 0.0, 1e-12 * expected) << i;
    EXPECT_NEAR(rest(3 * i + 2), 0.0, 1e-12 * expected) << i;
    s += l;
  }
  EXPECT_GT(rest(1), 1.0);  // a visible curl (1/m): the check is not vacuous
}

// Random curly hanging targets with gravity (25 cm, 20 segments, w L^3 / EI = 31, curvatures
// (40, 0, 10) 1/m plus uniform noise of +-15 1/m). Random shapes are not all holdable: the
// certificate decides. For every target, Kirchhoff's balance by quadrature (independent of the
// gradient that produced q0) holds at the target. A target certified stable stays put in the
// forward solve started at it (<= 1e-6 L) and is also reached from the gravity-free rest shape
// (the solver's default start, far away), while the naive rest shape (q0 = target) sags
// visibly; a target reported unstable is left by the forward solve for a stable equilibrium.
// Measured with seeds 1-8: 4 stable (naive sag 0.27-0.32 L, scaled eigenvalues 0.12-0.20), 4
// unstable (eigenvalues -0.13 to -0.40).
TEST(InvertStrand, CurlyHangingTargetsHoldOrAreReportedUnstable) {
  int stable = 0;
  for (unsigned seed = 1; seed <= 8; ++seed) {
    const int n = 20;
    StrandModel m = MakeStrand(0.25, n, 0.4, Vec3::Zero(), DownFrame());
    VecX q = RandomCurvatures(n, 15.0, seed);
    for (int i = 0; i < n; ++i) q.segment<3>(3 * i) += Vec3(40.0, 0.0, 10.0);
    const InverseResult r = InvertStrand(m, q);
    SCOPED_TRACE(r.message);
    std::printf("seed %u: %s\n", seed, r.message.c_str());
    EXPECT_LT(r.kirchhoff_residual, 1e-12);
    ASSERT_TRUE(r.forward.Converged());
    EXPECT_TRUE(r.forward.stable);
    EXPECT_EQ(r.stable, r.min_eigenvalue > 0.0);
    if (!r.stable) {
      EXPECT_GT(r.deviation, 1e-3 * m.Length());
      continue;
    }
    ++stable;
    EXPECT_LE(r.deviation, 1e-6 * m.Length());
    EXPECT_GT(r.naive_deviation, 0.05 * m.Length());
    StrandModel inverted = m;
    inverted.rest_curvatures = r.rest_curvatures;
    const StrandSolution from_rest = SolveStrand(inverted, InverseOptions{}.solver);
    ASSERT_TRUE(from_rest.summary.Converged());
    EXPECT_GT(CentrelineDeviation(m, r.rest_curvatures, q, 4), 0.05 * m.Length());
    EXPECT_LE(CentrelineDeviation(m, from_rest.curvatures, q, 4), 1e-6 * m.Length());
  }
  EXPECT_GE(stable, 4);  // anti-vacuity: most targets are held
}

// With body contact: the target is the equilibrium of a known rest shape draped on a sphere
// (ringlet's own groom, contact forces included). The inversion recovers that rest shape, to the
// forward solve's tolerance, and the target holds.
TEST(InvertStrand, RoundTripWithContactRecoversTheRestShape) {
  for (unsigned seed : {5u, 6u}) {
    const int n = 16;
    StrandModel m = MakeStrand(0.25, n, 0.0, Vec3(-20.0, 0.0, 5.0), HorizontalFrame());
    m.root_position = Vec3(0, 0, 0.1);
    m.contact.obstacle = std::make_shared<SphereObstacle>(Vec3::Zero(), 0.1);
    m.contact.clearance = 0.002;
    m.rest_curvatures = m.NaturalCurvatures() + RandomCurvatures(n, 5.0, seed);
    SolveOptions tight;
    tight.tolerance = 1e-12;
    const StrandSolution groom = SolveStrand(m, tight);
    ASSERT_TRUE(groom.summary.Converged()) << groom.summary.message;
    ASSERT_GT(groom.summary.contact.samples_in_contact, 0);  // it does rest on the sphere

    const InverseResult r = InvertStrand(m, groom.curvatures);
    SCOPED_TRACE(r.message);
    const double scale = m.rest_curvatures.cwiseAbs().maxCoeff();
    EXPECT_LE((r.rest_curvatures - m.rest_curvatures).cwiseAbs().maxCoeff(), 1e-7 * scale);
    EXPECT_TRUE(r.stable);
    EXPECT_LE(r.deviation, 1e-6 * m.Length());
    EXPECT_GT(r.naive_deviation, 0.01 * m.Length());
  }
}

// Greenhill's column (reference/greenhill.h): a straight strand standing up, target q = 0. The
// gravity moment about the axis vanishes, so q0 = 0; the Hessian at the target decides. With
// n = 30 segments the discrete critical load is 7.84004 (greenhill_test.cpp,
// DiscreteCriticalLoadFromTheHessianConverges), and the scaled Hessian's smallest eigenvalue is
// exactly 1 - lambda / 7.84004 at the straight state. Below: stable, held. Above: reported
// unstable, and the closest stable alternative (the forward solve leaving along the negative
// curvature) is the buckled column, far from the target.
TEST(InvertStrand, GreenhillBelowAndAboveTheCriticalLoad) {
  const int n = 30;
  const double discrete_critical = 7.84004;
  for (double factor : {0.95, 1.05}) {
    StrandModel m = MakeStrand(0.05, n, 0.0, Vec3::Zero(), Mat3::Identity());  // t = +z
    const double load = factor * reference::kGreenhillPublished;
    m.material.density =
        load * m.Stiffness()(0) / (std::pow(m.Length(), 3) * m.section.Area() * m.gravity.norm());
    ASSERT_NEAR(m.GravityParameter(), load, 1e-12 * load);
    const InverseResult r = InvertStrand(m, VecX::Zero(3 * n));
    SCOPED_TRACE(r.message);
    EXPECT_LE(r.rest_curvatures.cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_NEAR(r.min_eigenvalue, 1.0 - load / discrete_critical, 2e-4);
    if (factor < 1.0) {
      EXPECT_TRUE(r.stable);
      EXPECT_EQ(r.failed_segment, -1);
      EXPECT_LE(r.deviation, 1e-9 * m.Length());
    } else {
      EXPECT_FALSE(r.stable);
      EXPECT_GE(r.failed_segment, 0);
      ASSERT_TRUE(r.forward.Converged());
      EXPECT_TRUE(r.forward.stable);              // the alternative is a stable equilibrium
      EXPECT_GT(r.forward.stability_restarts, 0);  // reached by leaving the target
      EXPECT_GT(r.deviation, 0.05 * m.Length());
      EXPECT_NE(r.message.find("UNSTABLE"), std::string::npos);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Fit.

// Largest distance between the centreline of (m, q) and that of a fit with the same segment
// count, sampled at 8 points per segment (at the same fractions of each segment's length).
double CentrelineGap(const StrandModel& m, const VecX& q, const HelixFit& fit) {
  StrandModel f = m;
  f.segment_lengths = fit.segment_lengths;
  f.root_position = fit.root_position;
  f.root_frame = fit.root_frame;
  const std::vector<Vec3> a = SampleCentreline(m, q, 8), b = SampleCentreline(f, fit.curvatures, 8);
  double gap = 0.0;
  for (size_t k = 0; k < a.size(); ++k) gap = std::max(gap, (a[k] - b[k]).norm());
  return gap;
}

// A polyline sampled at exact arc lengths from a known piecewise helix (4 points per segment,
// breaks at points) is recovered to rounding: distances, lengths and curvatures.
TEST(FitPiecewiseHelix, RecoversAKnownPiecewiseHelix) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const int n = 8;
    StrandModel m = MakeStrand(0.2, n, 0.0, Vec3::Zero(), RandomRotation(seed));
    m.segment_lengths = GradedSegments(0.2, n, 2.0);
    m.root_position = Vec3(0.01, -0.02, 0.3);
    VecX q = RandomCurvatures(n, 40.0, seed + 10);
    const std::vector<Vec3> points = SampleCentreline(m, q, 4);
    FitOptions options;
    options.segments = n;
    HelixFit fit;
    std::string why;
    ASSERT_TRUE(FitPiecewiseHelix(points, &m.root_frame, options, &fit, &why)) << why;
    EXPECT_LE(fit.max_distance, 1e-9 * m.Length());
    EXPECT_NEAR(fit.length, m.Length(), 1e-9 * m.Length());
    for (int i = 0; i < n; ++i) {
      EXPECT_NEAR(fit.segment_lengths[i], m.segment_lengths[i], 1e-9 * m.Length()) << i;
    }
    EXPECT_LE((fit.curvatures - q).cwiseAbs().maxCoeff(), 1e-6 * q.cwiseAbs().maxCoeff());
    // The arc length of each point: 4 per segment, at j l_i / 4.
    EXPECT_NEAR(fit.arc_lengths[6], m.segment_lengths[0] + 0.5 * m.segment_lengths[1],
                1e-9 * m.Length());
  }
}

// Without the root frame (as from a .hair file) the same polylines are recovered to rounding:
// the root tangent is an unknown of the global refinement (the first edge's direction is off by
// half the edge's turning angle, several degrees here, and the greedy fit alone carries that
// error along the strand). The curvatures are compared after turning the true ones by the gauge
// rotation about the root tangent between the two root frames (a turn Rz of the root frame about
// t leaves the centreline and turns every (kappa1, kappa2) by Rz^T).
TEST(FitPiecewiseHelix, RecoversAKnownPiecewiseHelixWithoutItsRootFrame) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const int n = 8;
    StrandModel m = MakeStrand(0.2, n, 0.0, Vec3::Zero(), RandomRotation(seed));
    m.segment_lengths = GradedSegments(0.2, n, 2.0);
    m.root_position = Vec3(0.01, -0.02, 0.3);
    const VecX q = RandomCurvatures(n, 40.0, seed + 10);
    const std::vector<Vec3> points = SampleCentreline(m, q, 4);
    FitOptions options;
    options.segments = n;
    HelixFit fit;
    std::string why;
    ASSERT_TRUE(FitPiecewiseHelix(points, nullptr, options, &fit, &why)) << why;
    EXPECT_LE(fit.max_distance, 1e-9 * m.Length()) << seed;
    EXPECT_NEAR(fit.root_frame.col(2).dot(m.root_frame.col(2)), 1.0, 1e-12) << seed;
    EXPECT_NEAR(fit.length, m.Length(), 1e-9 * m.Length());
    const Mat3 rz = m.root_frame.transpose() * fit.root_frame;  // a turn about e3
    EXPECT_NEAR(rz(2, 2), 1.0, 1e-12);
    for (int i = 0; i < n; ++i) {
      EXPECT_NEAR(fit.segment_lengths[i], m.segment_lengths[i], 1e-9 * m.Length()) << i;
      const Vec3 expected = rz.transpose() * q.segment<3>(3 * i);
      EXPECT_LE((fit.curvatures.segment<3>(3 * i) - expected).cwiseAbs().maxCoeff(),
                1e-6 * q.cwiseAbs().maxCoeff())
          << seed << " " << i;
    }
    // The greedy initialization alone (no refinement) is far from it: what the refinement buys.
    options.refine_iterations = 0;
    HelixFit greedy;
    ASSERT_TRUE(FitPiecewiseHelix(points, nullptr, options, &greedy, &why)) << why;
    std::printf("seed %u: free root, refined max %.3g L, greedy alone %.3g L\n", seed,
                fit.max_distance / m.Length(), greedy.max_distance / m.Length());
  }
}

// The same target rounded to float (what a .hair file holds, 7 significant digits; coordinates
// up to 0.5 m here, so rounding moves points by at most 0.5 * 2^-24 m = 3e-8 m = 1.5e-7 L): the
// fit without the root frame follows the rounded points, its largest distance is of the order
// of the rounding, not of the 0.075 L that the greedy fit left on such files (docs/inverse.md).
TEST(FitPiecewiseHelix, FloatRoundedPiecewiseHelixIsFittedToTheRounding) {
  const int n = 15;
  StrandModel m = MakeStrand(0.25, n, 0.0, Vec3::Zero(), DownFrame());
  m.root_position = Vec3(0.02, 0.05, 0.45);
  const VecX q = RandomCurvatures(n, 60.0, 7);
  std::vector<Vec3> points = SampleCentreline(m, q, 4);
  for (Vec3& p : points) p = p.cast<float>().cast<double>();
  FitOptions options;
  options.segments = n;
  HelixFit fit;
  std::string why;
  ASSERT_TRUE(FitPiecewiseHelix(points, nullptr, options, &fit, &why)) << why;
  EXPECT_LE(fit.max_distance, 3e-8);
  EXPECT_LE(CentrelineGap(m, q, fit), 1e-6 * m.Length());
}

// A circular arc of radius R over 2 rad, written with cos and sin (not the helix code), with its
// exact tangent at the root: one segment of curvature 1/R about the arc's binormal, no twist,
// length 2 R.
TEST(FitPiecewiseHelix, CircleArcAgainstClosedForm) {
  const double radius = 0.04;
  std::vector<Vec3> points;
  for (int j = 0; j <= 12; ++j) {
    const double a = 2.0 * j / 12.0;
    points.push_back(Vec3(radius * std::sin(a), 0.0, radius * (1.0 - std::cos(a))));
  }
  // t = +x at the root, the circle turns toward +z: with n1 = +z (HorizontalFrame), the arc
  // bends about n2 = -y with kappa2 = 1/R.
  const Mat3 frame = HorizontalFrame();
  FitOptions options;
  options.segments = 1;
  HelixFit fit;
  std::string why;
  ASSERT_TRUE(FitPiecewiseHelix(points, &frame, options, &fit, &why)) << why;
  EXPECT_NEAR(fit.length, 2.0 * radius, 1e-12);
  EXPECT_NEAR(fit.curvatures(1), 1.0 / radius, 1e-9 / radius);
  EXPECT_NEAR(fit.curvatures(0), 0.0, 1e-9 / radius);
  EXPECT_NEAR(fit.curvatures(2), 0.0, 1e-9 / radius);
  EXPECT_LE(fit.max_distance, 1e-12);
}

// A circular helix x = R cos t, y = R sin t, z = c t has curvature R / (R^2 + c^2), torsion
// c / (R^2 + c^2) and arc length sqrt(R^2 + c^2) t. With n1 the principal normal at the root
// (-x) and t the tangent, one segment fits it with Omega = (0, kappa, torsion): dt/ds = kappa n1
// = Omega x t requires kappa2 = kappa, and the Frenet frame twists at the torsion.
TEST(FitPiecewiseHelix, HelixAgainstClosedForm) {
  const double r = 0.01, c = 0.004, turns = 1.5;
  std::vector<Vec3> points;
  for (int j = 0; j <= 30; ++j) {
    const double t = 2.0 * kPi * turns * j / 30.0;
    points.push_back(Vec3(r * std::cos(t), r * std::sin(t), c * t));
  }
  const double speed = std::hypot(r, c);
  Mat3 frame;
  frame.col(2) = Vec3(0.0, r, c) / speed;  // unit tangent at t = 0
  frame.col(0) = Vec3(-1.0, 0.0, 0.0);     // principal normal
  frame.col(1) = frame.col(2).cross(frame.col(0));
  FitOptions options;
  options.segments = 1;
  HelixFit fit;
  std::string why;
  ASSERT_TRUE(FitPiecewiseHelix(points, &frame, options, &fit, &why)) << why;
  const double kappa = r / (r * r + c * c), torsion = c / (r * r + c * c);
  EXPECT_NEAR(fit.curvatures(0), 0.0, 1e-8 * kappa);
  EXPECT_NEAR(fit.curvatures(1), kappa, 1e-8 * kappa);
  EXPECT_NEAR(fit.curvatures(2), torsion, 1e-8 * kappa);
  EXPECT_NEAR(fit.length, speed * 2.0 * kPi * turns, 1e-10);
  EXPECT_LE(fit.max_distance, 1e-11);
}

// A planar curve that is no piecewise helix (a parabola z = x^2 / (2 a), a = 0.05 m, 64 edges)
// with its exact root tangent (+x): the automatic segment count meets the tolerance 1e-3 L and
// half as many segments do not. Measured largest distances: 2.2e-4 L with 8 segments, 4.1e-3 L
// with 4 (the greedy fit before the global refinement needed 32 segments). Without a root frame
// the root tangent is fitted too: it ends closer to the true one (+x) than the first edge's
// direction (1.8 degrees off), and the tolerance is met with as few segments.
TEST(FitPiecewiseHelix, AutomaticSegmentCountMeetsTheTolerance) {
  std::vector<Vec3> points;
  for (int j = 0; j <= 64; ++j) {
    const double x = 0.2 * j / 64.0;
    points.push_back(Vec3(x, 0.0, x * x / 0.1));
  }
  double polyline = 0.0;
  for (size_t j = 1; j < points.size(); ++j) polyline += (points[j] - points[j - 1]).norm();
  const Mat3 frame = HorizontalFrame();  // t = +x, the parabola's tangent at its vertex
  FitOptions options;
  options.tolerance = 1e-3;
  HelixFit fit;
  std::string why;
  ASSERT_TRUE(FitPiecewiseHelix(points, &frame, options, &fit, &why)) << why;
  const int chosen = fit.NumSegments();
  EXPECT_LE(fit.max_distance, 1e-3 * polyline);
  EXPECT_EQ(chosen, 8);
  EXPECT_LE(fit.rms_distance, fit.max_distance);
  options.segments = chosen / 2;
  HelixFit coarse;
  ASSERT_TRUE(FitPiecewiseHelix(points, &frame, options, &coarse, &why)) << why;
  EXPECT_GT(coarse.max_distance, 1e-3 * polyline);
  std::printf("parabola: %d segments, max %.3g L, rms %.3g L; %d segments: max %.3g L\n", chosen,
              fit.max_distance / polyline, fit.rms_distance / polyline, chosen / 2,
              coarse.max_distance / polyline);

  options.segments = 0;
  HelixFit free_root;
  ASSERT_TRUE(FitPiecewiseHelix(points, nullptr, options, &free_root, &why)) << why;
  EXPECT_LE(free_root.max_distance, 1e-3 * polyline);
  EXPECT_LE(free_root.NumSegments(), chosen);
  const double edge_angle = std::acos((points[1] - points[0]).normalized().x());
  const double fitted_angle = std::atan2(free_root.root_frame.col(2).tail<2>().norm(),
                                         free_root.root_frame.col(2).x());
  EXPECT_LT(fitted_angle, edge_angle);
  std::printf("free root: %d segments, root tangent %.3g rad off (first edge %.3g rad)\n",
              free_root.NumSegments(), fitted_angle, edge_angle);
}

// A closed-form error bound on a curve that is no piecewise helix: the parabola z = x^2 / (2a)
// (a = 0.05 m, x in [0, 0.2], 64 edges equal in x), fitted with n = 4, 8, 16, 32 segments.
// The fit minimizes the sum of squared distances over every G1 piecewise helix with breaks at
// the same points, so its RMS distance is at most that of any such curve. One of them, C, has
// segment i of the parabola's own arc length h_i and the constant curvature
// (theta(s_(i+1)) - theta(s_i)) / h_i (theta = atan(x / a), the tangent angle): its tangent angle
// is the linear interpolant of theta, off by at most max|theta''| h_i^2 / 8 = max|kappa'| h^2 / 8,
// so its points at the parabola's arc lengths are off by at most
//   B = max|kappa'| sum_i h_i^3 / 8,  max|kappa'| = 3 (5/6)^3 / (sqrt(5) a^2)
// (kappa' = -3 x / (a^3 (1 + x^2/a^2)^3), largest at x = a / sqrt 5). Checked: the fit's RMS is
// at most C's (computed here in 2-D with sin and cos, independently of the helix code) and at
// most B, with the exact root tangent and without it (C has the exact one, which the free fit
// may also take).
TEST(FitPiecewiseHelix, ParabolaWithinTheClosedFormBound) {
  const double a = 0.05;
  const int edges = 64;
  std::vector<Vec3> points;
  std::vector<double> arc;  // the parabola's arc length at each point
  for (int j = 0; j <= edges; ++j) {
    const double x = 0.2 * j / edges;
    points.push_back(Vec3(x, 0.0, x * x / (2.0 * a)));
    arc.push_back(0.5 * x * std::sqrt(1.0 + x * x / (a * a)) + 0.5 * a * std::asinh(x / a));
  }
  const double dkappa = 3.0 * 125.0 / 216.0 / (std::sqrt(5.0) * a * a);
  const Mat3 frame = HorizontalFrame();  // t = +x, the parabola's tangent at its vertex
  for (int n : {4, 8, 16, 32}) {
    double bound = 0.0, candidate2 = 0.0;
    double cx = 0.0, cz = 0.0;  // C's position at the start of the segment
    for (int i = 0; i < n; ++i) {
      const int b0 = i * edges / n, b1 = (i + 1) * edges / n;
      const double h = arc[b1] - arc[b0];
      bound += dkappa * h * h * h / 8.0;
      const double t0 = std::atan(points[b0].x() / a), t1 = std::atan(points[b1].x() / a);
      const double k = (t1 - t0) / h;
      for (int j = b0 + 1; j <= b1; ++j) {
        const double u = arc[j] - arc[b0];
        const double x = cx + (std::sin(t0 + k * u) - std::sin(t0)) / k;
        const double z = cz - (std::cos(t0 + k * u) - std::cos(t0)) / k;
        candidate2 += std::pow(x - points[j].x(), 2) + std::pow(z - points[j].z(), 2);
        if (j == b1) cx = x, cz = z;
      }
    }
    const double candidate = std::sqrt(candidate2 / static_cast<double>(points.size()));
    FitOptions options;
    options.segments = n;
    HelixFit fixed, free_root;
    std::string why;
    ASSERT_TRUE(FitPiecewiseHelix(points, &frame, options, &fixed, &why)) << why;
    ASSERT_TRUE(FitPiecewiseHelix(points, nullptr, options, &free_root, &why)) << why;
    EXPECT_LE(candidate, bound) << n;  // the bound's own derivation
    EXPECT_LE(fixed.rms_distance, candidate * (1.0 + 1e-9)) << n;
    EXPECT_LE(free_root.rms_distance, candidate * (1.0 + 1e-9)) << n;
    std::printf("parabola, %d segments: rms %.3g L (free root %.3g L), max %.3g L (%.3g L); "
                "C %.3g L, bound %.3g L\n",
                n, fixed.rms_distance / arc.back(), free_root.rms_distance / arc.back(),
                fixed.max_distance / arc.back(), free_root.max_distance / arc.back(),
                candidate / arc.back(), bound / arc.back());
  }
}

TEST(FitPiecewiseHelix, BadInputNamesThePoint) {
  FitOptions options;
  HelixFit fit;
  std::string why;
  EXPECT_FALSE(FitPiecewiseHelix({Vec3::Zero()}, nullptr, options, &fit, &why));
  EXPECT_NE(why.find("at least 2 points"), std::string::npos) << why;
  EXPECT_FALSE(FitPiecewiseHelix({Vec3::Zero(), Vec3(1, 0, 0), Vec3(1, 0, 0)}, nullptr, options,
                                 &fit, &why));
  EXPECT_NE(why.find("point 2: repeats point 1"), std::string::npos) << why;
  EXPECT_FALSE(FitPiecewiseHelix({Vec3::Zero(), Vec3(std::nan(""), 0, 0)}, nullptr, options, &fit,
                                 &why));
  EXPECT_NE(why.find("point 1: not finite"), std::string::npos) << why;
}

TEST(DefaultRootFrame, ProjectsTheAxisAndFallsBackNearTheTangent) {
  const Mat3 f = DefaultRootFrame(Vec3(1, 0, 1), Vec3::UnitZ());
  EXPECT_NEAR((f.transpose() * f - Mat3::Identity()).norm(), 0.0, 1e-15);
  EXPECT_NEAR(f.determinant(), 1.0, 1e-15);
  EXPECT_NEAR(f.col(0).dot(Vec3(-1, 0, 1).normalized()), 1.0, 1e-15);  // z projected
  const Mat3 g = DefaultRootFrame(Vec3(0, 0.1, 1), Vec3::UnitZ());      // z too close to t
  EXPECT_NEAR(g.col(0).dot(Vec3::UnitX()), 1.0, 1e-15);                 // x: least aligned
}

}  // namespace
}  // namespace ringlet
