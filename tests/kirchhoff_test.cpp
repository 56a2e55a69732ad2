// The equilibrium certificate: Kirchhoff's balance by quadrature, independent of the gradient code.
#include "ringlet/kirchhoff.h"

#include <gtest/gtest.h>

#include "ringlet/energy.h"
#include "ringlet/statics.h"
#include "test_util.h"

namespace ringlet {
namespace {

// At any configuration the segment-averaged moment imbalance equals the energy gradient (the
// gradient is the internal moment, DESIGN.md): two independent computations of one quantity,
// one by the adjoint sweep through the closed forms, one by quadrature of M(u) = (T - (L-u) r) x f.
TEST(Kirchhoff, ImbalanceEqualsEnergyGradient) {
  for (unsigned seed : {1u, 2u, 3u}) {
    StrandModel m = testing::MakeStrand(0.25, 12, 0.5, Vec3(40.0, 10.0, -8.0),
                                        testing::RandomRotation(seed));
    m.root_position = Vec3(0.3, -0.2, 1.5);
    const VecX q = testing::RandomCurvatures(12, 80.0, seed + 10);  // up to ~2 rad per segment
    StrandEnergy energy(m);
    VecX gradient;
    energy.Evaluate(q, &gradient);
    const VecX b = KirchhoffImbalance(m, q);
    ASSERT_GT(gradient.norm(), 0.0);
    EXPECT_LT((b - gradient).cwiseAbs().maxCoeff(), 1e-10 * gradient.cwiseAbs().maxCoeff())
        << "seed " << seed;
  }
}

TEST(Kirchhoff, CertifiesSolutionsAndCatchesPerturbations) {
  StrandModel m = testing::MakeStrand(0.2, 20, 0.3, Vec3(50.0, 0.0, 10.0),
                                      testing::HorizontalFrame());
  const StrandSolution s = SolveStrand(m);
  ASSERT_TRUE(s.summary.Converged());
  // Converged to residual 1e-9; the quadrature adds ~1e-13.
  EXPECT_LT(KirchhoffResidual(m, s.curvatures), 2e-9);
  // One segment's curvature off by 1%: far above any sensible check tolerance.
  VecX bad = s.curvatures;
  bad(3 * 5) *= 1.01;
  EXPECT_GT(KirchhoffResidual(m, bad), 1e-4);
  // The natural shape is not in equilibrium under gravity.
  EXPECT_GT(KirchhoffResidual(m, m.NaturalCurvatures()), 1e-2);
}

}  // namespace
}  // namespace ringlet

namespace ringlet {
namespace {

// Regression (issue 16): a curvature of 1e300 1/m made the piece count overflow a float-to-int
// conversion (undefined behaviour, caught by UBSan). The count is capped; the residual is
// still computed (and is not a finite success).
TEST(KirchhoffResidual, HugeCurvatureDoesNotOverflowThePieceCount) {
  StrandModel m = testing::MakeStrand(0.1, 3);
  VecX q = VecX::Zero(9);
  q(0) = 1e300;
  const double r = KirchhoffResidual(m, q);
  EXPECT_FALSE(r <= 1e-6) << r;
}

}  // namespace
}  // namespace ringlet
