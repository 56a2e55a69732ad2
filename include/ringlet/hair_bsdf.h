// Light scattering by a human hair fibre: Marschner et al. 2003 ("Light scattering from human hair
// fibers", SIGGRAPH 2003) with its elliptic-cross-section adjustment, and the energy-conserving
// variant of d'Eon et al. 2011 / Chiang et al. 2016. Eccentricity is the same number as the
// mechanical one (cross_section.h; the paper, section 4): one parameter for shape and look.
#pragma once

#include <cstdint>
#include <string>

#include "ringlet/fibre_scattering.h"

namespace ringlet {

enum class HairScatteringModel : std::uint8_t {
  /// Chiang, Bitterli, Tappan & Burley 2016, "A practical and controllable hair and fur model
  /// for production path tracing": R, TT, TRT and a residual lobe, d'Eon's longitudinal lobes,
  /// logistic azimuthal lobes; conserves energy (white furnace) and is importance sampled.
  kChiang2016,
  /// Marschner et al. 2003: Gaussian longitudinal lobes M_p(theta_h - alpha_p, beta_p) and the
  /// azimuthal terms N_p from the exit-angle roots with Fresnel and absorption.
  kMarschner2003,
};

/// The physical parameters of the fibre's optics (SI; angles in rad).
struct HairOptics {
  HairScatteringModel model = HairScatteringModel::kChiang2016;
  double eta = 1.55;                ///< refractive index of the fibre (Marschner 2003, Table 1)
  /// Cross-section eccentricity e = sqrt(1 - b^2/a^2) in [0, 1): the mechanical one.
  double eccentricity = 0.0;
  /// Absorption coefficient of the cortex per unit fibre diameter (dimensionless, per channel):
  /// see AbsorptionFromMelanin.
  Rgb sigma_a = Rgb(0.06, 0.10, 0.20);
  double cuticle_tilt = 0.035;      ///< alpha: the scales' tilt (rad), ~2 degrees
  double longitudinal_roughness = 0.3;  ///< beta_m in (0, 1] (Chiang 2016's v-mapped roughness)
  double azimuthal_roughness = 0.3;     ///< beta_n in (0, 1]
};

/// Absorption per unit diameter from melanin concentrations (Chiang et al. 2016, section 4.2,
/// after d'Eon et al. 2011): sigma_a = eumelanin * (0.419, 0.697, 1.37)
///                                   + pheomelanin * (0.187, 0.4, 1.05).
/// Black hair ~8 eumelanin, brown ~1.3, blonde ~0.3, red: pheomelanin ~1-3 (dimensionless).
Rgb AbsorptionFromMelanin(double eumelanin, double pheomelanin);

/// Marschner et al. 2003's fibre scattering, FibreScattering's conventions.
class HairBsdf final : public FibreScattering {
 public:
  explicit HairBsdf(const HairOptics& optics);

  Rgb Eval(const Vec3& wo, const Vec3& wi, const FibreHit& hit) const override;
  ScatterSample Sample(const Vec3& wo, const FibreHit& hit,
                       const std::array<double, 4>& u) const override;
  double Pdf(const Vec3& wo, const Vec3& wi, const FibreHit& hit) const override;
  Rgb Transmittance(const Vec3& wo, const FibreHit& hit) const override;

  const HairOptics& optics() const { return optics_; }

 private:
  HairOptics optics_;
};

/// Checks optics: a one-line message naming the field and the expected range, or "" when valid.
std::string CheckHairOptics(const HairOptics& optics);

}  // namespace ringlet
