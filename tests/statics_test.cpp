// Equilibria: natural helix without gravity, invariance under rigid motions, Greenhill's
// self-buckling, honest termination reasons, agreement of the minimizers.
#include "ringlet/statics.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <numbers>

#include "ringlet/strand_geometry.h"
#include "ringlet/strand_hessian.h"
#include "test_util.h"

namespace ringlet {
namespace {

using testing::HorizontalFrame;
using testing::MakeStrand;

Mat3 UpFrame() {  // t = +z, n1 = +x, n2 = +y
  return Mat3::Identity();
}

// With no gravity the equilibrium is the natural helix, for any segment count: zero energy,
// radius kappa/(kappa^2 + tau^2), pitch 2 pi tau/(kappa^2 + tau^2) (kappa = |(kappa1, kappa2)|).
TEST(Statics, ZeroGravityGivesNaturalHelix) {
  const Vec3 natural(50.0, 0.0, 10.0);
  const double omega2 = natural.squaredNorm();
  const double radius = 50.0 / omega2, pitch = 2 * std::numbers::pi * 10.0 / omega2;
  const double period = 2 * std::numbers::pi / std::sqrt(omega2);  // arc length of one turn
  for (int n : {1, 7, 15, 64}) {
    StrandModel m = MakeStrand(0.3, n, 0.4, natural, testing::RandomRotation(n));
    m.gravity = Vec3::Zero();
    const StrandSolution s = SolveStrand(m);
    ASSERT_TRUE(s.summary.Converged()) << n;
    EXPECT_TRUE(s.summary.stable);
    EXPECT_EQ(s.summary.energy.total, 0.0);
    EXPECT_EQ(s.summary.iterations, 0);
    // Geometry: sample one period finely; axis a = Q0 Omega / |Omega|.
    const Vec3 axis = m.root_frame * natural.normalized();
    StrandModel one_turn = m;
    one_turn.segment_lengths = UniformSegments(period, 1);
    const int k = 360;
    const std::vector<Vec3> pts = SampleCentreline(one_turn, natural, k);
    // Pitch: after one period the point has moved by pitch along the axis, nothing across.
    EXPECT_NEAR((pts.back() - pts.front()).dot(axis), pitch, 1e-14);
    EXPECT_LT(((pts.back() - pts.front()) - pitch * axis).norm(), 1e-14);
    // Radius: points (without the last, a repeat) projected across the axis lie on a circle.
    Vec3 centre = Vec3::Zero();
    for (int i = 0; i < k; ++i) centre += pts[i] - pts[i].dot(axis) * axis;
    centre /= k;
    for (int i = 0; i < k; ++i) {
      const Vec3 across = pts[i] - pts[i].dot(axis) * axis;
      EXPECT_NEAR((across - centre).norm(), radius, 1e-13) << i;
    }
    // The solved strand itself is that helix: its tip is where the natural helix puts it.
    const StrandGeometry g = ComputeGeometry(m, s.curvatures);
    const std::vector<Vec3> ref = SampleCentreline(MakeStrand(0.3, 1, 0.4, natural, m.root_frame),
                                                   natural, 1);
    EXPECT_LT((g.points.back() - ref.back()).norm(), 1e-14);
  }
}

// Internal energy and the equilibrium are invariant under a rigid motion applied to the root and
// to gravity together; the equilibrium shape moves rigidly with them.
TEST(Statics, RigidMotionInvariance) {
  const Vec3 natural(40.0, -15.0, 12.0);
  StrandModel a = MakeStrand(0.15, 20, 0.5, natural, HorizontalFrame());
  StrandModel b = a;
  const Mat3 rot = testing::RandomRotation(99);
  b.root_frame = rot * a.root_frame;
  b.root_position = Vec3(0.1, -0.3, 1.7);
  b.gravity = rot * a.gravity;
  const VecX q = testing::RandomCurvatures(20, 60.0, 5);
  StrandEnergy ea(a), eb(b);
  VecX ga, gb;
  EnergyTerms ta, tb;
  ea.Evaluate(q, &ga, &ta);
  eb.Evaluate(q, &gb, &tb);
  EXPECT_EQ(ta.elastic, tb.elastic);
  EXPECT_NEAR(ta.gravity, tb.gravity, 1e-12 * std::abs(ta.gravity));
  EXPECT_LT((ga - gb).norm(), 1e-11 * ga.norm());

  const StrandSolution sa = SolveStrand(a), sb = SolveStrand(b);
  ASSERT_TRUE(sa.summary.Converged() && sb.summary.Converged());
  EXPECT_NEAR(sa.summary.energy.total, sb.summary.energy.total,
              1e-10 * std::abs(sa.summary.energy.total));
  const StrandGeometry pa = ComputeGeometry(a, sa.curvatures), pb = ComputeGeometry(b, sb.curvatures);
  for (size_t i = 0; i < pa.points.size(); ++i) {
    const Vec3 moved = b.root_position + rot * (pa.points[i] - a.root_position);
    EXPECT_LT((pb.points[i] - moved).norm(), 1e-9 * a.Length()) << i;
  }
}

// Greenhill (1881): a vertical column clamped at its foot buckles under its own weight when
// w L^3 / EI > 7.8373. Below, the straight state is stable; above, the solver must leave it.
StrandModel StandingStrand(double load, int n) {
  StrandModel m = MakeStrand(0.05, n, 0.0, Vec3::Zero(), UpFrame());
  // Choose the density so that w L^3 / (E I) = load.
  const double ei = m.Stiffness()(0);
  const double l = m.Length();
  m.material.density = load * ei / (l * l * l * m.section.Area() * 9.81);
  return m;
}

TEST(Statics, GreenhillBelowCriticalStaysStraight) {
  StrandModel m = StandingStrand(0.9 * 7.8373, 30);
  // Start slightly bent: it must come back to straight.
  const VecX start = testing::RandomCurvatures(30, 0.5, 7);
  const StrandSolution s = SolveStrand(m, {}, &start);
  ASSERT_TRUE(s.summary.Converged());
  EXPECT_TRUE(s.summary.stable);
  EXPECT_GT(s.summary.min_eigenvalue, 0.0);
  const StrandGeometry g = ComputeGeometry(m, s.curvatures);
  EXPECT_NEAR(g.points.back().z(), m.Length(), 1e-9 * m.Length());
  EXPECT_LT(g.points.back().head<2>().norm(), 1e-7 * m.Length());
}

TEST(Statics, GreenhillAboveCriticalFallsOver) {
  StrandModel m = StandingStrand(1.3 * 7.8373, 30);
  // The straight state is an exact equilibrium (zero gradient): only the Hessian shows it is
  // unstable. Starting exactly on it, the solver must detect that and leave.
  const StrandSolution s = SolveStrand(m);
  ASSERT_TRUE(s.summary.Converged()) << s.summary.message;
  EXPECT_TRUE(s.summary.stable);
  EXPECT_GE(s.summary.stability_restarts, 1);
  EXPECT_GT(s.summary.min_eigenvalue, 0.0);
  const StrandGeometry g = ComputeGeometry(m, s.curvatures);
  // Buckled: the tip has left the vertical by a finite amount and the energy is below the
  // straight state's (zero elastic, gravity -w L^2 / 2 measured from the root... energy < 0 here
  // because gravity points down: straight-up gravity energy is +w L^2/2).
  EXPECT_GT(g.points.back().head<2>().norm(), 0.05 * m.Length());
  const double straight = 0.5 * m.WeightPerLength().norm() * m.Length() * m.Length();
  EXPECT_LT(s.summary.energy.total, straight);
  // With the stability check disabled, the unstable straight state is returned, and its
  // summary says it is not known to be stable.
  SolveOptions no_check;
  no_check.check_stability = false;
  const StrandSolution u = SolveStrand(m, no_check);
  EXPECT_FALSE(u.summary.stable);
  EXPECT_FALSE(u.summary.stability_checked);
  // ...and the Hessian there has a negative eigenvalue.
  EXPECT_LT(MinScaledHessianEigenvalue(m, u.curvatures), -1e-3);
}

// An unconverged result is never reported as converged.
TEST(Statics, IterationBudgetIsReported) {
  StrandModel m = MakeStrand(0.2, 15, 0.3, Vec3(50.0, 0.0, 10.0), HorizontalFrame());
  SolveOptions o;
  o.max_iterations = 2;
  const StrandSolution s = SolveStrand(m, o);
  EXPECT_EQ(s.summary.termination, Termination::kMaxIterations);
  EXPECT_FALSE(s.summary.Converged());
  EXPECT_FALSE(s.summary.stable);
  EXPECT_GT(s.summary.residual, o.tolerance);
  EXPECT_STREQ(TerminationName(s.summary.termination), "max_iterations");
}

TEST(Statics, NonFiniteInputIsReported) {
  StrandModel m = MakeStrand(0.2, 5);
  VecX start = m.NaturalCurvatures();
  start(4) = std::nan("");
  const StrandSolution s = SolveStrand(m, {}, &start);
  EXPECT_EQ(s.summary.termination, Termination::kNonFinite);
  EXPECT_FALSE(s.summary.stable);
}

// The three minimizers reach the same equilibrium (energy to 1e-12, residual below tolerance).
TEST(Statics, MinimizersAgree) {
  StrandModel m = MakeStrand(0.2, 20, 0.6, Vec3(50.0, 0.0, 10.0), HorizontalFrame());
  double energies[3];
  int i = 0;
  for (Method method : {Method::kLbfgs, Method::kBfgs, Method::kNewton}) {
    SolveOptions o;
    o.method = method;
    const StrandSolution s = SolveStrand(m, o);
    ASSERT_TRUE(s.summary.Converged()) << i;
    EXPECT_TRUE(s.summary.stable);
    EXPECT_LE(s.summary.residual, o.tolerance);
    energies[i++] = s.summary.energy.total;
  }
  // Not vacuous: gravity moved the strand away from its natural shape, lowering the energy.
  StrandEnergy e(m);
  const double natural = e.Evaluate(m.NaturalCurvatures(), nullptr);
  EXPECT_LT(energies[0], natural - 0.1 * std::abs(natural));
  EXPECT_NEAR(energies[1], energies[0], 1e-12 * std::abs(energies[0]));
  EXPECT_NEAR(energies[2], energies[0], 1e-12 * std::abs(energies[0]));
}

// Heavy curly hair (w L^3 / EI = 2040 L^3 for this section: 1488 at 0.9 m): Newton with the exact
// Hessian reaches the equilibrium L-BFGS reaches, in far fewer iterations; kAuto picks Newton
// here and L-BFGS for light strands (bit-identical to an explicit L-BFGS solve there).
TEST(Statics, HeavyStrandsNewtonAgreesWithLbfgsAndAutoPicksIt) {
  StrandModel m = MakeStrand(0.9, 30, 0.0, Vec3(50.0, 0.0, 10.0), HorizontalFrame());
  m.segment_lengths = GradedSegments(0.9, 30, RecommendedGradingRatio(m.GravityParameter()));
  ASSERT_GT(m.GravityParameter(), kAutoNewtonLoad);
  EXPECT_EQ(ResolveMethod(Method::kAuto, m), Method::kNewton);
  SolveOptions lbfgs, newton, automatic;
  lbfgs.method = Method::kLbfgs;
  newton.method = Method::kNewton;
  const StrandSolution a = SolveStrand(m, lbfgs);
  const StrandSolution b = SolveStrand(m, newton);
  const StrandSolution c = SolveStrand(m, automatic);
  ASSERT_TRUE(a.summary.Converged() && b.summary.Converged()) << b.summary.message;
  EXPECT_TRUE(a.summary.stable && b.summary.stable);
  EXPECT_NEAR(b.summary.energy.total, a.summary.energy.total, 1e-10 * std::abs(a.summary.energy.total));
  const StrandGeometry ga = ComputeGeometry(m, a.curvatures), gb = ComputeGeometry(m, b.curvatures);
  EXPECT_LT((ga.points.back() - gb.points.back()).norm(), 1e-6 * m.Length());
  EXPECT_LT(3 * b.summary.iterations, a.summary.iterations);
  EXPECT_GT(b.summary.hessian_evaluations, 0);
  EXPECT_EQ(c.curvatures, b.curvatures);

  const StrandModel light = MakeStrand(0.2, 15, 0.3, Vec3(50.0, 0.0, 10.0), HorizontalFrame());
  ASSERT_LT(light.GravityParameter(), kAutoNewtonLoad);
  EXPECT_EQ(ResolveMethod(Method::kAuto, light), Method::kLbfgs);
  EXPECT_EQ(SolveStrand(light, automatic).curvatures, SolveStrand(light, lbfgs).curvatures);
}

// The certificate's reported eigenvalue is an inverse-iteration estimate from above of the
// smallest eigenvalue of the scaled exact Hessian, checked against a dense eigensolver of the
// same matrix scaled independently here (x = sqrt(l K) (q - q0)).
TEST(Statics, CertificateEigenvalueBoundsTheDenseOne) {
  StrandModel m = MakeStrand(0.6, 25, 0.5, Vec3(40.0, 5.0, 10.0), HorizontalFrame());
  SolveOptions lbfgs;  // one Hessian: the certificate's (Newton would add one per step)
  lbfgs.method = Method::kLbfgs;
  const StrandSolution s = SolveStrand(m, lbfgs);
  ASSERT_TRUE(s.summary.Converged() && s.summary.stability_checked);
  StrandHessian h;
  ComputeStrandHessian(m, s.curvatures, &h);
  VecX scale(75);
  for (int i = 0; i < 25; ++i) {
    scale.segment<3>(3 * i) = (m.segment_lengths[static_cast<size_t>(i)] * m.Stiffness()).cwiseSqrt();
  }
  const MatX scaled = scale.cwiseInverse().asDiagonal() * h.Dense() * scale.cwiseInverse().asDiagonal();
  const double lambda = Eigen::SelfAdjointEigenSolver<MatX>(scaled).eigenvalues()(0);
  ASSERT_GT(lambda, 0.0);
  EXPECT_LT(lambda, 0.9);  // anti-vacuity: gravity changes the unloaded value 1
  EXPECT_GE(s.summary.min_eigenvalue, lambda * (1.0 - 1e-9));
  EXPECT_LE(s.summary.min_eigenvalue, lambda * 1.05);
  EXPECT_NEAR(MinScaledHessianEigenvalue(m, s.curvatures), lambda, 1e-6 * lambda);
  EXPECT_EQ(s.summary.hessian_evaluations, 1);
}

// Regression (issue 16): one strand of 20,000 segments with the default stability check threw
// std::bad_alloc (the dense finite-difference Hessian needed 28.8 GB). The exact Hessian is O(n)
// in memory and time: the solve completes and is certified, and an unstable 20,000-segment
// equilibrium (a standing strand past Greenhill's load) finds its negative mode without a dense
// matrix (shifted inverse iteration).
TEST(Statics, TwentyThousandSegmentsAreCertifiedWithoutADenseHessian) {
  StrandModel m = MakeStrand(0.2, 20000, 0.3, Vec3(50.0, 0.0, 10.0), HorizontalFrame());
  const StrandSolution s = SolveStrand(m);
  EXPECT_TRUE(s.summary.Converged()) << s.summary.message;
  EXPECT_TRUE(s.summary.stability_checked);
  EXPECT_TRUE(s.summary.stable);
  EXPECT_GT(s.summary.min_eigenvalue, 0.0);

  const StrandModel standing = StandingStrand(1.3 * 7.8373, 20000);
  VecX mode;
  const double lambda = MinScaledHessianEigenvalue(standing, VecX::Zero(60000), &mode);
  // The n-segment straight state's lambda_min is 1 - load / lambda_c(n) with lambda_c(n) ->
  // 7.8373 (docs/validation.md, Greenhill): -0.3 here, to the accuracy of the iteration.
  EXPECT_NEAR(lambda, 1.0 - 1.3, 0.02);
  EXPECT_EQ(mode.size(), 60000);
}

// A warm start at the equilibrium needs no iteration; a perturbed equilibrium is caught by the
// residual.
TEST(Statics, WarmStartAndResidual) {
  StrandModel m = MakeStrand(0.1, 15, 0.0, Vec3::Zero(), HorizontalFrame());
  const StrandSolution s = SolveStrand(m);
  ASSERT_TRUE(s.summary.Converged());
  const StrandSolution again = SolveStrand(m, {}, &s.curvatures);
  EXPECT_EQ(again.summary.iterations, 0);
  EXPECT_TRUE(again.summary.Converged());
  VecX bad = s.curvatures;
  bad(3 * 7 + 1) *= 1.01;  // 1% more curvature on one segment
  StrandEnergy e(m);
  VecX g;
  e.Evaluate(bad, &g);
  EXPECT_GT(EquilibriumResidual(m, bad, g), 1e-4);
  e.Evaluate(s.curvatures, &g);
  EXPECT_LE(EquilibriumResidual(m, s.curvatures, g), 1e-9);
}

TEST(Statics, OptionsValidate) {
  std::string why;
  SolveOptions o;
  EXPECT_TRUE(o.IsValid(&why));
  o.tolerance = 0.0;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("tolerance"), std::string::npos);
  o = {};
  o.max_iterations = 0;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("max_iterations"), std::string::npos);
}

}  // namespace
}  // namespace ringlet
