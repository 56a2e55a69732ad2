// Inverse statics (inverse.h): the rest shape against the closed form of a straight cantilever,
// round trips through the forward solver (gravity, contact), the sag of the naive rest shape,
// Greenhill's column below and above its critical load, and the piecewise-helix fit against
// known piecewise helices, circles and helices in closed form.
#include "ringlet/inverse.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <set>

#include "reference/greenhill.h"
#include "ringlet/contact.h"
#include "ringlet/energy.h"
#include "ringlet/helix.h"
#include "ringlet/kirchhoff.h"
#include "ringlet/obstacle.h"
#include "ringlet/strand_geometry.h"
#include "ringlet/strand_hessian.h"
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
// (ringlet's own groom, contact forces included). With the penalty forces of the model at the
// target (contact forces not unknowns), the inversion recovers that rest shape, to the forward
// solve's tolerance, and the target holds.
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

    InverseOptions penalty_only;  // the model's penalty forces at the target, not unknowns
    penalty_only.contact_forces = false;
    const InverseResult r = InvertStrand(m, groom.curvatures, penalty_only);
    SCOPED_TRACE(r.message);
    EXPECT_TRUE(r.supports.empty());
    EXPECT_TRUE(r.support_offsets.empty());
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
// Contact forces as unknowns.

// The elastic energy 1/2 sum_i l_i (q0_i - q0nat)^T K (q0_i - q0nat) of a rest shape, written
// here from its definition (inverse.h, InverseResult::rest_energy).
double RestEnergyOf(const StrandModel& m, const VecX& rest) {
  double e = 0.0;
  for (int i = 0; i < m.NumSegments(); ++i) {
    const Vec3 d = rest.segment<3>(3 * i) - m.natural_curvature;
    e += 0.5 * m.segment_lengths[i] * d.dot(m.Stiffness().cwiseProduct(d));
  }
  return e;
}

// PointForceGradient against central differences of -F . x(q), with x(q) the sample position
// from the public geometry (ComputeGeometry and HelixChord), for a curly strand, samples inside
// and at the end of segments.
TEST(PointForceGradient, MatchesFiniteDifferencesOfTheWork) {
  const int n = 7;
  StrandModel m = MakeStrand(0.2, n, 0.3, Vec3(25.0, -10.0, 8.0), RandomRotation(3));
  const VecX q = m.NaturalCurvatures() + RandomCurvatures(n, 10.0, 4);
  const Vec3 force(0.3, -1.2, 0.7);
  for (auto [segment, fraction] : {std::pair{0, 0.25}, std::pair{3, 0.5}, std::pair{6, 1.0}}) {
    const double u = fraction * m.segment_lengths[segment];
    const auto work = [&](const VecX& c) {
      const StrandGeometry g = ComputeGeometry(m, c);
      const Vec3 x = g.points[segment] +
                     g.frames[segment] * HelixChord(c.segment<3>(3 * segment), u);
      return -force.dot(x);
    };
    const VecX gradient = PointForceGradient(m, q, segment, u, force);
    ASSERT_GT(gradient.norm(), 1e-6);  // anti-vacuity (a 1-N force moves ~l^2 per 1/m)
    for (int k = 0; k < 3 * n; ++k) {
      const double fd = testing::CentralDifference(work, q, k, 1e-6);
      EXPECT_NEAR(gradient(k), fd, 1e-7 * gradient.norm()) << segment << " " << k;
    }
  }
}

// Each batched column equals the column of its force alone, bit for bit (sharing the segments'
// closed forms changes no operation), with several forces per segment, forces in the first and
// the last segment, and none in some. (PointForceGradient is one force's batch; its values are
// checked against differences of the work above.)
TEST(PointForceGradients, EqualTheSingleColumnsBitForBit) {
  const int n = 9;
  StrandModel m = MakeStrand(0.3, n, 0.3, Vec3(25.0, -10.0, 8.0), RandomRotation(5));
  const VecX q = m.NaturalCurvatures() + RandomCurvatures(n, 10.0, 6);
  std::vector<PointForce> forces;
  for (auto [segment, fraction] : {std::pair{0, 0.5}, std::pair{0, 1.0}, std::pair{3, 0.25},
                                   std::pair{3, 0.75}, std::pair{3, 1.0}, std::pair{4, 0.5},
                                   std::pair{8, 1.0}}) {
    forces.push_back({segment, fraction * m.segment_lengths[segment],
                      Vec3(0.3 * segment - 1.0, std::cos(fraction * 7.0), 0.5)});
  }
  const MatX all = PointForceGradients(m, q, forces);
  ASSERT_EQ(all.rows(), 3 * n);
  ASSERT_EQ(all.cols(), static_cast<Eigen::Index>(forces.size()));
  for (size_t c = 0; c < forces.size(); ++c) {
    const VecX single = PointForceGradient(m, q, forces[c].segment, forces[c].u, forces[c].force);
    ASSERT_GT(single.norm(), 0.0);
    EXPECT_EQ(all.col(static_cast<Eigen::Index>(c)), single) << c;
  }
  EXPECT_EQ(PointForceGradients(m, q, {}).cols(), 0);
}

// ContactModel::support_offsets: the contact energy's gradient with per-sample clearances
// against central differences of the energy (a curly strand pressed into a sphere, offsets of
// both signs), so the forward model and the inversion's closed form agree on them; and a wrong
// count is a one-line error naming the field.
TEST(SupportOffsets, GradientMatchesFiniteDifferencesAndSizeIsChecked) {
  const int n = 6;
  StrandModel m = MakeStrand(0.12, n, 0.0, Vec3(20.0, 0.0, 5.0), HorizontalFrame());
  m.root_position = Vec3(0, 0, 0.1);
  m.contact.obstacle = std::make_shared<SphereObstacle>(Vec3(0.03, 0, 0.085), 0.02);
  m.contact.clearance = 0.002;
  const int samples = n * m.contact.samples_per_segment;
  for (int j = 0; j < samples; ++j) m.contact.support_offsets.push_back(0.001 * ((j % 5) - 2));
  std::string why;
  ASSERT_TRUE(IsValid(m, &why)) << why;
  const VecX q = m.NaturalCurvatures() + RandomCurvatures(n, 3.0, 9);
  VecX gradient;
  EnergyTerms terms;
  StrandEnergy(m).Evaluate(q, &gradient, &terms);
  ASSERT_GT(terms.contact, 0.0);  // anti-vacuity: samples are inside their layers
  StrandModel plain = m;
  plain.contact.support_offsets.clear();
  EnergyTerms plain_terms;
  StrandEnergy(plain).Evaluate(q, nullptr, &plain_terms);
  EXPECT_NE(terms.contact, plain_terms.contact);  // the offsets change the penalty
  const auto energy = [&](const VecX& c) { return StrandEnergy(m).Evaluate(c, nullptr); };
  for (int k = 0; k < 3 * n; ++k) {
    EXPECT_NEAR(gradient(k), testing::CentralDifference(energy, q, k, 1e-7),
                1e-6 * gradient.norm()) << k;
  }
  m.contact.support_offsets.pop_back();
  EXPECT_FALSE(IsValid(m, &why));
  EXPECT_NE(why.find("support offsets"), std::string::npos) << why;
}

// Lawson-Hanson against brute force: the NNLS minimum is the best of the unconstrained least
// squares solutions on every subset of the columns that are feasible (x >= 0), enumerated here
// (2^6 subsets), for random 9x6 problems; and the KKT conditions hold.
// Both forms: QR of the passive columns and the normal equations (well-conditioned columns).
TEST(NonNegativeLeastSquares, MatchesEnumerationOfActiveSetsAndKkt) {
  for (auto* solve : {&NonNegativeLeastSquares, &NonNegativeLeastSquaresNormal}) {
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  int constrained = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const int rows = 9, cols = 6;
    MatX a(rows, cols);
    VecX b(rows);
    for (int i = 0; i < rows; ++i) {
      for (int j = 0; j < cols; ++j) a(i, j) = normal(rng) * (j == 2 ? 1e3 : 1.0);  // scaling
      b(i) = normal(rng);
    }
    VecX x;
    const int iterations = solve(a, b, &x);
    ASSERT_GE(iterations, 0);
    double best = (b).squaredNorm();  // the empty subset: x = 0
    for (int mask = 1; mask < (1 << cols); ++mask) {
      std::vector<int> set;
      for (int j = 0; j < cols; ++j) {
        if (mask & (1 << j)) set.push_back(j);
      }
      MatX sub(rows, static_cast<int>(set.size()));
      for (size_t k = 0; k < set.size(); ++k) sub.col(static_cast<int>(k)) = a.col(set[k]);
      const VecX z = sub.householderQr().solve(b);
      if (z.minCoeff() < 0.0) continue;
      best = std::min(best, (sub * z - b).squaredNorm());
    }
    const double objective = (a * x - b).squaredNorm();
    EXPECT_NEAR(objective, best, 1e-10 * b.squaredNorm()) << trial;
    // KKT: x >= 0, w = A^T (b - A x) <= 0 where x = 0 and = 0 where x > 0 (column-scaled).
    const VecX w = a.transpose() * (b - a * x);
    for (int j = 0; j < cols; ++j) {
      const double scale = a.col(j).norm() * b.norm();
      EXPECT_GE(x(j), 0.0);
      if (x(j) > 0.0) {
        EXPECT_NEAR(w(j), 0.0, 1e-10 * scale) << trial << " " << j;
      } else {
        EXPECT_LE(w(j), 1e-10 * scale) << trial << " " << j;
        ++constrained;
      }
    }
  }
  EXPECT_GT(constrained, 10);  // anti-vacuity: the bound is active in many of them
  }
}

// A heavy straight rod clamped horizontally with its tip resting on a sphere (a propped
// cantilever): the target q = 0 lies on the sphere at the tip only. With a straight natural
// shape the support force f minimizes sum_i l_i EI (a_i - f c_i)^2, the complementary energy
// int M^2/(2EI) ds discretized (Menabrea's theorem), where, averaged over segment i,
//   a_i = w ((L - s_i)^3 - (L - s_(i+1))^3) / (6 EI l_i)  (the weight's moment / EI, as above),
//   c_i = ((L - s_i)^2 - (L - s_(i+1))^2) / (2 EI l_i)     (a unit tip force's moment / EI),
// so f = sum l_i a_i c_i / sum l_i c_i^2, which tends to the propped cantilever's reaction
// 3 w L / 8 (beam tables; 8.4e-4 relative below it at n = 10, computed from the sums above).
// The rest curvature is a_i - f c_i, the forward penalty carries exactly f at the target, and
// the forward solve holds the target. The support is a sphere of radius 1 m (nearly flat): on a
// small ball the tip would slide off sideways (frictionless contact on a convex surface has the
// negative tangential stiffness f/R, here above the rod's lateral tip stiffness 3EI/L^3 for
// R < 2.5 cm), which the certificate rightly reports as unstable.
TEST(InvertStrand, ProppedCantileverSupportForceFromMomentBalance) {
  const int n = 10;
  const double length = 0.1, radius = 1.0;
  StrandModel m = MakeStrand(length, n, 0.0, Vec3::Zero(), HorizontalFrame());
  m.root_position = Vec3::Zero();
  m.contact.obstacle = std::make_shared<SphereObstacle>(Vec3(length, 0, -radius), radius);
  InverseOptions options;
  options.support_tolerance = 1e-6;  // 1e-7 m: the next sample lies (L/40)^2 / 2R = 3e-6 m above
  const InverseResult r = InvertStrand(m, VecX::Zero(3 * n), options);
  SCOPED_TRACE(r.message);
  ASSERT_EQ(r.supports.size(), 1u);  // the tip sample only
  EXPECT_EQ(r.supports[0].segment, n - 1);
  EXPECT_EQ(r.supported_samples, 1);
  const double w = m.WeightPerLength().norm();
  const double ei = m.Stiffness()(1);
  double sac = 0.0, scc = 0.0, s = 0.0;
  std::vector<double> a(n), c(n);
  for (int i = 0; i < n; ++i) {
    const double l = m.segment_lengths[i];
    a[i] = w * (std::pow(length - s, 3) - std::pow(length - s - l, 3)) / (6.0 * ei * l);
    c[i] = (std::pow(length - s, 2) - std::pow(length - s - l, 2)) / (2.0 * ei * l);
    sac += l * a[i] * c[i];
    scc += l * c[i] * c[i];
    s += l;
  }
  const double expected = sac / scc;
  EXPECT_NEAR(r.support_force, expected, 1e-9 * expected);
  EXPECT_NEAR(r.support_force, 3.0 * w * length / 8.0, 1e-3 * expected);
  for (int i = 0; i < n; ++i) {
    EXPECT_NEAR(r.rest_curvatures(3 * i + 1), a[i] - expected * c[i], 1e-9 * a[0]) << i;
    EXPECT_NEAR(r.rest_curvatures(3 * i), 0.0, 1e-9 * a[0]) << i;
  }
  // The forward penalty at the target carries the chosen force (recomputed by contact.h).
  StrandModel inverted = m;
  inverted.rest_curvatures = r.rest_curvatures;
  inverted.contact.support_offsets = r.support_offsets;
  const std::vector<ContactForce> forces = ComputeContactForces(inverted, VecX::Zero(3 * n));
  ASSERT_EQ(forces.size(), 1u);
  EXPECT_NEAR(forces[0].force.z(), expected, 1e-9 * expected);
  EXPECT_NEAR(forces[0].force.head<2>().norm(), 0.0, 1e-12 * expected);
  EXPECT_TRUE(r.stable);
  EXPECT_LE(r.deviation, 1e-6 * length);
  EXPECT_LT(r.rest_energy, 0.2 * r.rest_energy_unsupported);  // the support carries most
}

// A strand draped on a sphere (the equilibrium of a known rest shape, ringlet's own groom) with
// contact forces as unknowns: the forces satisfy the KKT conditions of
//   J(f) = 1/2 sum l_i (q0_i(f) - q0nat)^T K (q0_i(f) - q0nat),  f >= 0,
// checked by finite differences of J through the public closed form (InverseRestCurvatures of
// the model with the support offsets of f, the penalty path, not the NNLS matrix); the rest
// energy is at most that of the known rest shape (a feasible point: its penalty forces); and the
// forward solve from the recovered rest shape holds the target.
TEST(InvertStrand, DrapedOnASphereForcesAreOptimalAndHold) {
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
    // Every penetrating sample is within the support tolerance (the penalty lets this strand
    // 7.8e-3 L into its layer: the tolerance is raised to 1e-2 L), so the known rest shape with
    // its penalty forces is a feasible point of the problem.
    InverseOptions options;
    options.support_tolerance = 1e-2;
    ASSERT_GT(groom.summary.contact.samples_in_contact, 0);
    ASSERT_LT(groom.summary.contact.max_clearance_violation,
              options.support_tolerance * m.Length());

    const InverseResult r = InvertStrand(m, groom.curvatures, options);
    SCOPED_TRACE(r.message);
    ASSERT_GE(r.nnls_iterations, 0);
    EXPECT_GT(r.supported_samples, 2);
    EXPECT_LE(r.rest_energy, RestEnergyOf(m, m.rest_curvatures) * (1.0 + 1e-9));
    EXPECT_NEAR(r.rest_energy, RestEnergyOf(m, r.rest_curvatures), 1e-12 * r.rest_energy);
    EXPECT_TRUE(r.stable);
    EXPECT_LE(r.deviation, 1e-6 * m.Length());
    EXPECT_GT(r.naive_deviation, 0.01 * m.Length());

    // Supports left at f = 0 carry neither force nor stiffness at the target: each sits off its
    // shifted surface (x < 0, not x = 0 up to a rounding error of either sign), so the exact
    // Hessian of the inverted model, the certificate's, equals that of the model with those
    // supports moved 1e-3 L away (a one-sided contact pulled away from the body has no penalty
    // stiffness; counting it would certify stability the strand does not have).
    {
      StrandModel inverted = m, far = m;
      inverted.contact.support_offsets = r.support_offsets;
      far.contact.support_offsets = r.support_offsets;
      int zero = 0;
      for (const SupportSample& p : r.supports) {
        if (p.force > 0.0) continue;
        ++zero;
        const size_t at = static_cast<size_t>(p.segment * m.contact.samples_per_segment + p.index);
        const double x = m.contact.clearance + r.support_offsets[at] -
                         m.contact.obstacle->SignedDistance(p.position, nullptr);
        EXPECT_LT(x, 0.0) << "zero-force support " << p.segment << "/" << p.index;
        far.contact.support_offsets[at] -= 1e-3 * m.Length();
      }
      EXPECT_GT(zero, 0);
      StrandHessian h, h_far;
      ComputeStrandHessian(inverted, groom.curvatures, &h);
      ComputeStrandHessian(far, groom.curvatures, &h_far);
      EXPECT_EQ((h.Dense() - h_far.Dense()).cwiseAbs().maxCoeff(), 0.0);
    }

    // KKT by differences of J(f) (the quadratic of the problem). The penalty cannot pull (f < 0 gives no force), so the
    // derivative is one-sided, (4 J(f + h) - J(f + 2h) - 3 J(f)) / (2h): exact for a quadratic.
    const double k = m.ContactStiffness();
    const int samples = m.contact.samples_per_segment;
    const auto objective = [&](const VecX& f) {
      StrandModel with = m;
      with.contact.support_offsets.assign(static_cast<size_t>(n * samples), 0.0);
      for (size_t c = 0; c < r.supports.size(); ++c) {
        const SupportSample& p = r.supports[c];
        const double weight = m.segment_lengths[p.segment] / samples;
        with.contact.support_offsets[static_cast<size_t>(p.segment * samples + p.index)] =
            f(static_cast<int>(c)) / (k * weight) + p.distance;
      }
      return RestEnergyOf(m, InverseRestCurvatures(with, groom.curvatures));
    };
    VecX f(static_cast<int>(r.supports.size()));
    for (size_t c = 0; c < r.supports.size(); ++c) f(static_cast<int>(c)) = r.supports[c].force;
    EXPECT_NEAR(objective(f), r.rest_energy, 1e-9 * r.rest_energy);
    const double step = 1e-3 * f.maxCoeff();
    const auto derivative = [&](const VecX& at, int c) {
      VecX p1 = at, p2 = at;
      p1(c) += step;
      p2(c) += 2.0 * step;
      return (4.0 * objective(p1) - objective(p2) - 3.0 * objective(at)) / (2.0 * step);
    };
    // The gradient's scale: J's derivative at f = 0 (where the supports are not yet used).
    double scale = 0.0;
    for (int c = 0; c < f.size(); ++c) {
      scale = std::max(scale, std::abs(derivative(VecX::Zero(f.size()), c)));
    }
    ASSERT_GT(scale, 0.0);
    int active = 0;
    for (int c = 0; c < f.size(); ++c) {
      const double d = derivative(f, c);
      if (f(c) > 0.0) {
        EXPECT_NEAR(d, 0.0, 1e-6 * scale) << c;
      } else {
        EXPECT_GE(d, -1e-6 * scale) << c;
        ++active;
      }
    }
    std::printf("seed %u: %d of %d supports at f = 0, %d carry %.4g N, rest energy %.4g J "
                "(known rest shape %.4g J, without supports %.4g J), deviation %.3g L\n",
                seed, active, static_cast<int>(f.size()), r.supported_samples, r.support_force,
                r.rest_energy, RestEnergyOf(m, m.rest_curvatures), r.rest_energy_unsupported,
                r.deviation / m.Length());
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

// The automatic count is searched from a prediction (1 segment first, then up or down from the
// count that its distance predicts, inverse.h): it must be the smallest n of 1, 2, 4, ..., 64
// whose fit with that count given explicitly meets the tolerance (the reference: every count
// fitted in turn). Two curves of 64 edges, free root tangent: the parabola z = x^2 / (2a)
// (a = 0.05 m), whose distance falls faster than the prediction assumes (the search goes down),
// and two straight edges meeting at a 30-degree corner at point 21, which no G1 curve follows:
// its distance falls only ~2x per doubling (the search goes up). Tolerances are chosen between
// the explicit counts' distances (printed), at least 10 % away from each.
void ExpectSmallestPassingCount(const std::vector<Vec3>& points,
                                const std::vector<double>& tolerances, const char* name) {
  double polyline = 0.0;
  for (size_t j = 1; j < points.size(); ++j) polyline += (points[j] - points[j - 1]).norm();
  std::string why;
  std::vector<double> explicit_distance;  // the largest distance with n = 1, 2, 4, ..., 64
  for (int n = 1; n <= 64; n *= 2) {
    FitOptions options;
    options.segments = n;
    HelixFit fit;
    ASSERT_TRUE(FitPiecewiseHelix(points, nullptr, options, &fit, &why)) << why;
    explicit_distance.push_back(fit.max_distance / polyline);
    std::printf("%s, %d segments: max %.3g L\n", name, n, fit.max_distance / polyline);
  }
  std::set<int> counts;
  for (double tolerance : tolerances) {
    int expected = 64;
    for (size_t k = 0; k < explicit_distance.size(); ++k) {
      // Within 10 % of the tolerance the automatic count's refinement may stop a little earlier
      // (inverse.h): the comparison would test rounding, not the search.
      ASSERT_GT(std::abs(explicit_distance[k] / tolerance - 1.0), 0.1) << name << " " << tolerance;
      if (explicit_distance[k] <= tolerance) {
        expected = 1 << k;
        break;
      }
    }
    FitOptions options;
    options.tolerance = tolerance;
    HelixFit fit;
    ASSERT_TRUE(FitPiecewiseHelix(points, nullptr, options, &fit, &why)) << why;
    EXPECT_EQ(fit.NumSegments(), expected) << name << ", tolerance " << tolerance;
    EXPECT_LE(fit.max_distance, tolerance * polyline);
    counts.insert(expected);
  }
  EXPECT_GE(counts.size(), 4u) << name;  // the tolerances span several counts
}

TEST(FitPiecewiseHelix, AutomaticSegmentCountIsTheSmallestPassingCount) {
  std::vector<Vec3> parabola, corner;
  const double angle = 30.0 * 3.14159265358979323846 / 180.0;
  for (int j = 0; j <= 64; ++j) {
    const double x = 0.2 * j / 64.0;
    parabola.push_back(Vec3(x, 0.0, x * x / 0.1));
    const double s = 0.2 * j / 64.0, s0 = 0.2 * 21 / 64.0;
    corner.push_back(j <= 21 ? Vec3(s, 0.0, 0.0)
                             : Vec3(s0 + (s - s0) * std::cos(angle), 0.0,
                                    (s - s0) * std::sin(angle)));
  }
  ExpectSmallestPassingCount(parabola, {5e-2, 2e-2, 5e-3, 5e-4, 5e-5, 5e-6, 1e-8}, "parabola");
  ExpectSmallestPassingCount(corner, {2.5e-2, 1.4e-2, 7e-3, 4e-3, 1.5e-3, 1e-4}, "corner");
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
