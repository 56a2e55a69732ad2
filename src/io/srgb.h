// The sRGB transfer function (IEC 61966-2-1:1999, section 5.2; private to io/, exposed to tests).
#pragma once

#include <cmath>

namespace ringlet::internal {

/// Linear value in [0, 1] -> sRGB-encoded value in [0, 1] (IEC 61966-2-1, eq. for R'sRGB):
///   12.92 c                    for c <= 0.0031308,
///   1.055 c^(1/2.4) - 0.055    otherwise.
/// The two branches meet at c = 0.0031308 (both give 0.0404499...).
inline double LinearToSrgb(double c) {
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

/// The inverse: sRGB-encoded v in [0, 1] -> linear (the standard's decoding, threshold 0.04045):
///   v / 12.92                  for v <= 0.04045,
///   ((v + 0.055) / 1.055)^2.4  otherwise.
inline double SrgbToLinear(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

/// Linear radiance times exposure -> 8-bit sRGB code: clamped to [0, 1] first (NaN counts as 0,
/// +infinity as 1), encoded, then rounded to the nearest of the 256 codes.
inline unsigned char LinearToSrgb8(double c) {
  if (!(c > 0.0)) return 0;  // also NaN
  if (c >= 1.0) return 255;
  return static_cast<unsigned char>(std::lround(LinearToSrgb(c) * 255.0));
}

}  // namespace ringlet::internal
