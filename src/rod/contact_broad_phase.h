// The contact broad phase shared by ContactEnergy (energy.cpp) and ComputeStrandHessian
// (strand_hessian.cpp): which segments need their contact samples evaluated.
// Internal (docs/body.md, "Broad phase").
#pragma once

#include <algorithm>
#include <cmath>

#include "ringlet/math.h"
#include "ringlet/obstacle.h"

namespace ringlet::internal {

// The test (section 3.1's samples; docs/body.md): segment i's samples, at arc length <= l_i/2
// from one of its ends, are at distance >= min(d_start, d_end) - l_i/2 from the obstacle, so the
// segment is sampled only when
//   min(d_start, d_end) - l_i / 2 < SegmentClearance(i).                                    (1)
// Each segment costs one query at its end. Lipschitz culling saves most of those far from the
// obstacle: with |d(x) - d(y)| <= L |x - y| (Obstacle::LipschitzBound), a lower bound b of d at
// the segment's start gives d_end >= b - L l_i (the chord is no longer than the arc; the chord's
// own length would cost a square root and only helps tight curls), and when that bound already
// satisfies the negation of (1), (1) is false for the exact values too: the segment is skipped
// without a query and the bound carried on. Otherwise d_end is queried and decides (1) exactly
// as before, with d_start's bound where that suffices and the exact d_start (queried then) where
// it does not. The decisions, hence every sample
// and every bit of the energy, gradient and Hessian, are those of the exact test; `margin`
// covers the rounding of the positions and of the distances.
class ContactBroadPhase {
 public:
  // root: the strand's root (m, world); positions below are relative to it. scale (m) bounds
  // the positions' magnitude (|root| + strand length), for the rounding margin.
  ContactBroadPhase(const Obstacle& obstacle, const Vec3& root, double scale)
      : obstacle_(obstacle),
        root_(root),
        lipschitz_(obstacle.LipschitzBound()),
        cull_(std::isfinite(lipschitz_)),
        margin_(1e-9 * (1.0 + scale)),
        lower_(obstacle.SignedDistance(root, nullptr)) {}

  // Whether the segment from root + start to root + end (arc length l, largest sample
  // clearance clearance) needs its samples: test (1). Call once per segment, in order.
  bool Near(const Vec3& start, const Vec3& end, double l, double clearance) {
    if (cull_) {
      const double end_lower = lower_ - lipschitz_ * l - margin_;
      // min(lower_, end_lower) = end_lower; false for NaN, which goes to the exact test.
      if (end_lower - 0.5 * l - margin_ >= clearance) {
        lower_ = end_lower;
        exact_ = false;
        ++skipped_;
        return false;
      }
    }
    const double d_end = obstacle_.SignedDistance(root_ + end, nullptr);
    bool near;
    if (exact_) {
      near = std::min(lower_, d_end) - 0.5 * l < clearance;
    } else if (d_end - 0.5 * l < clearance) {
      near = true;  // (1) holds whatever d_start is (min <= d_end)
    } else if (lower_ - 0.5 * l >= clearance) {
      near = false;  // d_start >= lower_: (1) fails for the exact d_start too
    } else {
      const double d_start = obstacle_.SignedDistance(root_ + start, nullptr);
      near = std::min(d_start, d_end) - 0.5 * l < clearance;
    }
    lower_ = d_end;
    exact_ = true;
    return near;
  }

  // Segments skipped by the bound alone so far.
  int skipped() const { return skipped_; }

 private:
  const Obstacle& obstacle_;
  Vec3 root_;
  double lipschitz_;
  bool cull_;
  double margin_;
  double lower_;  // d at the current segment's start (exact_) or a lower bound of it
  bool exact_ = true;
  int skipped_ = 0;
};

}  // namespace ringlet::internal
