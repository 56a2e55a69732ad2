// Parallel solve: identical results on 1 and N threads, in model order, with progress reports.
#include "ringlet/solve_strands.h"

#include <gtest/gtest.h>

#include <atomic>

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

// BatchOptions::cancel: an unset flag changes nothing (bit for bit); a flag set from the progress
// callback after the third strand (one thread: strands run in order) skips every later strand,
// whose solution is empty and says so; a flag set before the call skips all.
TEST(SolveStrands, CancelSkipsTheStrandsNotYetStartedAndChangesNothingElse) {
  const std::vector<StrandModel> models = MixedStrands();
  BatchOptions plain;
  plain.threads = 1;
  const std::vector<StrandSolution> reference = SolveStrands(models, SolveOptions{}, plain);

  std::atomic<bool> cancel{false};
  BatchOptions unset = plain;
  unset.cancel = &cancel;
  const std::vector<StrandSolution> same = SolveStrands(models, SolveOptions{}, unset);
  for (size_t i = 0; i < models.size(); ++i) {
    EXPECT_EQ(same[i].curvatures, reference[i].curvatures) << i;
    EXPECT_EQ(same[i].summary.iterations, reference[i].summary.iterations) << i;
  }

  BatchOptions late = unset;
  late.progress = [&cancel](int finished, int) {
    if (finished == 3) cancel.store(true);
  };
  const std::vector<StrandSolution> part = SolveStrands(models, SolveOptions{}, late);
  ASSERT_EQ(part.size(), models.size());
  for (size_t i = 0; i < models.size(); ++i) {
    if (i < 3) {
      EXPECT_EQ(part[i].curvatures, reference[i].curvatures) << i;
    } else {
      EXPECT_EQ(part[i].curvatures.size(), 0) << i;
      EXPECT_EQ(part[i].summary.message, kCancelledMessage) << i;
      EXPECT_EQ(part[i].summary.iterations, 0) << i;
      EXPECT_FALSE(part[i].summary.Converged()) << i;
    }
  }

  // Set before the call (any thread count): nothing is solved.
  BatchOptions early;
  early.threads = 2;
  early.cancel = &cancel;
  for (const StrandSolution& s : SolveStrands(models, SolveOptions{}, early)) {
    EXPECT_EQ(s.curvatures.size(), 0);
    EXPECT_EQ(s.summary.message, kCancelledMessage);
  }
}

}  // namespace
}  // namespace ringlet
