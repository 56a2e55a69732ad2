// A body whose head turns on a still torso: the head part of a Body follows the head's rigid
// motion, the torso part only its translation (docs/body.md, "Head and torso"; docs/dynamics.md,
// "The body moves with the head").
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ringlet/body.h"
#include "ringlet/math.h"
#include "ringlet/obstacle.h"

namespace ringlet {

/// A Body split into its head part and its torso part (Body::sphere_part, Body::mesh_part), to be
/// placed with the two parts moved differently. Immutable once created; thread-safe.
///
/// The placed obstacle's signed distance folds the same components as the body, in the same way
/// (docs/body.md, "Union"): the spheres in the body's order, each where its part puts it, then
/// the head part's meshes and the torso part's meshes, each part's meshes as one component (their
/// own union, or distance grid, evaluated in the part's frame: d(R^T (x - t)), gradient R grad d,
/// Hessian R Hess d R^T). With blend 0 this is the minimum over the moved components: outside,
/// the exact distance to the union of the moved solids, whatever their relative placement. With
/// blend k > 0 the quadratic smooth minimum rounds the creases of the union as placed now (the
/// crease between the turned head and the still neck moves with them), equals the minimum where
/// the distances differ by more than k and stays 1-Lipschitz. With both parts placed alike it is
/// the body itself moved rigidly, up to the rounding of the moved centres and, for meshes, the
/// order of the fold (the body folds all meshes, or grids their union, at once; here each part's
/// grid is its own: the two grids differ from the union's grid only within a few grid spacings
/// of where the parts' meshes meet).
class SplitBody : public std::enable_shared_from_this<SplitBody> {
 public:
  /// The split of body; null when the body has no torso part (it then moves rigidly as a whole).
  /// With a distance grid (MeshDistanceOptions::kGrid) the meshes of each part get a grid of
  /// their own, built here with the body's options (grid_build_seconds). Throws
  /// std::invalid_argument for a null body, or if a part's grid cannot be built.
  static std::shared_ptr<const SplitBody> Create(std::shared_ptr<const Body> body);

  /// The obstacle of the body with its head part moved by x -> head_rotation x + head_translation
  /// (a proper rotation) and its torso part by x -> x + torso_translation. Its LipschitzBound is
  /// the body's (1 without a grid, 1.75 with one): each component keeps its bound under a rigid
  /// motion, and a minimum or smooth minimum of L-Lipschitz functions is L-Lipschitz.
  std::shared_ptr<const Obstacle> Place(const Mat3& head_rotation, const Vec3& head_translation,
                                        const Vec3& torso_translation) const;

  /// The body split.
  const Body& body() const { return *body_; }
  /// Seconds Create spent building the parts' grids (0 without a grid).
  double grid_build_seconds() const { return grid_build_seconds_; }

 private:
  friend class PlacedSplitBody;
  SplitBody() = default;

  std::shared_ptr<const Body> body_;
  std::vector<Eigen::Vector4d> spheres_;  // (cx, cy, cz, r) at rest, in the body's order
  std::vector<std::uint8_t> sphere_torso_;  // 1 for a torso sphere
  // Each part's meshes as a body of their own (the body's blend and mesh distance), or null.
  std::shared_ptr<const Body> head_meshes_, torso_meshes_;
  double blend_ = 0.0;
  double lipschitz_ = 1.0;
  double grid_build_seconds_ = 0.0;
};

/// The body with its head part moved by x -> head_rotation x + head_translation and its torso
/// part by x -> torso_rotation x + torso_translation (proper rotations), as a new Body: sphere
/// centres and mesh vertices moved, names, parts and blend kept, exact mesh distances (no grid:
/// this is for drawing the body where it is, `ringlet simulate --render`). The meshes are built
/// again (TriangleMesh::Create). False with one line in *error on failure (*moved untouched).
bool MoveBodyParts(const Body& body, const Mat3& head_rotation, const Vec3& head_translation,
                   const Mat3& torso_rotation, const Vec3& torso_translation, Body* moved,
                   std::string* error);

}  // namespace ringlet
