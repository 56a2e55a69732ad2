// The building blocks of the hair scattering models (hair_bsdf.h), exposed for tests: longitudinal
// and azimuthal lobes, Fresnel, the elliptic index adjustment and the per-(wo, h) lobe setup of
// Chiang et al. 2016. Private to the library (src/), not public API.
#pragma once

#include <array>

#include "ringlet/hair_bsdf.h"

namespace ringlet::hair {

inline constexpr double kPi = 3.14159265358979323846;
/// Number of lobes of the Chiang model: R (p = 0), TT (1), TRT (2) and the residual p_max = 3.
inline constexpr int kLobes = 4;

/// d'Eon et al. 2011's longitudinal lobe M(theta_i, theta_o; v) (1/rad, a density in theta_i with
/// respect to cos(theta_i) d theta_i):
///   M = csch(1/v) / (2 v) exp(-sin(theta_i) sin(theta_o) / v) I0(cos(theta_i) cos(theta_o) / v),
/// evaluated in log space so that small v (1/v up to ~1e4) neither overflows nor loses digits.
/// Both directions point away from the fibre, so the peak is at theta_i = -theta_o. Symmetric in
/// (theta_i, theta_o); integral over theta_i in [-pi/2, pi/2] of M cos(theta_i) = 1 for every
/// theta_o.
double LongitudinalDeon(double sin_i, double cos_i, double sin_o, double cos_o, double v);

/// Logistic density with scale s > 0 (1/rad): e^{-|x|/s} / (s (1 + e^{-|x|/s})^2).
double Logistic(double x, double s);
/// Its cumulative distribution 1 / (1 + e^{-x/s}).
double LogisticCdf(double x, double s);
/// Logistic density truncated to [-pi, pi] and renormalized (1/rad); 0 outside.
double TrimmedLogistic(double x, double s);
/// Inverse of the trimmed logistic's CDF: x in [-pi, pi] for u in [0, 1).
double SampleTrimmedLogistic(double u, double s);

/// Unpolarized Fresnel reflectance of a dielectric interface (exact, both polarizations averaged)
/// for light arriving from the medium of index 1 at incidence cosine cos_i in [0, 1] onto index
/// eta (any eta > 0; total internal reflection returns 1).
double FresnelDielectric(double cos_i, double eta);

/// Reflectance (unpolarized) of a fibre of index eta under a water film of index eta_water, for
/// light from air (index 1) at incidence cosine cos_i in [0, 1]: per polarization the exact
/// Fresnel reflectances R1 of air | water and R2 of water | fibre (at the angle refracted into
/// the water; the film's faces are parallel locally) summed incoherently over the reflections
/// inside the film, R = R1 + (1 - R1)^2 R2 / (1 - R1 R2), then averaged over the polarizations.
/// A lossless stack reflects equally from both sides (Stokes relations), so the same value serves
/// light inside the fibre. At normal incidence, eta = 1.55 and eta_water = 1.333: 0.0258 instead
/// of the dry fibre's 0.0465.
double FresnelWaterFilm(double cos_i, double eta_water, double eta);

/// Chiang et al. 2016, eq. 7: longitudinal variance v (rad^2) of the R lobe from beta_m in (0, 1]:
/// v = (0.726 beta_m + 0.812 beta_m^2 + 3.7 beta_m^20)^2.
double LongitudinalVariance(double beta_m);
/// Chiang et al. 2016, eq. 8: logistic scale s (rad) from beta_n in (0, 1]:
/// s = sqrt(pi/8) (0.265 beta_n + 1.194 beta_n^2 + 5.372 beta_n^22).
double AzimuthalScale(double beta_n);

/// Marschner's eccentricity parameter a (ratio of the axes, the one along phi_h = 0 over the
/// other) for ringlet's mechanical eccentricity e = sqrt(1 - b^2/a^2) with phi_h measured from the
/// MAJOR axis: a = 1 / sqrt(1 - e^2) >= 1 (derivation in hair_bsdf.h).
double MarschnerAxisRatio(double eccentricity);
/// Marschner et al. 2003, section 4.3: the eccentricity-adjusted index
///   eta*(phi_h) = (eta1* + eta2*)/2 + cos(2 phi_h) (eta1* - eta2*)/2,
///   eta1* = 2 (eta - 1) a^2 - eta + 2,  eta2* = 2 (eta - 1) a^-2 - eta + 2,
/// with a = MarschnerAxisRatio(e) and cos_2phi_h = cos(2 phi_h), phi_h from the major axis.
/// Clamped below at 1 + (eta - 1)/4: the paper's formula is a linearization about a = 1 (fitted for
/// a in [0.85, 1]) and would drop below 1 for a^2 >= 2; the clamp is inactive for e < 0.61.
/// Returns eta itself (bit for bit) when e == 0.
double EllipticEta(double eta, double eccentricity, double cos_2phi_h);

/// Marschner et al. 2003, eq. 8: the azimuthal term N_p(phi) (1/rad, per channel) of path p for
/// the relative azimuth phi = phi_i - phi_o, index eta (eta* for an elliptic TRT), the difference
/// angle theta_d (sin, cos) and sigma_a: the sum over the roots gamma of the cubic exit-angle
/// polynomial of A(p, h) / |2 d phi / d h| (see hair_bsdf.cpp). Integrates over phi to half the
/// integral of A(p, h) over h in [-1, 1] (minus the caustic clamp's loss for p = 2).
Rgb MarschnerAzimuthal(int p, double phi, double eta, double sin_d, double cos_d,
                       const Rgb& sigma_a);

/// Everything of the Chiang model that depends on wo and h only (not on wi).
struct ChiangLobes {
  double sin_theta_o = 0.0, cos_theta_o = 1.0;  ///< longitudinal angle of wo
  double phi_o = 0.0;                           ///< azimuth of wo (rad), pi/2 by convention
  std::array<Rgb, kLobes> a{};                  ///< attenuations A_p (R, TT, TRT, residual)
  std::array<double, kLobes> v{};               ///< longitudinal variances (rad^2)
  /// tilted wo per lobe: theta_o - 2 alpha_p (sin, |cos|); the residual lobe is not tilted.
  std::array<double, kLobes> sin_o{}, cos_o{};
  std::array<double, 3> phi{};       ///< lobe centres Phi(p, h) = phi_i - phi_o (rad)
  double s = 1.0;                    ///< logistic scale (rad)
  std::array<double, kLobes> pdf{};  ///< lobe selection probabilities (sum 1)
};

/// Sets up the Chiang lobes for wo (unit, local frame) and the hit (see hair_bsdf.h for formulas).
ChiangLobes ComputeChiangLobes(const HairOptics& optics, const Vec3& wo, const FibreHit& hit);

}  // namespace ringlet::hair
