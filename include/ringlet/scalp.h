// The scalp: where hair grows, blue-noise root positions on it, and combed root frames.
//
// Two scalp descriptions share one root sampler: a region of a head sphere bounded by a hairline
// (SphereScalp) and a set of triangles chosen from a body mesh (MeshScalp). Roots are placed by
// dart throwing with a spatial grid (a Poisson-disk process: no two roots closer than the disk
// radius), then each gets a material frame whose tangent leans from the scalp normal toward a comb
// direction, optionally combed away from a parting.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "ringlet/math.h"

namespace ringlet {

/// The head's reference axes, in world coordinates. `up` and `front` may have any non-zero length
/// and need not be orthogonal: the frame uses up/|up| and the part of `front` orthogonal to it.
/// The third axis is left = up x front (the person's left when up is z and the face looks +y).
struct HeadFrame {
  Vec3 centre = Vec3::Zero();  ///< centre of the head (m)
  Vec3 up = Vec3::UnitZ();     ///< from the centre toward the crown (direction only)
  Vec3 front = Vec3::UnitY();  ///< the direction the face looks (direction only)
};

/// Where a point sits on the head, in the HeadFrame's spherical coordinates.
struct HeadCoordinates {
  double polar_angle = 0.0;  ///< angle from `up` seen from the centre, in [0, pi] (rad)
  /// Angle about `up` from `front` toward `left` (counter-clockwise seen from above), in (-pi, pi]
  /// (rad): 0 is the forehead, +pi/2 the left ear, -pi/2 the right ear, pi the nape.
  double azimuth = 0.0;
  double height = 0.0;  ///< (p - centre) . up, signed height above the centre (m)
};

/// Checks that the axes are finite, non-zero and not parallel; otherwise says why.
bool IsValid(const HeadFrame& head, std::string* why);

/// Orthonormal (up, front, left) of a valid head frame, as the columns of a proper rotation.
Mat3 HeadAxes(const HeadFrame& head);

/// Spherical coordinates of a world point p (m) in the head frame.
HeadCoordinates ComputeHeadCoordinates(const HeadFrame& head, const Vec3& p);

/// A scalp on a head sphere: the points whose polar angle from `up` is at most the hairline
/// polar angle of their azimuth. The hairline is given at three azimuths and interpolated by
///   theta_max(phi) = a0 + a1 cos(phi) + a2 cos(2 phi),
/// the smooth curve, symmetric between left and right, through theta_max(0) = hairline_front,
/// theta_max(+-pi/2) = hairline_side and theta_max(pi) = hairline_back. So a forehead hairline
/// higher than the nape's (front < back) and a side value above the ears exclude face and ears.
/// Every field is a plain number or a 3-vector, ready for JSON; angles in radians.
struct SphereScalp {
  HeadFrame head;                 ///< centre and axes of the head sphere
  double radius = 0.1;            ///< sphere radius (m)
  double hairline_front = 1.047;  ///< hairline polar angle on the forehead, (0, pi) (rad); 60 deg
  double hairline_side = 1.484;   ///< hairline polar angle above the ears, (0, pi) (rad); 85 deg
  double hairline_back = 1.920;   ///< hairline polar angle at the nape, (0, pi) (rad); 110 deg
};

/// Checks the head frame, radius > 0 and that the hairline curve stays inside (0, pi) at every
/// azimuth; otherwise says which field is wrong and what was expected.
bool IsValid(const SphereScalp& scalp, std::string* why);

/// The hairline polar angle theta_max(phi) (rad) at azimuth phi (rad).
double HairlinePolarAngle(const SphereScalp& scalp, double azimuth);

/// True when p (m) is on the scalp region: its polar angle is at most the hairline's plus
/// `angle_tolerance` (rad). The distance to the sphere is not checked.
bool InScalp(const SphereScalp& scalp, const Vec3& p, double angle_tolerance = 0.0);

/// Area of the scalp region (m^2): R^2 * integral over phi of (1 - cos theta_max(phi)), by the
/// trapezoidal rule on 4096 azimuths (exponentially accurate for this smooth periodic integrand).
double ScalpArea(const SphereScalp& scalp);

/// A scalp made of triangles chosen from a body mesh. Triangle k has corners
/// vertices[triangles[k][0..2]]. Normals are the triangle normals turned away from head.centre
/// (so the winding order does not matter; a scalp is star-shaped about the head centre).
/// Zero-area triangles are allowed and never receive roots.
struct MeshScalp {
  HeadFrame head;                             ///< head axes (comb, parting, root coordinates)
  std::vector<Vec3> vertices;                 ///< vertex positions (m)
  std::vector<std::array<int, 3>> triangles;  ///< vertex indices of each scalp triangle
};

/// Checks the head frame, finite vertices, indices in range and a positive total area.
bool IsValid(const MeshScalp& scalp, std::string* why);

/// Total area of the triangles (m^2).
double ScalpArea(const MeshScalp& scalp);

/// How many roots to place and how.
///
/// Disk radius. The roots are a Poisson-disk set: every pair is at least r apart (straight-line
/// distance). For a region of area A and a requested count N,
///   r = sqrt(packing * A / N).
/// Random sequential dart throwing on a plane saturates ("jams") when the disks of radius r/2
/// cover 54.7% of the area (Feder, J. Theor. Biol. 87, 1980), i.e. at N r^2 / A = 0.547 * 4/pi =
/// 0.697; the default packing 0.55 asks for 79% of that, dense enough for a blue-noise spectrum
/// and sparse enough that the count is reached in a few trials per root. A hexagonal lattice would
/// reach 2/sqrt(3) = 1.155.
struct RootSamplingOptions {
  int count = 1000;         ///< requested number of roots, >= 1
  uint64_t seed = 0;        ///< random seed; the same seed gives bit-identical roots
  double packing = 0.55;    ///< N r^2 / A, in (0, 0.69]: sets the disk radius (above)
  int trials_per_root = 200;  ///< dart-throwing budget: at most count * trials_per_root darts
};

/// Checks count >= 1, packing in (0, 0.69], trials_per_root >= 1.
bool IsValid(const RootSamplingOptions& options, std::string* why);

/// How roots are combed: the direction of the strand tangent at the root.
///
/// The tangent is t = cos(tilt) n + sin(tilt) c, with n the outward scalp normal and c the unit
/// comb direction in the tangent plane:
/// - c starts as `direction` projected into the tangent plane (e.g. (0, 0, -1): "down", which on
///   the back of the head is "down the back"). Any constant direction vanishes where the normal is
///   parallel to it (a whorl: the hairy ball theorem says some point always has one); where its
///   projection is shorter than 1e-3 |direction|, `fallback_direction` is projected instead.
/// - with a parting, the plane parting_normal . (p - head.centre) = parting_offset splits the
///   scalp into two sides (a great circle through the crown when the offset is 0 and the normal
///   is horizontal). On side s = sign(parting_normal . (p - centre) - offset), u = s times the
///   unit projection of parting_normal is "away from the part": c loses any component toward
///   the part (c -= min(0, c . u) u) and gains parting_strength * u, so every root leans away.
///
/// Root frame [n1 n2 t]: n1 = unit(n x c) is lateral (tangent to the scalp, perpendicular to the
/// comb), n2 = t x n1 is the part of the normal orthogonal to t (pointing away from the scalp).
/// Why lateral n1: n1 carries the major axis of the elliptic section and kappa1 (bending about n1)
/// is the soft direction (cross_section.h). With n1 lateral the flat side of the fibre faces the
/// scalp, the soft bending is the one that drapes the strand over the head under gravity, and a
/// positive natural kappa1 curls the tip toward the scalp (dt/ds = kappa1 n1 x t = -kappa1 n2),
/// like hair that curls under. The other choice (n1 in the plane of n and t) would make draping
/// use the stiff axis.
struct CombOptions {
  double tilt = 1.2;  ///< angle between tangent and scalp normal, [0, pi/2] (rad); ~69 deg
  Vec3 direction = Vec3(0.0, 0.0, -1.0);           ///< global comb direction (world, non-zero)
  Vec3 fallback_direction = Vec3(0.0, -1.0, 0.0);  ///< used at the whorl of `direction`
  bool parting = false;                            ///< comb away from a parting plane
  Vec3 parting_normal = Vec3(1.0, 0.0, 0.0);  ///< parting plane normal (world, non-zero)
  double parting_offset = 0.0;                ///< plane offset from the head centre (m)
  double parting_strength = 1.0;  ///< weight of "away from the part" against c, >= 0
  /// Comb away from the face (before the parting): c += face_sweep (1 + cos phi) / 2 b, phi the
  /// root's azimuth from the face, b the unit tangential part of sign(phi) (-sin(phi) front +
  /// cos(phi) left), the direction of growing |phi|: sideways at the forehead (the hair falls
  /// beside the face), backward above the ears, nothing at the nape (docs/hairstyle-format.md).
  /// It must exceed 1 to beat `direction` where the two are opposed. 0 = off, >= 0.
  double face_sweep = 0.0;
  /// The sense of each strand's natural curl at its root: false (the default) starts it away
  /// from the head; true starts it into the head, as combing lays hair down: the curl then
  /// presses the strand onto the scalp instead of lifting it (short, light strands, whose
  /// weight cannot pull their curl down, otherwise stand up from the crown). BuildMasters and
  /// the curl operation apply it through CurlStartSign (below).
  bool curl_inward = false;
};

/// The sign of kappa1^0 at the root in the comb frame (n2 away from the scalp, dt/ds =
/// kappa1 n1 x t = -kappa1 n2): -1 starts the curl away from the head, +1 into it.
inline double CurlStartSign(const CombOptions& comb) { return comb.curl_inward ? 1.0 : -1.0; }

/// Checks finite fields, tilt in [0, pi/2], non-zero directions, parting_strength >= 0,
/// face_sweep >= 0.
bool IsValid(const CombOptions& comb, std::string* why);

/// One hair root.
struct Root {
  Vec3 position = Vec3::Zero();  ///< on the scalp (m)
  Vec3 normal = Vec3::UnitZ();   ///< outward unit scalp normal
  Mat3 frame = Mat3::Identity();  ///< material frame [n1 n2 t], world_from_material (CombOptions)
  HeadCoordinates head;          ///< polar angle, azimuth, height: for hull layers by root position
  int triangle = -1;             ///< index of the MeshScalp triangle holding it; -1 on a sphere
  int parting_side = 0;          ///< +1 or -1: side of the parting plane; 0 without parting
};

/// The comb frame [n1 n2 t] at a scalp point (m) with outward unit normal n (CombOptions).
/// `comb` and `head` must be valid.
Mat3 CombedRootFrame(const Vec3& position, const Vec3& normal, const HeadFrame& head,
                     const CombOptions& comb, int* parting_side = nullptr);

/// What the root sampler did.
struct RootSamplingSummary {
  int requested = 0;        ///< the requested count N
  int achieved = 0;         ///< roots placed; less than N only when the dart budget ran out
  double disk_radius = 0.0;  ///< minimum distance between any two roots, r (m)
  double area = 0.0;         ///< area of the scalp (m^2)
  int64_t darts = 0;         ///< candidate points thrown
  std::string message;       ///< one line for logs, e.g. "placed 1000 of 1000 roots ..."
};

/// Places up to options.count roots on the scalp and combs them. Returns false only for invalid
/// input (with `why` naming the field); a count short of the request is reported in the summary.
/// Deterministic: the same inputs and seed give bit-identical roots.
bool SampleRoots(const SphereScalp& scalp, const RootSamplingOptions& options,
                 const CombOptions& comb, std::vector<Root>* roots, RootSamplingSummary* summary,
                 std::string* why);

/// The same on triangles; candidates are drawn uniformly by area (a triangle chosen with
/// probability proportional to its area, then a uniform point by the square-root barycentric map
/// of Osada et al., "Shape distributions", ACM TOG 21(4), 2002, eq. 1).
bool SampleRoots(const MeshScalp& scalp, const RootSamplingOptions& options,
                 const CombOptions& comb, std::vector<Root>* roots, RootSamplingSummary* summary,
                 std::string* why);

}  // namespace ringlet
