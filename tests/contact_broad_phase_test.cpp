// The contact broad phase's Lipschitz culling (docs/body.md, "Contact broad phase"): skipping the
// distance queries of segments that the bound proves clear changes no bit of the energy, the
// gradient or the exact Hessian, and it does skip queries. The reference is the same body with
// culling off (no Lipschitz bound declared), where every segment end is queried as before.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "ringlet/body.h"
#include "ringlet/energy.h"
#include "ringlet/strand_hessian.h"
#include "rod/contact_broad_phase.h"
#include "test_util.h"

namespace ringlet {
namespace {

using testing::HorizontalFrame;
using testing::MakeStrand;
using testing::RandomCurvatures;

// Forwards every query to a body and counts them; with cull = false it declares no Lipschitz
// bound, which turns the culling off.
class CountingObstacle final : public Obstacle {
 public:
  CountingObstacle(std::shared_ptr<const Body> body, bool cull)
      : body_(std::move(body)), cull_(cull) {}
  double SignedDistance(const Vec3& x, Vec3* gradient) const override {
    ++queries;
    return body_->SignedDistance(x, gradient);
  }
  double SignedDistanceHessian(const Vec3& x, Vec3* gradient, Mat3* hessian) const override {
    ++queries;
    return body_->SignedDistanceHessian(x, gradient, hessian);
  }
  double LipschitzBound() const override {
    return cull_ ? body_->LipschitzBound() : std::numeric_limits<double>::infinity();
  }
  mutable int queries = 0;  // single-threaded test

 private:
  std::shared_ptr<const Body> body_;
  bool cull_;
};

bool SameBits(const double* a, const double* b, size_t n) {
  return std::memcmp(a, b, n * sizeof(double)) == 0;
}

// A closed cube of half-side a centred at the origin, outward counter-clockwise triangles.
TriangleMesh Cube(double a) {
  std::vector<Vec3> v;
  for (int k = 0; k < 8; ++k) v.emplace_back(k & 1 ? a : -a, k & 2 ? a : -a, k & 4 ? a : -a);
  const std::vector<TriangleMesh::Triangle> t = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6},
                                                 {0, 1, 5}, {0, 5, 4}, {2, 6, 7}, {2, 7, 3},
                                                 {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  TriangleMesh mesh;
  std::string error;
  EXPECT_TRUE(TriangleMesh::Create(v, t, "cube", &mesh, &error)) << error;
  return mesh;
}

// A 60 cm strand that starts 30 cm from the body, crosses over its top (z = top) and leaves it on
// the other side, with random curvatures of the given amplitude: culling on and off give the same
// bits, and culling saves queries.
void ExpectCullingChangesNothing(const std::shared_ptr<const Body>& body, double top,
                                 int straight_skips) {
  int in_contact = 0;
  for (double amplitude : {0.0, 0.5, 2.0, 6.0}) {
    for (unsigned seed : {1u, 2u, 3u}) {
      const int n = 30;
      StrandModel on = MakeStrand(0.6, n, 0.0, Vec3::Zero(), HorizontalFrame());
      on.root_position = Vec3(-0.3, 0.0, top + 0.002);
      on.contact.clearance = 0.004;
      StrandModel off = on;
      auto culling = std::make_shared<CountingObstacle>(body, true);
      auto reference = std::make_shared<CountingObstacle>(body, false);
      on.contact.obstacle = culling;
      off.contact.obstacle = reference;
      const VecX q = RandomCurvatures(n, amplitude, seed);
      const std::string where =
          "amplitude " + std::to_string(amplitude) + ", seed " + std::to_string(seed);

      StrandEnergy e_on(on), e_off(off);
      VecX g_on, g_off;
      EnergyTerms t_on, t_off;
      e_on.Evaluate(q, &g_on, &t_on);
      e_off.Evaluate(q, &g_off, &t_off);
      EXPECT_TRUE(SameBits(&t_on.contact, &t_off.contact, 1)) << where;
      EXPECT_TRUE(SameBits(&t_on.total, &t_off.total, 1)) << where;
      EXPECT_TRUE(SameBits(g_on.data(), g_off.data(), 3 * n)) << where;
      in_contact += t_off.contact > 0.0;

      StrandHessian h_on, h_off;
      ComputeStrandHessian(on, q, &h_on);
      ComputeStrandHessian(off, q, &h_off);
      EXPECT_EQ(h_on.translational, h_off.translational) << where;
      for (int i = 0; i < n; ++i) {
        EXPECT_TRUE(SameBits(h_on.diagonal[i].data(), h_off.diagonal[i].data(), 9)) << where;
        EXPECT_TRUE(SameBits(h_on.twist[i].data(), h_off.twist[i].data(), 18)) << where;
        EXPECT_TRUE(SameBits(h_on.load[i].data(), h_off.load[i].data(), 18)) << where;
      }
      // The reference queries every segment end (n + 1 per sweep) plus the samples. The root is
      // 22 cm from the body, so the first segment is always skipped; the straight strand skips
      // at least straight_skips per sweep (two sweeps: energy and Hessian).
      EXPECT_LT(culling->queries, reference->queries) << where;
      if (amplitude == 0.0) {
        EXPECT_LE(culling->queries + 2 * straight_skips, reference->queries) << where;
      }
    }
  }
  EXPECT_GE(in_contact, 6) << "vacuous: too few configurations touch the body";
}

TEST(ContactBroadPhase, LipschitzCullingOnSpheresChangesNoBit) {
  auto body = std::make_shared<Body>();
  std::string error;
  ASSERT_TRUE(Body::Create({Sphere{Vec3::Zero(), 0.1, "head"}, Sphere{Vec3(0, 0, -0.17), 0.08, "neck"}},
                           {}, body.get(), &error))
      << error;
  EXPECT_EQ(body->LipschitzBound(), 1.0);
  // From d = 0.217 m at the root, 2 cm segments: 10 skipped before the exact test is needed
  // (0.217 - 0.02 k - 0.01 >= 0.004), one extra query where it is.
  ExpectCullingChangesNothing(body, 0.1, 8);
}

TEST(ContactBroadPhase, LipschitzCullingOnADistanceGridChangesNoBit) {
  // The grid's B-spline is Lipschitz with sqrt(3) at most (docs/body.md): the body says 1.75.
  // Beyond the band the grid is clamped to +band, so a wide band (25 cm) lets the bound work.
  auto body = std::make_shared<Body>();
  std::string error;
  MeshDistanceOptions grid;
  grid.mode = MeshDistanceOptions::Mode::kGrid;
  grid.spacing = 0.02;
  grid.band = 0.25;
  grid.threads = 1;
  ASSERT_TRUE(Body::Create({}, {Cube(0.08)}, body.get(), &error, 0.0, grid)) << error;
  EXPECT_EQ(body->LipschitzBound(), 1.75);
  // From d ~ 0.22 m, steps of 1.75 x 2 cm: 5 skipped (0.22 - 0.035 k - 0.01 >= 0.004).
  ExpectCullingChangesNothing(body, 0.08, 4);
}

TEST(ContactBroadPhase, DecidesAsTheExactTestOnEverySegment) {
  // A random walk of 2,000 steps of 0 to 3 cm around two spheres, from far away to inside:
  // Near() must equal the exact test min(d_start, d_end) - l/2 < clearance on every step, here
  // computed from fresh queries, and skip queries on many of them.
  Body body;
  std::string error;
  ASSERT_TRUE(Body::Create({Sphere{Vec3::Zero(), 0.1, "a"}, Sphere{Vec3(0.15, 0, 0), 0.05, "b"}}, {},
                           &body, &error))
      << error;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), step(0.0, 0.03);
  const Vec3 root(0.4, 0.1, -0.2);
  internal::ContactBroadPhase broad_phase(body, root, 2.0);
  Vec3 r = Vec3::Zero();
  int near = 0, far = 0;
  for (int i = 0; i < 2000; ++i) {
    Vec3 direction(unit(rng), unit(rng), unit(rng));
    // Drift toward the body's centre so the walk crosses the surface both ways.
    direction += 0.1 * (-(root + r)).normalized();
    const double l = step(rng);
    const Vec3 next = r + l * direction.normalized();
    const double clearance = 0.004 * (i % 3);
    const bool exact = std::min(body.SignedDistance(root + r, nullptr),
                                body.SignedDistance(root + next, nullptr)) -
                           0.5 * l <
                       clearance;
    ASSERT_EQ(broad_phase.Near(r, next, l, clearance), exact) << "step " << i;
    (exact ? near : far) += 1;
    r = next;
  }
  EXPECT_GT(near, 200);
  EXPECT_GT(far, 200);
  EXPECT_GT(broad_phase.skipped(), 100);
  std::printf("near %d, far %d, skipped by the bound %d\n", near, far, broad_phase.skipped());
}

TEST(ContactBroadPhase, ObstaclesWithoutABoundAreNotCulled) {
  // The default LipschitzBound is +infinity: unknown obstacles keep the exact test.
  class Plane final : public Obstacle {
   public:
    double SignedDistance(const Vec3& x, Vec3* gradient) const override {
      if (gradient) *gradient = Vec3::UnitZ();
      return x.z();
    }
  };
  EXPECT_EQ(Plane().LipschitzBound(), std::numeric_limits<double>::infinity());
}

}  // namespace
}  // namespace ringlet
