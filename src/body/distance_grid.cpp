// The distance grid: exact samples near the surface, a tricubic B-spline between them
// (src/body/distance_grid.h, docs/body.md).
#include "body/distance_grid.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cassert>
#include <cmath>

namespace ringlet::internal {
namespace {

// Nodes per block edge for the band test of Build.
constexpr int kBlock = 4;

// Uniform cubic B-spline weights of the nodes i-1, i, i+1, i+2 at t in [0, 1) of cell i, with
// their first and second derivatives in t (de Boor; the basis is C^2, the weights sum to 1).
struct Weights {
  double w[4], dw[4], ddw[4];
};

inline Weights SplineWeights(double t) {
  const double s = 1.0 - t, t2 = t * t, t3 = t2 * t;
  Weights r;
  r.w[0] = s * s * s / 6.0;
  r.w[1] = (3.0 * t3 - 6.0 * t2 + 4.0) / 6.0;
  r.w[2] = (-3.0 * t3 + 3.0 * t2 + 3.0 * t + 1.0) / 6.0;
  r.w[3] = t3 / 6.0;
  r.dw[0] = -0.5 * s * s;
  r.dw[1] = 1.5 * t2 - 2.0 * t;
  r.dw[2] = -1.5 * t2 + t + 0.5;
  r.dw[3] = 0.5 * t2;
  r.ddw[0] = s;
  r.ddw[1] = 3.0 * t - 2.0;
  r.ddw[2] = 1.0 - 3.0 * t;
  r.ddw[3] = t;
  return r;
}

}  // namespace

DistanceGrid DistanceGrid::Build(const std::function<double(const Vec3&)>& distance,
                                 const Box3& box, double spacing, double band, int threads) {
  assert(!box.isEmpty() && spacing > 0.0 && band > 0.0);
  DistanceGrid grid;
  grid.spacing_ = spacing;
  grid.inverse_spacing_ = 1.0 / spacing;
  grid.band_ = band;
  // Margin band + 3 h: the 4^3 support of every point within 2 h of the grid's border holds only
  // nodes farther than band from the surface, all clamped to +band, so F = band there and the
  // constant outside continues it smoothly.
  const double margin = band + 3.0 * spacing;
  grid.origin_ = box.min() - Vec3::Constant(margin);
  const Vec3 extent = box.sizes() + Vec3::Constant(2.0 * margin);
  for (int a = 0; a < 3; ++a) {
    grid.size_(a) = static_cast<int>(std::ceil(extent(a) / spacing)) + 1;
  }
  const int nx = grid.size_.x(), ny = grid.size_.y(), nz = grid.size_.z();
  grid.values_.assign(static_cast<size_t>(nx) * ny * nz, static_cast<float>(band));

  // Blocks of kBlock^3 nodes, in parallel; each node is written by one block only and its value
  // depends on its position only: the result is independent of the thread count and order.
  const int bx = (nx + kBlock - 1) / kBlock, by = (ny + kBlock - 1) / kBlock,
            bz = (nz + kBlock - 1) / kBlock;
  const double half_diagonal = 0.5 * std::sqrt(3.0) * (kBlock - 1) * spacing;
  std::atomic<size_t> queries{0};
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<long>(0, static_cast<long>(bx) * by * bz),
                      [&](const tbb::blocked_range<long>& range) {
                        size_t local = 0;
                        for (long b = range.begin(); b != range.end(); ++b) {
                          const int i0 = static_cast<int>(b % bx) * kBlock;
                          const int j0 = static_cast<int>((b / bx) % by) * kBlock;
                          const int k0 =
                              static_cast<int>(b / (static_cast<long>(bx) * by)) * kBlock;
                          const int i1 = std::min(i0 + kBlock, nx), j1 = std::min(j0 + kBlock, ny),
                                    k1 = std::min(k0 + kBlock, nz);
                          // The block's centre decides whether its nodes can be within the band
                          // (1-Lipschitz).
                          const Vec3 centre = grid.origin_ + spacing * Vec3(0.5 * (i0 + i1 - 1),
                                                                            0.5 * (j0 + j1 - 1),
                                                                            0.5 * (k0 + k1 - 1));
                          const double dc = distance(centre);
                          ++local;
                          if (std::abs(dc) >= band + half_diagonal) {
                            const float fill = static_cast<float>(dc > 0.0 ? band : -band);
                            for (int k = k0; k < k1; ++k)
                              for (int j = j0; j < j1; ++j)
                                for (int i = i0; i < i1; ++i)
                                  grid.values_[(static_cast<size_t>(k) * ny + j) * nx + i] = fill;
                            continue;
                          }
                          for (int k = k0; k < k1; ++k) {
                            for (int j = j0; j < j1; ++j) {
                              for (int i = i0; i < i1; ++i) {
                                const double d = distance(grid.origin_ + spacing * Vec3(i, j, k));
                                ++local;
                                grid.values_[(static_cast<size_t>(k) * ny + j) * nx + i] =
                                    static_cast<float>(std::clamp(d, -band, band));
                              }
                            }
                          }
                        }
                        queries += local;
                      });
  });
  grid.queries_ = queries.load();
  return grid;
}

double DistanceGrid::Evaluate(const Vec3& x, Vec3* gradient, Mat3* hessian) const {
  // Cell i = floor(u) and t = u - i per axis; outside the nodes 1 .. n - 3 the support would
  // leave the grid, where F = band (Build's margin).
  const Vec3 u = (x - origin_) * inverse_spacing_;
  int cell[3];
  double t[3];
  for (int a = 0; a < 3; ++a) {
    const double f = std::floor(u(a));
    if (!(f >= 1.0 && f <= size_(a) - 3.0)) {
      if (gradient) gradient->setZero();
      if (hessian) hessian->setZero();
      return band_;
    }
    cell[a] = static_cast<int>(f);
    t[a] = u(a) - f;
  }
  const float* base =
      values_.data() +
      ((static_cast<size_t>(cell[2] - 1) * size_.y() + (cell[1] - 1)) * size_.x() + (cell[0] - 1));
  // The broad phase asks for values only, contact samples for gradients, the certificate for
  // Hessians: three instances of one contraction, each computing only what it returns.
  if (hessian) return Contract<2>(base, t, gradient, hessian);
  if (gradient) return Contract<1>(base, t, gradient, nullptr);
  return Contract<0>(base, t, nullptr, nullptr);
}

template <int kOrder>
double DistanceGrid::Contract(const float* base, const double t[3], Vec3* gradient,
                              Mat3* hessian) const {
  Weights w[3];
  for (int a = 0; a < 3; ++a) w[a] = SplineWeights(t[a]);
  const int nx = size_.x(), ny = size_.y();
  // Contract x first, then y, then z, carrying the derivative weights along: 16 rows of 4
  // nodes give value, d/dx and d2/dx2 per row; then per z-slice the y contraction.
  double value = 0.0;
  Vec3 g = Vec3::Zero();
  Mat3 h = Mat3::Zero();
  for (int c = 0; c < 4; ++c) {
    // Per slice: f, fx, fxx, fy, fxy, fyy.
    double s[6] = {0, 0, 0, 0, 0, 0};
    for (int b = 0; b < 4; ++b) {
      const float* row = base + (static_cast<size_t>(c) * ny + b) * nx;
      double r0 = 0.0, r1 = 0.0, r2 = 0.0;
      for (int a = 0; a < 4; ++a) {
        const double v = row[a];
        r0 += w[0].w[a] * v;
        if constexpr (kOrder >= 1) r1 += w[0].dw[a] * v;
        if constexpr (kOrder >= 2) r2 += w[0].ddw[a] * v;
      }
      s[0] += w[1].w[b] * r0;
      if constexpr (kOrder >= 1) {
        s[1] += w[1].w[b] * r1;
        s[3] += w[1].dw[b] * r0;
      }
      if constexpr (kOrder >= 2) {
        s[2] += w[1].w[b] * r2;
        s[4] += w[1].dw[b] * r1;
        s[5] += w[1].ddw[b] * r0;
      }
    }
    const double wz = w[2].w[c];
    value += wz * s[0];
    if constexpr (kOrder >= 1) {
      const double dwz = w[2].dw[c];
      g.x() += wz * s[1];
      g.y() += wz * s[3];
      g.z() += dwz * s[0];
      if constexpr (kOrder >= 2) {
        const double ddwz = w[2].ddw[c];
        h(0, 0) += wz * s[2];
        h(0, 1) += wz * s[4];
        h(1, 1) += wz * s[5];
        h(0, 2) += dwz * s[1];
        h(1, 2) += dwz * s[3];
        h(2, 2) += ddwz * s[0];
      }
    }
  }
  if constexpr (kOrder >= 1) *gradient = g * inverse_spacing_;
  if constexpr (kOrder >= 2) {
    h(1, 0) = h(0, 1);
    h(2, 0) = h(0, 2);
    h(2, 1) = h(1, 2);
    *hessian = h * (inverse_spacing_ * inverse_spacing_);
  }
  return value;
}

}  // namespace ringlet::internal
