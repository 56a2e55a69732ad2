// Exact targets for inverse statics from ringlet's own result files (`ringlet solve` results and
// the masters.json of `ringlet groom`): piecewise helices given by their curvatures, no fit needed.
#pragma once

#include <string>
#include <vector>

#include "ringlet/math.h"

namespace ringlet {

/// One strand of a result file as an exact target.
struct ExactTarget {
  Vec3 root_position = Vec3::Zero();   ///< the first point (m)
  /// world_from_material at the root (n1, n2, t). Result files store the points and the
  /// curvatures, not the frame: the frame is the rotation that carries the centreline rebuilt
  /// from the curvatures (with the identity frame, root at the origin) onto the file's points,
  /// by least squares over all points (Kabsch: SVD of the 3x3 cross-covariance, determinant
  /// fixed to +1). A straight strand leaves the rotation about the tangent undetermined:
  /// frame_from_file is then false and the caller picks n1 (DefaultRootFrame).
  Mat3 root_frame = Mat3::Identity();
  bool frame_from_file = false;
  std::vector<double> segment_lengths;  ///< (m)
  VecX curvatures;                      ///< 3n (1/m)
  VecX rest_curvatures;                 ///< the file's rest shape (3n, 1/m), or empty
};

/// Parses the text of a result document ({"strands": [{"points", "curvatures",
/// "segment_lengths", ...}], ...}, docs/scene-format.md "Result format"). Checks the sizes
/// (points = n k + 1 for some k >= 1, n curvature triples, n lengths > 0), finiteness, and that
/// the points lie on the helix of the curvatures within 1e-6 L after the frame fit. On failure
/// returns false with one line naming the strand and the field or point
/// ("strands[3].points[7]: ..."). Never throws.
bool ParseResultTargets(const std::string& text, std::vector<ExactTarget>* targets,
                        std::string* why);

/// Reads the result file at path; messages start with the path.
bool ReadResultTargets(const std::string& path, std::vector<ExactTarget>* targets,
                       std::string* why);

}  // namespace ringlet
