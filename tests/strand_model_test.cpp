// Strand model: segment layouts, root frames, stiffness and validation.
#include "ringlet/strand_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "test_util.h"

namespace ringlet {
namespace {

TEST(StrandModel, GradedSegmentsSumToLengthWithRatio) {
  for (double ratio : {1.0, 2.0, 10.0, 100.0}) {
    const std::vector<double> l = GradedSegments(0.3, 25, ratio);
    ASSERT_EQ(l.size(), 25u);
    EXPECT_NEAR(std::accumulate(l.begin(), l.end(), 0.0), 0.3, 1e-15);
    EXPECT_NEAR(l.back() / l.front(), ratio, 1e-12 * ratio);
    for (size_t i = 1; i < l.size(); ++i) EXPECT_GE(l[i], l[i - 1] * (1 - 1e-15));
  }
  EXPECT_EQ(GradedSegments(0.3, 1, 5.0).size(), 1u);
}

TEST(StrandModel, RootFrameOrthogonalizesNormal) {
  Mat3 f;
  std::string why;
  ASSERT_TRUE(RootFrameFromTangentNormal(Vec3(0, 0, -2), Vec3(1, 0, 0.5), &f, &why));
  EXPECT_LT((f.transpose() * f - Mat3::Identity()).norm(), 1e-15);
  EXPECT_NEAR(f.determinant(), 1.0, 1e-15);
  EXPECT_LT((f.col(2) - Vec3(0, 0, -1)).norm(), 1e-15);  // t
  EXPECT_LT((f.col(0) - Vec3(1, 0, 0)).norm(), 1e-15);   // n1: normal minus its tangent part
  EXPECT_LT((f.col(0).cross(f.col(1)) - f.col(2)).norm(), 1e-15);  // n1 x n2 = t

  EXPECT_FALSE(RootFrameFromTangentNormal(Vec3::Zero(), Vec3(1, 0, 0), &f, &why));
  EXPECT_NE(why.find("tangent"), std::string::npos);
  EXPECT_FALSE(RootFrameFromTangentNormal(Vec3(0, 0, 1), Vec3(0, 0, 3), &f, &why));
  EXPECT_NE(why.find("parallel"), std::string::npos);
}

TEST(StrandModel, StiffnessAndLoad) {
  const StrandModel m = testing::MakeStrand(0.1, 10, 0.5);
  const Vec3 k = m.Stiffness();
  EXPECT_DOUBLE_EQ(k(0), 10e9 * m.section.I1());
  EXPECT_DOUBLE_EQ(k(1), 10e9 * m.section.I2());
  EXPECT_DOUBLE_EQ(k(2), 10e9 / 2.6 * m.section.J());
  // w = rho pi r^2 g for r = 50 um: 1300 * 7.854e-9 * 9.81 = 1.0016e-4 N/m.
  EXPECT_NEAR(m.WeightPerLength().norm(), 1300 * M_PI * 25e-10 * 9.81, 1e-18);
  EXPECT_NEAR(m.GravityParameter(), m.WeightPerLength().norm() * 1e-3 / k(0), 1e-12);
}

TEST(StrandModel, ValidationRejectsBadFields) {
  std::string why;
  StrandModel m = testing::MakeStrand(0.1, 10);
  EXPECT_TRUE(IsValid(m, &why)) << why;
  StrandModel bad = m;
  bad.segment_lengths[3] = -1;
  EXPECT_FALSE(IsValid(bad, &why));
  EXPECT_NE(why.find("segment"), std::string::npos);
  bad = m;
  bad.segment_lengths.clear();
  EXPECT_FALSE(IsValid(bad, &why));
  bad = m;
  bad.root_frame(0, 0) = 2.0;
  EXPECT_FALSE(IsValid(bad, &why));
  EXPECT_NE(why.find("rotation"), std::string::npos);
  bad = m;
  bad.natural_curvature.x() = INFINITY;
  EXPECT_FALSE(IsValid(bad, &why));
}

}  // namespace
}  // namespace ringlet
