// Energy terms and their exact gradients against central finite differences (STYLE.md: each term
// on its own, relative error with an absolute floor, non-vacuous).
#include "ringlet/energy.h"

#include <gtest/gtest.h>

#include "test_util.h"

namespace ringlet {
namespace {

using testing::MakeStrand;
using testing::RandomCurvatures;
using testing::RandomRotation;

struct GradientCase {
  double eccentricity;
  int segments;
  double amplitude;  // curvature amplitude (1/m)
  unsigned seed;
};

class GradientTest : public ::testing::TestWithParam<GradientCase> {};

// Compares an analytic gradient with central differences. h = 1e-6 / l_i in curvature keeps the
// truncation error (~h^2) and the rounding error (~eps E / h) both near 1e-10 relative.
void ExpectGradientMatchesFd(const std::function<double(const VecX&, VecX*)>& energy,
                             const VecX& q, double h, double rel_tol) {
  VecX g;
  energy(q, &g);
  ASSERT_EQ(g.size(), q.size());
  const double scale = g.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0.0) << "vacuous: zero gradient";
  auto f = [&](const VecX& x) { return energy(x, nullptr); };
  for (int i = 0; i < q.size(); ++i) {
    const double fd = testing::CentralDifference(f, q, i, h);
    // Relative error with an absolute floor of rel_tol * (largest gradient component).
    EXPECT_NEAR(g(i), fd, rel_tol * (std::abs(fd) + scale)) << "component " << i;
  }
}

TEST_P(GradientTest, ElasticMatchesFiniteDifferences) {
  const GradientCase c = GetParam();
  StrandModel m = MakeStrand(0.2, c.segments, c.eccentricity, Vec3(30.0, -10.0, 8.0),
                             RandomRotation(c.seed));
  const VecX q = RandomCurvatures(c.segments, c.amplitude, c.seed + 1);
  ExpectGradientMatchesFd([&](const VecX& x, VecX* g) { return ElasticEnergy(m, x, g); }, q,
                          1e-3, 1e-9);
}

TEST_P(GradientTest, GravityMatchesFiniteDifferences) {
  const GradientCase c = GetParam();
  StrandModel m = MakeStrand(0.2, c.segments, c.eccentricity, Vec3(30.0, -10.0, 8.0),
                             RandomRotation(c.seed));
  const VecX q = RandomCurvatures(c.segments, c.amplitude, c.seed + 1);
  LoadWorkspace ws;
  const double ell = m.segment_lengths[0];
  ExpectGradientMatchesFd(
      [&](const VecX& x, VecX* g) { return GravityEnergy(m, x, g, &ws); }, q, 1e-5 / ell, 1e-7);
}

INSTANTIATE_TEST_SUITE_P(
    Configurations, GradientTest,
    ::testing::Values(GradientCase{0.0, 1, 20.0, 11u}, GradientCase{0.0, 7, 50.0, 12u},
                      GradientCase{0.5, 15, 80.0, 13u}, GradientCase{0.9, 30, 200.0, 14u},
                      // large turning angles per segment (x > 2: the closed-form branch)
                      GradientCase{0.3, 4, 150.0, 15u},
                      // tiny curvatures (Taylor branch near zero)
                      GradientCase{0.3, 10, 1e-4, 16u}));

}  // namespace
}  // namespace ringlet
