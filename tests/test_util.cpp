#include "test_util.h"

#include <Eigen/LU>
#include <Eigen/QR>

namespace ringlet::testing {

Mat3 RandomRotation(unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  Mat3 a;
  for (int i = 0; i < 9; ++i) a(i) = n(rng);
  Eigen::HouseholderQR<Mat3> qr(a);
  Mat3 q = qr.householderQ();
  if (q.determinant() < 0) q.col(0) = -q.col(0);
  return q;
}

StrandModel MakeStrand(double length, int segments, double eccentricity, const Vec3& natural,
                       const Mat3& frame) {
  StrandModel m;
  m.segment_lengths = UniformSegments(length, segments);
  m.section = SectionFromEccentricity(50e-6, eccentricity);
  m.natural_curvature = natural;
  m.root_frame = frame;
  return m;
}

Mat3 HorizontalFrame() {
  // t = +x, n1 = +z (major axis vertical), n2 = t x n1 = -y.
  Mat3 q;
  q.col(0) = Vec3(0, 0, 1);
  q.col(1) = Vec3(0, -1, 0);
  q.col(2) = Vec3(1, 0, 0);
  return q;
}

}  // namespace ringlet::testing
