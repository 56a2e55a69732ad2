// Rigid obstacles a strand may touch, described by a signed distance (paper, section 3.1).
#pragma once

#include <limits>

#include "ringlet/math.h"

namespace ringlet {

/// A rigid obstacle (a body of spheres, a triangle mesh, ...) seen by the contact energy only
/// through its signed distance: negative inside, zero on the surface, positive outside (m).
/// Implementations must be thread-safe for concurrent queries (strands are solved in parallel)
/// and 1-Lipschitz (|d(x) - d(y)| <= |x - y|), which the contact broad phase relies on.
class Obstacle {
 public:
  virtual ~Obstacle() = default;

  /// Signed distance from x (m, world coordinates) to the surface (m). If gradient is not null it
  /// receives dd/dx, the outward unit normal of the closest surface point (any unit vector where
  /// the distance is not differentiable).
  virtual double SignedDistance(const Vec3& x, Vec3* gradient) const = 0;

  /// The signed distance with its gradient and its Hessian d^2 d / dx^2 (1/m), for the exact
  /// second derivatives of the contact energy (strand_hessian.h). gradient and hessian may be
  /// null. The default differentiates the gradient by central differences with a step of
  /// kDistanceHessianStep (m): right for obstacles whose gradient is smooth; bodies override it
  /// with the exact Hessian.
  virtual double SignedDistanceHessian(const Vec3& x, Vec3* gradient, Mat3* hessian) const;

  /// A bound L on how fast SignedDistance (as computed) can change, |d(x) - d(y)| <= L |x - y|,
  /// or +infinity when unknown (the default). With a finite L the contact broad phase
  /// (ContactEnergy, ComputeStrandHessian) skips the distance queries of segments that the bound
  /// alone proves clear of the obstacle (docs/body.md, "Broad phase"); the results do not change.
  /// Overriding it with a value below the true constant would skip contacts.
  virtual double LipschitzBound() const { return std::numeric_limits<double>::infinity(); }
  /// Step of the default SignedDistanceHessian (m).
  static constexpr double kDistanceHessianStep = 1e-7;
};

}  // namespace ringlet
