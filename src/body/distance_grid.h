// A signed distance sampled on a regular grid and interpolated by a uniform tricubic B-spline
// (C^2): the fast, smooth stand-in for the exact mesh distance (docs/body.md, "Distance grid").
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "ringlet/body.h"
#include "ringlet/math.h"

namespace ringlet::internal {

/// Node values d_ijk = clamp(d(origin + h (i, j, k)), -band, band) of an exact signed distance d,
/// and the interpolant F(x) = sum_ijk d_ijk B((x - x_i)/h) B((y - y_j)/h) B((z - z_k)/h) with B the
/// uniform cubic B-spline. F is C^2 (its Hessian is continuous across cell faces); each partial
/// derivative is a convex combination of node differences (d_(i+1) - d_i)/h, so |dF/dx_a| <= 1
/// for a 1-Lipschitz d. F is not interpolating: for smooth d, F = d + (h^2/6) Laplacian(d) +
/// O(h^4). Nodes are computed once, in parallel, each independently (the field does not depend on
/// the thread count); blocks of nodes whose centre is farther than band + the block's half
/// diagonal from the surface are filled with +-band without a query (d is 1-Lipschitz).
/// Outside the grid (the box given to Build plus band + 3 h on every side) F = band.
class DistanceGrid {
 public:
  /// Samples distance (1-Lipschitz, thread-safe) over box enlarged by band + 3 spacing.
  /// spacing and band (m) must be finite and > 0; box non-empty. threads <= 0: all cores.
  static DistanceGrid Build(const std::function<double(const Vec3&)>& distance, const Box3& box,
                            double spacing, double band, int threads = 0);

  /// F(x) (m), with its gradient and Hessian (1/m) if not null. Thread-safe, no allocation.
  double Evaluate(const Vec3& x, Vec3* gradient, Mat3* hessian) const;

  /// Grid spacing h (m).
  double spacing() const { return spacing_; }
  /// Clamp of the node values (m).
  double band() const { return band_; }
  /// Node counts per axis.
  const Eigen::Vector3i& size() const { return size_; }
  /// Node values (m), x fastest.
  const std::vector<float>& values() const { return values_; }
  /// Exact distance queries made by Build (nodes in the band plus one per block).
  std::size_t queries() const { return queries_; }
  /// Memory of the node values (bytes).
  std::size_t MemoryBytes() const { return values_.size() * sizeof(float); }

 private:
  // The B-spline contraction of the 4^3 nodes from base at cell coordinates t, with derivatives
  // up to kOrder (0, 1, 2).
  template <int kOrder>
  double Contract(const float* base, const double t[3], Vec3* gradient, Mat3* hessian) const;

  Vec3 origin_ = Vec3::Zero();
  double spacing_ = 0.0;
  double inverse_spacing_ = 0.0;
  double band_ = 0.0;
  Eigen::Vector3i size_ = Eigen::Vector3i::Zero();
  std::vector<float> values_;
  std::size_t queries_ = 0;
};

}  // namespace ringlet::internal
