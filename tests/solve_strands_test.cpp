// Parallel solve: identical results on 1 and N threads, in model order, with progress reports.
#include "ringlet/solve_strands.h"

#include <gtest/gtest.h>

#include "test_util.h"

namespace ringlet {
namespace {

using testing::HorizontalFrame;
using testing::MakeStrand;
using testing::RandomRotation;

std::vector<StrandModel> MixedStrands() {
  std::vector<StrandModel> models;
  for (int i = 0; i < 12; ++i) {
    // Straight and curly, light and heavy, in random orientations: solve times differ widely, so
    // threads finish out of order.
    const Vec3 natural = (i % 3 == 0) ? Vec3::Zero() : Vec3(40.0 + 10.0 * i, 0.0, 5.0 * (i % 4));
    models.push_back(MakeStrand(0.1 + 0.02 * i, 10 + i, 0.3 * (i % 3), natural,
                                i % 2 ? HorizontalFrame() : RandomRotation(100 + i)));
  }
  return models;
}

TEST(SolveStrands, SameResultsBitForBitOnOneAndTwoThreads) {
  const std::vector<StrandModel> models = MixedStrands();
  BatchOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const std::vector<StrandSolution> a = SolveStrands(models, SolveOptions{}, one);
  const std::vector<StrandSolution> b = SolveStrands(models, SolveOptions{}, two);
  ASSERT_EQ(a.size(), models.size());
  ASSERT_EQ(b.size(), models.size());
  for (size_t i = 0; i < models.size(); ++i) {
    EXPECT_TRUE(a[i].summary.Converged()) << i;
    EXPECT_EQ(a[i].curvatures, b[i].curvatures) << "strand " << i;  // exact equality
    EXPECT_EQ(a[i].summary.iterations, b[i].summary.iterations);
    // In model order: the same as solving strand i alone.
    const StrandSolution alone = SolveStrand(models[i]);
    EXPECT_EQ(alone.curvatures, a[i].curvatures) << "strand " << i;
  }
}

TEST(SolveStrands, ReportsProgressOncePerStrandInIncreasingOrder) {
  const std::vector<StrandModel> models = MixedStrands();
  std::vector<int> seen;
  BatchOptions batch;
  batch.threads = 2;
  batch.progress = [&](int finished, int total) {
    EXPECT_EQ(total, static_cast<int>(models.size()));
    seen.push_back(finished);
  };
  SolveStrands(models, SolveOptions{}, batch);
  ASSERT_EQ(seen.size(), models.size());
  for (size_t i = 0; i < seen.size(); ++i) EXPECT_EQ(seen[i], static_cast<int>(i) + 1);
}

TEST(SolveStrands, UsesWarmStarts) {
  const std::vector<StrandModel> models = MixedStrands();
  const std::vector<StrandSolution> cold = SolveStrands(models, SolveOptions{});
  std::vector<VecX> starts;
  for (const StrandSolution& s : cold) starts.push_back(s.curvatures);
  starts[3] = VecX();  // empty = natural shape
  const std::vector<StrandSolution> warm = SolveStrands(models, SolveOptions{}, {}, &starts);
  for (size_t i = 0; i < models.size(); ++i) {
    if (i == 3) {
      EXPECT_EQ(warm[i].summary.iterations, cold[i].summary.iterations);
    } else {
      // Starting at the equilibrium: at most a couple of iterations to re-certify it.
      EXPECT_LE(warm[i].summary.iterations, 2) << i;
    }
  }
}

}  // namespace
}  // namespace ringlet
