// Limits on the products that drive work and memory (issue 16, docs/robustness.md): each limit
// is checked exactly at its boundary (the largest allowed value passes, the next one fails with
// a message naming the fields and the limit). The expected numbers are the documented limits
// themselves: 1000 BFGS segments, 10^7 solved segments, 2^28 wisp points, 2^26 pixels,
// 2^30 camera samples, 10^5 rad of natural turning.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "ringlet/body.h"
#include "ringlet/cross_section.h"
#include "ringlet/hair_type.h"
#include "ringlet/hairstyle.h"
#include "ringlet/render.h"
#include "ringlet/statics.h"
#include "ringlet/strand_model.h"
#include "test_util.h"

namespace ringlet {
namespace {

TEST(Limits, DenseBfgsSegments) {
  std::string why;
  EXPECT_TRUE(CheckMethodSegments(1000, Method::kBfgs, &why));
  EXPECT_FALSE(CheckMethodSegments(1001, Method::kBfgs, &why));
  EXPECT_EQ(why,
            "1001 segments exceed the limit of 1000 for the method \"bfgs\" (its dense inverse "
            "Hessian takes 72 n^2 bytes); use \"lbfgs\", \"newton\" or \"auto\"");
  // The O(n) methods go up to kMaxSegments.
  for (Method m : {Method::kLbfgs, Method::kNewton, Method::kAuto}) {
    EXPECT_TRUE(CheckMethodSegments(kMaxSegments, m, &why));
    EXPECT_FALSE(CheckMethodSegments(kMaxSegments + 1, m, &why));
  }
}

// The library's own boundary: SolveStrand never builds BFGS's dense 3n x 3n inverse Hessian above
// kMaxBfgsSegments (72 MB per strand at 1001 segments, 28.8 GB at 20,000), whatever its caller
// asks; it solves with L-BFGS instead and says so. The evidence that L-BFGS ran: the curvatures
// equal, bit for bit, those of an explicit L-BFGS solve.
TEST(Limits, SolveStrandRefusesDenseBfgsAboveTheLimit) {
  SolveOptions bfgs;
  bfgs.method = Method::kBfgs;
  bfgs.max_iterations = 3;
  bfgs.check_stability = false;
  SolveOptions lbfgs = bfgs;
  lbfgs.method = Method::kLbfgs;
  const StrandModel big = testing::MakeStrand(0.1, kMaxBfgsSegments + 1, 0.0, Vec3::Zero(),
                                              testing::HorizontalFrame());
  const StrandSolution refused = SolveStrand(big, bfgs);
  EXPECT_NE(refused.summary.message.find(
                "(method \"bfgs\" refused above 1000 segments, its dense inverse Hessian takes "
                "72 n^2 bytes: solved with \"lbfgs\")"),
            std::string::npos)
      << refused.summary.message;
  EXPECT_TRUE(refused.curvatures == SolveStrand(big, lbfgs).curvatures);
  // At the limit BFGS runs as asked: no note, and not the L-BFGS iterates.
  const StrandModel at_limit = testing::MakeStrand(0.1, kMaxBfgsSegments, 0.0, Vec3::Zero(),
                                                   testing::HorizontalFrame());
  const StrandSolution dense = SolveStrand(at_limit, bfgs);
  EXPECT_EQ(dense.summary.message.find("refused"), std::string::npos);
  EXPECT_FALSE(dense.curvatures == SolveStrand(at_limit, lbfgs).curvatures);
}

TEST(Limits, RenderPixelsAndSamples) {
  std::string why;
  EXPECT_TRUE(CheckRenderSize(8192, 8192, 16, &why));  // 2^26 pixels x 16 = 2^30 samples
  EXPECT_FALSE(CheckRenderSize(8192, 8192, 17, &why));
  EXPECT_EQ(why,
            "width x height x samples_per_pixel = 8192 x 8192 x 17 = 1140850688 camera samples, "
            "more than the limit of 2^30 = 1073741824");
  EXPECT_FALSE(CheckRenderSize(8193, 8192, 1, &why));
  EXPECT_EQ(why,
            "width x height = 8193 x 8192 = 67117056 pixels, more than the limit of 2^26 = "
            "67108864 (e.g. 8192 x 8192)");
  // The largest sides and samples one at a time still multiply without overflow.
  EXPECT_FALSE(CheckRenderSize(65536, 65536, 1 << 20, &why));
  EXPECT_TRUE(CheckRenderSize(1, 1, 1 << 20, &why));
}

TEST(Limits, RenderRefusesTooManySamplesBeforeRendering) {
  RenderScene scene;  // nothing to trace: the size is checked first
  RenderOptions options;
  options.width = 4096;
  options.height = 4096;
  options.samples_per_pixel = 128;
  Image image;
  RenderStats stats;
  std::string why;
  EXPECT_FALSE(Render(scene, options, &image, &stats, &why));
  EXPECT_EQ(why.rfind("options: width x height x samples_per_pixel = 4096 x 4096 x 128", 0), 0u)
      << why;
  EXPECT_TRUE(image.pixels.empty());
}

TEST(Limits, NaturalTurning) {
  StrandModel model;
  model.section = SectionFromEccentricity(50e-6, 0.0);  // the paper's 50-um circular fibre
  model.segment_lengths = UniformSegments(1.0, 10);
  std::string why;
  model.natural_curvature = Vec3(0.6e5, 0.0, 0.8e5);  // |.| = 1e5 1/m over 1 m: the limit
  EXPECT_TRUE(IsValid(model, &why)) << why;
  EXPECT_DOUBLE_EQ(NaturalTurning(model), 1e5);
  model.natural_curvature = Vec3(0.6e5, 0.0, 0.8e5 + 1.0);
  EXPECT_FALSE(IsValid(model, &why));
  EXPECT_EQ(why.rfind("natural curvature and twist times length must be at most 100000 rad", 0),
            0u)
      << why;
}

Hairstyle Style(int masters, int segments, int strands_per_wisp, int points_per_strand) {
  Hairstyle style;
  style.body = std::make_shared<Body>();  // IsValid needs a body, not a particular one
  style.scalp = SphereScalp{};
  style.roots.count = masters;
  std::string why;
  EXPECT_TRUE(FindHairType("caucasian", "wavy", &style.hair_type, &why)) << why;
  style.segments = segments;
  style.wisps.strands_per_wisp = strands_per_wisp;
  style.wisps.points_per_strand = points_per_strand;
  return style;
}

TEST(Limits, HairstyleProducts) {
  std::string why;
  // masters x segments <= 10^7.
  EXPECT_TRUE(Style(500000, 20, 1, 2).IsValid(&why)) << why;
  EXPECT_FALSE(Style(500001, 20, 1, 2).IsValid(&why));
  EXPECT_EQ(why,
            "masters.count x masters.segments = 10000020 segments to solve, more than the limit "
            "of 10000000");
  // Every child solved: masters x (1 + strands per wisp) x segments <= 10^7.
  Hairstyle solved = Style(1000, 10, 999, 2);
  solved.solve_children = true;
  EXPECT_TRUE(solved.IsValid(&why)) << why;
  solved.wisps.strands_per_wisp = 1000;
  EXPECT_FALSE(solved.IsValid(&why));
  EXPECT_EQ(why,
            "masters.count x (1 + wisps.strands_per_wisp) x masters.segments = 10010000 "
            "segments to solve, more than the limit of 10000000");
  // masters x strands per wisp x points <= 2^28.
  EXPECT_TRUE(Style(4096, 1, 1024, 64).IsValid(&why)) << why;  // 2^28 points
  EXPECT_FALSE(Style(4097, 1, 1024, 64).IsValid(&why));
  EXPECT_EQ(why,
            "masters.count x wisps.strands_per_wisp x wisps.points_per_strand = 268500992 "
            "points, more than the limit of 2^28 = 268435456");
  // Dense BFGS on the masters.
  Hairstyle bfgs = Style(10, 1001, 1, 2);
  bfgs.solver.method = Method::kBfgs;
  EXPECT_FALSE(bfgs.IsValid(&why));
  EXPECT_EQ(why.rfind("masters.segments: 1001 segments exceed the limit of 1000", 0), 0u) << why;
  bfgs.segments = 1000;
  EXPECT_TRUE(bfgs.IsValid(&why)) << why;
}

}  // namespace
}  // namespace ringlet
