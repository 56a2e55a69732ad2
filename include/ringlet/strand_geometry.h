// Centreline and material frames of a strand from its curvatures, in closed form (no ODE stepping).
#pragma once

#include <vector>

#include "ringlet/math.h"
#include "ringlet/strand_model.h"

namespace ringlet {

/// Frames and positions at the n+1 segment ends, root (index 0) to tip (index n).
struct StrandGeometry {
  std::vector<Vec3> points;  ///< r_i (m), world coordinates
  std::vector<Mat3> frames;  ///< Q_i = world_from_material, columns (n1, n2, t)
};

/// Reconstructs the strand segment by segment: Q_(i+1) = Q_i R_i, r_(i+1) = r_i + Q_i p_i
/// (HelixSegment). curvatures has size 3n (kappa1, kappa2, tau per segment, 1/m).
StrandGeometry ComputeGeometry(const StrandModel& model, const VecX& curvatures);

/// The same, also keeping each segment's first moment c_i = int_0^l (l - u) exp(u W) e3 du (m^2,
/// segment i's start material frame; helix.h), so that int_segment r ds = l r_i + Q_i c_i needs
/// no second evaluation of the helix (the Kirchhoff certificate uses it). segment_moments is
/// resized to n.
StrandGeometry ComputeGeometry(const StrandModel& model, const VecX& curvatures,
                               std::vector<Vec3>* segment_moments);

/// The centreline sampled with k >= 1 points per segment (equal arc-length steps inside each
/// segment, exact on the helix), root to tip: n k + 1 points (m).
std::vector<Vec3> SampleCentreline(const StrandModel& model, const VecX& curvatures,
                                   int points_per_segment);

/// The centreline at the given arc lengths s_j (m, nondecreasing, each clamped to [0, L]), exact
/// on each helix: r(s) = r_i + Q_i p(s - s_i) in the segment i holding s (HelixChord). One point
/// per arc length: the sampling of a target polyline (`ringlet invert` writes its equilibria at
/// the target's points, HelixFit::arc_lengths). Returns an empty vector for a model without
/// segments.
std::vector<Vec3> SampleCentrelineAt(const StrandModel& model, const VecX& curvatures,
                                     const std::vector<double>& arc_lengths);

/// A centreline sampled together with its material frames: what the wisp generator needs to
/// place child strands in the master's cross-section (groom/wisp.cpp). All three arrays have the
/// same size (>= 2 for a usable strand), root to tip.
struct FramedCentreline {
  std::vector<Vec3> points;          ///< r(s_j) (m), world coordinates
  std::vector<Mat3> frames;          ///< Q(s_j) = world_from_material, columns (n1, n2, t)
  std::vector<double> arc_lengths;   ///< s_j (m), from 0 at the root, strictly increasing

  int NumPoints() const { return static_cast<int>(points.size()); }
  /// Arc length of the last sample, the strand length L (m); 0 when empty.
  double Length() const { return arc_lengths.empty() ? 0.0 : arc_lengths.back(); }
};

/// The centreline and material frames at k >= 1 points per segment (equal arc-length steps
/// inside each segment), root to tip: n k + 1 samples. Exact on each helix: at arc length u into
/// segment i, r = r_i + Q_i p(u) and Q = Q_i R(u) (HelixChord, HelixRotation); the points equal
/// SampleCentreline's and the samples at segment ends equal ComputeGeometry's.
FramedCentreline SampleFramedCentreline(const StrandModel& model, const VecX& curvatures,
                                        int points_per_segment);

}  // namespace ringlet
