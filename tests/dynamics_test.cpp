// Strand dynamics (docs/dynamics.md, docs/validation.md "Dynamics"): the mass matrix against an
// independent kinetic energy (finite differences of sampled positions and frames), the O(n)
// pieces against finite differences, the modal analysis against an independent Chebyshev
// eigen-solver of the rod (reference/beam_modes.h) and closed forms, free vibration, the rest
// state and the settling on the statics' equilibrium, and the energy of the implicit steps.
#include "ringlet/dynamics.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "dynamics/kinematics.h"
#include "reference/beam_modes.h"
#include "reference/rotating_rod.h"
#include "ringlet/body.h"
#include "ringlet/contact.h"
#include "ringlet/hair_type.h"
#include "ringlet/statics.h"
#include "ringlet/strand_geometry.h"
#include "ringlet/strand_hessian.h"
#include "test_util.h"

namespace ringlet {
namespace {

using reference::AxialLoad;
using reference::BeamEigenvalues;
using testing::MakeStrand;
using testing::RandomCurvatures;

constexpr double kPi = 3.14159265358979323846;

// Roots of 1 + cos(x) cosh(x) = 0 (the clamped-free beam; e.g. Blevins, Formulas for Natural
// Frequency and Mode Shape, table 8-1), and the first zeros of J0 (Abramowitz & Stegun, table 9.5).
constexpr double kCantileverBeta[3] = {1.875104069, 4.694091133, 7.854757438};
constexpr double kBesselJ0Zeros[3] = {2.404825558, 5.520078110, 8.653727913};
// lambda_1 = rho S omega_1^2 L^4 / EI of the hanging heavy rod at Gamma = 0, 1, 10, 100, 1000
// (the table).
constexpr double kHangingGamma[5] = {0.0, 1.0, 10.0, 100.0, 1000.0};
constexpr double kHangingLambda1[5] = {12.362, 13.933, 28.003, 165.60, 1497.34};
constexpr double kGreenhill = 7.837347;

// Tangent down (-z): n1 = +x, n2 = -y, t = -z.
Mat3 DownFrame() {
  Mat3 q;
  q.col(0) = Vec3(1, 0, 0);
  q.col(1) = Vec3(0, -1, 0);
  q.col(2) = Vec3(0, 0, -1);
  return q;
}

// A straight strand of circular section with gravity g chosen for the load Gamma = rho S g L^3/EI
// along the tangent: hanging (gravity along t) or standing (against it).
StrandModel LoadedRod(double length, int segments, double gamma, bool hanging,
                      double grading = 1.0) {
  StrandModel m = MakeStrand(length, segments, 0.0, Vec3::Zero(), hanging ? DownFrame() : Mat3::Identity());
  m.segment_lengths = GradedSegments(length, segments, grading);
  const double ei = m.material.young_modulus * m.section.I1();
  const double rho_s = m.material.density * m.section.Area();
  m.gravity = Vec3(0.0, 0.0, -gamma * ei / (rho_s * length * length * length));
  return m;
}

double LambdaScale(const StrandModel& m) {  // lambda = omega^2 * this
  const double ei = m.material.young_modulus * m.section.I1();
  const double rho_s = m.material.density * m.section.Area();
  const double l = m.Length();
  return rho_s * l * l * l * l / ei;
}

// ---------------------------------------------------------------------------------------------
// Pieces.

TEST(DynamicsQuadrature, GaussLegendreIsExactForPolynomials) {
  for (int points = 1; points <= 8; ++points) {
    const dynamics::GaussRule rule = dynamics::GaussLegendre01(points);
    for (int k = 0; k <= 2 * points - 1; ++k) {
      double sum = 0.0;
      for (int j = 0; j < points; ++j) sum += rule.weights[j] * std::pow(rule.nodes[j], k);
      EXPECT_NEAR(sum, 1.0 / (k + 1), 1e-15) << points << " " << k;
    }
    for (int j = 1; j < points; ++j) EXPECT_GT(rule.nodes[j], rule.nodes[j - 1]);
  }
}

// The kinetic energy 1/2 rho S int |dr/dt|^2 ds + 1/2 rho int omega^T Q diag(I1, I2, I1+I2) Q^T
// omega ds, computed independently: positions and frames at q +- eps v from the library's
// geometry (SampleFramedCentreline, tested on its own), central differences for dr/dt and for the
// frame's angular velocity (omega = Vee(dQ/dt Q^T) / 2), Simpson's rule with 128 intervals per
// segment. The mass matrix (Gauss-Legendre, twists, reverse sweep) must give the same number.
double ReferenceKineticEnergy(const StrandModel& m, const VecX& q, const VecX& v) {
  const double eps = 1e-6;
  const int k = 128;
  const FramedCentreline plus = SampleFramedCentreline(m, q + eps * v, k);
  const FramedCentreline minus = SampleFramedCentreline(m, q - eps * v, k);
  const FramedCentreline mid = SampleFramedCentreline(m, q, k);
  const double rho = m.material.density, area = m.section.Area();
  const Eigen::DiagonalMatrix<double, 3> inertia(m.section.I1(), m.section.I2(),
                                                 m.section.I1() + m.section.I2());
  double total = 0.0;
  for (int i = 0; i < m.NumSegments(); ++i) {
    const double h = m.segment_lengths[static_cast<size_t>(i)] / k;
    for (int j = 0; j <= k; ++j) {
      const size_t p = static_cast<size_t>(i * k + j);
      const Vec3 velocity = (plus.points[p] - minus.points[p]) / (2 * eps);
      const Mat3 dq = (plus.frames[p] - minus.frames[p]) / (2 * eps);
      const Vec3 omega = 0.5 * Vee(dq * mid.frames[p].transpose());
      const Vec3 local = mid.frames[p].transpose() * omega;
      const double density =
          0.5 * rho * area * velocity.squaredNorm() + 0.5 * rho * local.dot(inertia * local);
      const double weight = (j == 0 || j == k) ? 1.0 : (j % 2 ? 4.0 : 2.0);
      total += weight * h / 3.0 * density;
    }
  }
  return total;
}

TEST(DynamicsMassMatrix, KineticEnergyMatchesFiniteDifferencesOfPositions) {
  // A curly strand (turning up to ~1.5 rad per segment), elliptic, tilted root.
  StrandModel m = MakeStrand(0.1, 8, 0.6, Vec3(90.0, 20.0, 40.0), testing::RandomRotation(3));
  const VecX q = m.NaturalCurvatures() + RandomCurvatures(8, 30.0, 11);
  for (unsigned seed : {1u, 2u, 3u}) {
    const VecX v = RandomCurvatures(8, 50.0, seed);
    const double reference = ReferenceKineticEnergy(m, q, v);
    const StrandHessian mass = ComputeMassMatrix(m, q);
    VecX mv;
    mass.Multiply(v, &mv);
    std::printf("kinetic energy, seed %u: mass matrix %.12e J, reference %.12e J (relative %.1e)\n",
                seed, 0.5 * v.dot(mv), reference, 0.5 * v.dot(mv) / reference - 1.0);
    EXPECT_NEAR(0.5 * v.dot(mv), reference, 1e-8 * reference) << seed;
    EXPECT_NEAR(0.5 * v.dot(mass.Dense() * v), reference, 1e-8 * reference) << seed;
    EXPECT_NEAR(KineticEnergy(m, {q, v, 0.0}), reference, 1e-8 * reference) << seed;
  }
  // Without the section's rotational inertia: the centreline's energy alone, smaller.
  DynamicsOptions no_rotation;
  no_rotation.rotational_inertia = false;
  const VecX v = RandomCurvatures(8, 50.0, 4);
  const double with = KineticEnergy(m, {q, v, 0.0});
  const double without = KineticEnergy(m, {q, v, 0.0}, no_rotation);
  EXPECT_LT(without, with);
  EXPECT_GT(without, 0.9 * with);
}

// M is symmetric positive definite (also for a straight strand, whose twist moves no point of the
// centreline: the section's rotational inertia carries it) and the O(n) factorization of
// strand_hessian.h solves it like a dense Cholesky.
TEST(DynamicsMassMatrix, SymmetricPositiveDefiniteAndSolvedInLinearTime) {
  for (int curly = 0; curly < 2; ++curly) {
    StrandModel m = MakeStrand(0.2, 12, 0.3, curly ? Vec3(60.0, 0.0, 20.0) : Vec3::Zero(),
                               testing::RandomRotation(5));
    const VecX q = m.NaturalCurvatures() + (curly ? RandomCurvatures(12, 10.0, 7) : VecX::Zero(36));
    const StrandHessian mass = ComputeMassMatrix(m, q);
    const MatX dense = mass.Dense();
    EXPECT_LT((dense - dense.transpose()).norm(), 1e-14 * dense.norm());
    Eigen::LLT<MatX> llt(dense);
    ASSERT_EQ(llt.info(), Eigen::Success);
    StrandHessianFactor factor;
    ASSERT_TRUE(factor.Factor(mass, 0.0));
    const VecX b = RandomCurvatures(12, 1.0, 9);
    VecX x;
    factor.Solve(b, &x);
    const VecX expected = llt.solve(b);
    EXPECT_LT((x - expected).norm(), 1e-8 * expected.norm()) << curly;
  }
}

// The reverse sweep J^T (forces and frame adjoints at the samples to dPhi/dq) against central
// differences of Phi(q) = sum_s F_s . y_s(q) + <G_s, Q_s(q)>.
TEST(DynamicsKinematics, JacobianTransposeMatchesFiniteDifferences) {
  StrandModel m = MakeStrand(0.15, 6, 0.5, Vec3(70.0, -10.0, 30.0), testing::RandomRotation(8));
  const VecX q = m.NaturalCurvatures() + RandomCurvatures(6, 20.0, 12);
  const dynamics::GaussRule rule = dynamics::GaussLegendre01(4);
  dynamics::Kinematics kin;
  dynamics::ComputeKinematics(m, q, rule, &kin);
  std::vector<Vec3> forces;
  std::vector<Mat3> adjoints;
  for (size_t k = 0; k < kin.samples.size(); ++k) {
    forces.push_back(RandomCurvatures(1, 1.0, 100 + static_cast<unsigned>(k)));
    adjoints.push_back(testing::RandomRotation(200 + static_cast<unsigned>(k)));
  }
  VecX gradient;
  dynamics::ApplyJacobianTranspose(m, q, kin, forces, adjoints, &gradient);
  auto phi = [&](const VecX& x) {
    dynamics::Kinematics k2;
    dynamics::ComputeKinematics(m, x, rule, &k2);
    double sum = 0.0;
    for (size_t k = 0; k < k2.samples.size(); ++k) {
      sum += forces[k].dot(k2.samples[k].y) + (adjoints[k].array() * k2.samples[k].frame.array()).sum();
    }
    return sum;
  };
  for (int i = 0; i < q.size(); ++i) {
    const double fd = testing::CentralDifference(phi, q, i, 1e-5);
    EXPECT_NEAR(gradient(i), fd, 1e-7 * (1.0 + std::abs(fd))) << i;
  }
  // And the twists and own Jacobians against the sample velocities' finite differences.
  const VecX v = RandomCurvatures(6, 5.0, 13);
  std::vector<Vec3> angular, linear;
  dynamics::SampleVelocities(kin, v, &angular, &linear);
  const double eps = 1e-6;
  dynamics::Kinematics kp, km;
  dynamics::ComputeKinematics(m, q + eps * v, rule, &kp);
  dynamics::ComputeKinematics(m, q - eps * v, rule, &km);
  for (size_t k = 0; k < kin.samples.size(); ++k) {
    const Vec3 fd = (kp.samples[k].y - km.samples[k].y) / (2 * eps);
    EXPECT_LT((linear[k] - fd).norm(), 1e-7 * (1e-3 + fd.norm())) << k;
    const Mat3 dq = (kp.samples[k].frame - km.samples[k].frame) / (2 * eps);
    const Vec3 w = 0.5 * Vee(dq * kin.samples[k].frame.transpose());
    EXPECT_LT((angular[k] - w).norm(), 1e-7 * (1e-3 + w.norm())) << k;
  }
}

// The curvature of fixed point forces, d^2/dq^2 sum_s F_s . y_s(q) (semiseparable), against
// central differences of ApplyJacobianTranspose (itself checked above).
TEST(DynamicsKinematics, ForceCurvatureMatchesFiniteDifferences) {
  StrandModel m = MakeStrand(0.15, 6, 0.5, Vec3(70.0, -10.0, 30.0), testing::RandomRotation(8));
  const VecX q = m.NaturalCurvatures() + RandomCurvatures(6, 20.0, 14);
  const dynamics::GaussRule rule = dynamics::GaussLegendre01(3);
  dynamics::Kinematics kin;
  dynamics::ComputeKinematics(m, q, rule, &kin);
  std::vector<Vec3> forces;
  for (size_t k = 0; k < kin.samples.size(); ++k) {
    forces.push_back(RandomCurvatures(1, 1.0, 300 + static_cast<unsigned>(k)));
  }
  const std::vector<Mat3> no_adjoints(kin.samples.size(), Mat3::Zero());
  StrandHessian matrix;
  matrix.twist = kin.twist;
  matrix.diagonal.assign(6, Mat3::Zero());
  matrix.load.assign(6, Mat63::Zero());
  matrix.translational = true;
  dynamics::AddForceCurvature(m, q, kin, forces, &matrix);
  const MatX dense = matrix.Dense();
  const double eps = 1e-6;
  MatX fd(18, 18);
  for (int j = 0; j < 18; ++j) {
    VecX gp, gm;
    const VecX e = eps * VecX::Unit(18, j);
    dynamics::Kinematics kp, km;
    dynamics::ComputeKinematics(m, q + e, rule, &kp);
    dynamics::ComputeKinematics(m, q - e, rule, &km);
    dynamics::ApplyJacobianTranspose(m, q + e, kp, forces, no_adjoints, &gp);
    dynamics::ApplyJacobianTranspose(m, q - e, km, forces, no_adjoints, &gm);
    fd.col(j) = (gp - gm) / (2 * eps);
  }
  EXPECT_LT((dense - fd).norm(), 1e-6 * fd.norm());
  EXPECT_LT((dense - dense.transpose()).norm(), 1e-8 * fd.norm());
}

// ---------------------------------------------------------------------------------------------
// The independent reference on its own.

// Chebyshev collocation converges spectrally until the rounding of its fourth-derivative matrix
// (~N^8 eps) takes over: measured, N = 32 and 40 agree to 2e-7 relative at every load below (to
// 1e-8 from Gamma = 100 on), N = 48 and more drift by 1e-6. N = 32 is the reference.
constexpr int kReferencePoints = 32;

TEST(BeamModesReference, ReproducesClosedFormsAndPublishedValues) {
  // Weightless cantilever: lambda_k = (beta_k L)^4.
  const std::vector<double> free = BeamEigenvalues(0.0, AxialLoad::kHanging, kReferencePoints, 3);
  for (int k = 0; k < 3; ++k) {
    const double exact = std::pow(kCantileverBeta[k], 4);
    EXPECT_NEAR(free[static_cast<size_t>(k)], exact, 3e-8 * exact) << k;
  }
  // Converged: N = 32 and 40 agree to 3e-7 (rounding) at every load of the table.
  for (double gamma : kHangingGamma) {
    const std::vector<double> a = BeamEigenvalues(gamma, AxialLoad::kHanging, 40, 3);
    const std::vector<double> b = BeamEigenvalues(gamma, AxialLoad::kHanging, 32, 3);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], b[k], 3e-7 * b[k]) << gamma << " " << k;
  }
  // The hanging heavy rod: the lambda_1 to its printed digits, within 0.55 units of the
  // last one (measured 12.3623634, 13.9324945, 28.0029709, 165.604518, 1497.34211: the issue's
  // 13.933 is one unit too high in its last digit, 13.93249 rounds to 13.932).
  const double unit[5] = {1e-3, 1e-3, 1e-3, 1e-2, 1e-2};
  for (int i = 0; i < 5; ++i) {
    const double lambda = BeamEigenvalues(kHangingGamma[i], AxialLoad::kHanging, kReferencePoints, 1)[0];
    std::printf("reference hanging Gamma = %g: lambda_1 = %.8f (issue %g)\n", kHangingGamma[i],
                lambda, kHangingLambda1[i]);
    EXPECT_NEAR(lambda, kHangingLambda1[i], 0.55 * unit[i]) << i;
  }
  // Greenhill: lambda_1 of the standing column vanishes at Gamma = 7.837347.
  const double at = BeamEigenvalues(kGreenhill, AxialLoad::kStanding, kReferencePoints, 1)[0];
  EXPECT_NEAR(at, 0.0, 2e-6);
  EXPECT_GT(BeamEigenvalues(7.83, AxialLoad::kStanding, kReferencePoints, 1)[0], 0.0);
  EXPECT_LT(BeamEigenvalues(7.845, AxialLoad::kStanding, kReferencePoints, 1)[0], 0.0);
}

// As Gamma grows the heavy rod becomes the hanging chain, omega_k = (j_0,k / 2) sqrt(g / L), i.e.
// lambda_k / Gamma -> j_0,k^2 / 4. The gap closes like Gamma^(-1/2) (the bending layer at the
// clamp, of width L / sqrt(Gamma)): measured 3.6%, 11.8%, 38% at Gamma = 1000 and 1.0%, 2.2%, 7.5%
// at 10^4 (N = 80 resolves the layer there).
TEST(BeamModesReference, ApproachesTheHangingChain) {
  double previous[3] = {0, 0, 0};
  for (double gamma : {1e3, 1e4}) {
    const std::vector<double> lambdas = BeamEigenvalues(gamma, AxialLoad::kHanging, 80, 3);
    for (int k = 0; k < 3; ++k) {
      const double chain = kBesselJ0Zeros[k] * kBesselJ0Zeros[k] / 4.0;
      const double gap = lambdas[static_cast<size_t>(k)] / gamma / chain - 1.0;
      std::printf("Gamma = %g mode %d: lambda/Gamma = %.6f, chain %.6f, gap %.4f\n", gamma, k + 1,
                  lambdas[static_cast<size_t>(k)] / gamma, chain, gap);
      EXPECT_GT(gap, 0.0);
      if (previous[k] > 0.0) {
        EXPECT_LT(gap, previous[k] / 2.5) << k;  // sqrt(10) = 3.16 asymptotically
      }
      previous[k] = gap;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Modal analysis against the reference.

// lambda_k of the library's modes (each bending mode twice: two planes of a circular section).
std::vector<double> LibraryLambdas(const StrandModel& m, int count) {
  const Modes modes = ComputeModes(m, VecX::Zero(3 * m.NumSegments()), 2 * count);
  std::vector<double> lambdas;
  for (int k = 0; k < count; ++k) {
    const double a = modes.omega_squared(2 * k), b = modes.omega_squared(2 * k + 1);
    EXPECT_NEAR(a, b, 1e-7 * std::abs(b)) << "the two planes of mode " << k;
    lambdas.push_back(0.5 * (a + b) * LambdaScale(m));
  }
  return lambdas;
}

// The weightless cantilever: lambda_k = (beta_k L)^4, and the error falls as 1/n^2.
TEST(DynamicsModes, WeightlessCantileverConvergesToClosedForm) {
  double previous[3] = {0, 0, 0};
  for (int n : {10, 20, 40}) {
    StrandModel m = LoadedRod(0.1, n, 0.0, true);
    const std::vector<double> lambdas = LibraryLambdas(m, 3);
    for (int k = 0; k < 3; ++k) {
      const double exact = std::pow(kCantileverBeta[k], 4);
      const double error = std::abs(lambdas[static_cast<size_t>(k)] / exact - 1.0);
      std::printf("cantilever n = %d mode %d: beta L = %.7f, relative error of lambda %.3e\n", n,
                  k + 1, std::pow(lambdas[static_cast<size_t>(k)], 0.25), error);
      if (previous[k] > 0.0) {
        EXPECT_LT(error, previous[k] / 3.0) << n << " " << k;
      }
      previous[k] = error;
    }
  }
}

// The hanging heavy rod: the library's lambda_1..3 (graded segments, RecommendedGradingRatio)
// against the Chebyshev reference at every load of the table.
TEST(DynamicsModes, HangingHeavyRodMatchesReference) {
  for (int i = 0; i < 5; ++i) {
    const double gamma = kHangingGamma[i];
    const std::vector<double> reference = BeamEigenvalues(gamma, AxialLoad::kHanging, kReferencePoints, 3);
    double previous[3] = {0, 0, 0};
    for (int n : {20, 40}) {
      const StrandModel m = LoadedRod(0.1, n, gamma, true, RecommendedGradingRatio(gamma));
      const std::vector<double> lambdas = LibraryLambdas(m, 3);
      for (int k = 0; k < 3; ++k) {
        const double error = std::abs(lambdas[static_cast<size_t>(k)] / reference[static_cast<size_t>(k)] - 1.0);
        std::printf("hanging Gamma = %g n = %d mode %d: lambda = %.5f reference %.5f error %.2e\n",
                    gamma, n, k + 1, lambdas[static_cast<size_t>(k)], reference[static_cast<size_t>(k)], error);
        if (previous[k] > 0.0) {
          EXPECT_LT(error, previous[k] / 2.5) << gamma << " " << k;
        }
        previous[k] = error;
      }
    }
  }
}

// The standing column: lambda_1 of the library falls through 0 near Greenhill's load; the load
// where it vanishes (linear interpolation of lambda_1 between two loads) converges to 7.837347.
TEST(DynamicsModes, StandingColumnLosesStabilityAtGreenhillsLoad) {
  for (int n : {20, 40}) {
    const double g1 = 7.7, g2 = 7.95;
    const double l1 = LibraryLambdas(LoadedRod(0.1, n, g1, false), 1)[0];
    const double l2 = LibraryLambdas(LoadedRod(0.1, n, g2, false), 1)[0];
    const double critical = g1 + (g2 - g1) * l1 / (l1 - l2);
    std::printf("standing n = %d: lambda_1 = %.5f at %g, %.5f at %g, critical %.6f\n", n, l1, g1, l2,
                g2, critical);
    EXPECT_GT(l1, 0.0);
    EXPECT_LT(l2, 0.0);
  }
}

// The inexact steps' model tolerance (DynamicsOptions::model_tolerance) of the tests below.
// 0.03: the head benchmark's fast rows (benchmarks.md); 0.3 let the heavy curly strand below gain
// energy and halved 100 of the 864 film-frame steps of the hair types (tried).
constexpr double kInexact = 0.03;

// A weightless cantilever or a hanging rod released from rest in its first mode: the period of
// the tip, measured from zero crossings over four periods, is backward Euler's
// omega_h = atan(omega h) / h for the modal omega (the phase per step of 1 / (1 - i omega h)).
void CheckFreeVibration(const StrandModel& m, const char* name,
                        Integrator integrator = Integrator::kBackwardEuler, double model_tolerance = 0.0) {
  const int n = m.NumSegments();
  const Modes modes = ComputeModes(m, VecX::Zero(3 * n), 1);
  const double omega = std::sqrt(modes.omega_squared(0));
  const double period = 2.0 * kPi / omega;
  DynamicsOptions options;
  options.internal_friction = 0.0;
  options.air_drag = 0.0;
  options.time_step = period / 200.0;
  options.integrator = integrator;
  options.model_tolerance = model_tolerance;
  // Amplitude: tip deflection ~1e-4 L (linear regime).
  VecX shape = modes.shapes.col(0);
  const StrandGeometry rest = ComputeGeometry(m, VecX::Zero(3 * n));
  const StrandGeometry bent = ComputeGeometry(m, 1e-6 * shape);
  const Vec3 direction = (bent.points.back() - rest.points.back()).normalized();
  const double scale = 1e-4 * m.Length() / ((bent.points.back() - rest.points.back()).norm() / 1e-6);
  StrandDynamics dynamics(m, options, {scale * shape, VecX::Zero(3 * n), 0.0});
  double last = 1.0, last_time = 0.0;
  std::vector<double> crossings;
  const int steps = 4 * 200 + 50;
  for (int k = 0; k < steps; ++k) {
    const StepReport report = dynamics.Step();
    ASSERT_TRUE(report.converged) << report.message;
    EXPECT_EQ(report.halvings, 0);
    const StrandGeometry g = ComputeGeometry(m, dynamics.state().curvatures);
    const double x = (g.points.back() - rest.points.back()).dot(direction);
    if (k > 0 && (x > 0.0) != (last > 0.0)) {
      crossings.push_back(last_time + (report.time - last_time) * last / (last - x));
    }
    last = x;
    last_time = report.time;
  }
  ASSERT_GE(crossings.size(), 8u);
  const double measured = (crossings.size() - 1) * kPi / (crossings.back() - crossings.front());
  const double h = options.time_step;
  // Backward Euler: z = 1 / (1 - i omega h). BDF2 (3 z^2 - 4 z + 1 = 2 h lambda z^2, lambda =
  // i omega): the principal root z = (2 + sqrt(1 + 2 i omega h)) / (3 - 2 i omega h).
  const std::complex<double> i_omega_h(0.0, omega * h);
  const std::complex<double> z = integrator == Integrator::kBackwardEuler
                                     ? 1.0 / (1.0 - i_omega_h)
                                     : (2.0 + std::sqrt(1.0 + 2.0 * i_omega_h)) / (3.0 - 2.0 * i_omega_h);
  const double expected = std::arg(z) / h;
  std::printf("%s: modal omega = %.6f /s, measured %.6f /s, the scheme's %.6f /s (error %.2e)\n",
              name, omega, measured, expected, measured / expected - 1.0);
  EXPECT_NEAR(measured, expected, 1e-4 * expected);
}

TEST(DynamicsFreeVibration, WeightlessCantileverPeriodMatchesModes) {
  const StrandModel m = LoadedRod(0.1, 10, 0.0, true);
  CheckFreeVibration(m, "weightless cantilever");
  // And the modal omega against the closed form (beta L)^2 sqrt(EI / (rho S L^4)) at n = 10.
  const double exact = std::pow(kCantileverBeta[0], 2) / std::sqrt(LambdaScale(m));
  const double omega = std::sqrt(ComputeModes(m, VecX::Zero(30), 1).omega_squared(0));
  EXPECT_NEAR(omega, exact, 2.5e-3 * exact);
}

TEST(DynamicsFreeVibration, HangingRodPeriodMatchesModes) {
  CheckFreeVibration(LoadedRod(0.1, 12, 10.0, true), "hanging rod, Gamma = 10");
  CheckFreeVibration(LoadedRod(0.1, 12, 10.0, true), "hanging rod, Gamma = 10, BDF2",
                     Integrator::kBdf2);
}

// An inexact step on a linear problem is backward Euler (one Newton update solves it exactly):
// the same period, arg(1 / (1 - i omega h)) / h, to the same 1e-4.
TEST(DynamicsInexactSteps, FreeVibrationHasBackwardEulersPeriod) {
  CheckFreeVibration(LoadedRod(0.1, 12, 10.0, true), "hanging rod, Gamma = 10, inexact steps",
                     Integrator::kBackwardEuler, kInexact);
}

// ---------------------------------------------------------------------------------------------
// Consistency with the statics.

double MaxPointDistance(const StrandModel& m, const VecX& a, const VecX& b) {
  const std::vector<Vec3> pa = SampleCentreline(m, a, 4), pb = SampleCentreline(m, b, 4);
  double d = 0.0;
  for (size_t i = 0; i < pa.size(); ++i) d = std::max(d, (pa[i] - pb[i]).norm());
  return d;
}

// A curly 20-cm strand, clamped horizontally (its weight bends it), in the hair's air and
// internal friction.
StrandModel CurlyStrand() {
  return MakeStrand(0.2, 15, 0.5, Vec3(40.0, 0.0, 10.0), testing::HorizontalFrame());
}

// Started at rest on its certified equilibrium, the strand stays within 1e-6 L for 10 s of film
// frames (240 steps of 1/24 s).
void CheckRestAtEquilibrium(const DynamicsOptions& options, const char* name) {
  const StrandModel m = CurlyStrand();
  const StrandSolution solution = SolveStrand(m);
  ASSERT_TRUE(solution.summary.Converged() && solution.summary.stable);
  StrandDynamics dynamics(m, options, {solution.curvatures, VecX::Zero(45), 0.0});
  double worst = 0.0;
  for (int k = 0; k < 240; ++k) {
    const StepReport report = dynamics.Step();
    ASSERT_TRUE(report.converged) << report.message;
    EXPECT_EQ(report.halvings, 0);
    worst = std::max(worst, MaxPointDistance(m, dynamics.state().curvatures, solution.curvatures));
  }
  std::printf("rest at equilibrium (%s): largest drift over 10 s %.3e L\n", name,
              worst / m.Length());
  EXPECT_LT(worst, 1e-6 * m.Length());
  EXPECT_NEAR(dynamics.state().time, 10.0, 1e-12);
}

TEST(DynamicsStatics, RestAtEquilibriumStaysPut) { CheckRestAtEquilibrium({}, "Newton"); }

// Released from its natural (gravity-free) shape at rest, the damped strand falls, swings and
// settles on the equilibrium that SolveStrand finds, within 1e-6 L. Total energy never rises.
void CheckSettling(const DynamicsOptions& options, const char* name) {
  const StrandModel m = CurlyStrand();
  const StrandSolution solution = SolveStrand(m);
  ASSERT_TRUE(solution.summary.Converged() && solution.summary.stable);
  StrandDynamics dynamics(m, options, {m.NaturalCurvatures(), VecX::Zero(45), 0.0});
  double energy = dynamics.Potential().total + dynamics.Kinetic();
  int halved = 0, iterations = 0;
  double distance = 0.0;
  int k = 0;
  for (; k < 24 * 60; ++k) {
    const StepReport report = dynamics.Step();
    ASSERT_TRUE(report.converged) << report.message;
    halved += report.halvings > 0;
    iterations += report.newton_iterations;
    const double next = report.potential.total + report.kinetic;
    EXPECT_LE(next, energy + 1e-12 * std::abs(energy)) << "step " << k;
    energy = next;
    distance = MaxPointDistance(m, dynamics.state().curvatures, solution.curvatures);
    if (k >= 24 && distance < 1e-7 * m.Length() && report.kinetic < 1e-20) break;
  }
  std::printf("settling (%s): %.2f s (%d steps, %d halved, %.1f Newton iterations per step), "
              "distance to SolveStrand %.2e L\n", name, (k + 1) / 24.0, k + 1, halved,
              static_cast<double>(iterations) / (k + 1), distance / m.Length());
  EXPECT_LT(distance, 1e-6 * m.Length());
}

TEST(DynamicsStatics, DampedMotionSettlesOnTheStaticEquilibrium) { CheckSettling({}, "Newton"); }

// From another start (the equilibrium disturbed by random curvatures and rates), with BDF2 as
// well as backward Euler: the damped strand settles on the same equilibrium within 1e-6 L.
TEST(DynamicsStatics, SettlesFromADisturbedStartWithEitherScheme) {
  const StrandModel m = CurlyStrand();
  const StrandSolution solution = SolveStrand(m);
  ASSERT_TRUE(solution.summary.Converged() && solution.summary.stable);
  for (Integrator integrator : {Integrator::kBackwardEuler, Integrator::kBdf2}) {
    DynamicsOptions options;
    options.integrator = integrator;
    const StrandState start{solution.curvatures + RandomCurvatures(15, 5.0, 21),
                            RandomCurvatures(15, 50.0, 22), 0.0};
    StrandDynamics dynamics(m, options, start);
    double distance = 0.0;
    int k = 0;
    for (; k < 24 * 60; ++k) {
      const StepReport report = dynamics.Step();
      ASSERT_TRUE(report.converged) << report.message;
      distance = MaxPointDistance(m, dynamics.state().curvatures, solution.curvatures);
      if (k >= 24 && distance < 1e-7 * m.Length() && report.kinetic < 1e-20) break;
    }
    std::printf("%s from a disturbed start: settled after %.2f s, distance %.2e L\n",
                integrator == Integrator::kBdf2 ? "BDF2" : "backward Euler", (k + 1) / 24.0,
                distance / m.Length());
    EXPECT_LT(distance, 1e-6 * m.Length());
  }
}

// A moving clamp: the root accelerates uniformly, r(0)(t) = r0 + a t^2 / 2, frame fixed. In the
// clamp's frame the strand feels gravity g - a (the inertial force of the moving frame), so with
// damping it settles, relative to the clamp, on the equilibrium SolveStrand finds for gravity
// g - a, within 1e-6 L; the frame's inertia comes from the step's world positions alone. A clamp
// moving at constant velocity (a = 0, Galilean invariance) keeps a strand at rest on its
// equilibrium.
TEST(DynamicsClamp, UniformlyAcceleratedClampSettlesOnTheEquilibriumOfGravityMinusAcceleration) {
  const StrandModel m = CurlyStrand();
  const Vec3 a(2.0, -1.0, 3.0);
  StrandModel felt = m;
  felt.gravity = m.gravity - a;
  const StrandSolution target = SolveStrand(felt);
  ASSERT_TRUE(target.summary.Converged() && target.summary.stable);
  const StrandSolution still = SolveStrand(m);
  const double far = MaxPointDistance(m, target.curvatures, still.curvatures);
  ASSERT_GT(far, 0.05 * m.Length());  // the acceleration changes the shape
  // Still air would drag the moving strand back (a force -nu dr/dt in world velocity, physical):
  // internal friction only, so that the frame's inertia alone makes the difference.
  DynamicsOptions options;
  options.air_drag = 0.0;
  StrandDynamics dynamics(m, options, {m.NaturalCurvatures(), VecX::Zero(45), 0.0});
  const Vec3 r0 = m.root_position;
  const Mat3 q0 = m.root_frame;
  dynamics.SetClampMotion({[=](double t) -> Vec3 { return r0 + 0.5 * t * t * a; },
                           [=](double) -> Mat3 { return q0; }});
  double distance = 0.0;
  int k = 0;
  for (; k < 24 * 60; ++k) {
    const StepReport report = dynamics.Step();
    ASSERT_TRUE(report.converged) << report.message;
    distance = MaxPointDistance(m, dynamics.state().curvatures, target.curvatures);
    if (k >= 24 && distance < 1e-7 * m.Length()) break;
  }
  std::printf("accelerated clamp: settled after %.2f s within %.2e L of the equilibrium under g - a "
              "(that of g alone is %.2f L away); the root moved %.1f m\n",
              (k + 1) / 24.0, distance / m.Length(), far / m.Length(),
              (dynamics.model().root_position - r0).norm());
  EXPECT_LT(distance, 1e-6 * m.Length());

  // Constant velocity: at rest on the equilibrium relative to the clamp, it stays there.
  const Vec3 v(0.5, 0.2, -0.3);
  StrandDynamics moving(m, options, {still.curvatures, VecX::Zero(45), 0.0});
  moving.SetClampMotion({[=](double t) -> Vec3 { return r0 + t * v; },
                         [=](double) -> Mat3 { return q0; }});
  double worst = 0.0;
  for (int j = 0; j < 48; ++j) {
    const StepReport report = moving.Step();
    ASSERT_TRUE(report.converged) << report.message;
    worst = std::max(worst, MaxPointDistance(m, moving.state().curvatures, still.curvatures));
  }
  std::printf("clamp at constant velocity: drift over 2 s %.2e L\n", worst / m.Length());
  EXPECT_LT(worst, 1e-6 * m.Length());
  EXPECT_THROW(moving.SetClampMotion({}), std::logic_error);
}

// A straight rod on a clamp turning at Omega = 10 rad/s about a vertical axis 5 cm away, its
// tangent pointing outward: with internal friction it comes to rest in the turning frame, where
// gravity and the centrifugal load bend it (0.32 L from the static shape). Against the
// independent shooting solution of that relative equilibrium (reference/rotating_rod.h): in plane
// within the discretization error of n = 10 (the static shape is 1.7e-3 L from the same
// reference at Omega = 0; measured 1.0e-3 L at h = 1/480 s, docs/validation.md), and out of
// plane (no Coriolis or Euler load at rest in the turning frame) within 1e-4 L. BDF2: backward
// Euler's O(Omega h) lag bends it out of plane by 1.6e-2 L at this step (tools/dynamics_study).
TEST(DynamicsClamp, TurningClampSettlesOnTheRelativeEquilibrium) {
  const double length = 0.15, arm = 0.05, omega = 10.0;
  StrandModel m = MakeStrand(length, 10, 0.0, Vec3::Zero(), testing::HorizontalFrame());
  m.root_position = Vec3(arm, 0.0, 0.0);
  const StrandSolution rest = SolveStrand(m);
  ASSERT_TRUE(rest.summary.Converged());
  DynamicsOptions options;
  options.integrator = Integrator::kBdf2;
  options.time_step = 1.0 / 240.0;
  options.air_drag = 0.0;            // still air would drag the turning strand out of its plane
  options.internal_friction = 1e-8;  // settles the relative motion in ~0.2 s (not the shape)
  StrandDynamics dynamics(m, options, {rest.curvatures, VecX::Zero(30), 0.0});
  auto turn = [=](double t) {
    Mat3 r;
    r << std::cos(omega * t), -std::sin(omega * t), 0.0, std::sin(omega * t), std::cos(omega * t),
        0.0, 0.0, 0.0, 1.0;
    return r;
  };
  const Vec3 r0 = m.root_position;
  const Mat3 q0 = m.root_frame;
  dynamics.SetClampMotion({[=](double t) -> Vec3 { return turn(t) * r0; },
                           [=](double t) -> Mat3 { return turn(t) * q0; }});
  for (int k = 0; k < 360; ++k) {  // 1.5 s
    const StepReport report = dynamics.Step();
    ASSERT_TRUE(report.converged) << report.message;
  }
  reference::PlanarRotatingRod rod{length, arm, omega, m.material.density * m.section.Area(),
                                   m.material.young_modulus * m.section.I1(), -m.gravity.z()};
  rod.steps = 2000;
  const std::vector<reference::PlanarRotatingRod::State> shape = rod.Solve();
  std::vector<double> arcs;
  for (int j = 0; j <= 20; ++j) arcs.push_back(length * j / 20.0);
  // The shape relative to the clamp: the model with the root where it was at t = 0.
  const std::vector<Vec3> simulated = SampleCentrelineAt(m, dynamics.state().curvatures, arcs);
  const std::vector<Vec3> statics = SampleCentrelineAt(m, rest.curvatures, arcs);
  double in_plane = 0.0, out_of_plane = 0.0, moved = 0.0;
  for (int j = 0; j <= 20; ++j) {
    const auto& y = shape[static_cast<size_t>(j * 100)];
    const Vec3& p = simulated[static_cast<size_t>(j)];
    in_plane = std::max(in_plane, std::hypot(p.x() - y[0], p.z() - y[1]));
    out_of_plane = std::max(out_of_plane, std::abs(p.y()));
    moved = std::max(moved, (p - statics[static_cast<size_t>(j)]).norm());
  }
  std::printf("turning clamp: in plane %.2e L from the relative equilibrium, %.2e L out of plane; "
              "the turning moved the shape by %.3f L\n",
              in_plane / length, out_of_plane / length, moved / length);
  ASSERT_GT(moved, 0.3 * length);
  EXPECT_LT(in_plane, 2.5e-3 * length);
  EXPECT_LT(out_of_plane, 1e-4 * length);
}

// ---------------------------------------------------------------------------------------------
// Convergence in the time step.

// A horizontal curly strand released under gravity (20 cm, the tip moves 0.24 L in 0.5 s), no
// halving allowed: the error at t = 0.5 s against a fine BDF2 reference (h = T/1536) falls like h
// with backward Euler and like h^2 with BDF2 between h = T/96 and T/192 (measured 0.96 and 1.98
// at the finest pair of the study, docs/validation.md).
TEST(DynamicsConvergence, FirstOrderBackwardEulerSecondOrderBdf2) {
  StrandModel m = MakeStrand(0.2, 10, 0.3, Vec3(40.0, 0.0, 10.0), testing::HorizontalFrame());
  m.section = SectionFromEccentricity(40e-6, 0.3);
  const double duration = 0.5;
  auto run = [&](Integrator integrator, int steps, double model_tolerance = 0.0) {
    DynamicsOptions options;
    options.integrator = integrator;
    options.model_tolerance = model_tolerance;
    options.max_halvings = 0;
    StrandDynamics dynamics(m, options, {m.NaturalCurvatures(), VecX::Zero(30), 0.0});
    for (int k = 0; k < steps; ++k) {
      const StepReport report = dynamics.Step(duration / steps);
      EXPECT_TRUE(report.converged) << report.message;
    }
    return SampleCentreline(m, dynamics.state().curvatures, 4);
  };
  const std::vector<Vec3> reference = run(Integrator::kBdf2, 1536);
  auto error = [&](const std::vector<Vec3>& r) {
    double e = 0.0;
    for (size_t j = 0; j < r.size(); ++j) e = std::max(e, (r[j] - reference[j]).norm());
    return e / m.Length();
  };
  for (Integrator integrator : {Integrator::kBackwardEuler, Integrator::kBdf2}) {
    const double coarse = error(run(integrator, 96)), fine = error(run(integrator, 192));
    const double order = std::log2(coarse / fine);
    const bool bdf2 = integrator == Integrator::kBdf2;
    std::printf("swing, %s: error %.2e L at h = T/96, %.2e L at T/192, order %.2f\n",
                bdf2 ? "BDF2" : "backward Euler", coarse, fine, order);
    EXPECT_NEAR(order, bdf2 ? 2.0 : 1.0, bdf2 ? 0.3 : 0.25);
  }
  // Inexact steps (mostly one Newton update) keep each scheme's order.
  for (Integrator integrator : {Integrator::kBackwardEuler, Integrator::kBdf2}) {
    const double coarse = error(run(integrator, 96, kInexact));
    const double fine = error(run(integrator, 192, kInexact));
    const double order = std::log2(coarse / fine);
    const bool bdf2 = integrator == Integrator::kBdf2;
    std::printf("swing, %s, inexact steps: error %.2e L at h = T/96, %.2e L at T/192, order %.2f\n",
                bdf2 ? "BDF2" : "backward Euler", coarse, fine, order);
    EXPECT_NEAR(order, bdf2 ? 2.0 : 1.0, bdf2 ? 0.3 : 0.25);
  }
}

// ---------------------------------------------------------------------------------------------
// Energy of the implicit steps.

// Without dissipation, backward Euler still loses energy (its numerical damping, 1/(1 + (omega
// h)^2) per step in each mode's energy): over 10^4 steps the total energy must never rise, and
// the loss is reported.
TEST(DynamicsEnergy, UndampedEnergyIsBoundedOverTenThousandSteps) {
  StrandModel m = MakeStrand(0.1, 6, 0.0, Vec3(30.0, 0.0, 0.0), testing::HorizontalFrame());
  const StrandSolution solution = SolveStrand(m);
  ASSERT_TRUE(solution.summary.Converged());
  for (Integrator integrator : {Integrator::kBackwardEuler, Integrator::kBdf2}) {
    DynamicsOptions options;
    options.internal_friction = 0.0;
    options.air_drag = 0.0;
    options.time_step = 1e-3;
    options.integrator = integrator;
    options.mass_points = 3;
    StrandDynamics dynamics(m, options, {m.NaturalCurvatures(), VecX::Zero(18), 0.0});
    const double initial = dynamics.Potential().total + dynamics.Kinetic();
    const double range = initial - solution.summary.energy.total;  // above the equilibrium
    double energy = initial, highest = initial, lowest = initial;
    int rises = 0;
    for (int k = 0; k < 10000; ++k) {
      const StepReport report = dynamics.Step();
      ASSERT_TRUE(report.converged) << report.message;
      EXPECT_EQ(report.halvings, 0);
      const double next = report.potential.total + report.kinetic;
      rises += next > energy + 1e-12 * std::abs(initial);
      energy = next;
      highest = std::max(highest, energy);
      lowest = std::min(lowest, energy);
    }
    // Backward Euler's energy never rises; BDF2's need not fall monotonically, but it stays below
    // the start.
    if (integrator == Integrator::kBackwardEuler) {
      EXPECT_EQ(rises, 0);
    }
    std::printf("undamped, %s, h = 1 ms: energy above equilibrium %.4e J at start, %.4e J after "
                "10^4 steps (%.2f%% lost), highest %.3e above the start, %d rises\n",
                integrator == Integrator::kBdf2 ? "BDF2" : "backward Euler", range,
                energy - solution.summary.energy.total, 100.0 * (initial - energy) / range,
                (highest - initial) / range, rises);
    EXPECT_LE(highest, initial + 1e-3 * range);
    EXPECT_GE(lowest, solution.summary.energy.total - 1e-12 * std::abs(initial));
    if (integrator == Integrator::kBdf2) {
      EXPECT_LT(initial - energy, 0.5 * range);
    }
  }
}

// A heavy curly strand (50 cm, Gamma = 460) released horizontally whips round at one step per
// film frame: Newton converges without halving and the total energy never rises. (Predicting the
// next step from J qdot instead of the samples' own velocities fed energy in here: the total rose
// 30-fold in 0.4 s and the steps failed at 0.8 s.)
void CheckHeavyCurlyStrand(const DynamicsOptions& options) {
  StrandModel m;
  m.segment_lengths = UniformSegments(0.5, 25);
  m.section = SectionFromEccentricity(40e-6, 0.5);
  m.natural_curvature = Vec3(60.0, 0.0, 20.0);
  m.root_frame = testing::HorizontalFrame();
  StrandDynamics dynamics(m, options, {m.NaturalCurvatures(), VecX::Zero(75), 0.0});
  double energy = dynamics.Potential().total + dynamics.Kinetic();
  const double scale = std::abs(energy);
  for (int k = 0; k < 24; ++k) {
    const StepReport report = dynamics.Step();
    ASSERT_TRUE(report.converged) << report.message;
    EXPECT_EQ(report.halvings, 0) << k;
    const double next = report.potential.total + report.kinetic;
    EXPECT_LE(next, energy + 1e-12 * scale) << "step " << k;
    energy = next;
  }
}

TEST(DynamicsEnergy, HeavyCurlyStrandAtFilmFramesNeverGainsEnergy) { CheckHeavyCurlyStrand({}); }

// ---------------------------------------------------------------------------------------------
// Film frames with contact.

// Every hair type (the 12 presets of hair_type.h, origin x curl, one strand each), 30 cm,
// rooted near the top of a spherical head (Body, radius 10 cm), released from its natural shape: one step per film frame (h = 1/24 s) for 3 s, with
// contact. Every step must converge; halvings are counted and reported.
void CheckEveryHairType(const DynamicsOptions& options, const char* name) {
  Body head;
  std::string error;
  ASSERT_TRUE(Body::Create({Sphere{Vec3::Zero(), 0.1, "head"}}, {}, &head, &error)) << error;
  const auto obstacle = std::make_shared<const Body>(std::move(head));
  int total_halved = 0, total_steps = 0;
  for (std::string_view origin : HairOrigins()) {
    for (std::string_view curl : CurlTypes()) {
      HairType type;
      ASSERT_TRUE(FindHairType(origin, curl, &type, &error)) << error;
      const StrandParameters p = SampleStrand(type, 1, 0);
      StrandModel m;
      m.section = p.section;
      m.material = p.material;
      m.natural_curvature = p.natural_curvature;
      m.segment_lengths = UniformSegments(0.3, 20);
      // Rooted near the top of the head (70 degrees up), growing 27 degrees off the scalp
      // towards the side: gravity lays it on the head.
      const double angle = 1.2;
      const Vec3 normal(std::cos(angle), 0.0, std::sin(angle));
      const Vec3 down_the_scalp(std::sin(angle), 0.0, -std::cos(angle));
      m.root_position = 0.1 * normal;
      Mat3 frame;
      ASSERT_TRUE(RootFrameFromTangentNormal(0.5 * normal + down_the_scalp, Vec3(0, 1, 0), &frame,
                                             &error)) << error;
      m.root_frame = frame;
      m.contact.obstacle = obstacle;
      m.contact.clearance = 1e-3;
      StrandDynamics dynamics(m, options, {m.NaturalCurvatures(), VecX::Zero(60), 0.0});
      const double initial_depth = MeasureContact(m, m.NaturalCurvatures()).max_penetration;
      int halved = 0, iterations = 0, contact_steps = 0;
      double deepest = 0.0;
      for (int k = 0; k < 72; ++k) {
        const StepReport report = dynamics.Step();
        ASSERT_TRUE(report.converged) << origin << " " << curl << ": " << report.message;
        halved += report.halvings > 0;
        iterations += report.newton_iterations;
        const ContactMeasure contact = MeasureContact(m, dynamics.state().curvatures);
        contact_steps += contact.samples_in_contact > 0;
        deepest = std::max(deepest, contact.max_penetration);
      }
      std::printf("%s %s: 72 frames, %d halved, %.1f Newton iterations per frame, in contact in "
                  "%d frames, deepest penetration %.2f mm (%.2f mm at the start)\n",
                  std::string(origin).c_str(), std::string(curl).c_str(), halved,
                  iterations / 72.0, contact_steps, 1e3 * deepest, 1e3 * initial_depth);
      EXPECT_GT(contact_steps, 0) << origin << " " << curl;
      total_halved += halved;
      total_steps += 72;
    }
  }
  std::printf("film frames (%s): %d of %d steps halved\n", name, total_halved, total_steps);
  // Measured: none (Newton: 3.7-4.4 iterations per frame; 1.5 for the stiff kinky coils).
  EXPECT_LE(total_halved, total_steps / 20);
}

TEST(DynamicsFilmFrames, EveryHairTypeWithContactAtOneStepPerFrame) {
  CheckEveryHairType({}, "Newton");
}

// ---------------------------------------------------------------------------------------------
// Inexact steps (DynamicsOptions::model_tolerance): mostly one Newton update per step,
// with 2 mass samples per segment, the configuration of the head benchmark's fast rows.

DynamicsOptions LinearlyImplicit() {
  DynamicsOptions options;
  options.model_tolerance = kInexact;
  options.mass_points = 2;
  return options;
}

// At the equilibrium with no rates the one update is Newton's from the solution: the strand stays
// within 1e-6 L for 10 s.
TEST(DynamicsInexactSteps, RestAtEquilibriumStaysPut) {
  CheckRestAtEquilibrium(LinearlyImplicit(), "inexact steps");
}

// A fixed point of the step has zero gradient of E (the inertia and dissipation terms vanish at
// rest), so damped motion settles on SolveStrand's equilibrium, within 1e-6 L; the total energy
// never rises on the way.
TEST(DynamicsInexactSteps, DampedMotionSettlesOnTheStaticEquilibrium) {
  CheckSettling(LinearlyImplicit(), "inexact steps");
}

TEST(DynamicsInexactSteps, HeavyCurlyStrandAtFilmFramesNeverGainsEnergy) {
  CheckHeavyCurlyStrand(LinearlyImplicit());
}

TEST(DynamicsInexactSteps, EveryHairTypeWithContactAtOneStepPerFrame) {
  CheckEveryHairType(LinearlyImplicit(), "inexact steps");
}

// ---------------------------------------------------------------------------------------------
// Reports, determinism, bad input.

// A step whose Newton iterations run out is halved and says so; with no halving allowed it fails,
// says why and leaves the state as it was.
TEST(DynamicsSteps, HalvingIsReportedAndFailureLeavesTheStateUnchanged) {
  const StrandModel m = CurlyStrand();
  DynamicsOptions options;
  options.max_newton_iterations = 4;
  StrandDynamics halving(m, options, {m.NaturalCurvatures(), VecX::Zero(45), 0.0});
  const StepReport report = halving.Step();
  ASSERT_TRUE(report.converged) << report.message;
  EXPECT_GT(report.halvings, 0);
  EXPECT_GT(report.substeps, 1);
  EXPECT_NE(report.message.find("halved"), std::string::npos) << report.message;
  EXPECT_NEAR(report.time, 1.0 / 24.0, 1e-15);

  options.max_halvings = 0;
  StrandDynamics failing(m, options, {m.NaturalCurvatures(), VecX::Zero(45), 0.0});
  const StepReport failed = failing.Step();
  EXPECT_FALSE(failed.converged);
  EXPECT_NE(failed.message.find("Newton did not converge in 4"), std::string::npos) << failed.message;
  EXPECT_EQ(failing.state().curvatures, m.NaturalCurvatures());
  EXPECT_EQ(failing.state().rates, VecX::Zero(45));
  EXPECT_EQ(failing.state().time, 0.0);
}

// The same run twice gives the same bits (no threads, no uninitialized state).
TEST(DynamicsSteps, Deterministic) {
  const StrandModel m = CurlyStrand();
  DynamicsOptions options;
  options.integrator = Integrator::kBdf2;
  StrandDynamics a(m, options, {m.NaturalCurvatures(), VecX::Zero(45), 0.0});
  StrandDynamics b(m, options, {m.NaturalCurvatures(), VecX::Zero(45), 0.0});
  for (int k = 0; k < 12; ++k) {
    a.Step();
    b.Step();
  }
  EXPECT_EQ(a.state().curvatures, b.state().curvatures);
  EXPECT_EQ(a.state().rates, b.state().rates);
}

TEST(DynamicsSteps, BadInputIsRefusedWithTheFieldNamed) {
  const StrandModel m = CurlyStrand();
  auto message = [&](const DynamicsOptions& options, const StrandState& state) {
    try {
      StrandDynamics dynamics(m, options, state);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const StrandState good{m.NaturalCurvatures(), VecX::Zero(45), 0.0};
  DynamicsOptions options;
  EXPECT_EQ(message(options, good), "");
  options.time_step = 0.0;
  EXPECT_NE(message(options, good).find("time_step"), std::string::npos);
  options = {};
  options.air_drag = -1.0;
  EXPECT_NE(message(options, good).find("air_drag"), std::string::npos);
  options = {};
  options.internal_friction = std::nan("");
  EXPECT_NE(message(options, good).find("internal_friction"), std::string::npos);
  options = {};
  options.mass_points = 9;
  EXPECT_NE(message(options, good).find("mass_points"), std::string::npos);
  options = {};
  options.model_tolerance = 1.0;
  EXPECT_NE(message(options, good).find("model_tolerance"), std::string::npos);
  StrandState bad = good;
  bad.rates = VecX::Zero(44);
  EXPECT_NE(message({}, bad).find("rates must be 45"), std::string::npos);
  bad = good;
  bad.curvatures(3) = std::numeric_limits<double>::infinity();
  EXPECT_NE(message({}, bad).find("curvatures must be 45 finite"), std::string::npos);
  StrandDynamics dynamics(m, {}, good);
  EXPECT_THROW(dynamics.Step(-1.0), std::invalid_argument);
  StrandModel big = MakeStrand(1.0, kMaxModalSegments + 1);
  EXPECT_THROW(ComputeModes(big, VecX::Zero(3 * big.NumSegments()), 1), std::invalid_argument);
}

}  // namespace
}  // namespace ringlet
