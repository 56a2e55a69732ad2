#include "render/camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace ringlet {
namespace {

bool IsFinite(const Vec3& v) { return v.allFinite(); }

}  // namespace

Camera FrameCamera(const Eigen::AlignedBox3d& box, const Vec3& view_direction,
                   double vertical_fov, double aspect) {
  // The bounding sphere (centre, radius = half the diagonal) seen under half-angle asin(R / d)
  // must fit the narrower half field of view with a margin: d = margin R / sin(half_fov).
  constexpr double kMargin = 1.1;
  Camera camera;
  camera.vertical_fov = vertical_fov;
  const Vec3 center = box.isEmpty() ? Vec3::Zero() : Vec3(box.center());
  const double radius = box.isEmpty() ? 1.0 : std::max(0.5 * box.diagonal().norm(), 1e-9);
  const double half_vertical = 0.5 * vertical_fov;
  const double half_horizontal = std::atan(aspect * std::tan(half_vertical));
  const double half_fov = std::min(half_vertical, half_horizontal);
  const double distance = kMargin * radius / std::sin(half_fov);
  Vec3 view = view_direction;
  if (!(view.norm() > 0.0) || !view.allFinite()) view = Vec3(0.0, 1.0, 0.0);
  view.normalize();
  camera.position = center - distance * view;
  camera.look_at = center;
  // Up is +z, unless the camera looks (almost) straight up or down: then +y.
  camera.up = std::abs(view.z()) > 0.999 ? Vec3::UnitY() : Vec3::UnitZ();
  return camera;
}

namespace render {

bool MakePinholeCamera(const Camera& camera, int width, int height, PinholeCamera* out,
                       std::string* why) {
  auto fail = [&](const std::string& message) {
    *why = message;
    return false;
  };
  if (!IsFinite(camera.position)) return fail("camera.position: expected finite coordinates (m)");
  if (!IsFinite(camera.look_at)) return fail("camera.look_at: expected finite coordinates (m)");
  if (!IsFinite(camera.up) || !(camera.up.norm() > 0.0)) {
    return fail("camera.up: expected a finite non-zero vector");
  }
  if (!(camera.vertical_fov > 0.0 && camera.vertical_fov < std::numbers::pi)) {
    std::ostringstream message;
    message << "camera.vertical_fov: expected a number in (0, pi) (rad), got "
            << camera.vertical_fov;
    return fail(message.str());
  }
  const Vec3 view = camera.look_at - camera.position;
  if (!(view.norm() > 0.0)) return fail("camera.look_at: must differ from camera.position");
  PinholeCamera result;
  result.position = camera.position;
  result.forward = view.normalized();
  const Vec3 right = result.forward.cross(camera.up.normalized());
  if (!(right.norm() > 1e-9)) {
    return fail("camera.up: must not be parallel to the view direction (look_at - position)");
  }
  result.right = right.normalized();
  result.up = result.right.cross(result.forward);
  result.half_height = std::tan(0.5 * camera.vertical_fov);
  result.half_width = result.half_height * width / height;
  result.width = width;
  result.height = height;
  *out = result;
  return true;
}

}  // namespace render
}  // namespace ringlet
