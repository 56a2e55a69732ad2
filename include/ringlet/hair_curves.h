// A set of hair curves: what the groom produces and the exporters and renderer consume.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

namespace ringlet {

/// Single precision point: hair files store floats and a full head holds ~10^7 points.
using Vec3f = Eigen::Vector3f;

/// Strands as polylines, stored flat (the layout of Yuksel's .hair files and USD BasisCurves):
/// strand k has point_counts[k] >= 2 consecutive points starting at the sum of the counts before it.
struct HairCurves {
  std::vector<std::uint32_t> point_counts;  ///< points per strand (each >= 2)
  std::vector<Vec3f> points;                ///< centreline points, root to tip (m, world coordinates)
  std::vector<float> widths;                ///< fibre diameter at each point (m); same size as points
  /// Optional per-strand linear RGB colour in [0, 1] (empty, or one per strand).
  std::vector<Vec3f> colors;
  /// Optional per-point direction of the elliptic cross-section's major axis (empty, or one per
  /// point): the material frame's n1 (cross_section.h), unit, normal to the strand, world
  /// coordinates. The groom fills it from the masters' frames; the renderer orients each fibre's
  /// ellipse by it (and picks a random orientation per strand when it is empty). File formats do
  /// not store it.
  std::vector<Vec3f> major_axes;
  /// Optional per-strand wetness in [0, 1] (empty = all dry, or one per strand): the fraction
  /// of the fibre's surface under a water film. The styling operations set it (StyledStrands:
  /// 1 for the strands of wet masters); the renderer's fibre optics follow it (hair_bsdf.h).
  /// File formats do not store it.
  std::vector<float> wetness;

  int NumStrands() const { return static_cast<int>(point_counts.size()); }
  int NumPoints() const { return static_cast<int>(points.size()); }
};

/// Checks what the exporters and the renderer rely on: each strand has >= 2 points, the counts
/// add up to points.size() (no overflow), widths.size() == points.size(), colors is empty or has
/// one entry per strand, major_axes is empty or has one per point, wetness is empty or has one
/// value in [0, 1] per strand, coordinates, colours and axes are finite, widths finite and >= 0. On failure *why gets one line that starts with name and
/// the field ("frames[2].widths[7]: ...").
bool CheckHairCurves(const HairCurves& curves, std::string_view name, std::string* why);

}  // namespace ringlet
