// The immutable description of one hair strand: a Kirchhoff rod clamped at its root (paper, section 2).
#pragma once

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "ringlet/cross_section.h"
#include "ringlet/material.h"
#include "ringlet/math.h"
#include "ringlet/obstacle.h"

namespace ringlet {

/// Contact of a strand with a rigid obstacle by an elastic penalty (paper, section 3.1): the
/// energy
///   E_c = int_0^L 1/2 k x(s)^2 ds,   x(s) = max(0, clearance - d(r(s))),
/// where d is the obstacle's signed distance, is added to E_e + E_g. The integral is a rectangle
/// rule with m = samples_per_segment points on each helical segment, at arc lengths
/// (j + 1) l_i / m, j = 0..m-1, each of weight l_i / m: contact is felt between segment ends, and
/// every segment end, the tip included, is a sample. The root point itself is never a sample (it
/// is clamped on the scalp).
struct ContactModel {
  /// The obstacle (a body of spheres or meshes); null means no contact. Shared, never modified.
  std::shared_ptr<const Obstacle> obstacle;
  /// Distance from the surface below which the penalty acts (m): the wisp thickness r_w (paper,
  /// section 3.1) plus the hull-layer offset (Lee & Ko 2001). 0 = the bare surface.
  double clearance = 0.0;
  /// Penalty stiffness k per unit length (N/m^2: force per length per metre of penetration).
  /// 0 selects DefaultContactStiffness.
  double stiffness = 0.0;
  /// Samples per segment m >= 1.
  int samples_per_segment = 4;
  /// Per-sample shifts of the clearance (m), empty (the default) or one per sample: sample j of
  /// segment i (at arc length (j + 1) l_i / m) uses the clearance clearance + support_offsets[i m
  /// + j]. Inverse statics with contact forces as unknowns (inverse.h, docs/inverse.md) sets them
  /// so that the penalty k x reproduces, at the target, the normal support forces it chose:
  /// x = f / (k l_i / m). Empty gives bit for bit the model without offsets.
  std::vector<double> support_offsets;

  /// The clearance of sample j of segment i (m): clearance plus its support offset, if any.
  double SampleClearance(int segment, int j) const {
    return support_offsets.empty()
               ? clearance
               : clearance + support_offsets[static_cast<size_t>(segment * samples_per_segment + j)];
  }
  /// The largest SampleClearance of segment i (m), for the contact broad phase.
  double SegmentClearance(int segment) const {
    if (support_offsets.empty()) return clearance;
    double c = SampleClearance(segment, 0);
    for (int j = 1; j < samples_per_segment; ++j) c = std::max(c, SampleClearance(segment, j));
    return c;
  }
};

/// One inextensible, unshearable Kirchhoff rod of elliptic section, clamped at its root, divided
/// into segments of constant curvature and twist (each an exact helix).
///
/// The unknowns of a strand are its curvatures: a vector q of size 3n with q[3i..3i+2] =
/// (kappa1, kappa2, tau) of segment i in 1/m, in material coordinates (the paper's eq. 1, Omega =
/// kappa1 n1 + kappa2 n2 + tau t). Segment 0 starts at the root.
struct StrandModel {
  /// Length of each segment, root to tip (m). Their sum is the strand length L.
  std::vector<double> segment_lengths;
  /// Elliptic section (semi-axes in m; the major axis lies along n1).
  CrossSection section;
  /// Elastic constants and density.
  Material material;
  /// Natural curvatures and twist (kappa1^0, kappa2^0, tau^0) in 1/m, the same on every segment
  /// unless rest_curvatures is given: the hair type's natural curl (the paper's constant
  /// Omega^0). Styling (grow) gives new segments this curvature.
  Vec3 natural_curvature = Vec3::Zero();
  /// The rest shape per segment (issue 13: inverse statics): empty (the default) means
  /// natural_curvature on every segment; otherwise size 3n with (kappa1^0, kappa2^0, tau^0) of
  /// segment i at [3i, 3i + 3) (1/m). Every use of the natural curvature goes through
  /// NaturalCurvature(i) / NaturalCurvatures(), so a vector filled with natural_curvature gives
  /// bit for bit the same energies, gradients and solves as the empty one.
  VecX rest_curvatures;
  /// Position of the root, r(0) (m).
  Vec3 root_position = Vec3::Zero();
  /// Material frame at the root, world_from_material: columns (n1, n2, t), a proper rotation.
  Mat3 root_frame = Mat3::Identity();
  /// Gravitational acceleration vector (m/s^2); the paper's g = 9.81 m/s^2 pointing down (-z).
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);
  /// Contact with a body (none by default).
  ContactModel contact;

  /// Number of segments n.
  int NumSegments() const { return static_cast<int>(segment_lengths.size()); }
  /// Length L, the sum of the segment lengths (m).
  double Length() const;
  /// Diagonal of the stiffness K = diag(E I1, E I2, mu J) (N m^2), the paper's eq. 3.
  Vec3 Stiffness() const;
  /// Weight per unit length f = rho S g (N/m), a vector along gravity.
  Vec3 WeightPerLength() const;
  /// Natural curvatures of all segments, the 3n-vector (kappa1^0, kappa2^0, tau^0, ...) (1/m):
  /// rest_curvatures when given, natural_curvature repeated otherwise.
  VecX NaturalCurvatures() const;
  /// Natural curvatures (kappa1^0, kappa2^0, tau^0) of segment i (1/m): rest_curvatures' triple
  /// i when given, natural_curvature otherwise.
  Vec3 NaturalCurvature(int i) const {
    return rest_curvatures.size() == 0 ? natural_curvature
                                       : Vec3(rest_curvatures.segment<3>(3 * i));
  }
  /// Whether the rest shape varies per segment (rest_curvatures given).
  bool HasRestShape() const { return rest_curvatures.size() != 0; }
  /// Dimensionless load |f| L^3 / (E I1): the ratio of weight to bending stiffness in the soft
  /// direction (Greenhill's self-buckling parameter; 7.8373 is the critical value).
  double GravityParameter() const;
  /// The contact stiffness in use: contact.stiffness, or DefaultContactStiffness when it is 0.
  double ContactStiffness() const;
};

/// The default penalty stiffness (N/m^2): a normal load of kContactLoadFactor times the strand's
/// weight per length |f| is carried at a penetration of kContactPenetration L,
///   k = kContactLoadFactor |f| / (kContactPenetration L).
/// A strand draped over a sphere of radius R carries a normal load of about |f| (1 + L/R) per
/// length (its weight plus the tension |f| L over the curvature 1/R): for L = 3R that is 4 |f|, so
/// the penetration stays near 0.4e-3 L (0.1 mm for 30 cm of hair). Falls back to the bending
/// scale E I1 / L^3 per length when there is no gravity.
double DefaultContactStiffness(const StrandModel& model);
inline constexpr double kContactLoadFactor = 10.0;
inline constexpr double kContactPenetration = 1e-3;

/// n segments of equal length L/n (m).
std::vector<double> UniformSegments(double length, int segments);

/// n segments whose lengths grow geometrically from root to tip, with last/first = ratio >= 1,
/// summing to L. Short segments at the root resolve the bending boundary layer of heavy hair,
/// whose width is about L / sqrt(w L^3 / EI). ratio = 1 gives uniform segments.
std::vector<double> GradedSegments(double length, int segments, double ratio);

/// The last/first segment-length ratio recommended for a strand of load lambda = w L^3 / (E I1):
///   ratio = 1 + lambda / (2 sqrt(1 + lambda / 64)),
/// about 1 + lambda/2 for light strands and 4 sqrt(lambda) for heavy ones, whose bending layer at
/// the root has width ~L / sqrt(lambda). Fitted to the ratio minimizing the tip error of a
/// horizontally clamped straight strand against the planar heavy-elastica reference for lambda in
/// [0.5, 3000] and n in [10, 50] (tip error within 6.4% of the best ratio's; docs/validation.md).
/// Curled strands prefer 3-8 times smaller ratios. The scene's `"grading": "auto"` uses it.
double RecommendedGradingRatio(double gravity_parameter);

/// The root frame (n1, n2, t) from a tangent and a normal (any lengths): t is normalized, n1 is the
/// normal orthogonalized against t (Gram-Schmidt) and normalized, n2 = t x n1 so n1 x n2 = t.
/// Returns false, with a reason, when the tangent is zero or not finite or when the normal is
/// (nearly) parallel to the tangent.
bool RootFrameFromTangentNormal(const Vec3& tangent, const Vec3& normal, Mat3* frame,
                                std::string* why);

/// Largest segment count a model may have; more is almost certainly a mistake in the input.
inline constexpr int kMaxSegments = 100000;

/// sum_i |(kappa1^0, kappa2^0, tau^0)_i| l_i (rad): the angle the natural (rest) shape turns
/// through, per segment when rest_curvatures is set.
double NaturalTurning(const StrandModel& model);

/// Largest total natural turning |(kappa1^0, kappa2^0, tau^0)| L of a strand (rad): 10^5 rad,
/// about 16,000 turns of its natural helix (the tightest human curl, R ~ 2 mm on a 1-m strand, is
/// ~500 rad). The work of the Kirchhoff certificate (kirchhoff.h) grows with the turning (its
/// quadrature pieces turn by at most 1 rad), so this bounds it at ~10^5 pieces per strand on
/// top of 1 per segment (docs/robustness.md).
inline constexpr double kMaxNaturalTurning = 1e5;

/// Checks every field (finite, positive lengths, valid section and material, proper rotation,
/// rest_curvatures of size 0 or 3n and finite, natural turning within kMaxNaturalTurning, ...).
bool IsValid(const StrandModel& model, std::string* why);

}  // namespace ringlet
