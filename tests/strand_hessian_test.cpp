// The exact Hessian (strand_hessian.h) against central differences of the exact gradient (energy.h,
// tested on its own against differences of the energy in energy_test.cpp), term by term; its O(n)
// product, factorization and solve against dense linear algebra; and the obstacles' distance
// Hessians against differences of their gradients.
#include "ringlet/strand_hessian.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <memory>

#include "ringlet/body.h"
#include "ringlet/energy.h"
#include "ringlet/statics.h"
#include "test_util.h"

namespace ringlet {
namespace {

using testing::HorizontalFrame;
using testing::MakeStrand;
using testing::RandomCurvatures;
using testing::RandomRotation;

// d(gradient)/dq by central differences, column j with step h_j = step / l_(segment of j): the
// curvature change turns its segment by `step` rad. Truncation ~h^2, rounding ~eps |g| / h.
MatX FiniteDifferenceHessian(const StrandModel& model, const VecX& q, double step) {
  StrandEnergy energy(model);
  const int n = static_cast<int>(q.size());
  MatX h(n, n);
  VecX gp, gm, x = q;
  for (int j = 0; j < n; ++j) {
    const double dq = step / model.segment_lengths[static_cast<size_t>(j / 3)];
    x(j) = q(j) + dq;
    energy.Evaluate(x, &gp);
    x(j) = q(j) - dq;
    energy.Evaluate(x, &gm);
    x(j) = q(j);
    h.col(j) = (gp - gm) / (2.0 * dq);
  }
  return h;
}

// Every entry of the exact Hessian within rel_tol of the largest entry of the difference of
// the two (a relative error with an absolute floor), and not vacuous: the loads contribute.
void ExpectHessianMatchesFd(const StrandModel& model, const VecX& q, double rel_tol) {
  StrandHessian hessian;
  ComputeStrandHessian(model, q, &hessian);
  const MatX exact = hessian.Dense();
  const MatX fd = FiniteDifferenceHessian(model, q, 1e-6);
  const double scale = fd.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0.0);
  EXPECT_LE((exact - fd).cwiseAbs().maxCoeff(), rel_tol * scale)
      << "exact:\n" << exact.topLeftCorner(6, 6) << "\nfd:\n" << fd.topLeftCorner(6, 6);
  // Anti-vacuity: the external loads change the Hessian by much more than the tolerance.
  MatX elastic = MatX::Zero(q.size(), q.size());
  const Vec3 k = model.Stiffness();
  for (int i = 0; i < model.NumSegments(); ++i) {
    elastic.block<3, 3>(3 * i, 3 * i) = (model.segment_lengths[static_cast<size_t>(i)] * k).asDiagonal();
  }
  EXPECT_GT((exact - elastic).cwiseAbs().maxCoeff(), 1e3 * rel_tol * scale);
}

struct HessianCase {
  double length;
  int segments;
  double eccentricity;
  double amplitude;  // random curvature amplitude (1/m)
  double gravity_scale;  // times the paper's g (heavier than hair: larger load terms)
  unsigned seed;
};

class GravityHessianTest : public ::testing::TestWithParam<HessianCase> {};

TEST_P(GravityHessianTest, MatchesFiniteDifferencesOfTheGradient) {
  const HessianCase c = GetParam();
  StrandModel model = MakeStrand(c.length, c.segments, c.eccentricity,
                                 Vec3(20.0, -5.0, 8.0), RandomRotation(c.seed));
  model.gravity *= c.gravity_scale;
  const VecX q = RandomCurvatures(c.segments, c.amplitude, c.seed + 1);
  ExpectHessianMatchesFd(model, q, 2e-7);
}

INSTANTIATE_TEST_SUITE_P(
    Configurations, GravityHessianTest,
    ::testing::Values(HessianCase{0.2, 5, 0.0, 30.0, 1e3, 1u},     // round, moderate curvature
                      HessianCase{0.2, 12, 0.6, 80.0, 1e3, 2u},    // elliptic, turns > 2 rad
                      HessianCase{0.3, 20, 0.3, 1e-4, 1e4, 3u},    // nearly straight (Taylor)
                      HessianCase{0.05, 8, 0.9, 300.0, 1e5, 4u},   // tight curls, x up to 5
                      HessianCase{0.5, 30, 0.5, 10.0, 1e2, 5u}));  // long

TEST(GravityHessian, GradedSegmentsAndZeroCurvature) {
  StrandModel model = MakeStrand(0.4, 15, 0.4, Vec3::Zero(), HorizontalFrame());
  model.segment_lengths = GradedSegments(0.4, 15, 6.0);
  model.gravity *= 1e3;
  ExpectHessianMatchesFd(model, VecX::Zero(45), 2e-7);
}

// Spheres with exact distances, as test obstacles (independent of src/body).
class SphereObstacle final : public Obstacle {
 public:
  SphereObstacle(const Vec3& c, double r) : c_(c), r_(r) {}
  double SignedDistance(const Vec3& x, Vec3* gradient) const override {
    const Vec3 d = x - c_;
    const double n = d.norm();
    if (gradient) *gradient = d / n;
    return n - r_;
  }

 private:
  Vec3 c_;
  double r_;
};

// A strand draped over a sphere at its equilibrium, where many samples press into the clearance
// layer (the configuration the certificate is used at).
StrandModel DrapedStrand(std::shared_ptr<const Obstacle> obstacle, VecX* q) {
  StrandModel m = MakeStrand(0.3, 20, 0.5, Vec3(15.0, 0.0, 5.0), HorizontalFrame());
  m.root_position = Vec3(0, 0, 0.1);
  m.contact.obstacle = std::move(obstacle);
  m.contact.clearance = 2e-3;
  SolveOptions options;
  options.check_stability = false;
  *q = SolveStrand(m, options).curvatures;
  return m;
}

TEST(ContactHessian, MatchesFiniteDifferencesOnADrapedStrand) {
  // The test obstacle has no Hessian of its own: its default (differences of its gradient)
  // is used, accurate to ~1e-7 relative, well inside the tolerance.
  VecX q;
  const StrandModel m = DrapedStrand(std::make_shared<SphereObstacle>(Vec3::Zero(), 0.1), &q);
  const ContactMeasure contact = MeasureContact(m, q);
  ASSERT_GT(contact.samples_in_contact, 10) << "vacuous: no contact";
  ExpectHessianMatchesFd(m, q, 1e-6);
  // The contact part alone is significant: removing the obstacle changes the Hessian.
  StrandModel free = m;
  free.contact.obstacle = nullptr;
  StrandHessian with, without;
  ComputeStrandHessian(m, q, &with);
  ComputeStrandHessian(free, q, &without);
  EXPECT_GT((with.Dense() - without.Dense()).cwiseAbs().maxCoeff(),
            1e-2 * with.Dense().cwiseAbs().maxCoeff());
}

// The eigenvalue from a Hessian already computed (what the inversion does) against the one that
// computes its own, and against a dense eigensolver of the scaled Hessian.
TEST(MinScaledHessianEigenvalue, FromAComputedHessianAgrees) {
  VecX q;
  const StrandModel m = DrapedStrand(std::make_shared<SphereObstacle>(Vec3::Zero(), 0.1), &q);
  StrandHessian h;
  ComputeStrandHessian(m, q, &h);
  const double from_hessian = MinScaledHessianEigenvalue(m, h);
  const double own = MinScaledHessianEigenvalue(m, q);
  EXPECT_NEAR(from_hessian, own, 1e-12 * std::abs(own));
  const int n = m.NumSegments();
  VecX s(3 * n);
  for (int i = 0; i < n; ++i) {
    s.segment<3>(3 * i) = (m.segment_lengths[i] * m.Stiffness()).cwiseSqrt().cwiseInverse();
  }
  const MatX scaled = s.asDiagonal() * h.Dense() * s.asDiagonal();
  const double dense = Eigen::SelfAdjointEigenSolver<MatX>(scaled).eigenvalues()(0);
  ASSERT_GT(dense, 0.0);
  ASSERT_LT(dense, 0.9);  // the loads matter (1 = no load)
  // Inverse iteration's Rayleigh quotient: from above, within a few percent here (it converges
  // as (lambda_1 / lambda_2)^(2k) and this strand's two smallest are close).
  EXPECT_GE(from_hessian, dense * (1.0 - 1e-12));
  EXPECT_LE(from_hessian, dense * 1.03);
}

TEST(ContactHessian, MatchesFiniteDifferencesOnBlendedAndMeshBodies) {
  // Two overlapping spheres with a smooth union, then a closed mesh (an octahedron under the
  // strand): the bodies' exact distance Hessians.
  std::vector<Sphere> spheres = {{Vec3(0, 0, 0), 0.1, "a"}, {Vec3(0.12, 0, -0.02), 0.08, "b"}};
  auto blended = std::make_shared<Body>();
  std::string error;
  ASSERT_TRUE(Body::Create(spheres, {}, blended.get(), &error, 0.02)) << error;
  VecX q;
  StrandModel m = DrapedStrand(blended, &q);
  ASSERT_GT(MeasureContact(m, q).samples_in_contact, 10);
  ExpectHessianMatchesFd(m, q, 1e-6);

  // The strand (along +x from the apex) lies on a face, then crosses an edge and hangs.
  const double a = 0.2;
  std::vector<Vec3> v = {{a, a, 0}, {-a, a, 0}, {-a, -a, 0}, {a, -a, 0}, {0, 0, 0.1}, {0, 0, -0.15}};
  std::vector<TriangleMesh::Triangle> t = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4},
                                           {1, 0, 5}, {2, 1, 5}, {3, 2, 5}, {0, 3, 5}};
  TriangleMesh mesh;
  ASSERT_TRUE(TriangleMesh::Create(v, t, "octahedron", &mesh, &error)) << error;
  auto body = std::make_shared<Body>();
  ASSERT_TRUE(Body::Create({}, {mesh}, body.get(), &error)) << error;
  m = DrapedStrand(body, &q);
  ASSERT_GT(MeasureContact(m, q).samples_in_contact, 5);
  ExpectHessianMatchesFd(m, q, 1e-6);
}

TEST(BodyDistanceHessian, MatchesDifferencesOfTheGradient) {
  std::vector<Sphere> spheres = {{Vec3(0, 0, 0), 0.1, "a"}, {Vec3(0.12, 0, -0.02), 0.08, "b"}};
  std::vector<Vec3> v = {{0.35, 0, 0}, {0.25, 0, 0}, {0.3, 0.05, 0},
                         {0.3, -0.05, 0}, {0.3, 0, 0.05}, {0.3, 0, -0.05}};
  std::vector<TriangleMesh::Triangle> t = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                           {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  TriangleMesh mesh;
  std::string error;
  ASSERT_TRUE(TriangleMesh::Create(v, t, "octahedron", &mesh, &error)) << error;
  for (double blend : {0.0, 0.03}) {
    Body body;
    ASSERT_TRUE(Body::Create(spheres, {mesh}, &body, &error, blend)) << error;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-0.25, 0.45);
    int curved = 0;
    for (int trial = 0; trial < 200; ++trial) {
      const Vec3 x(u(rng), 0.6 * u(rng), 0.6 * u(rng));
      Vec3 g;
      Mat3 h;
      const double d = body.SignedDistanceHessian(x, &g, &h);
      Vec3 g_plain;
      EXPECT_EQ(d, body.SignedDistance(x, &g_plain));
      EXPECT_LE((g - g_plain).norm(), 1e-15);
      // Differences of the gradient; skip points near a kink of the gradient (medial axis,
      // blend boundaries), where the Hessian is not defined, detected by a step-halving check.
      Mat3 fd, fd_half;
      for (int j = 0; j < 3; ++j) {
        for (double step : {1e-6, 5e-7}) {
          Vec3 gp, gm;
          body.SignedDistance(x + step * Vec3::Unit(j), &gp);
          body.SignedDistance(x - step * Vec3::Unit(j), &gm);
          (step == 1e-6 ? fd : fd_half).col(j) = (gp - gm) / (2 * step);
        }
      }
      if ((fd - fd_half).norm() > 1e-4 * (1.0 + fd.norm())) continue;
      EXPECT_LE((h - fd).norm(), 1e-5 * (1.0 + fd.norm())) << "x = " << x.transpose();
      if (h.norm() > 1.0) ++curved;
    }
    EXPECT_GT(curved, 100) << "vacuous: flat everywhere";
  }
}

StrandModel HeavyStrand(int segments, unsigned seed, VecX* q) {
  StrandModel m = MakeStrand(0.3, segments, 0.4, Vec3(40.0, 10.0, 5.0), RandomRotation(seed));
  m.gravity *= 300.0;
  *q = RandomCurvatures(segments, 20.0, seed + 3);
  return m;
}

TEST(StrandHessian, MultiplyEqualsTheDenseProduct) {
  VecX q;
  const StrandModel m = HeavyStrand(25, 11, &q);
  StrandHessian h;
  ComputeStrandHessian(m, q, &h);
  const MatX dense = h.Dense();
  const VecX v = RandomCurvatures(25, 1.0, 12);
  VecX hv;
  h.Multiply(v, &hv);
  EXPECT_LE((hv - dense * v).norm(), 1e-12 * (dense * v).norm());
  EXPECT_LE((dense - dense.transpose()).cwiseAbs().maxCoeff(), 1e-12 * dense.cwiseAbs().maxCoeff());
}

TEST(StrandHessian, ScaleIsTheCongruence) {
  VecX q;
  const StrandModel m = HeavyStrand(10, 21, &q);
  StrandHessian h;
  ComputeStrandHessian(m, q, &h);
  const MatX before = h.Dense();
  const VecX s = RandomCurvatures(10, 1.0, 22).cwiseAbs().array() + 0.1;
  h.Scale(s);
  EXPECT_LE((h.Dense() - s.asDiagonal() * before * s.asDiagonal()).cwiseAbs().maxCoeff(),
            1e-12 * h.Dense().cwiseAbs().maxCoeff());
}

TEST(StrandHessianFactor, AgreesWithDenseCholeskyAndSolves) {
  // Shifts below and above the smallest eigenvalue: Factor succeeds exactly when the dense
  // Cholesky of H - shift I does, and then solves like it.
  for (unsigned seed : {31u, 32u, 33u}) {
    VecX q;
    const StrandModel m = HeavyStrand(18, seed, &q);
    StrandHessian h;
    ComputeStrandHessian(m, q, &h);
    const MatX dense = h.Dense();
    const Eigen::SelfAdjointEigenSolver<MatX> eig(dense);
    const double lambda = eig.eigenvalues()(0);
    const double spread = eig.eigenvalues()(eig.eigenvalues().size() - 1) - lambda;
    for (double offset : {-0.1, -1e-3, 1e-3, 0.1}) {
      const double shift = lambda + offset * spread;
      StrandHessianFactor factor;
      const bool ok = factor.Factor(h, shift);
      const MatX shifted = dense - shift * MatX::Identity(dense.rows(), dense.cols());
      const Eigen::LLT<MatX> llt(shifted);
      EXPECT_EQ(ok, llt.info() == Eigen::Success) << "seed " << seed << " offset " << offset;
      EXPECT_EQ(ok, offset < 0.0);
      if (!ok) {
        EXPECT_GE(factor.failed_segment(), 0);
        continue;
      }
      const VecX b = RandomCurvatures(18, 1.0, seed + 100);
      VecX x;
      factor.Solve(b, &x);
      EXPECT_LE((shifted * x - b).norm(), 1e-9 * b.norm() * shifted.norm() * x.norm() / b.norm() + 1e-12);
      EXPECT_LE((x - llt.solve(b)).norm(), 1e-8 * x.norm());
    }
  }
}

// The energy and gradient of ComputeStrandEnergyAndHessian (the Hessian sweep's adjoints through
// the segments' derivative matrices) against StrandEnergy::Evaluate (LoadSweep: HelixSegmentVjp
// and HelixChordVjp, tested against differences of the energy in energy_test.cpp), with and
// without contact; its Hessian is ComputeStrandHessian's, bit for bit.
void ExpectEnergyAndGradientAgree(const StrandModel& model, const VecX& q) {
  StrandEnergy energy(model);
  VecX reference_gradient;
  EnergyTerms reference;
  const double reference_total = energy.Evaluate(q, &reference_gradient, &reference);
  StrandHessian fused, alone;
  VecX gradient;
  EnergyTerms terms;
  const double total = ComputeStrandEnergyAndHessian(model, q, &fused, &gradient, &terms);
  ComputeStrandHessian(model, q, &alone);
  // Relative to the largest of the gradient and its elastic part (at an equilibrium the loads'
  // part cancels the elastic one: the sum is ~0, its parts are not).
  VecX elastic_gradient;
  ElasticEnergy(model, q, &elastic_gradient);
  const double scale = std::max(reference_gradient.cwiseAbs().maxCoeff(),
                                elastic_gradient.cwiseAbs().maxCoeff());
  ASSERT_GT(scale, 0.0);
  ASSERT_EQ(gradient.size(), reference_gradient.size());
  EXPECT_LE((gradient - reference_gradient).cwiseAbs().maxCoeff(), 1e-11 * scale);
  const double size = std::abs(reference.elastic) + std::abs(reference.gravity) +
                      std::abs(reference.contact);
  EXPECT_NEAR(terms.elastic, reference.elastic, 1e-13 * size);
  EXPECT_NEAR(terms.gravity, reference.gravity, 1e-13 * size);
  EXPECT_NEAR(terms.contact, reference.contact, 1e-13 * size);
  EXPECT_NEAR(total, reference_total, 1e-13 * size);
  EXPECT_EQ(terms.total, total);
  EXPECT_TRUE(fused.Dense() == alone.Dense());
}

TEST(StrandEnergyAndHessian, EnergyAndGradientAreStrandEnergys) {
  for (const HessianCase& c : {HessianCase{0.2, 12, 0.6, 80.0, 1e3, 2u},
                               HessianCase{0.3, 20, 0.3, 1e-4, 1e4, 3u},
                               HessianCase{0.05, 8, 0.9, 300.0, 1e5, 4u}}) {
    StrandModel model = MakeStrand(c.length, c.segments, c.eccentricity,
                                   Vec3(20.0, -5.0, 8.0), RandomRotation(c.seed));
    model.gravity *= c.gravity_scale;
    ExpectEnergyAndGradientAgree(model, RandomCurvatures(c.segments, c.amplitude, c.seed + 1));
  }
  VecX q;
  const StrandModel draped =
      DrapedStrand(std::make_shared<SphereObstacle>(Vec3::Zero(), 0.1), &q);
  ASSERT_GT(MeasureContact(draped, q).samples_in_contact, 10) << "vacuous: no contact";
  ExpectEnergyAndGradientAgree(draped, q);
  // Away from the equilibrium the contact forces do not balance the rest: a gradient of size.
  ExpectEnergyAndGradientAgree(draped, q + RandomCurvatures(20, 2.0, 9u));
  std::vector<Sphere> spheres = {{Vec3(0, 0, 0), 0.1, "a"}, {Vec3(0.12, 0, -0.02), 0.08, "b"}};
  auto blended = std::make_shared<Body>();
  std::string error;
  ASSERT_TRUE(Body::Create(spheres, {}, blended.get(), &error, 0.02)) << error;
  const StrandModel on_body = DrapedStrand(blended, &q);
  ASSERT_GT(MeasureContact(on_body, q).samples_in_contact, 10);
  ExpectEnergyAndGradientAgree(on_body, q + RandomCurvatures(20, 2.0, 10u));
}

}  // namespace
}  // namespace ringlet
