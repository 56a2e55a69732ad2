// The pinhole camera's rays. Private to src/render.
#pragma once

#include <string>

#include "ringlet/math.h"
#include "ringlet/render.h"

namespace ringlet::render {

/// A Camera prepared for an image of width x height pixels: an orthonormal basis (right, up,
/// forward) and the half extents of the image plane at distance 1.
struct PinholeCamera {
  Vec3 position = Vec3::Zero();
  Vec3 forward = Vec3::UnitY();
  Vec3 right = Vec3::UnitX();
  Vec3 up = Vec3::UnitZ();
  double half_height = 1.0;  ///< tan(vertical_fov / 2)
  double half_width = 1.0;   ///< half_height * width / height
  int width = 1;
  int height = 1;

  /// The unit direction of the ray through image point (px, py) in pixels: (0, 0) is the
  /// top-left corner of the image, (width, height) the bottom-right, pixel (i, j)'s centre is
  /// (i + 1/2, j + 1/2).
  Vec3 Direction(double px, double py) const {
    const double sx = (2.0 * px / width - 1.0) * half_width;
    const double sy = (1.0 - 2.0 * py / height) * half_height;
    return (forward + sx * right + sy * up).normalized();
  }
};

/// Checks the camera (finite, position != look_at, up not along the view, fov in (0, pi)) and
/// builds its rays; false with one line naming the field ("camera.vertical_fov: ...").
bool MakePinholeCamera(const Camera& camera, int width, int height, PinholeCamera* out,
                       std::string* why);

}  // namespace ringlet::render
