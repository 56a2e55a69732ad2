// SampleFramedCentreline: points and material frames inside segments, against ComputeGeometry,
// SampleCentreline and independent properties of the rotation exp(u [Omega]x).
#include "ringlet/strand_geometry.h"

#include <gtest/gtest.h>

#include <cmath>

#include "test_util.h"

namespace ringlet {
namespace {

struct Curly {
  StrandModel model;
  VecX q;
};

// A 20-cm strand of 7 graded segments with random curvatures up to 60 1/m (several turns), a
// random root frame and an off-origin root.
Curly MakeCurly(unsigned seed) {
  Curly c;
  c.model = testing::MakeStrand(0.2, 7, 0.3, Vec3::Zero(), testing::RandomRotation(seed));
  c.model.segment_lengths = GradedSegments(0.2, 7, 3.0);
  c.model.root_position = Vec3(0.01, -0.02, 0.3);
  c.q = testing::RandomCurvatures(7, 60.0, seed + 1);
  return c;
}

TEST(SampleFramedCentreline, SegmentEndsEqualComputeGeometry) {
  const Curly c = MakeCurly(3);
  const int k = 5;
  const FramedCentreline f = SampleFramedCentreline(c.model, c.q, k);
  const StrandGeometry g = ComputeGeometry(c.model, c.q);
  const int n = c.model.NumSegments();
  ASSERT_EQ(f.NumPoints(), n * k + 1);
  ASSERT_EQ(f.frames.size(), f.points.size());
  ASSERT_EQ(f.arc_lengths.size(), f.points.size());
  double s = 0.0;
  for (int i = 0; i <= n; ++i) {
    EXPECT_LT((f.points[i * k] - g.points[i]).norm(), 1e-15) << i;
    EXPECT_LT((f.frames[i * k] - g.frames[i]).cwiseAbs().maxCoeff(), 1e-15) << i;
    EXPECT_NEAR(f.arc_lengths[i * k], s, 1e-15) << i;
    if (i < n) s += c.model.segment_lengths[i];
  }
  EXPECT_NEAR(f.Length(), 0.2, 1e-15);
}

TEST(SampleFramedCentreline, PointsEqualSampleCentreline) {
  const Curly c = MakeCurly(5);
  for (int k : {1, 2, 7}) {
    const FramedCentreline f = SampleFramedCentreline(c.model, c.q, k);
    const std::vector<Vec3> p = SampleCentreline(c.model, c.q, k);
    ASSERT_EQ(f.points.size(), p.size());
    for (size_t j = 0; j < p.size(); ++j) EXPECT_LT((f.points[j] - p[j]).norm(), 1e-15) << j;
  }
}

// Independent check of the interior frames: between consecutive samples of one segment the
// relative rotation Q_j^T Q_(j+1) is exp(h [Omega]x), a rotation by h |Omega| about Omega
// (Rodrigues): it fixes Omega and has trace 1 + 2 cos(h |Omega|). And the tangent t = Q e3 is the
// derivative of the points: |(r_(j+1) - r_(j-1)) / (2h) - t_j| = O(h^2 |Omega|^2 / 6).
TEST(SampleFramedCentreline, InteriorFramesAreTheHelixRotation) {
  const Curly c = MakeCurly(8);
  const int k = 40;
  const FramedCentreline f = SampleFramedCentreline(c.model, c.q, k);
  const int n = c.model.NumSegments();
  double max_angle = 0.0;
  for (int i = 0; i < n; ++i) {
    const Vec3 omega = c.q.segment<3>(3 * i);
    const double h = c.model.segment_lengths[i] / k;
    for (int j = i * k; j < (i + 1) * k; ++j) {
      const Mat3& qa = f.frames[j];
      const Mat3& qb = f.frames[j + 1];
      EXPECT_LT((qa.transpose() * qa - Mat3::Identity()).cwiseAbs().maxCoeff(), 1e-13);
      const Mat3 r = qa.transpose() * qb;
      EXPECT_LT((r * omega - omega).norm(), 1e-12 * omega.norm()) << j;
      EXPECT_NEAR(r.trace(), 1.0 + 2.0 * std::cos(h * omega.norm()), 1e-13) << j;
      max_angle = std::max(max_angle, h * omega.norm());
      if (j > i * k) {
        const Vec3 derivative = (f.points[j + 1] - f.points[j - 1]) / (2.0 * h);
        const double bound = h * h * omega.squaredNorm() / 6.0 * 1.01 + 1e-12;
        EXPECT_LT((derivative - qa.col(2)).norm(), bound) << j;
      }
    }
  }
  EXPECT_GT(max_angle, 0.01);  // anti-vacuity: the frames do turn between samples
}

}  // namespace
}  // namespace ringlet
