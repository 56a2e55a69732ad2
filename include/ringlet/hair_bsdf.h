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
  double eta = 1.55;  ///< refractive index of the fibre (Marschner 2003, Table 1)
  /// Cross-section eccentricity e = sqrt(1 - b^2/a^2) in [0, 1): the mechanical one. Enters
  /// the TRT lobe through Marschner's eta*(phi_h) (see HairBsdf); e = 0 is the circular model
  /// bit for bit.
  double eccentricity = 0.0;
  /// Absorption coefficient of the cortex times the fibre radius (dimensionless, per channel,
  /// >= 0): the transmittance of one crossing is T = exp(-sigma_a 2 cos(gamma_t) / cos(theta_t)),
  /// 2 cos(gamma_t) / cos(theta_t) being the chord in radii (Chiang et al. 2016, eq. 4; pbrt-v3).
  /// Chiang's melanin fits (AbsorptionFromMelanin) are for this expression.
  Rgb sigma_a = Rgb(0.06, 0.10, 0.20);
  /// alpha: the scales' tilt (rad), ~2 degrees, in [-0.2, 0.2]. Positive = free edges toward the
  /// tip (x): lobe p peaks at theta_h = (theta_i + theta_o)/2 = alpha_p with alpha_R = -alpha,
  /// alpha_TT = alpha/2, alpha_TRT = 3 alpha/2 (Marschner 2003, Table 1: R shifts to the root).
  double cuticle_tilt = 0.035;
  /// beta_m in (0, 1]: Chiang 2016's longitudinal roughness, variance v = (0.726 b + 0.812 b^2 +
  /// 3.7 b^20)^2 (rad^2) for R, v/4 for TT, 4v for TRT and the residual; Marschner's Gaussian
  /// widths are beta_R = sqrt(v), beta_TT = beta_R/2, beta_TRT = 2 beta_R (rad).
  double longitudinal_roughness = 0.3;
  /// beta_n in (0, 1]: Chiang 2016's azimuthal roughness, logistic scale s = sqrt(pi/8) (0.265 b
  /// + 1.194 b^2 + 5.372 b^22) (rad). Marschner 2003 has no azimuthal roughness (only its
  /// sampling density uses s).
  double azimuthal_roughness = 0.3;
  /// Refractive index of the water film on wet fibres (FibreHit::wetness > 0), > 1: 1.333 (pure
  /// water at 20 C and 589 nm; Hale & Querry, Applied Optics 12(3), 1973).
  double water_eta = 1.333;
};

/// Absorption sigma_a (HairOptics::sigma_a's units) from melanin concentrations (Chiang et al.
/// 2016, section 4.2, after d'Eon et al. 2011): sigma_a = eumelanin * (0.419, 0.697, 1.37)
///                                   + pheomelanin * (0.187, 0.4, 1.05).
/// Black hair ~8 eumelanin, brown ~1.3, blonde ~0.3, red: pheomelanin ~1-3 (dimensionless).
Rgb AbsorptionFromMelanin(double eumelanin, double pheomelanin);

/// A display colour (linear RGB in (0, 1]) for hair with these melanins, for viewers that draw
/// flat-coloured curves: exp(-3 sigma_a) per channel, sigma_a = AbsorptionFromMelanin, the
/// transmittance of a path of 3 fibre radii through the cortex (between the TT path's chord of
/// 2 radii and the TRT path's 4 at normal incidence; Chiang et al. 2016, eq. 4). A simple
/// mapping, not a rendered colour: the exporters write it (.hair colour array, USD
/// primvars:displayColor, OBJ vertex colours) and the studio draws with it.
Rgb MelaninDisplayColour(double eumelanin, double pheomelanin);

/// Hair fibre scattering with FibreScattering's conventions (local frame x = tangent, phi_o =
/// pi/2, h = sin(gamma_o); f includes every cosine, so the white furnace integral of f is <= 1).
///
/// kChiang2016: f = sum_{p=0..2} M_p(theta_i, theta_o - 2 alpha_p; v_p) A_p(theta_o, h)
///   N_p(phi_i - phi_o - Phi(p, h); s) + M_3(theta_i, theta_o; v_3) A_3 / (2 pi), with d'Eon's
///   M_p, A_p from the exact dielectric Fresnel at cos(theta_o) cos(gamma_o) and the absorption T,
///   Phi(p, h) = 2 p gamma_t - 2 gamma_o + p pi, sin(gamma_t) = h / eta', eta' = Bravais' index,
///   the trimmed logistic N_p and the residual A_3 = A_2 f T / (1 - f T). Energy conserving:
///   the integral of f is sum_p A_p, exactly 1 for sigma_a = 0.
/// kMarschner2003: f = cos(theta_i) / cos^2(theta_d) sum_{p=0..2} (1/2) g(beta_p; theta_h -
///   alpha_p) N_p(phi), N_p from the roots of the cubic exit-angle polynomial (c = asin(1/eta'))
///   with Bravais' Fresnel and absorption; the 1/2 is d theta_h / d theta_i. The TRT caustic
///   is handled by capping 1/|d phi / d gamma| at 20 (instead of the paper's glint term); the
///   model is the h-averaged one (hit.h unused) and is not energy conserving (furnace 0.78-0.90).
/// Sample (both models): lobe p with probability proportional to the channel mean of A_p, then
///   theta_i exactly from d'Eon's M_p, then phi_i from the logistic N_p (uniform for p = 3);
///   Pdf is that mixture density, so Sample's weight is f / Pdf exactly.
/// Elliptic fibres (Marschner 2003, section 4.3): the TRT lobe uses
///   eta*(phi_h) = (eta1* + eta2*)/2 + cos(2 phi_h) (eta1* - eta2*)/2,
///   eta1* = 2 (eta - 1) a^2 - eta + 2, eta2* = 2 (eta - 1) / a^2 - eta + 2,
/// with phi_h the half angle of phi_i and phi_o measured from the major axis
/// (FibreHit::major_axis_angle) and a = major / minor = 1 / sqrt(1 - e^2). Why this a: phi_h = 0
/// means light travelling along the major axis, where the front face's radius of curvature b^2/a
/// is smallest, so rays focus more strongly, as in a circle of higher index: eta* > eta needs
/// a > 1 in eta1*. (A paraxial estimate, (eta* - 1)/eta* = (eta - 1)/eta (a/b)^2, gives the same
/// sign and a similar slope, d eta*/d a^2 = eta (eta - 1) vs Marschner's 2 (eta - 1).) The
/// paper's Table 1 range 0.85-1 is this ratio measured the other way round, for phi_h from the
/// minor axis. eta* is clamped below at 1 + (eta - 1)/4 (the linearization would drop below 1
/// for a^2 >= 2). Chiang: eta* moves only the TRT lobe centre Phi(2, h), with phi_h taken between
/// phi_o and the circular TRT exit (so N_TRT stays normalized and A_p unchanged: the furnace is
/// still exactly 1). Marschner: eta* replaces eta in the whole TRT term (roots, Fresnel,
/// absorption) with the actual phi_i.
/// Transmittance: A_TT = (1 - f)^2 T of the Chiang model (exact for a smooth cylinder), both
/// models.
/// Wet fibres (kChiang2016; FibreHit::wetness w in [0, 1], the fraction of the surface under a
///   water film): the film (index water_eta, between air and the fibre) replaces the fibre's
///   Fresnel reflectance f by the film stack's, R = R1 + (1 - R1)^2 R2 / (1 - R1 R2) per
///   polarization (R1 air | water, R2 water | keratin, incoherent multiple reflections), in every
///   lobe: A_R, the entry and exit (1 - f)^2 and the internal reflections f of TRT and the
///   residual. A thin concentric film keeps the ray's offset invariant (Bouguer's n r sin i), so
///   gamma_t and the absorption are unchanged. With w, A_p = (1 - w) A_p(dry) + w A_p(wet): still
///   exactly 1 in the furnace. R drops to 0.555 of dry at normal incidence, TRT to ~0.5, TT
///   rises; more light enters the absorbing cortex, and in a hair volume it goes deeper before
///   coming back (Lekner & Dorf 1988's explanation of wet darkening: less index contrast, more
///   forward scattering, more absorption). kMarschner2003 ignores wetness.
class HairBsdf final : public FibreScattering {
 public:
  /// optics must pass CheckHairOptics (asserted).
  explicit HairBsdf(const HairOptics& optics);

  Rgb Eval(const Vec3& wo, const Vec3& wi, const FibreHit& hit) const override;
  ScatterSample Sample(const Vec3& wo, const FibreHit& hit,
                       const std::array<double, 4>& u) const override;
  double Pdf(const Vec3& wo, const Vec3& wi, const FibreHit& hit) const override;
  Rgb Transmittance(const Vec3& wo, const FibreHit& hit) const override;
  /// Sum of the Chiang attenuations A_p (exact for kChiang2016; a guide for kMarschner2003).
  Rgb Albedo(const Vec3& wo, const FibreHit& hit) const override;

  const HairOptics& optics() const { return optics_; }

 private:
  HairOptics optics_;
};

/// Checks optics: a one-line message naming the field and the expected range, or "" when valid:
/// eta > 1 finite, eccentricity in [0, 1), sigma_a >= 0 finite, cuticle_tilt in [-0.2, 0.2] rad
/// (measured tilts are 2-5 degrees; 0.2 rad = 11.5 degrees leaves room without letting the
/// shifted lobes wrap over the poles for ordinary views), both roughnesses in (0, 1], water_eta
/// > 1 finite.
std::string CheckHairOptics(const HairOptics& optics);

}  // namespace ringlet
