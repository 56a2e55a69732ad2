// Eigen aliases used throughout ringlet. Double precision everywhere; fixed-size blocks on the stack.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products
#include <Eigen/LU>        // determinants

namespace ringlet {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;

/// The cross-product matrix [v]x, so that [v]x w = v x w.
inline Mat3 Hat(const Vec3& v) {
  Mat3 m;
  m << 0.0, -v.z(), v.y(),  //
      v.z(), 0.0, -v.x(),   //
      -v.y(), v.x(), 0.0;
  return m;
}

/// The inverse of Hat on the skew part: Vee(X) = (X21 - X12, X02 - X20, X10 - X01).
/// For any X, the Frobenius product <X, [v]x> equals v . Vee(X).
inline Vec3 Vee(const Mat3& x) {
  return Vec3(x(2, 1) - x(1, 2), x(0, 2) - x(2, 0), x(1, 0) - x(0, 1));
}

}  // namespace ringlet
