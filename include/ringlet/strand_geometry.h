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

/// The centreline sampled with k >= 1 points per segment (equal arc-length steps inside each
/// segment, exact on the helix), root to tip: n k + 1 points (m).
std::vector<Vec3> SampleCentreline(const StrandModel& model, const VecX& curvatures,
                                   int points_per_segment);

}  // namespace ringlet
