// Contact of a strand with its obstacle, measured from a configuration (paper, section 3.1).
#pragma once

#include <vector>

#include "ringlet/math.h"
#include "ringlet/strand_model.h"

namespace ringlet {

/// One penalty force on the strand: at a sample of ContactModel that lies inside the
/// clearance layer, the force is F = -dE_c/dx = w k x n (N), with w = l_i / m the sample's
/// weight, x the penetration of the layer (of the sample's ContactModel::SampleClearance) and n
/// the outward normal of the obstacle.
struct ContactForce {
  int segment = 0;       ///< segment index
  double u = 0.0;        ///< arc length inside the segment (m)
  Vec3 position;         ///< sample position (m, world)
  Vec3 force;            ///< force on the strand (N, world)
};

/// The penalty forces at a configuration, recomputed from the geometry (closed-form partial
/// chords) and the obstacle, independently of the energy's reverse sweep. Empty without an
/// obstacle.
std::vector<ContactForce> ComputeContactForces(const StrandModel& model, const VecX& curvatures);

/// How deep a configuration goes into its obstacle.
struct ContactMeasure {
  /// Largest depth below the obstacle's surface, max(0, -d) (m), over the contact samples and
  /// the segment ends after the root: how far the hair visibly enters the body.
  double max_penetration = 0.0;
  /// Largest depth into the clearance layer, max(0, clearance - d) (m), same points.
  double max_clearance_violation = 0.0;
  /// Number of samples inside the clearance layer (those that carry a force; with support
  /// offsets, inside their own SampleClearance).
  int samples_in_contact = 0;
};

/// Measures the penetration of a configuration (all zeros without an obstacle).
ContactMeasure MeasureContact(const StrandModel& model, const VecX& curvatures);

}  // namespace ringlet
