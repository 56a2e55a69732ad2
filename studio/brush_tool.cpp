// The studio's brush tools without GL (brush_tool.h).
#include "brush_tool.h"

#include <cmath>
#include <limits>

#include "ringlet/strand_geometry.h"

namespace ringlet::studio {

std::optional<Vec3> PickMasterPoint(const StyledHair& hair, const Ray& ray, double reach) {
  const Vec3 u = ray.direction.normalized();
  std::optional<Vec3> best;
  double best_depth = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < hair.masters.models.size() && i < hair.solutions.size(); ++i) {
    for (const Vec3& p : SampleCentreline(hair.masters.models[i], hair.solutions[i].curvatures, 4)) {
      const double depth = (p - ray.origin).dot(u);  // along the ray
      if (!(depth > 0.0)) continue;                    // behind the eye
      const double off = (p - ray.origin - depth * u).norm();
      if (off <= reach && depth < best_depth) {
        best_depth = depth;
        best = p;
      }
    }
  }
  return best;
}

std::optional<Vec3> PickBodyPoint(const Body& body, const Ray& ray, double max_distance) {
  const Vec3 u = ray.direction.normalized();
  double t = 0.0;
  double d = body.SignedDistance(ray.origin, nullptr);
  if (!(d > 0.0)) return std::nullopt;  // the eye inside the body (or no body)
  constexpr double kHit = 1e-6;
  for (int step = 0; step < 1000 && t <= max_distance; ++step) {
    if (d <= kHit) return ray.origin + t * u;
    // A step of d cannot cross the surface (the signed distance is 1-Lipschitz).
    t += d;
    d = body.SignedDistance(ray.origin + t * u, nullptr);
  }
  return std::nullopt;
}

Vec3 StrokeEnd(const Vec3& from, const Ray& release, const Vec3& view) {
  const Vec3 n = view.normalized();
  const double along = release.direction.dot(n);
  if (!(std::abs(along) > 1e-9)) return from;
  const double t = (from - release.origin).dot(n) / along;
  if (!(t > 0.0) || !std::isfinite(t)) return from;
  return release.origin + t * release.direction;
}

namespace {

Brush MakeBrush(const BrushSettings& settings, const Vec3& centre) {
  Brush b;
  b.centre = centre;
  b.radius = settings.radius;
  b.strength = settings.strength;
  b.falloff = settings.falloff;
  b.mirror = settings.mirror;
  return b;
}

}  // namespace

StyleOperation SculptOperation(const BrushSettings& brush, const Vec3& from, const Vec3& to) {
  StyleOperation op;
  op.kind = StyleOperation::Kind::kSculpt;
  op.sculpt.brush = MakeBrush(brush, from);
  op.sculpt.to = to;
  return op;
}

StyleOperation PuffOperation(const BrushSettings& brush, const Vec3& centre, bool flatten) {
  StyleOperation op;
  op.kind = StyleOperation::Kind::kPuff;
  op.puff_brush = MakeBrush(brush, centre);
  op.puff_angle = flatten ? -brush.puff_angle : brush.puff_angle;
  return op;
}

std::optional<Vec3> PickBrushCentre(const StyledHair& hair, const Ray& ray, double reach,
                                    double max_distance) {
  if (const std::optional<Vec3> p = PickMasterPoint(hair, ray, reach)) return p;
  if (!hair.style.body) return std::nullopt;
  return PickBodyPoint(*hair.style.body, ray, max_distance);
}

namespace {

StyleOperation BrushOperation(StyleOperation::Kind kind, const BrushSettings& brush,
                              const Vec3& centre) {
  StyleOperation op;
  op.kind = kind;
  op.brush = MakeBrush(brush, centre);
  return op;
}

}  // namespace

StyleOperation LengthOperation(const BrushSettings& brush, const Vec3& centre, bool invert) {
  StyleOperation op = BrushOperation(StyleOperation::Kind::kLength, brush, centre);
  op.factor = invert ? 1.0 / brush.length_factor : brush.length_factor;
  return op;
}

StyleOperation ClumpOperation(const BrushSettings& brush, const Vec3& centre, bool invert) {
  StyleOperation op = BrushOperation(StyleOperation::Kind::kClump, brush, centre);
  op.factor = invert ? 1.0 / brush.clump_factor : brush.clump_factor;
  return op;
}

StyleOperation FrizzOperation(const BrushSettings& brush, const Vec3& centre, bool invert) {
  StyleOperation op = BrushOperation(StyleOperation::Kind::kFrizz, brush, centre);
  op.frizz_amplitude = invert ? 0.0 : brush.frizz_amplitude;
  return op;
}

StyleOperation CurlOperation(const BrushSettings& brush, const Vec3& centre, double radius,
                             double pitch, bool invert) {
  StyleOperation op;
  op.kind = StyleOperation::Kind::kCurl;
  op.curl_brushed = true;
  op.curl_brush = MakeBrush(brush, centre);
  op.curl_radius = invert ? std::numeric_limits<double>::infinity() : radius;
  op.curl_pitch = invert ? 0.0 : pitch;
  return op;
}

}  // namespace ringlet::studio
