// Closed-form helical segments against an independent numerical integration of the frame ODE
// (the paper's eq. 1), and the Taylor branches near zero curvature.
#include "ringlet/helix.h"
#include "ringlet/helix_jacobian.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "ringlet/strand_geometry.h"
#include "test_util.h"

namespace ringlet {
namespace {

// Reference: classical RK4 on dQ/du = Q [Omega]x, dP/du = Q e3, dC/du = P (so that C(l) =
// int_0^l P = the first moment c), starting from Q = I, P = C = 0. Written here, sharing no code
// with the library. With 2000 steps per radian of turn the global error is ~ x (1/2000)^4 / 100,
// far below 1e-12.
struct OdeState {
  Mat3 q;
  Vec3 p, c;
};
OdeState Derivative(const OdeState& s, const Mat3& w) {
  return OdeState{s.q * w, s.q.col(2), s.p};
}
OdeState Axpy(const OdeState& s, double h, const OdeState& d) {
  return OdeState{s.q + h * d.q, s.p + h * d.p, s.c + h * d.c};
}
OdeState IntegrateFrameOde(const Vec3& omega, double length, int steps) {
  Mat3 w;
  w << 0, -omega.z(), omega.y(), omega.z(), 0, -omega.x(), -omega.y(), omega.x(), 0;
  OdeState s{Mat3::Identity(), Vec3::Zero(), Vec3::Zero()};
  const double h = length / steps;
  for (int k = 0; k < steps; ++k) {
    const OdeState k1 = Derivative(s, w);
    const OdeState k2 = Derivative(Axpy(s, h / 2, k1), w);
    const OdeState k3 = Derivative(Axpy(s, h / 2, k2), w);
    const OdeState k4 = Derivative(Axpy(s, h, k3), w);
    s.q += h / 6 * (k1.q + 2 * k2.q + 2 * k3.q + k4.q);
    s.p += h / 6 * (k1.p + 2 * k2.p + 2 * k3.p + k4.p);
    s.c += h / 6 * (k1.c + 2 * k2.c + 2 * k3.c + k4.c);
  }
  return s;
}

struct HelixCase {
  Vec3 omega;  // 1/m
  double length;
};

class HelixVsOde : public ::testing::TestWithParam<HelixCase> {};

TEST_P(HelixVsOde, MatchesNumericalIntegration) {
  const HelixCase c = GetParam();
  const HelixSegment s = EvaluateHelixSegment(c.omega, c.length);
  const int steps = std::max(4000, static_cast<int>(2000 * c.omega.norm() * c.length));
  const OdeState ref = IntegrateFrameOde(c.omega, c.length, steps);
  const double l = c.length;
  EXPECT_LT((s.rotation - ref.q).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((s.chord - ref.p).norm(), 1e-12 * l);
  EXPECT_LT((s.moment - ref.c).norm(), 1e-12 * l * l);
  // The rotation is a proper rotation to rounding.
  EXPECT_LT((s.rotation.transpose() * s.rotation - Mat3::Identity()).norm(), 1e-14);
}

INSTANTIATE_TEST_SUITE_P(
    Turns, HelixVsOde,
    ::testing::Values(HelixCase{Vec3(50, 0, 10), 0.02},       // curly hair segment, x ~ 1
                      HelixCase{Vec3(0, 0, 0), 0.1},          // straight
                      HelixCase{Vec3(0, 0, 300), 0.05},       // pure twist: chord straight
                      HelixCase{Vec3(3, -4, 12), 0.01},       // small turn (Taylor branch)
                      HelixCase{Vec3(120, 80, -40), 0.03},    // x ~ 4.5 (closed-form branch)
                      HelixCase{Vec3(-900, 200, 500), 0.02},  // several full turns, x ~ 21
                      HelixCase{Vec3(1e-3, 2e-3, 0), 0.2}));

// Limits at zero curvature: exact values, no NaN, continuous with the general case.
TEST(HelixLimits, ZeroCurvature) {
  const HelixSegment s = EvaluateHelixSegment(Vec3::Zero(), 0.3);
  EXPECT_EQ(s.rotation, Mat3::Identity());
  EXPECT_EQ(s.chord, Vec3(0, 0, 0.3));
  EXPECT_DOUBLE_EQ(s.moment.z(), 0.5 * 0.3 * 0.3);
  EXPECT_EQ(s.moment.x(), 0.0);
}

TEST(HelixLimits, TinyCurvature) {
  for (double k : {1e-12, 1e-300}) {
    const Vec3 omega(k, -2 * k, 3 * k);
    const HelixSegment s = EvaluateHelixSegment(omega, 0.2);
    ASSERT_TRUE(s.rotation.allFinite() && s.chord.allFinite() && s.moment.allFinite()) << k;
    EXPECT_NEAR(s.chord.z(), 0.2, 1e-16);
    // First-order bend: chord_x = l^2/2 (Omega x e3)_x = l^2/2 * (-2k) (Omega x e3 = (ky, -kx, 0)).
    EXPECT_NEAR(s.chord.x(), 0.5 * 0.04 * (-2 * k), 1e-6 * 0.04 * k);
    EXPECT_NEAR(s.chord.y(), 0.5 * 0.04 * (-k), 1e-6 * 0.04 * k);
    const Vec3 g = HelixSegmentVjp(omega, 0.2, s.functions, Mat3::Identity(), Vec3(1, 2, 3),
                                   Vec3(-1, 0, 2));
    EXPECT_TRUE(g.allFinite()) << k;
  }
}

// The series and closed-form branches of G_m agree at the switch (x = 2) and G_m(0) = 1/m!.
TEST(HelixFunctions, BranchesAgreeAndLimits) {
  const double factorial[7] = {1, 1, 2, 6, 24, 120, 720};
  const HelixFunctions zero = EvaluateHelixFunctions(0.0);
  for (int m = 1; m <= 6; ++m) EXPECT_DOUBLE_EQ(zero.g[m], 1.0 / factorial[m]);
  const HelixFunctions below = EvaluateHelixFunctions(std::nextafter(2.0, 0.0));
  const HelixFunctions above = EvaluateHelixFunctions(2.0);
  for (int m = 1; m <= 6; ++m) {
    EXPECT_NEAR(below.g[m], above.g[m], 1e-14 / factorial[m]) << "G" << m;
  }
  // Spot values against the defining closed forms, far from both ends.
  const double x = 0.7;
  const HelixFunctions h = EvaluateHelixFunctions(x);
  EXPECT_NEAR(h.g[1], std::sin(x) / x, 1e-16);
  EXPECT_NEAR(h.g[2], (1 - std::cos(x)) / (x * x), 1e-16);
  EXPECT_NEAR(h.g[3], (x - std::sin(x)) / (x * x * x), 1e-15);
  EXPECT_NEAR(h.g[4], (x * x / 2 - 1 + std::cos(x)) / std::pow(x, 4), 1e-14);
}

// The VJP against central differences of the closed forms for one segment, every output.
TEST(HelixVjp, MatchesFiniteDifferences) {
  const double l = 0.03;
  for (const Vec3& omega : {Vec3(40, -20, 15), Vec3(1e-3, 0, 2e-3), Vec3(150, 60, 90)}) {
    const Mat3 dr = testing::RandomRotation(3);
    const Vec3 dp(0.3, -1.2, 0.7), dc(2.0, 0.5, -0.4);
    auto scalar = [&](const Vec3& om) {
      const HelixSegment s = EvaluateHelixSegment(om, l);
      return (dr.cwiseProduct(s.rotation)).sum() + dp.dot(s.chord) + dc.dot(s.moment);
    };
    const HelixSegment s = EvaluateHelixSegment(omega, l);
    const Vec3 g = HelixSegmentVjp(omega, l, s.functions, dr, dp, dc);
    ASSERT_GT(g.norm(), 0.0);
    for (int j = 0; j < 3; ++j) {
      const double h = 1e-4;
      Vec3 plus = omega, minus = omega;
      plus(j) += h;
      minus(j) -= h;
      const double fd = (scalar(plus) - scalar(minus)) / (2 * h);
      EXPECT_NEAR(g(j), fd, 1e-8 * (std::abs(fd) + g.norm())) << "component " << j;
    }
  }
}

// A strand of constant Omega is one helix whatever n: geometry is independent of the split.
TEST(StrandGeometry, SplitInvariance) {
  const Vec3 omega(50, 0, 10);
  StrandModel one = testing::MakeStrand(0.2, 1);
  StrandModel many = testing::MakeStrand(0.2, 37);
  VecX q(3 * 37);
  for (int i = 0; i < 37; ++i) q.segment<3>(3 * i) = omega;
  VecX q1 = omega;
  const StrandGeometry ga = ComputeGeometry(one, q1);
  const StrandGeometry gb = ComputeGeometry(many, q);
  EXPECT_LT((ga.points.back() - gb.points.back()).norm(), 1e-14);
  EXPECT_LT((ga.frames.back() - gb.frames.back()).norm(), 1e-13);
  // Sampled centreline: k points per segment, the ends coincide with the segment ends.
  const std::vector<Vec3> pts = SampleCentreline(many, q, 4);
  ASSERT_EQ(pts.size(), 37u * 4 + 1);
  EXPECT_LT((pts[8] - gb.points[2]).norm(), 1e-15);
}

}  // namespace
}  // namespace ringlet

namespace ringlet {
namespace {

// The chord-only helpers agree with the general closed forms and their derivative.
TEST(HelixChordVjp, MatchesTheGeneralVjpAndTheChord) {
  for (unsigned seed : {1u, 2u, 3u, 4u}) {
    const VecX q = testing::RandomCurvatures(1, seed == 4 ? 1e-4 : 80.0, seed);
    const Vec3 omega = q.segment<3>(0);
    const Vec3 d = testing::RandomCurvatures(1, 1.0, seed + 10).segment<3>(0);
    for (double u : {1e-3, 0.01, 0.04}) {
      const HelixFunctions f = EvaluateHelixFunctions(omega.norm() * u);
      EXPECT_LT((HelixChordFromFunctions(omega, u, f) - HelixChord(omega, u)).norm(), 1e-15);
      const Vec3 general = HelixSegmentVjp(omega, u, f, Mat3::Zero(), d, Vec3::Zero());
      const Vec3 special = HelixChordVjp(omega, u, f, d);
      EXPECT_LT((general - special).norm(), 1e-13 * (general.norm() + 1e-30)) << seed << " " << u;
    }
  }
}

}  // namespace
}  // namespace ringlet

namespace ringlet {
namespace {

// The chord's full Jacobian against central differences of the chord (an independent
// evaluation: EvaluateHelixSegment's closed form, no derivative code), in both branches of the
// G_m (turning angles below and above 2) and near zero curvature; the tangent against the
// rotation's third column.
TEST(HelixChordJacobian, MatchesFiniteDifferencesAndTheRotation) {
  for (const Vec3& omega : {Vec3(40, -20, 15), Vec3(1e-3, 0, 2e-3), Vec3(150, 60, 90),
                            Vec3(0, 0, 0)}) {
    for (double u : {1e-3, 0.01, 0.04}) {
      const HelixFunctions f = EvaluateHelixFunctions(omega.norm() * u);
      const Mat3 jac = HelixChordJacobian(omega, u, f);
      for (int j = 0; j < 3; ++j) {
        const double h = 1e-4;
        Vec3 plus = omega, minus = omega;
        plus(j) += h;
        minus(j) -= h;
        const Vec3 fd = (HelixChord(plus, u) - HelixChord(minus, u)) / (2 * h);
        // Central differences: error ~h^2 u^4 |p'''| ~ 1e-8 u^2 relative here.
        EXPECT_LT((jac.col(j) - fd).norm(), 1e-7 * u * u + 1e-18)
            << "omega " << omega.transpose() << " u " << u << " column " << j;
      }
      const Vec3 tangent = HelixRotation(omega, u).col(2);
      EXPECT_LT((HelixTangentFromFunctions(omega, u, f) - tangent).norm(), 1e-15);
    }
  }
}

}  // namespace
}  // namespace ringlet
