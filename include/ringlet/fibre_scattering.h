// How one hair fibre scatters light: the interface between the renderer (which finds fibres)
// and the scattering models (hair_bsdf.h, or simple ones in tests).
#pragma once

#include <array>

#include "ringlet/math.h"

namespace ringlet {

/// Linear RGB triple (radiance, throughput, reflectance); no unit unless stated.
using Rgb = Eigen::Vector3d;

/// Where a ray met a fibre, in the fibre's local frame. The local frame at a hit (the
/// convention of pbrt-v3's HairBSDF, Pharr, Jakob & Humphreys, "Physically Based Rendering",
/// 3rd ed., section 9.9):
///   x = the fibre's unit tangent (root to tip),
///   z = the component of the outgoing direction wo normal to x, normalized (toward the viewer),
///   y = z cross x,
/// so that an outgoing direction wo has azimuth phi_o = atan2(wo.z, wo.y) = pi/2 and
/// sin(theta_o) = wo.x (theta is the longitudinal angle, from the normal plane).
struct FibreHit {
  /// Offset of the hit across the fibre, h = ((p_hit - p_axis) . y) / radius, in [-1, 1]:
  /// h = sin(gamma_o) of Marschner et al. 2003.
  double h = 0.0;
  /// Angle of the cross-section's major axis in the normal plane, measured from y toward z
  /// (rad); only elliptic fibres (eccentricity > 0) depend on it.
  double major_axis_angle = 0.0;
  /// How wet the fibre is, in [0, 1]: the fraction of its surface covered by a water film
  /// (HairCurves::wetness); 0 is dry. Models that ignore water ignore it.
  double wetness = 0.0;
};

/// One draw of an incident direction from a scattering model.
struct ScatterSample {
  Vec3 wi = Vec3::Zero();     ///< incident direction, unit, local frame (points away from the hit)
  Rgb weight = Rgb::Zero();   ///< f(wo, wi) / pdf: the path throughput factor
  double pdf = 0.0;           ///< density of wi (1/sr); 0 when the draw failed
};

/// A fibre's scattering kernel f (1/sr), in the local frame above, including every cosine:
/// radiance leaving toward wo is L_o(wo) = integral over the sphere of f(wo, wi) L_i(wi) dw_i,
/// so energy conservation reads integral f(wo, wi) dw_i <= 1 for every wo and h (the white
/// furnace test). Both directions point away from the hit. Implementations are immutable and
/// thread-safe.
class FibreScattering {
 public:
  virtual ~FibreScattering() = default;

  /// f(wo, wi) (1/sr), >= 0 componentwise.
  virtual Rgb Eval(const Vec3& wo, const Vec3& wi, const FibreHit& hit) const = 0;
  /// Draws wi with density Pdf(wo, wi, hit) from uniform numbers u in [0, 1)^4.
  virtual ScatterSample Sample(const Vec3& wo, const FibreHit& hit,
                               const std::array<double, 4>& u) const = 0;
  /// The density (1/sr) with which Sample draws wi.
  virtual double Pdf(const Vec3& wo, const Vec3& wi, const FibreHit& hit) const = 0;
  /// Fraction of light that crosses the fibre going straight on (the TT lobe's attenuation
  /// A_TT of Marschner et al. 2003), for a ray along -wo hitting at offset hit.h: the per-fibre
  /// transmittance of shadow rays in the renderer's fast shadow mode. In [0, 1] componentwise.
  virtual Rgb Transmittance(const Vec3& wo, const FibreHit& hit) const = 0;
  /// The directional albedo, integral of f(wo, wi) over wi, in [0, 1] componentwise: a guide
  /// for the denoiser (denoise.h), not used for light transport. The default estimates it with
  /// 16 fixed stratified samples of Sample; models that know it exactly override it.
  virtual Rgb Albedo(const Vec3& wo, const FibreHit& hit) const {
    Rgb sum = Rgb::Zero();
    for (int i = 0; i < 16; ++i) {
      const double a = (i % 4 + 0.5) / 4.0, b = (i / 4 + 0.5) / 4.0;
      const ScatterSample s = Sample(wo, hit, {a, b, 0.5 * (a + b), 1.0 - a});
      if (s.pdf > 0.0) sum += s.weight;
    }
    return (sum / 16.0).cwiseMax(0.0).cwiseMin(1.0);
  }
};

}  // namespace ringlet
