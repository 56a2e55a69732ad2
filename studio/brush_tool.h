// The studio's brush tools without GL (docs/studio.md, "Brushes"): where a ray from the eye meets
// the hair or the body, where a comb stroke ends, and the hairstyle operations a stroke records
// (styling.h: Sculpt, Puff, LengthBrush, ClumpBrush, FrizzBrush). A stroke is data: the window turns the mouse into these operations
// and the session applies them like any other, so `ringlet style` replays them bit for bit.
#pragma once

#include <optional>

#include "ringlet/body.h"
#include "ringlet/math.h"
#include "ringlet/styling.h"

namespace ringlet::studio {

/// A ray from the eye: origin (m) and unit direction.
struct Ray {
  Vec3 origin = Vec3::Zero();
  Vec3 direction = Vec3::UnitY();
};

/// The point of the masters' equilibrium centrelines (4 samples per segment) closest to the ray
/// among those within `reach` (m) of it and in front of the eye; of several within reach, the
/// one nearest the eye (what the user sees first). None when no sample is within reach.
std::optional<Vec3> PickMasterPoint(const StyledHair& hair, const Ray& ray, double reach);

/// The first point where the ray enters the body (SignedDistance = 0), by sphere tracing
/// (steps of the signed distance, which never overshoots the surface: |grad d| <= 1) until
/// within 1e-6 m of it, at most max_distance (m) from the origin. None when it misses.
std::optional<Vec3> PickBodyPoint(const Body& body, const Ray& ray, double max_distance);

/// Where a comb stroke ends: the release ray meets the plane through `from` facing the camera
/// (normal `view`, the camera's forward axis), so the hair moves in the view plane as the mouse
/// does. `from` itself when the ray is parallel to the plane or meets it behind the eye.
Vec3 StrokeEnd(const Vec3& from, const Ray& release, const Vec3& view);

/// The brush as the panel sets it.
struct BrushSettings {
  double radius = 0.03;    ///< (m)
  double strength = 0.5;   ///< in (0, 1]
  Brush::Falloff falloff = Brush::Falloff::kSmooth;
  bool mirror = true;      ///< mirror symmetry across the head's mid-plane
  double puff_angle = 0.3; ///< (rad) of a puff click at full weight
  double length_factor = 0.8;     ///< a length click's factor (Shift: 1 / factor, lengthen)
  double clump_factor = 0.6;      ///< a clump click's factor (Shift: 1 / factor, unclump)
  double frizz_amplitude = 0.003; ///< a frizz click's amplitude (m; Shift: 0, smooth)
};

/// The sculpt operation of a comb stroke from `from` to `to` (m).
StyleOperation SculptOperation(const BrushSettings& brush, const Vec3& from, const Vec3& to);

/// The puff operation of a click at `centre` (m); flatten turns the angle's sign.
StyleOperation PuffOperation(const BrushSettings& brush, const Vec3& centre, bool flatten);

/// Where a length, clump or frizz click acts: the hair under the brush (PickMasterPoint with
/// the brush radius as reach), else where the ray enters the body (PickBodyPoint, within
/// max_distance m). None when it meets neither.
std::optional<Vec3> PickBrushCentre(const StyledHair& hair, const Ray& ray, double reach,
                                    double max_distance);

/// The length operation of a click at `centre`: factor length_factor, or its inverse with
/// invert (Shift: lengthen).
StyleOperation LengthOperation(const BrushSettings& brush, const Vec3& centre, bool invert);

/// The clump operation of a click: factor clump_factor, or its inverse with invert (unclump).
StyleOperation ClumpOperation(const BrushSettings& brush, const Vec3& centre, bool invert);

/// The frizz operation of a click: amplitude frizz_amplitude, or 0 with invert (smooth).
StyleOperation FrizzOperation(const BrushSettings& brush, const Vec3& centre, bool invert);

/// The curl operation of a click (CurlBrush): toward the helix of radius and pitch (m), or
/// straight (radius +infinity) with invert (Shift: straighten).
StyleOperation CurlOperation(const BrushSettings& brush, const Vec3& centre, double radius,
                             double pitch, bool invert);

}  // namespace ringlet::studio
