// The Embree 3 scene of a render: hair strands as round linear curves, body spheres as sphere
// points and body meshes as triangles; ray queries in double precision at the interface, the
// fibre's local frame at a hit, and shadow rays through fibres. Private to src/render.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "ringlet/body.h"
#include "ringlet/fibre_scattering.h"
#include "ringlet/hair_curves.h"
#include "ringlet/math.h"

// Embree's handles, without its headers in ours.
typedef struct RTCDeviceTy* RTCDevice;
typedef struct RTCSceneTy* RTCScene;

namespace ringlet::render {

inline constexpr std::uint32_t kNoSegment = std::numeric_limits<std::uint32_t>::max();

/// Fibre hits a ray must skip: the fibre segment it leaves from (a ray leaving a thin fibre
/// would otherwise find the same fibre again at t ~ 0, or from inside) and, closer than
/// neighbour_t, its neighbours on the same strand, whose round joints overlap the segment.
struct RayIgnore {
  std::uint32_t segment = kNoSegment;         ///< Embree primitive of the hair geometry
  std::uint32_t first_neighbour = kNoSegment;  ///< segments [first, last] of the same strand
  std::uint32_t last_neighbour = kNoSegment;
  float neighbour_t = 0.0f;                    ///< m along the ray
};

/// What a ray met.
enum class HitKind : std::uint8_t { kNone, kHair, kBody };

/// The closest hit of a ray.
struct SurfaceHit {
  HitKind kind = HitKind::kNone;
  double t = 0.0;           ///< distance along the (unit) ray direction (m)
  Vec3 p = Vec3::Zero();    ///< hit point (m)
  // Hair hits.
  std::uint32_t segment = kNoSegment;  ///< Embree primitive (segment) index
  int strand = -1;                     ///< strand index in HairCurves
  Vec3 tangent = Vec3::UnitX();        ///< unit segment direction, root to tip
  Vec3 axis_point = Vec3::Zero();      ///< closest point of the segment's axis to p (m)
  double radius = 0.0;                 ///< fibre radius at axis_point (m)
  /// Major axis of the cross-section at axis_point (HairCurves::major_axes interpolated along
  /// the segment, not normalized); zero when the curves carry none.
  Vec3 major_axis = Vec3::Zero();
  double wetness = 0.0;  ///< HairCurves::wetness of the strand (0 when the curves carry none)
  // Body hits.
  Vec3 normal = Vec3::UnitZ();  ///< outward unit geometric normal
  /// Outward unit normal for shading: a sphere's exact normal; on a mesh, the corner normals
  /// (area-weighted means of the faces around each vertex within 60 degrees of the hit face)
  /// interpolated with the hit's barycentric coordinates (Phong shading), so that a tessellated
  /// smooth surface does not show its facets and a sharp crease stays sharp. Rays still leave
  /// from the geometric surface (normal).
  Vec3 shading_normal = Vec3::UnitZ();
};

/// The local frame of a fibre hit (fibre_scattering.h): x tangent, z the part of wo normal to
/// x, y = z cross x; and the FibreHit (h, major_axis_angle).
struct FibreFrame {
  Vec3 x, y, z;
  FibreHit hit;
  Vec3 ToLocal(const Vec3& w) const { return Vec3(w.dot(x), w.dot(y), w.dot(z)); }
  Vec3 ToWorld(const Vec3& l) const { return l.x() * x + l.y() * y + l.z() * z; }
};

/// Builds the frame of a hair hit for the outgoing direction wo (unit, world): h = ((p -
/// p_axis) . y) / r clamped to [-1, 1]; major_axis_angle the angle from y toward z of
/// hit.major_axis projected on the normal plane, in [0, pi) (an ellipse's axis is a line: theta
/// and theta + pi are the same), or, when the hit has no axis (or one along the fibre), uniform
/// in [0, pi) per strand, hashed from orientation_seed and the strand index.
FibreFrame MakeFibreFrame(const SurfaceHit& hit, const Vec3& wo, std::uint64_t orientation_seed);

/// Hair and body in one Embree scene. Immutable once created; queries are thread-safe.
class EmbreeScene {
 public:
  /// Builds the scene (hair and body may each be null; both are referenced, not copied, and
  /// must outlive the scene). Embree errors -> null and one line in *error.
  static std::unique_ptr<EmbreeScene> Create(const HairCurves* hair, const Body* body,
                                             std::string* error);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  /// The closest hit of the ray org + t dir (dir unit), t in [tnear, tfar] (m).
  SurfaceHit Intersect(const Vec3& org, const Vec3& dir, double tnear, double tfar,
                       const RayIgnore& ignore) const;
  /// Whether anything blocks the ray in [tnear, tfar].
  bool Occluded(const Vec3& org, const Vec3& dir, double tnear, double tfar,
                const RayIgnore& ignore) const;

  /// What a ray leaving the fibre of this hair hit must skip.
  RayIgnore IgnoreFor(const SurfaceHit& hit) const;

  /// Offset (m) of rays leaving the body along its normal: 1e-5 of the scene's size (floats
  /// carry ~6e-8 relative precision; Embree's intersections lose a few bits more).
  double body_offset() const { return body_offset_; }
  int hair_segments() const { return hair_segments_; }
  int body_primitives() const { return body_primitives_; }

 private:
  EmbreeScene() = default;
  // Finds the strand of a segment (binary search in strand_first_segment_).
  int StrandOfSegment(std::uint32_t segment) const;

  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  const HairCurves* hair_ = nullptr;
  const Body* body_ = nullptr;
  unsigned hair_geometry_ = ~0u;
  unsigned sphere_geometry_ = ~0u;
  std::vector<int> mesh_of_geometry_;  // geometry ID -> mesh index, or -1
  std::vector<std::vector<Vec3>> corner_normals_;  // per body mesh, 3 per triangle (unit)
  std::vector<std::uint32_t> strand_first_segment_;  // per strand, + one past the end
  int hair_segments_ = 0;
  int body_primitives_ = 0;
  double body_offset_ = 0.0;
};

/// The fraction of light that reaches tfar along org + t dir (kFibreTransmittance shadows): the
/// product of FibreScattering::Transmittance over the fibres crossed (wo = -dir, h of each
/// crossing), 0 when the body blocks. Traces up to max_crossings rays (then returns 0: the
/// remaining light is negligible for hair of any density a groom makes) and stops early when
/// every channel is below min_throughput (returns 0). rays (may be null) counts the rays traced.
Rgb ShadowTransmittance(const EmbreeScene& scene, const FibreScattering& fibre,
                        std::uint64_t orientation_seed, const Vec3& org, const Vec3& dir,
                        double tnear, double tfar, const RayIgnore& ignore,
                        std::int64_t* rays, int max_crossings = 64,
                        double min_throughput = 1e-4);

}  // namespace ringlet::render
