// Hair fibre scattering: Chiang et al. 2016 (default) and Marschner et al. 2003, with Marschner's
// eccentricity adjustment of the TRT lobe. Formulas and conventions are documented in
// include/ringlet/hair_bsdf.h; this file cites the equation of each step.
#include "ringlet/hair_bsdf.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <sstream>
#include <type_traits>

#include "render/hair_terms.h"

namespace ringlet {
namespace hair {
namespace {

double Clamp1(double x) { return std::clamp(x, -1.0, 1.0); }
double SafeSqrt(double x) { return std::sqrt(std::max(0.0, x)); }
/// Angle wrapped to [-pi, pi].
double Wrap(double x) { return std::remainder(x, 2.0 * kPi); }

/// log I0(a) for a >= 0: libstdc++'s cyl_bessel_i (C++17 special functions) while it cannot
/// overflow, then the asymptotic series I0(a) ~ e^a / sqrt(2 pi a) (1 + 1/(8a) + 9/(128 a^2)
/// + 225/(3072 a^3)) (Abramowitz & Stegun 9.7.1), whose next term is < 1e-12 relative at a > 500.
double LogI0(double a) {
  if (a <= 500.0) return std::log(std::cyl_bessel_i(0.0, a));
  const double r = 1.0 / (8.0 * a);
  return a - 0.5 * std::log(2.0 * kPi * a) + std::log1p(r + 4.5 * r * r + 37.5 * r * r * r);
}

/// Unpolarized Fresnel reflectance with Bravais' two indices (Marschner et al. 2003, section 4.1
/// and appendix B): the s (perpendicular) polarization refracts with eta_perp, the p (parallel)
/// polarization with eta_par; gamma is the incidence angle in the normal plane.
double FresnelBravais(double eta_perp, double eta_par, double gamma) {
  const double cos_i = std::abs(std::cos(gamma));
  const double sin_i = std::abs(std::sin(gamma));
  double rs2 = 1.0;
  const double sin_ts = sin_i / eta_perp;
  if (sin_ts < 1.0) {
    const double cos_ts = std::sqrt(1.0 - sin_ts * sin_ts);
    const double rs = (cos_i - eta_perp * cos_ts) / (cos_i + eta_perp * cos_ts);
    rs2 = rs * rs;
  }
  double rp2 = 1.0;
  const double sin_tp = sin_i / eta_par;
  if (sin_tp < 1.0) {
    const double cos_tp = std::sqrt(1.0 - sin_tp * sin_tp);
    const double rp = (eta_par * cos_i - cos_tp) / (eta_par * cos_i + cos_tp);
    rp2 = rp * rp;
  }
  return 0.5 * (rs2 + rp2);
}

/// Real roots in [-pi/2, pi/2] of Marschner's cubic exit-angle approximation (2003, eq. 10)
///   g(gamma) = (6 p c / pi - 2) gamma - (8 p c / pi^3) gamma^3 = t,  c = asin(1 / eta'),
/// where t = phi - p pi wrapped to [-pi, pi] (g is odd and |g| <= pi on the interval). Closed
/// form (Cardano / trigonometric), polished by two Newton steps. Returns the number of roots.
int ExitAngleRoots(int p, double c, double t, std::array<double, 3>* roots) {
  const double a1 = 6.0 * p * c / kPi - 2.0;
  const double a3 = -8.0 * p * c / (kPi * kPi * kPi);
  std::array<double, 3> cand{};
  int n = 0;
  if (p == 0) {
    cand[n++] = t / a1;
  } else {
    // gamma^3 + P gamma + Q = 0.
    const double P = a1 / a3;
    const double Q = -t / a3;
    const double disc = 0.25 * Q * Q + P * P * P / 27.0;
    if (disc > 0.0) {
      const double sq = std::sqrt(disc);
      cand[n++] = std::cbrt(-0.5 * Q + sq) + std::cbrt(-0.5 * Q - sq);
    } else {
      // Three real roots (P < 0).
      const double m = 2.0 * std::sqrt(-P / 3.0);
      const double arg = Clamp1(3.0 * Q / (P * m));
      const double theta = std::acos(arg) / 3.0;
      for (int k = 0; k < 3; ++k) cand[n++] = m * std::cos(theta - 2.0 * kPi * k / 3.0);
    }
  }
  int count = 0;
  for (int k = 0; k < n; ++k) {
    double x = cand[k];
    for (int it = 0; it < 2 && p > 0; ++it) {
      const double d = a1 + 3.0 * a3 * x * x;
      if (std::abs(d) < 1e-12) break;
      x -= (a1 * x + a3 * x * x * x - t) / d;
    }
    if (std::abs(x) <= 0.5 * kPi) (*roots)[count++] = x;
  }
  return count;
}

/// The root density 1/|d phi/d gamma| is capped at 1/kCausticSlope (rad/rad): Marschner's TRT
/// caustic (d phi/d gamma = 0) is spread over the azimuths where |d phi/d gamma| < 0.05. This
/// replaces the paper's glint term (k_G, w_c, Delta eta'; section 4.2.2), a documented
/// approximation: it loses about A cos(gamma_c) * 0.05 / |phi''(gamma_c)| per caustic, ~1% of
/// A_TRT for eta = 1.55, and needs no artistic constants.
constexpr double kCausticSlope = 0.05;

}  // namespace

/// Marschner et al. 2003, eq. 8: N_p(phi) = sum over roots of A(p, h) / |2 d phi / d h|, with
/// eta' and eta'' the Bravais indices for theta_d (appendix B), the cubic exit angle for the roots
/// and the exact gamma_t for the attenuation:
///   A(0, h) = F(eta', eta'', gamma_i),
///   A(p, h) = (1 - F(eta', eta'', gamma_i))^2 F(1/eta', 1/eta'', gamma_t)^(p-1) T^p,
///   T = exp(-sigma_a 2 cos(gamma_t) / cos(theta_t)).
/// T uses the chord length 2 cos(gamma_t) of the unit circle (d'Eon et al. 2011, Chiang et al.
/// 2016) instead of the paper's 2 + 2 cos(2 gamma_t) (the squared chord, a known slip), so that
/// sigma_a means the same in both models. Since dh = cos(gamma) d gamma, the sum is
/// A cos(gamma) / (2 |g'(gamma)|).
Rgb MarschnerAzimuthal(int p, double phi, double eta, double sin_d, double cos_d,
                       const Rgb& sigma_a) {
  const double root = std::sqrt(eta * eta - sin_d * sin_d);
  const double eta_perp = root / cos_d;
  const double eta_par = eta * eta * cos_d / root;
  const double sin_t = sin_d / eta;
  const double cos_t = SafeSqrt(1.0 - sin_t * sin_t);
  const double c = std::asin(1.0 / eta_perp);
  std::array<double, 3> roots{};
  const int n = ExitAngleRoots(p, c, Wrap(phi - p * kPi), &roots);
  const double a1 = 6.0 * p * c / kPi - 2.0;
  const double a3 = -8.0 * p * c / (kPi * kPi * kPi);
  Rgb sum = Rgb::Zero();
  for (int k = 0; k < n; ++k) {
    const double gamma_i = roots[k];
    const double slope = std::max(std::abs(a1 + 3.0 * a3 * gamma_i * gamma_i), kCausticSlope);
    const double jacobian = std::cos(gamma_i) / (2.0 * slope);
    const double f_in = FresnelBravais(eta_perp, eta_par, gamma_i);
    if (p == 0) {
      sum += Rgb::Constant(f_in * jacobian);
      continue;
    }
    const double gamma_t = std::asin(Clamp1(std::sin(gamma_i) / eta_perp));
    const double f_inside = FresnelBravais(1.0 / eta_perp, 1.0 / eta_par, gamma_t);
    const Rgb t = (-sigma_a * (2.0 * std::cos(gamma_t) / cos_t)).array().exp().matrix();
    Rgb a = Rgb::Constant((1.0 - f_in) * (1.0 - f_in) * std::pow(f_inside, p - 1));
    for (int q = 0; q < p; ++q) a = a.cwiseProduct(t);
    sum += a * jacobian;
  }
  return sum;
}

namespace {

/// Unit-area Gaussian g(beta; x) (1/rad).
double Gaussian(double beta, double x) {
  return std::exp(-0.5 * x * x / (beta * beta)) / (beta * std::sqrt(2.0 * kPi));
}

/// Cuticle tilt of lobe p as the shift of theta_h = (theta_i + theta_o)/2 (Marschner 2003,
/// Table 1: alpha_R < 0, alpha_TT = -alpha_R/2, alpha_TRT = -3 alpha_R/2) with alpha_R = -alpha.
double LobeShift(int p, double alpha) {
  constexpr std::array<double, 3> kFactor = {-1.0, 0.5, 1.5};
  return kFactor[p] * alpha;
}

double Mean(const Rgb& c) { return (c.x() + c.y() + c.z()) / 3.0; }

}  // namespace

double LongitudinalDeon(double sin_i, double cos_i, double sin_o, double cos_o, double v) {
  // d'Eon et al. 2011, eq. 6, in log space: csch(x)/2 * x with x = 1/v and
  // log sinh(x) = x - log 2 + log1p(-e^{-2x}).
  const double x = 1.0 / v;
  const double a = cos_i * cos_o * x;
  const double b = sin_i * sin_o * x;
  // csch(x) / (2 v) = x e^{-x} / (1 - e^{-2x}).
  const double log_m = std::log(x) - x - std::log1p(-std::exp(-2.0 * x)) - b + LogI0(a);
  return std::exp(log_m);
}

double Logistic(double x, double s) {
  const double e = std::exp(-std::abs(x) / s);
  return e / (s * (1.0 + e) * (1.0 + e));
}

double LogisticCdf(double x, double s) { return 1.0 / (1.0 + std::exp(-x / s)); }

double TrimmedLogistic(double x, double s) {
  if (std::abs(x) > kPi) return 0.0;
  return Logistic(x, s) / (LogisticCdf(kPi, s) - LogisticCdf(-kPi, s));
}

double SampleTrimmedLogistic(double u, double s) {
  const double lo = LogisticCdf(-kPi, s);
  const double y = u * (LogisticCdf(kPi, s) - lo) + lo;
  const double x = -s * std::log(1.0 / y - 1.0);
  return std::clamp(x, -kPi, kPi);
}

double FresnelDielectric(double cos_i, double eta) {
  cos_i = std::clamp(cos_i, 0.0, 1.0);
  const double sin_t2 = (1.0 - cos_i * cos_i) / (eta * eta);
  if (sin_t2 >= 1.0) return 1.0;
  const double cos_t = std::sqrt(1.0 - sin_t2);
  const double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
  const double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

double FresnelWaterFilm(double cos_i, double eta_water, double eta) {
  // Per polarization: the air-water interface (r1) and the water-fibre one (r2, relative index
  // eta / eta_water, at the angle refracted into the water), their multiple reflections summed
  // incoherently (a film many wavelengths thick): R = R1 + (1 - R1)^2 R2 / (1 - R1 R2) (Stokes;
  // e.g. Born & Wolf, Principles of Optics, section 1.6, without the phase).
  cos_i = std::clamp(cos_i, 0.0, 1.0);
  const double sin_w2 = (1.0 - cos_i * cos_i) / (eta_water * eta_water);
  const double cos_w = std::sqrt(std::max(0.0, 1.0 - sin_w2));  // never total reflection: n > 1
  const double eta2 = eta / eta_water;
  const double sin_t2 = (1.0 - cos_w * cos_w) / (eta2 * eta2);
  const double cos_t = std::sqrt(std::max(0.0, 1.0 - sin_t2));
  auto reflectance = [](double ci, double ct, double n) {
    const double rs = (ci - n * ct) / (ci + n * ct);
    const double rp = (n * ci - ct) / (n * ci + ct);
    return std::array<double, 2>{rs * rs, rp * rp};
  };
  const std::array<double, 2> r1 = reflectance(cos_i, cos_w, eta_water);
  // eta2 < 1 (a fibre less dense than water) could reflect totally: 1 then.
  const std::array<double, 2> r2 =
      sin_t2 < 1.0 ? reflectance(cos_w, cos_t, eta2) : std::array<double, 2>{1.0, 1.0};
  double sum = 0.0;
  for (int k = 0; k < 2; ++k) {
    const double denominator = 1.0 - r1[k] * r2[k];
    sum += denominator > 0.0 ? r1[k] + (1.0 - r1[k]) * (1.0 - r1[k]) * r2[k] / denominator : 1.0;
  }
  return 0.5 * sum;
}

double LongitudinalVariance(double beta_m) {
  const double w = 0.726 * beta_m + 0.812 * beta_m * beta_m + 3.7 * std::pow(beta_m, 20);
  return w * w;
}

double AzimuthalScale(double beta_n) {
  return std::sqrt(kPi / 8.0) *
         (0.265 * beta_n + 1.194 * beta_n * beta_n + 5.372 * std::pow(beta_n, 22));
}

double MarschnerAxisRatio(double eccentricity) {
  return 1.0 / std::sqrt(1.0 - eccentricity * eccentricity);
}

double EllipticEta(double eta, double eccentricity, double cos_2phi_h) {
  if (eccentricity == 0.0) return eta;                          // the circular model, bit for bit
  const double a2 = 1.0 / (1.0 - eccentricity * eccentricity);  // a^2, a = major / minor
  const double eta1 = 2.0 * (eta - 1.0) * a2 - eta + 2.0;
  const double eta2 = 2.0 * (eta - 1.0) / a2 - eta + 2.0;
  const double eta_star = 0.5 * (eta1 + eta2) + 0.5 * cos_2phi_h * (eta1 - eta2);
  return std::max(eta_star, 1.0 + 0.25 * (eta - 1.0));
}

ChiangLobes ComputeChiangLobes(const HairOptics& optics, const Vec3& wo, const FibreHit& hit) {
  ChiangLobes lobes;
  // Angles of wo (fibre_scattering.h: sin(theta_o) = wo.x, phi_o = atan2(wo.z, wo.y)).
  lobes.sin_theta_o = Clamp1(wo.x());
  lobes.cos_theta_o = SafeSqrt(1.0 - lobes.sin_theta_o * lobes.sin_theta_o);
  lobes.phi_o = std::atan2(wo.z(), wo.y());
  const double h = Clamp1(hit.h);
  const double gamma_o = std::asin(h);
  const double cos_gamma_o = SafeSqrt(1.0 - h * h);

  // Refraction (Bravais): theta_t from Snell along the fibre, gamma_t with the apparent index
  // eta' = sqrt(eta^2 - sin^2 theta_o) / cos theta_o in the normal plane (Marschner 2003, app. B).
  const double eta = optics.eta;
  auto sin_gamma_t_for = [&](double eta_in) {
    if (lobes.cos_theta_o < 1e-12) return 0.0;  // grazing along the fibre: eta' -> infinity
    const double eta_perp =
        std::sqrt(eta_in * eta_in - lobes.sin_theta_o * lobes.sin_theta_o) / lobes.cos_theta_o;
    return Clamp1(h / eta_perp);
  };
  const double sin_theta_t = lobes.sin_theta_o / eta;
  const double cos_theta_t = SafeSqrt(1.0 - sin_theta_t * sin_theta_t);
  const double gamma_t = std::asin(sin_gamma_t_for(eta));
  const double cos_gamma_t = std::cos(gamma_t);

  // Attenuations (Chiang 2016, eqs. 3-5 and 6 for the residual): exact dielectric Fresnel at the
  // 3D incidence cosine cos(theta_o) cos(gamma_o); the same f serves the internal reflections
  // (Fresnel reciprocity); absorption along the chord 2 cos(gamma_t) / cos(theta_t) (radii).
  const double cos_incidence = lobes.cos_theta_o * cos_gamma_o;
  const Rgb t = (-optics.sigma_a * (2.0 * cos_gamma_t / cos_theta_t)).array().exp().matrix();
  const auto attenuations = [&t](double f) {
    std::array<Rgb, kLobes> a;
    a[0] = Rgb::Constant(f);
    a[1] = (1.0 - f) * (1.0 - f) * t;
    a[2] = a[1].cwiseProduct(f * t);
    for (int c = 0; c < 3; ++c) {
      const double ft = f * t[c];
      a[3][c] = ft < 1.0 ? a[2][c] * ft / (1.0 - ft) : 0.0;  // A_2 = 0 when f t = 1
    }
    return a;
  };
  lobes.a = attenuations(FresnelDielectric(cos_incidence, eta));
  // A wet fibre (hair_bsdf.h, "Wet fibres"): the fraction `wetness` of its surface is under a
  // water film, whose reflectance replaces f in every lobe; the lobes of the dry and the wet
  // surface are mixed by area. Each set sums to 1 without absorption, so their mix does too.
  const double wetness = std::clamp(hit.wetness, 0.0, 1.0);
  if (wetness > 0.0) {
    const std::array<Rgb, kLobes> wet =
        attenuations(FresnelWaterFilm(cos_incidence, optics.water_eta, eta));
    for (int p = 0; p < kLobes; ++p) lobes.a[p] = (1.0 - wetness) * lobes.a[p] + wetness * wet[p];
  }

  // Longitudinal variances (Chiang eq. 7; v_TT = v/4, v_TRT = v_residual = 4 v as Marschner's
  // beta_TT = beta_R/2, beta_TRT = 2 beta_R) and the tilt: lobe p peaks at theta_h = alpha_p,
  // i.e. M_p is evaluated with theta_o replaced by theta_o - 2 alpha_p.
  const double v = LongitudinalVariance(optics.longitudinal_roughness);
  lobes.v = {v, 0.25 * v, 4.0 * v, 4.0 * v};
  for (int p = 0; p < 3; ++p) {
    const double shift = 2.0 * LobeShift(p, optics.cuticle_tilt);
    const double cs = std::cos(shift), sn = std::sin(shift);
    lobes.sin_o[p] = lobes.sin_theta_o * cs - lobes.cos_theta_o * sn;
    lobes.cos_o[p] = std::abs(lobes.cos_theta_o * cs + lobes.sin_theta_o * sn);
  }
  lobes.sin_o[3] = lobes.sin_theta_o;
  lobes.cos_o[3] = lobes.cos_theta_o;

  // Azimuthal lobe centres Phi(p, h) = 2 p gamma_t - 2 gamma_o + p pi (Chiang eq. 9). The TRT
  // lobe of an elliptic fibre uses eta*(phi_h) (Marschner 2003, section 4.3) with phi_h the half
  // angle between phi_o and the circular TRT exit phi_o + Phi(2): it depends on wo and h only,
  // so N_TRT stays a normalized density that Sample draws exactly.
  for (int p = 0; p < 3; ++p) lobes.phi[p] = 2.0 * p * gamma_t - 2.0 * gamma_o + p * kPi;
  if (optics.eccentricity > 0.0) {
    const double cos_2phi_h =
        std::cos(2.0 * lobes.phi_o + lobes.phi[2] - 2.0 * hit.major_axis_angle);
    const double eta_star = EllipticEta(eta, optics.eccentricity, cos_2phi_h);
    lobes.phi[2] = 4.0 * std::asin(sin_gamma_t_for(eta_star)) - 2.0 * gamma_o + 2.0 * kPi;
  }
  lobes.s = AzimuthalScale(optics.azimuthal_roughness);

  // Lobe selection by the channel-mean attenuation (Chiang section 5.2).
  double total = 0.0;
  for (int p = 0; p < kLobes; ++p) total += Mean(lobes.a[p]);
  for (int p = 0; p < kLobes; ++p) lobes.pdf[p] = Mean(lobes.a[p]) / total;
  return lobes;
}

}  // namespace hair

using hair::kLobes;
using hair::kPi;

namespace {

struct DirectionAngles {
  double sin_theta, cos_theta, phi;
};

DirectionAngles Angles(const Vec3& w) {
  DirectionAngles d;
  d.sin_theta = std::clamp(w.x(), -1.0, 1.0);
  d.cos_theta = std::sqrt(std::max(0.0, 1.0 - d.sin_theta * d.sin_theta));
  d.phi = std::atan2(w.z(), w.y());
  return d;
}

/// Chiang 2016, eq. 2 and 6: sum_p M_p A_p N_p, or with weights instead of A_p: the pdf.
template <typename Weight>
auto ChiangSum(const hair::ChiangLobes& lobes, const Vec3& wi, Weight weight) {
  using T = std::decay_t<decltype(weight(0))>;
  const DirectionAngles in = Angles(wi);
  const double dphi = in.phi - lobes.phi_o;
  T sum = weight(0) * 0.0;
  for (int p = 0; p < 3; ++p) {
    const double m = hair::LongitudinalDeon(in.sin_theta, in.cos_theta, lobes.sin_o[p],
                                            lobes.cos_o[p], lobes.v[p]);
    const double n = hair::TrimmedLogistic(std::remainder(dphi - lobes.phi[p], 2.0 * kPi), lobes.s);
    sum += weight(p) * (m * n);
  }
  const double m = hair::LongitudinalDeon(in.sin_theta, in.cos_theta, lobes.sin_o[3],
                                          lobes.cos_o[3], lobes.v[3]);
  sum += weight(3) * (m / (2.0 * kPi));
  return sum;
}

double ChiangPdf(const hair::ChiangLobes& lobes, const Vec3& wi) {
  return ChiangSum(lobes, wi, [&](int p) { return lobes.pdf[p]; });
}

}  // namespace

HairBsdf::HairBsdf(const HairOptics& optics) : optics_(optics) {
  assert(CheckHairOptics(optics).empty());
}

Rgb HairBsdf::Eval(const Vec3& wo, const Vec3& wi, const FibreHit& hit) const {
  if (optics_.model == HairScatteringModel::kChiang2016) {
    const hair::ChiangLobes lobes = hair::ComputeChiangLobes(optics_, wo, hit);
    return ChiangSum(lobes, wi, [&](int p) -> Rgb { return lobes.a[p]; });
  }
  // Marschner et al. 2003, eq. 4: S = sum_p M_p(theta_h) N_p(phi) / cos^2(theta_d), times
  // cos(theta_i) (the irradiance of the fibre, his eq. 1) and 1/2, the Jacobian d theta_h /
  // d theta_i at fixed theta_o that turns his unit-area Gaussians in theta_h into densities in
  // theta_i. The model is the h-averaged (far-field) one: hit.h is not used.
  const DirectionAngles out = Angles(wo);
  const DirectionAngles in = Angles(wi);
  const double theta_o = std::asin(out.sin_theta);
  const double theta_i = std::asin(in.sin_theta);
  const double theta_h = 0.5 * (theta_i + theta_o);
  const double theta_d = 0.5 * (theta_o - theta_i);
  const double cos_d = std::cos(theta_d);
  if (cos_d < 1e-9) return Rgb::Zero();  // theta_i = -theta_o = +-pi/2: no azimuth defined
  const double sin_d = std::sin(theta_d);
  const double phi = std::remainder(in.phi - out.phi, 2.0 * kPi);
  const double beta = std::sqrt(hair::LongitudinalVariance(optics_.longitudinal_roughness));
  const std::array<double, 3> betas = {beta, 0.5 * beta, 2.0 * beta};
  Rgb sum = Rgb::Zero();
  for (int p = 0; p < 3; ++p) {
    double eta = optics_.eta;
    if (p == 2 && optics_.eccentricity > 0.0) {
      // Marschner section 4.3: eta* in place of eta for the whole TRT term, phi_h = (phi_i +
      // phi_o)/2 measured from the major axis, so cos(2 phi_h) = cos(phi_i + phi_o - 2 psi).
      eta = hair::EllipticEta(optics_.eta, optics_.eccentricity,
                              std::cos(in.phi + out.phi - 2.0 * hit.major_axis_angle));
    }
    const double m =
        0.5 * hair::Gaussian(betas[p], theta_h - hair::LobeShift(p, optics_.cuticle_tilt));
    sum += m * hair::MarschnerAzimuthal(p, phi, eta, sin_d, cos_d, optics_.sigma_a);
  }
  return sum * (in.cos_theta / (cos_d * cos_d));
}

double HairBsdf::Pdf(const Vec3& wo, const Vec3& wi, const FibreHit& hit) const {
  // Both models sample with Chiang's lobes (Marschner's f is close to it; any density works).
  return ChiangPdf(hair::ComputeChiangLobes(optics_, wo, hit), wi);
}

ScatterSample HairBsdf::Sample(const Vec3& wo, const FibreHit& hit,
                               const std::array<double, 4>& u) const {
  const hair::ChiangLobes lobes = hair::ComputeChiangLobes(optics_, wo, hit);
  // 1. The lobe, with probability pdf[p] (u[0]).
  int p = 0;
  double cdf = lobes.pdf[0];
  while (p < kLobes - 1 && u[0] >= cdf) cdf += lobes.pdf[++p];
  // 2. theta_i from d'Eon's lobe (d'Eon et al. 2011, section 4.3; Chiang section 5.2): the
  // angle Theta to the cone direction of a von Mises-Fisher lobe with kappa = 1/v, whose
  // azimuthal integral is exactly M_p: cos Theta = 1 + v log(u + (1 - u) e^{-2/v}).
  const double v = lobes.v[p];
  const double u1 = std::max(u[1], 1e-16);
  const double cos_big =
      std::clamp(1.0 + v * std::log(u1 + (1.0 - u1) * std::exp(-2.0 / v)), -1.0, 1.0);
  const double sin_big = std::sqrt(std::max(0.0, 1.0 - cos_big * cos_big));
  const double sin_i = std::clamp(
      -cos_big * lobes.sin_o[p] + sin_big * std::cos(2.0 * kPi * u[2]) * lobes.cos_o[p], -1.0, 1.0);
  const double cos_i = std::sqrt(std::max(0.0, 1.0 - sin_i * sin_i));
  // 3. phi_i from the trimmed logistic around Phi(p, h) (u[3]); the residual lobe is uniform.
  const double dphi =
      p < 3 ? lobes.phi[p] + hair::SampleTrimmedLogistic(u[3], lobes.s) : 2.0 * kPi * u[3];
  const double phi_i = lobes.phi_o + dphi;
  ScatterSample sample;
  sample.wi = Vec3(sin_i, cos_i * std::cos(phi_i), cos_i * std::sin(phi_i));
  // 4. Weight f / pdf with the exact mixture density over all lobes.
  sample.pdf = ChiangPdf(lobes, sample.wi);
  if (!(sample.pdf > 0.0) || !std::isfinite(sample.pdf)) return ScatterSample{};
  const Rgb f = optics_.model == HairScatteringModel::kChiang2016
                    ? ChiangSum(lobes, sample.wi, [&](int q) -> Rgb { return lobes.a[q]; })
                    : Eval(wo, sample.wi, hit);
  sample.weight = f / sample.pdf;
  return sample;
}

Rgb HairBsdf::Transmittance(const Vec3& wo, const FibreHit& hit) const {
  return hair::ComputeChiangLobes(optics_, wo, hit).a[1];
}

Rgb HairBsdf::Albedo(const Vec3& wo, const FibreHit& hit) const {
  // The Chiang model's integral of f is sum_p A_p exactly (each lobe's M_p N_p integrates to 1);
  // Marschner's is close to it (not energy conserving; a guide only).
  const hair::ChiangLobes lobes = hair::ComputeChiangLobes(optics_, wo, hit);
  Rgb sum = Rgb::Zero();
  for (const Rgb& a : lobes.a) sum += a;
  return sum.cwiseMin(1.0);
}

Rgb AbsorptionFromMelanin(double eumelanin, double pheomelanin) {
  // Chiang et al. 2016, section 4.2 (after d'Eon et al. 2011); the same numbers are in pbrt-v3's
  // HairMaterial (materials/hair.cpp).
  return eumelanin * Rgb(0.419, 0.697, 1.37) + pheomelanin * Rgb(0.187, 0.4, 1.05);
}

Rgb MelaninDisplayColour(double eumelanin, double pheomelanin) {
  const Rgb sigma_a = AbsorptionFromMelanin(eumelanin, pheomelanin);
  return (-3.0 * sigma_a).array().exp().matrix();
}

std::string CheckHairOptics(const HairOptics& optics) {
  std::ostringstream why;
  auto in_unit = [](double x) { return std::isfinite(x) && x > 0.0 && x <= 1.0; };
  if (optics.model != HairScatteringModel::kChiang2016 &&
      optics.model != HairScatteringModel::kMarschner2003) {
    why << "model: expected kChiang2016 or kMarschner2003";
  } else if (!std::isfinite(optics.eta) || optics.eta <= 1.0) {
    why << "eta: expected a finite refractive index > 1, got " << optics.eta;
  } else if (!std::isfinite(optics.eccentricity) || optics.eccentricity < 0.0 ||
             optics.eccentricity >= 1.0) {
    why << "eccentricity: expected a value in [0, 1), got " << optics.eccentricity;
  } else if (!optics.sigma_a.allFinite() || (optics.sigma_a.array() < 0.0).any()) {
    why << "sigma_a: expected finite values >= 0 per channel, got (" << optics.sigma_a.x() << ", "
        << optics.sigma_a.y() << ", " << optics.sigma_a.z() << ")";
  } else if (!std::isfinite(optics.cuticle_tilt) || std::abs(optics.cuticle_tilt) > 0.2) {
    why << "cuticle_tilt: expected an angle in [-0.2, 0.2] rad, got " << optics.cuticle_tilt;
  } else if (!in_unit(optics.longitudinal_roughness)) {
    why << "longitudinal_roughness: expected a value in (0, 1], got "
        << optics.longitudinal_roughness;
  } else if (!std::isfinite(optics.water_eta) || optics.water_eta <= 1.0) {
    why << "water_eta: expected a finite refractive index > 1, got " << optics.water_eta;
  } else if (!in_unit(optics.azimuthal_roughness)) {
    why << "azimuthal_roughness: expected a value in (0, 1], got " << optics.azimuthal_roughness;
  }
  return why.str();
}

}  // namespace ringlet
