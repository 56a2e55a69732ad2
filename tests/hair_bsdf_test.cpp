// Tests of the hair scattering models (hair_bsdf.h): energy (white furnace), positivity,
// reciprocity, Sample/Pdf consistency, published melanin numbers, and an independent reference
// for the azimuthal lobes: brute-force ray tracing of a dielectric cylinder with Snell's law and
// Fresnel.
#include "ringlet/hair_bsdf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <type_traits>
#include <vector>

#include "render/hair_terms.h"

namespace ringlet {
namespace {

using hair::kPi;

constexpr double kDeg = kPi / 180.0;

/// Direction with longitudinal angle theta (from the normal plane) and azimuth phi (from y to z).
Vec3 Dir(double theta, double phi) {
  return Vec3(std::sin(theta), std::cos(theta) * std::cos(phi), std::cos(theta) * std::sin(phi));
}
/// An outgoing direction in the convention of fibre_scattering.h: phi_o = pi/2.
Vec3 Wo(double theta_o) { return Dir(theta_o, 0.5 * kPi); }

/// Gauss-Legendre rule with n points on [a, b] (Newton on P_n, Golub-Welsch-free classic).
struct Rule {
  std::vector<double> x, w;
};
Rule GaussLegendre(int n, double a, double b) {
  Rule r;
  for (int i = 0; i < n; ++i) {
    double z = std::cos(kPi * (i + 0.75) / (n + 0.5));
    double dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1.0);
      const double dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-15) break;
    }
    r.x.push_back(0.5 * (a + b) + 0.5 * (b - a) * z);
    r.w.push_back((b - a) / ((1.0 - z * z) * dp * dp));
  }
  return r;
}

/// Integral over the sphere of g(wi) dw = cos(theta) d theta d phi: Gauss-Legendre in theta,
/// the midpoint rule in phi (spectrally accurate for smooth periodic integrands).
template <typename G>
auto SphereIntegral(const G& g, int n_theta, int n_phi) {
  const Rule rule = GaussLegendre(n_theta, -0.5 * kPi, 0.5 * kPi);
  using T = std::decay_t<decltype(g(Vec3(1.0, 0.0, 0.0)))>;
  T sum = g(Vec3(1.0, 0.0, 0.0)) * 0.0;
  const double dphi = 2.0 * kPi / n_phi;
  for (int i = 0; i < n_theta; ++i) {
    for (int j = 0; j < n_phi; ++j) {
      const double phi = -kPi + (j + 0.5) * dphi;
      sum += T(g(Dir(rule.x[i], phi)) * (rule.w[i] * std::cos(rule.x[i]) * dphi));
    }
  }
  return sum;
}

HairOptics Optics(double beta_m, double beta_n, const Rgb& sigma_a = Rgb::Zero(),
                  HairScatteringModel model = HairScatteringModel::kChiang2016) {
  HairOptics o;
  o.model = model;
  o.longitudinal_roughness = beta_m;
  o.azimuthal_roughness = beta_n;
  o.sigma_a = sigma_a;
  return o;
}

/// Fresnel reflectance written independently of the library (Hecht, Optics, eq. 4.42/4.43):
/// R_s = sin^2(i - t) / sin^2(i + t), R_p = tan^2(i - t) / tan^2(i + t), from n1 into n2.
double HechtFresnel(double cos_i, double n1, double n2) {
  const double i = std::acos(std::min(1.0, std::abs(cos_i)));
  const double sin_t = n1 / n2 * std::sin(i);
  if (sin_t >= 1.0) return 1.0;
  const double t = std::asin(sin_t);
  if (i < 1e-9) return std::pow((n1 - n2) / (n1 + n2), 2);
  const double rs = std::pow(std::sin(i - t) / std::sin(i + t), 2);
  const double rp = std::pow(std::tan(i - t) / std::tan(i + t), 2);
  return 0.5 * (rs + rp);
}

// ---------------------------------------------------------------------------------------------
// Published numbers and validation.

TEST(HairBsdf, MelaninCoefficientsArePublishedOnes) {
  // Chiang et al. 2016, section 4.2: eumelanin (0.419, 0.697, 1.37), pheomelanin
  // (0.187, 0.4, 1.05) per unit concentration; linear in the concentrations.
  EXPECT_EQ(AbsorptionFromMelanin(1.0, 0.0), Rgb(0.419, 0.697, 1.37));
  EXPECT_EQ(AbsorptionFromMelanin(0.0, 1.0), Rgb(0.187, 0.4, 1.05));
  const Rgb mix = AbsorptionFromMelanin(1.3, 0.5);
  EXPECT_NEAR(mix.x(), 1.3 * 0.419 + 0.5 * 0.187, 1e-15);
  EXPECT_NEAR(mix.y(), 1.3 * 0.697 + 0.5 * 0.4, 1e-15);
  EXPECT_NEAR(mix.z(), 1.3 * 1.37 + 0.5 * 1.05, 1e-15);
  EXPECT_EQ(AbsorptionFromMelanin(0.0, 0.0), Rgb::Zero());
}

// The display colour exp(-3 sigma_a), with Chiang et al. 2016's melanin absorption written out
// here (eumelanin (0.419, 0.697, 1.37), pheomelanin (0.187, 0.4, 1.05) per unit concentration).
TEST(HairBsdf, MelaninDisplayColourIsTheTransmittanceOfThreeRadii) {
  const double eu = 1.3, pheo = 0.2;
  const double sigma[3] = {eu * 0.419 + pheo * 0.187, eu * 0.697 + pheo * 0.4,
                           eu * 1.37 + pheo * 1.05};
  const Rgb c = MelaninDisplayColour(eu, pheo);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], std::exp(-3.0 * sigma[k]), 1e-15) << k;
  // Brown: red > green > blue; no melanin: white; black hair (eumelanin 8): nearly black.
  EXPECT_GT(c[0], c[1]);
  EXPECT_GT(c[1], c[2]);
  EXPECT_EQ(MelaninDisplayColour(0.0, 0.0), Rgb(1.0, 1.0, 1.0));
  EXPECT_LT(MelaninDisplayColour(8.0, 0.0).maxCoeff(), 1e-4);
}

TEST(HairBsdf, CheckHairOpticsNamesTheField) {
  EXPECT_EQ(CheckHairOptics(HairOptics{}), "");
  auto first_word = [](HairOptics o) {
    const std::string why = CheckHairOptics(o);
    return why.substr(0, why.find(':'));
  };
  HairOptics o;
  o.eta = 1.0;
  EXPECT_EQ(first_word(o), "eta");
  o = HairOptics{};
  o.eta = NAN;
  EXPECT_EQ(first_word(o), "eta");
  o = HairOptics{};
  o.eccentricity = 1.0;
  EXPECT_EQ(first_word(o), "eccentricity");
  o = HairOptics{};
  o.eccentricity = -0.1;
  EXPECT_EQ(first_word(o), "eccentricity");
  o = HairOptics{};
  o.sigma_a = Rgb(0.1, -0.1, 0.2);
  EXPECT_EQ(first_word(o), "sigma_a");
  o = HairOptics{};
  o.sigma_a = Rgb(0.1, INFINITY, 0.2);
  EXPECT_EQ(first_word(o), "sigma_a");
  o = HairOptics{};
  o.cuticle_tilt = 0.3;
  EXPECT_EQ(first_word(o), "cuticle_tilt");
  o = HairOptics{};
  o.longitudinal_roughness = 0.0;
  EXPECT_EQ(first_word(o), "longitudinal_roughness");
  o = HairOptics{};
  o.azimuthal_roughness = 1.5;
  EXPECT_EQ(first_word(o), "azimuthal_roughness");
}

// ---------------------------------------------------------------------------------------------
// Lobes on their own.

TEST(HairBsdf, DeonLongitudinalLobeIsNormalizedAndSymmetric) {
  // d'Eon et al. 2011: integral of M(theta_i, theta_o) cos(theta_i) d theta_i = 1 for every
  // theta_o, from very smooth (v = 20) to very sharp (v = 1e-3, 1/v = 1000: the log-space path).
  // 2000-point Gauss-Legendre resolves the sharpest lobe (std ~0.03 rad) to < 1e-9.
  const Rule rule = GaussLegendre(2000, -0.5 * kPi, 0.5 * kPi);
  for (double v : {1e-3, 0.01, 0.1, 1.0, 20.0}) {
    for (double theta_o : {-1.5, -0.6, 0.0, 0.3, 1.2}) {
      double sum = 0.0;
      for (size_t k = 0; k < rule.x.size(); ++k) {
        const double t = rule.x[k];
        sum += rule.w[k] * std::cos(t) *
               hair::LongitudinalDeon(std::sin(t), std::cos(t), std::sin(theta_o),
                                      std::cos(theta_o), v);
      }
      EXPECT_NEAR(sum, 1.0, 1e-8) << "v " << v << " theta_o " << theta_o;
    }
  }
  // Reciprocity of the longitudinal term (no tilt): M(theta_i, theta_o) = M(theta_o, theta_i).
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> angle(-0.5 * kPi, 0.5 * kPi);
  for (int k = 0; k < 100; ++k) {
    const double a = angle(rng), b = angle(rng);
    const double v = 0.01 + 0.5 * (k % 5);
    const double m_ab =
        hair::LongitudinalDeon(std::sin(a), std::cos(a), std::sin(b), std::cos(b), v);
    const double m_ba =
        hair::LongitudinalDeon(std::sin(b), std::cos(b), std::sin(a), std::cos(a), v);
    EXPECT_NEAR(m_ab, m_ba, 1e-13 * std::max(1.0, m_ab));
  }
}

TEST(HairBsdf, TrimmedLogisticIsADensityAndSampleInvertsItsCdf) {
  for (double s : {0.005, 0.1, 1.0, 5.0}) {
    // Midpoint rule, 20000 cells of 3e-4 rad (>= 16 per s for the sharpest).
    double sum = 0.0;
    const int n = 20000;
    for (int k = 0; k < n; ++k) sum += hair::TrimmedLogistic(-kPi + (k + 0.5) * 2 * kPi / n, s);
    EXPECT_NEAR(sum * 2 * kPi / n, 1.0, 1e-6) << s;
    // The sample of u is the u-quantile.
    for (double u : {0.01, 0.3, 0.5, 0.9}) {
      const double x = hair::SampleTrimmedLogistic(u, s);
      const double k = hair::LogisticCdf(kPi, s) - hair::LogisticCdf(-kPi, s);
      EXPECT_NEAR((hair::LogisticCdf(x, s) - hair::LogisticCdf(-kPi, s)) / k, u, 1e-12);
    }
  }
}

TEST(HairBsdf, FresnelMatchesHecht) {
  for (double eta : {1.01, 1.55, 2.5}) {
    for (double c : {1.0, 0.9, 0.5, 0.1, 1e-3}) {
      EXPECT_NEAR(hair::FresnelDielectric(c, eta), HechtFresnel(c, 1.0, eta), 1e-12);
      // Inside-out (index 1/eta) with total internal reflection.
      EXPECT_NEAR(hair::FresnelDielectric(c, 1.0 / eta), HechtFresnel(c, eta, 1.0), 1e-12);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Energy.

TEST(HairBsdf, WhiteFurnaceChiangConservesEnergy) {
  // sigma_a = 0: integral of f over the sphere = sum of A_p = 1 exactly (Chiang 2016, section 4:
  // the residual lobe closes the geometric series); only the quadrature errs. 96 x 128 points:
  // the sharpest lobe here (TT, beta_m = 0.25: std 0.1 rad; beta_n = 0.25: s = 0.09 rad) is
  // resolved to ~1e-5 (measured max deviation printed below); the tolerance is 1e-4.
  double worst = 0.0;
  for (const auto& [bm, bn] :
       std::vector<std::pair<double, double>>{{0.25, 0.25}, {0.5, 0.3}, {1.0, 1.0}}) {
    const HairBsdf bsdf(Optics(bm, bn));
    for (double theta_o : {-80.0, -40.0, 0.0, 30.0, 80.0}) {
      for (double h : {-0.9, 0.0, 0.6}) {
        const Vec3 wo = Wo(theta_o * kDeg);
        const FibreHit hit{h, 0.0};
        const Rgb e =
            SphereIntegral([&](const Vec3& wi) { return bsdf.Eval(wo, wi, hit); }, 96, 128);
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(e[c], 1.0, 1e-4) << bm << " " << bn << " " << theta_o << " " << h;
          worst = std::max(worst, std::abs(e[c] - 1.0));
        }
      }
    }
  }
  std::printf("[ furnace ] Chiang sigma_a = 0: max |integral - 1| = %.2e\n", worst);
}

TEST(HairBsdf, FurnaceChiangWithAbsorptionIsTheSumOfAttenuations) {
  // With absorption the integral is sum_p A_p < 1, with A_p written out here independently:
  // f = Fresnel(cos theta_o cos gamma_o), T = exp(-sigma_a 2 cos gamma_t / cos theta_t),
  // A = f + (1-f)^2 T + (1-f)^2 f T^2 + (1-f)^2 f^2 T^3 / (1 - f T).
  const Rgb sigma_a(0.2, 0.6, 1.5);
  const double eta = 1.55;
  const HairBsdf bsdf(Optics(0.4, 0.4, sigma_a));
  for (double theta_o : {-60.0, 10.0, 70.0}) {
    for (double h : {-0.5, 0.3, 0.95}) {
      const double t_o = theta_o * kDeg;
      const Vec3 wo = Wo(t_o);
      const Rgb e = SphereIntegral(
          [&](const Vec3& wi) {
            return bsdf.Eval(wo, wi, {h, 0.0});
          },
          160, 256);
      const double f = HechtFresnel(std::cos(t_o) * std::sqrt(1 - h * h), 1.0, eta);
      const double eta_perp = std::sqrt(eta * eta - std::pow(std::sin(t_o), 2)) / std::cos(t_o);
      const double cos_gt = std::sqrt(1 - h * h / (eta_perp * eta_perp));
      const double cos_tt = std::sqrt(1 - std::pow(std::sin(t_o) / eta, 2));
      for (int c = 0; c < 3; ++c) {
        const double t = std::exp(-sigma_a[c] * 2 * cos_gt / cos_tt);
        const double expected =
            f + (1 - f) * (1 - f) * t * (1 + f * t + f * f * t * t / (1 - f * t));
        EXPECT_NEAR(e[c], expected, 1e-4) << theta_o << " " << h << " channel " << c;
        EXPECT_LT(e[c], 1.0);
      }
    }
  }
}

TEST(HairBsdf, FurnaceMarschnerStaysBelowOne) {
  // Marschner 2003 is not energy conserving: no residual lobe (the missing ~(1-f) f^2 of light
  // scattered more than twice inside), Gaussians in theta_h truncated at the poles, the
  // cos(theta_i)/cos^2(theta_d) factor, and the caustic clamp. The integral must not exceed 1 by
  // more than the quadrature error (1e-2: 1024 azimuths resolve the root-based N_p, whose 1/sqrt
  // edges at the caustics converge slowly). Measured (printed): 0.78 (-60 deg), 0.90 (0),
  // 0.90 (30), 0.80 (75); the lower bound 0.7 checks that the lobes carry most of the light.
  const HairBsdf bsdf(Optics(0.3, 0.3, Rgb::Zero(), HairScatteringModel::kMarschner2003));
  for (double theta_o : {-60.0, 0.0, 30.0, 75.0}) {
    const Vec3 wo = Wo(theta_o * kDeg);
    const Rgb e = SphereIntegral(
        [&](const Vec3& wi) {
          return bsdf.Eval(wo, wi, {0.0, 0.0});
        },
        96, 1024);
    std::printf("[ furnace ] Marschner sigma_a = 0, theta_o = %5.1f deg: integral = %.4f\n",
                theta_o, e.x());
    EXPECT_LE(e.x(), 1.01) << theta_o;
    EXPECT_GT(e.x(), 0.7) << theta_o;
  }
}

TEST(HairBsdf, NeverNegativeOrNan) {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < 20000; ++k) {
    HairOptics o;
    o.model = k % 2 ? HairScatteringModel::kMarschner2003 : HairScatteringModel::kChiang2016;
    o.longitudinal_roughness = 0.02 + 0.98 * u(rng);
    o.azimuthal_roughness = 0.02 + 0.98 * u(rng);
    o.eccentricity = k % 3 ? 0.95 * u(rng) : 0.0;
    o.cuticle_tilt = 0.4 * u(rng) - 0.2;
    o.eta = 1.05 + 1.5 * u(rng);
    o.sigma_a = Rgb(u(rng), 3 * u(rng), 10 * u(rng));
    ASSERT_EQ(CheckHairOptics(o), "");
    const HairBsdf bsdf(o);
    const double theta_o = (k % 97 == 0) ? 0.5 * kPi : std::asin(2 * u(rng) - 1);
    const Vec3 wo = Wo(theta_o);
    const Vec3 wi = Dir(std::asin(2 * u(rng) - 1), 2 * kPi * u(rng));
    const FibreHit hit{k % 89 == 0 ? 1.0 : 2 * u(rng) - 1, 2 * kPi * u(rng)};
    const Rgb f = bsdf.Eval(wo, wi, hit);
    const double pdf = bsdf.Pdf(wo, wi, hit);
    ASSERT_TRUE(f.allFinite() && (f.array() >= 0).all()) << k << " " << f.transpose();
    ASSERT_TRUE(std::isfinite(pdf) && pdf >= 0) << k;
    const ScatterSample s = bsdf.Sample(wo, hit, {u(rng), u(rng), u(rng), u(rng)});
    ASSERT_TRUE(s.weight.allFinite() && (s.weight.array() >= 0).all()) << k;
    const Rgb t = bsdf.Transmittance(wo, hit);
    ASSERT_TRUE((t.array() >= 0).all() && (t.array() <= 1).all()) << k;
  }
}

// ---------------------------------------------------------------------------------------------
// Reciprocity and the cuticle tilt.

TEST(HairBsdf, MarschnerIsReciprocal) {
  // Marschner's S = f / cos(theta_i) is reciprocal: theta_h and cos^2 theta_d are symmetric,
  // N_p(-phi) = N_p(phi) (g is odd, A even in h), and eta*(phi_h) depends on phi_i + phi_o.
  // (Chiang's f is defined per offset h of the outgoing ray and is not reciprocal per h.) To keep
  // wo at phi = pi/2, the swapped pair is rotated about the fibre axis, with the major axis.
  HairOptics o = Optics(0.3, 0.3, Rgb(0.2, 0.5, 1.0), HairScatteringModel::kMarschner2003);
  o.eccentricity = 0.4;
  o.cuticle_tilt = 0.05;
  const HairBsdf bsdf(o);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int nonzero = 0;
  for (int k = 0; k < 2000; ++k) {
    const double to = std::asin(1.8 * u(rng) - 0.9), ti = std::asin(1.8 * u(rng) - 0.9);
    const double phi_i = 2 * kPi * u(rng), psi = kPi * u(rng);
    const Rgb f = bsdf.Eval(Dir(to, 0.5 * kPi), Dir(ti, phi_i), {0.0, psi});
    // Rotate by r = pi/2 - phi_i about x: wi goes to pi/2, wo to pi - phi_i, psi to psi + r.
    const double r = 0.5 * kPi - phi_i;
    const Rgb g = bsdf.Eval(Dir(ti, 0.5 * kPi), Dir(to, 0.5 * kPi + r), {0.0, psi + r});
    const Rgb s_f = f / std::cos(ti), s_g = g / std::cos(to);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(s_f[c], s_g[c], 1e-9 * std::max(1.0, s_f[c])) << k;
    nonzero += s_f.x() > 1e-3;
  }
  EXPECT_GT(nonzero, 200);  // anti-vacuity
}

TEST(HairBsdf, CuticleTiltShiftsTheReflectionTowardTheRoot) {
  // Marschner 2003, Table 1: alpha_R = -alpha < 0 (scales tilted toward the tip make R peak at
  // theta_h = -alpha, i.e. theta_i = -theta_o - 2 alpha). Only R survives sigma_a = 1e3
  // (T = e^{-2000}); at theta_o = 0, h = 0 its azimuth is phi_i = phi_o.
  for (double alpha : {0.035, -0.05}) {
    HairOptics o = Optics(0.1, 0.3, Rgb::Constant(1e3));
    o.cuticle_tilt = alpha;
    for (auto model : {HairScatteringModel::kChiang2016, HairScatteringModel::kMarschner2003}) {
      o.model = model;
      const HairBsdf bsdf(o);
      double best = -1.0, best_theta = 0.0;
      for (double t = -0.3; t <= 0.3; t += 1e-4) {
        const double f = bsdf.Eval(Wo(0.0), Dir(t, 0.5 * kPi), {0.0, 0.0}).x();
        if (f > best) best = f, best_theta = t;
      }
      // The d'Eon lobe's mode at theta_o' = 2 alpha lies within v tan(2 alpha) ~ 1e-3 of -2 alpha.
      EXPECT_NEAR(best_theta, -2.0 * alpha, 2e-3) << alpha;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Sampling.

TEST(HairBsdf, SampleWeightAndPdfAgreeWithEvalAndPdf) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (auto model : {HairScatteringModel::kChiang2016, HairScatteringModel::kMarschner2003}) {
    for (double e : {0.0, 0.5}) {
      HairOptics o = Optics(0.3, 0.4, Rgb(0.3, 0.6, 1.2), model);
      o.eccentricity = e;
      const HairBsdf bsdf(o);
      for (double theta_o : {-0.7, 0.2, 1.2}) {
        for (double h : {-0.5, 0.3}) {
          const FibreHit hit{h, 0.4};
          for (int k = 0; k < 500; ++k) {
            const ScatterSample s = bsdf.Sample(Wo(theta_o), hit, {u(rng), u(rng), u(rng), u(rng)});
            ASSERT_GT(s.pdf, 0.0);
            EXPECT_NEAR(s.wi.norm(), 1.0, 1e-12);
            const double pdf = bsdf.Pdf(Wo(theta_o), s.wi, hit);
            EXPECT_NEAR(s.pdf, pdf, 1e-10 * pdf);
            const Rgb f = bsdf.Eval(Wo(theta_o), s.wi, hit);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(s.weight[c], f[c] / pdf, 1e-10 * f[c] / pdf);
          }
        }
      }
    }
  }
}

TEST(HairBsdf, PdfIntegratesToOne) {
  HairOptics o = Optics(0.3, 0.3, Rgb(0.5, 0.5, 0.5));
  o.eccentricity = 0.5;
  const HairBsdf bsdf(o);
  for (double theta_o : {-1.3, 0.0, 0.8}) {
    for (double h : {-0.7, 0.2}) {
      const double total = SphereIntegral(
          [&](const Vec3& wi) {
            return bsdf.Pdf(Wo(theta_o), wi, {h, 1.0});
          },
          160, 256);
      EXPECT_NEAR(total, 1.0, 1e-4) << theta_o << " " << h;
    }
  }
}

TEST(HairBsdf, SampledDirectionsFollowPdf) {
  // Histogram of 200k samples in 24 x 48 equal-area cells (sin theta_i, phi_i) against the Pdf
  // integrated over each cell (6 x 6 midpoint points). Pearson chi^2 over cells expecting >= 10
  // counts: for a correct sampler chi^2/dof ~ 1 +- sqrt(2/dof) (~0.045 for dof ~1000); we accept
  // < 1.25 (5 sigma) -- a sampler off by a few percent in any lobe gives chi^2/dof >> 2.
  HairOptics o = Optics(0.4, 0.5, Rgb(0.2, 0.4, 0.8));
  o.eccentricity = 0.5;
  o.cuticle_tilt = 0.06;
  const HairBsdf bsdf(o);
  const Vec3 wo = Wo(0.5);
  const FibreHit hit{0.35, 0.3};
  const int nt = 24, np = 48, n = 200000;
  std::vector<double> count(nt * np, 0.0);
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < n; ++k) {
    const ScatterSample s = bsdf.Sample(wo, hit, {u(rng), u(rng), u(rng), u(rng)});
    const int i = std::min(nt - 1, static_cast<int>((s.wi.x() + 1.0) / 2.0 * nt));
    const double phi = std::atan2(s.wi.z(), s.wi.y());
    const int j = std::min(np - 1, static_cast<int>((phi + kPi) / (2 * kPi) * np));
    count[i * np + j] += 1.0;
  }
  double chi2 = 0.0, expected_total = 0.0;
  int dof = 0;
  const int sub = 6;
  for (int i = 0; i < nt; ++i) {
    for (int j = 0; j < np; ++j) {
      double mass = 0.0;
      for (int a = 0; a < sub; ++a) {
        for (int b = 0; b < sub; ++b) {
          const double z = -1.0 + (i + (a + 0.5) / sub) * 2.0 / nt;
          const double phi = -kPi + (j + (b + 0.5) / sub) * 2 * kPi / np;
          mass += bsdf.Pdf(wo, Dir(std::asin(z), phi), hit);
        }
      }
      mass *= (2.0 / nt) * (2 * kPi / np) / (sub * sub);
      expected_total += mass;
      const double expected = mass * n;
      if (expected < 10) continue;
      chi2 += std::pow(count[i * np + j] - expected, 2) / expected;
      ++dof;
    }
  }
  std::printf("[ sampling ] chi^2/dof = %.3f over %d cells, pdf mass in the grid = %.5f\n",
              chi2 / dof, dof, expected_total);
  EXPECT_NEAR(expected_total, 1.0, 2e-3);
  EXPECT_GT(dof, 300);
  EXPECT_LT(chi2 / dof, 1.25);
}

// ---------------------------------------------------------------------------------------------
// Independent reference: brute-force ray tracing of a dielectric cylinder.

struct Traced {
  Vec3 exit = Vec3::Zero();  ///< direction of the ray leaving the fibre
  Rgb weight = Rgb::Zero();  ///< Fresnel factors and absorption along the path
};

/// Traces the camera ray along -wo hitting the unit-radius cylinder y^2 + z^2 = 1 (axis x) at
/// offset h, with Snell's law in vector form and Hecht's Fresnel at each interface, through p
/// internal segments (p = 0: reflection at entry). Absorption exp(-sigma_a L), L the geometric
/// length inside in radii. By reversibility the light arrives from wi = exit.
Traced TraceCylinder(const Vec3& wo, double h, double eta, const Rgb& sigma_a, int p) {
  Vec3 d = -wo;
  // Start far out along wo from the point at offset h (y = h) and intersect the cylinder.
  Vec3 o = Vec3(0.0, h, 0.0) + 10.0 * wo;
  auto hit_cylinder = [](const Vec3& org, const Vec3& dir, bool inside) {
    const double a = dir.y() * dir.y() + dir.z() * dir.z();
    const double b = 2 * (org.y() * dir.y() + org.z() * dir.z());
    const double c = org.y() * org.y() + org.z() * org.z() - 1.0;
    const double disc = std::sqrt(std::max(0.0, b * b - 4 * a * c));
    return inside ? (-b + disc) / (2 * a) : (-b - disc) / (2 * a);
  };
  auto normal = [](const Vec3& x) { return Vec3(0.0, x.y(), x.z()).normalized(); };
  auto refract = [](const Vec3& dir, const Vec3& n, double ratio) {  // n faces the incoming ray
    const double ci = -dir.dot(n);
    const double k = 1 - ratio * ratio * (1 - ci * ci);
    return Vec3(ratio * dir + (ratio * ci - std::sqrt(k)) * n);
  };
  Traced out;
  double t = hit_cylinder(o, d, false);
  Vec3 x = o + t * d;
  Vec3 n = normal(x);
  const double r_in = HechtFresnel(d.dot(n), 1.0, eta);
  if (p == 0) {
    out.exit = d - 2 * d.dot(n) * n;
    out.weight = Rgb::Constant(r_in);
    return out;
  }
  double w = 1.0 - r_in;
  double length = 0.0;
  d = refract(d, n, 1.0 / eta).normalized();
  for (int segment = 0; segment < p; ++segment) {
    t = hit_cylinder(x, d, true);
    length += t;
    x = x + t * d;
    n = normal(x);
    const double r = HechtFresnel(d.dot(n), eta, 1.0);
    if (segment + 1 < p) {
      w *= r;
      d = d - 2 * d.dot(n) * n;
    } else {
      w *= 1.0 - r;
      d = refract(d, -n, eta).normalized();
    }
  }
  out.exit = d;
  out.weight = w * (-sigma_a * length).array().exp().matrix();
  return out;
}

TEST(HairBsdf, RayTracedCylinderMatchesLobeCentresAndAttenuations) {
  // Per ray, the exit azimuth of path p is phi_o + Phi(p, h) (Chiang eq. 9 with Bravais' eta')
  // and its weight is A_p (Chiang eqs. 3-5); the exit stays on the specular cone theta_i =
  // -theta_o. The tracer knows nothing of gamma_t, eta' or the 1 - f products.
  const Rgb sigma_a(0.3, 0.7, 1.6);
  HairOptics o = Optics(0.3, 0.3, sigma_a);
  const HairBsdf bsdf(o);
  for (double theta_o : {0.0, 0.4, -1.0}) {
    for (int k = 0; k < 99; ++k) {
      const double h = -0.98 + 1.96 * k / 98.0;
      const Vec3 wo = Wo(theta_o);
      const hair::ChiangLobes lobes = hair::ComputeChiangLobes(o, wo, {h, 0.0});
      for (int p = 0; p < 3; ++p) {
        const Traced tr = TraceCylinder(wo, h, o.eta, sigma_a, p);
        EXPECT_NEAR(tr.exit.x(), -wo.x(), 1e-12);
        const double dphi = std::atan2(tr.exit.z(), tr.exit.y()) - 0.5 * kPi;
        EXPECT_NEAR(std::remainder(dphi - lobes.phi[p], 2 * kPi), 0.0, 1e-9)
            << "p " << p << " h " << h << " theta_o " << theta_o;
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(tr.weight[c], lobes.a[p][c], 1e-12);
        if (p == 1) {
          const Rgb transmittance = bsdf.Transmittance(wo, {h, 0.0});
          for (int c = 0; c < 3; ++c) EXPECT_NEAR(transmittance[c], tr.weight[c], 1e-12);
        }
      }
    }
  }
}

TEST(HairBsdf, RayTracedExitHistogramMatchesAzimuthalLobes) {
  // The h-averaged azimuthal distribution of each path p: a histogram (72 bins) of the exit
  // azimuths of 20000 stratified rays, weighted by their traced Fresnel/absorption factors,
  // against the model's bin masses (1/n) sum_k A_p(h_k) int_bin N_p(phi - Phi(p, h_k)) at
  // beta_n = 0.02 (s = 0.0036 rad). The logistic blur moves at most 2 s ln2 / bin ~ 6% of a
  // ray's mass into a neighbour bin, mostly exchanged back with the other neighbour (measured L1
  // 0.05-0.25% of the lobe's mass, printed); we allow 1%. A wrong lobe centre (sign of gamma,
  // missing p pi) would put the mass in other bins (L1 ~ 2x the mass).
  const Rgb sigma_a(0.2, 0.2, 0.2);
  const HairOptics o = Optics(0.3, 0.02, sigma_a);
  const int bins = 72, n = 20000;
  const double width = 2 * kPi / bins;
  const Vec3 wo = Wo(0.4);
  for (int p = 0; p < 3; ++p) {
    std::vector<double> traced(bins, 0.0), model(bins, 0.0);
    double mass = 0.0;
    for (int k = 0; k < n; ++k) {
      const double h = -1.0 + (k + 0.5) * 2.0 / n;
      const Traced tr = TraceCylinder(wo, h, o.eta, sigma_a, p);
      const double dphi = std::remainder(std::atan2(tr.exit.z(), tr.exit.y()) - 0.5 * kPi, 2 * kPi);
      const int b = std::min(bins - 1, static_cast<int>((dphi + kPi) / width));
      traced[b] += tr.weight.x() / n;
      mass += tr.weight.x() / n;
      const hair::ChiangLobes lobes = hair::ComputeChiangLobes(o, wo, {h, 0.0});
      const double s = lobes.s;
      const double norm = hair::LogisticCdf(kPi, s) - hair::LogisticCdf(-kPi, s);
      for (int j = 0; j < bins; ++j) {
        const double lo = std::remainder(-kPi + j * width - lobes.phi[p], 2 * kPi);
        const double hi = lo + width;
        double m = 0.0;
        if (hi <= kPi) {
          m = hair::LogisticCdf(hi, s) - hair::LogisticCdf(lo, s);
        } else {
          m = hair::LogisticCdf(kPi, s) - hair::LogisticCdf(lo, s) +
              hair::LogisticCdf(hi - 2 * kPi, s) - hair::LogisticCdf(-kPi, s);
        }
        model[j] += lobes.a[p].x() * m / norm / n;
      }
    }
    double l1 = 0.0;
    for (int j = 0; j < bins; ++j) l1 += std::abs(traced[j] - model[j]);
    std::printf("[ raytrace ] p = %d: lobe mass %.4f, L1(histogram - N_p) = %.2e\n", p, mass, l1);
    EXPECT_GT(mass, 0.02);
    EXPECT_LT(l1, 0.01 * mass) << "p " << p;
  }
}

TEST(HairBsdf, MarschnerAzimuthalTermsMatchRayTracedCircle) {
  // theta_d = 0 (Bravais indices = eta, so Marschner's Fresnel is the exact one): the root-based
  // N_p against the traced circle. (1) Its integral over phi equals the h-average of the traced
  // weights (change of variables h -> phi; exact for p = 0, 1; p = 2 loses the caustic clamp's
  // ~1%). (2) Bin masses (36 bins) vs the traced histogram: they differ only by the cubic
  // approximation of the exit angle: exact for p = 0 (measured L1 0.07% of the mass, allowed
  // 0.5%); for p = 1 a few degrees off (measured 4.1%, allowed 6%); for p = 2 the cubic puts the
  // caustic at g(gamma_c) = 0.359 rad instead of the exact 0.324 rad (both computed from the
  // formulas at eta = 1.55), moving the concentrated caustic mass across a bin edge (measured
  // 25%, allowed 30%). The lobe positions themselves are pinned by the cubic's exact end points.
  const Rgb sigma_a = Rgb::Constant(0.3);
  const double eta = 1.55;
  const int n_rays = 20000, bins = 36, sub = 200;
  const double width = 2 * kPi / bins;
  for (int p = 0; p < 3; ++p) {
    std::vector<double> traced(bins, 0.0), model(bins, 0.0);
    double mean_a = 0.0;
    for (int k = 0; k < n_rays; ++k) {
      const double h = -1.0 + (k + 0.5) * 2.0 / n_rays;
      const Traced tr = TraceCylinder(Wo(0.0), h, eta, sigma_a, p);
      const double dphi = std::remainder(std::atan2(tr.exit.z(), tr.exit.y()) - 0.5 * kPi, 2 * kPi);
      traced[std::min(bins - 1, static_cast<int>((dphi + kPi) / width))] += tr.weight.x() / n_rays;
      mean_a += tr.weight.x() / n_rays;
    }
    double integral = 0.0;
    for (int j = 0; j < bins; ++j) {
      for (int q = 0; q < sub; ++q) {
        const double phi = -kPi + (j + (q + 0.5) / sub) * width;
        model[j] += hair::MarschnerAzimuthal(p, phi, eta, 0.0, 1.0, sigma_a).x() * width / sub;
      }
      integral += model[j];
    }
    double l1 = 0.0;
    for (int j = 0; j < bins; ++j) l1 += std::abs(traced[j] - model[j]);
    std::printf("[ marschner ] p = %d: integral of N_p %.5f, traced mean A %.5f, L1 %.2e\n", p,
                integral, mean_a, l1);
    EXPECT_NEAR(integral, mean_a, (p == 2 ? 0.03 : 2e-3) * mean_a) << p;
    constexpr std::array<double, 3> kAllowed = {0.005, 0.06, 0.3};
    EXPECT_LT(l1, kAllowed[p] * mean_a) << p;
  }
}

// ---------------------------------------------------------------------------------------------
// Elliptic cross-section.

TEST(HairBsdf, ZeroEccentricityIsTheCircularModelBitForBit) {
  for (auto model : {HairScatteringModel::kChiang2016, HairScatteringModel::kMarschner2003}) {
    HairOptics o = Optics(0.3, 0.3, Rgb(0.2, 0.4, 0.9), model);
    o.eccentricity = 0.0;
    const HairBsdf bsdf(o);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int k = 0; k < 200; ++k) {
      const Vec3 wo = Wo(std::asin(2 * u(rng) - 1));
      const Vec3 wi = Dir(std::asin(2 * u(rng) - 1), 2 * kPi * u(rng));
      const double h = 2 * u(rng) - 1;
      const std::array<double, 4> us = {u(rng), u(rng), u(rng), u(rng)};
      const FibreHit a{h, 0.0}, b{h, 2 * kPi * u(rng)};
      EXPECT_EQ(bsdf.Eval(wo, wi, a), bsdf.Eval(wo, wi, b));
      EXPECT_EQ(bsdf.Pdf(wo, wi, a), bsdf.Pdf(wo, wi, b));
      EXPECT_EQ(bsdf.Sample(wo, a, us).wi, bsdf.Sample(wo, b, us).wi);
    }
  }
  // eta* = eta exactly at e = 0, and continuously nearby (Marschner's a = 1).
  EXPECT_EQ(hair::EllipticEta(1.55, 0.0, 0.3), 1.55);
  EXPECT_NEAR(hair::EllipticEta(1.55, 1e-6, 0.3), 1.55, 1e-11);
  // Anti-vacuity: e = 0.5 moves the TRT lobe centre, not R or TT.
  HairOptics o = Optics(0.3, 0.3);
  const hair::ChiangLobes circ = hair::ComputeChiangLobes(o, Wo(0.2), {0.4, 0.3});
  o.eccentricity = 0.5;
  const hair::ChiangLobes ell = hair::ComputeChiangLobes(o, Wo(0.2), {0.4, 0.3});
  EXPECT_EQ(circ.phi[0], ell.phi[0]);
  EXPECT_EQ(circ.phi[1], ell.phi[1]);
  EXPECT_GT(std::abs(circ.phi[2] - ell.phi[2]), 1e-3);
}

TEST(HairBsdf, EllipticEtaFollowsMarschnersFormula) {
  // a = major/minor = 1/sqrt(1 - e^2); e = 0.6 gives a^2 = 1.5625. With eta = 1.55:
  // eta1* = 2 * 0.55 * 1.5625 - 1.55 + 2 = 2.16875 (phi_h = 0: along the major axis),
  // eta2* = 2 * 0.55 / 1.5625 - 1.55 + 2 = 1.154 (phi_h = 90 deg), mean 1.661375 at 45 deg.
  EXPECT_NEAR(hair::MarschnerAxisRatio(0.6), 1.25, 1e-15);
  EXPECT_NEAR(hair::EllipticEta(1.55, 0.6, 1.0), 2.16875, 1e-12);
  EXPECT_NEAR(hair::EllipticEta(1.55, 0.6, -1.0), 1.154, 1e-12);
  EXPECT_NEAR(hair::EllipticEta(1.55, 0.6, 0.0), 1.661375, 1e-12);
  // The floor 1 + (eta - 1)/4 = 1.1375 guards the linearization beyond a^2 = 1.6 (e > 0.61).
  EXPECT_NEAR(hair::EllipticEta(1.55, 0.9, -1.0), 1.1375, 1e-12);
}

/// Largest TRT exit deviation from backscatter (rad) over rays from the viewer (travelling -z)
/// through the 2D ellipse (y/ay)^2 + (z/az)^2 <= 1 of index eta: the TRT caustic (Snell's law
/// only, no Fresnel: positions, not intensities).
double TracedEllipseTrtCaustic(double ay, double az, double eta) {
  double best = 0.0;
  const int n = 20000;
  for (int k = 0; k < n; ++k) {
    const double y0 = ay * (k + 0.5) / n;  // offsets across the visible half
    Eigen::Vector2d o(y0, 2.0 * az), d(0.0, -1.0);
    auto intersect = [&](const Eigen::Vector2d& org, const Eigen::Vector2d& dir, bool inside) {
      const double a = std::pow(dir.x() / ay, 2) + std::pow(dir.y() / az, 2);
      const double b = 2 * (org.x() * dir.x() / (ay * ay) + org.y() * dir.y() / (az * az));
      const double c = std::pow(org.x() / ay, 2) + std::pow(org.y() / az, 2) - 1.0;
      const double disc = std::sqrt(std::max(0.0, b * b - 4 * a * c));
      return inside ? (-b + disc) / (2 * a) : (-b - disc) / (2 * a);
    };
    auto normal = [&](const Eigen::Vector2d& x) {
      return Eigen::Vector2d(x.x() / (ay * ay), x.y() / (az * az)).normalized();
    };
    auto refract = [](const Eigen::Vector2d& dir, const Eigen::Vector2d& nn, double ratio,
                      bool* ok) {
      const double ci = -dir.dot(nn);
      const double q = 1 - ratio * ratio * (1 - ci * ci);
      *ok = q >= 0;
      return Eigen::Vector2d(ratio * dir + (ratio * ci - std::sqrt(std::max(0.0, q))) * nn);
    };
    bool ok = true;
    Eigen::Vector2d x = o + intersect(o, d, false) * d;
    d = refract(d, normal(x), 1.0 / eta, &ok).normalized();
    x = x + intersect(x, d, true) * d;
    const Eigen::Vector2d nb = normal(x);
    d = (d - 2 * d.dot(nb) * nb).normalized();
    x = x + intersect(x, d, true) * d;
    d = refract(d, -normal(x), eta, &ok).normalized();
    if (!ok) continue;
    // Deviation from the backscatter direction +z (phi = pi/2).
    best = std::max(best, std::abs(std::remainder(std::atan2(d.y(), d.x()) - 0.5 * kPi, 2 * kPi)));
  }
  return best;
}

/// The TRT caustic of a circle of index n (Phi(2, h) - 2 pi = 4 gamma_t - 2 gamma_o, extremal at
/// h^2 = (4 - n^2)/3).
double CircleTrtCaustic(double n) {
  const double h = std::sqrt((4 - n * n) / 3);
  return std::abs(4 * std::asin(h / n) - 2 * std::asin(h));
}

TEST(HairBsdf, EllipticEtaMovesTheTrtCausticLikeARayTracedEllipse) {
  // Independent reference for the eccentricity adjustment: trace rays through an ellipse with
  // light and view along the major axis (phi_h ~ 0 from the major axis, eta* ~ eta1* > eta) and
  // along the minor axis (eta* ~ eta2* < eta); the circle with eta* must place the TRT caustic
  // closer to the ellipse's than the circle with eta does, and on the same side. This pins down
  // a = major/minor for phi_h measured from the major axis (the reciprocal would move it the
  // wrong way). At the caustic the half angle is ~Phi/2 = 0.16 rad, so cos(2 phi_h) ~ 0.95.
  // Measured (printed): e = 0.2 major 0.291 traced / 0.268 eta* / 0.325 eta; minor 0.375 /
  // 0.386 / 0.325; e = 0.3 minor 0.439 / 0.472 / 0.325. At e = 0.3 along the major axis the
  // linearized eta* overshoots (0.290 traced, 0.201 eta*, 0.325 eta): there only the direction
  // of the shift is asserted -- a limit of Marschner's first-order formula, not of the code.
  const double eta = 1.55;
  const double circle = CircleTrtCaustic(eta);
  for (double e : {0.2, 0.3}) {
    const double ratio = 1.0 / std::sqrt(1 - e * e);  // major / minor
    for (bool along_major : {true, false}) {
      // Viewer along +z: major axis along z when along_major (psi = pi/2), else along y.
      const double traced = along_major ? TracedEllipseTrtCaustic(1.0, ratio, eta)
                                        : TracedEllipseTrtCaustic(ratio, 1.0, eta);
      const double psi = along_major ? 0.5 * kPi : 0.0;
      const double phi_h = 0.5 * kPi + 0.5 * circle;  // half angle of wo and the TRT exit
      const double eta_star = hair::EllipticEta(eta, e, std::cos(2 * (phi_h - psi)));
      const double model = CircleTrtCaustic(eta_star);
      std::printf(
          "[ ellipse ] e = %.1f, view along %s axis: caustic traced %.4f, circle(eta) "
          "%.4f, circle(eta* = %.4f) %.4f rad\n",
          e, along_major ? "major" : "minor", traced, circle, eta_star, model);
      if (e < 0.25 || !along_major) {
        EXPECT_LT(std::abs(model - traced), std::abs(circle - traced));
      }
      EXPECT_EQ(model > circle, traced > circle);
      EXPECT_GT(std::abs(traced - circle), 0.02);  // anti-vacuity: the ellipse does differ
    }
  }
}


// ---------------------------------------------------------------------------------------------
// Wet fibres: a water film between air and keratin.

/// Fresnel reflectances (R_s, R_p) from n1 into n2 at incidence angle i (Hecht, Optics, eqs.
/// 4.42-4.43: sin^2(i - t) / sin^2(i + t) and tan^2(i - t) / tan^2(i + t)).
std::pair<double, double> HechtRsRp(double i, double n1, double n2) {
  const double t = std::asin(n1 / n2 * std::sin(i));
  if (i < 1e-9) {
    const double r = std::pow((n1 - n2) / (n1 + n2), 2);
    return {r, r};
  }
  return {std::pow(std::sin(i - t) / std::sin(i + t), 2),
          std::pow(std::tan(i - t) / std::tan(i + t), 2)};
}

/// The film stack's reflectance written here from the two interfaces: per polarization the
/// geometric series of incoherent reflections inside the film, R1 + T1^2 R2 sum (R1 R2)^k =
/// R1 + (1 - R1)^2 R2 / (1 - R1 R2), then the polarizations averaged.
double FilmReflectance(double incidence, double n_water, double n_fibre) {
  const auto [rs1, rp1] = HechtRsRp(incidence, 1.0, n_water);
  const double in_water = std::asin(std::sin(incidence) / n_water);
  const auto [rs2, rp2] = HechtRsRp(in_water, n_water, n_fibre);
  const double rs = rs1 + (1 - rs1) * (1 - rs1) * rs2 / (1 - rs1 * rs2);
  const double rp = rp1 + (1 - rp1) * (1 - rp1) * rp2 / (1 - rp1 * rp2);
  return 0.5 * (rs + rp);
}

TEST(HairBsdf, WetFibreRLobeDropsByTheFilmFresnelRatio) {
  // With strong absorption (sigma_a = 1e4 per radius) only the R lobe is left: f = M_R A_R N_R,
  // and M_R N_R do not depend on water, so f_wet / f_dry = R_film / F_dry exactly. At normal
  // incidence (theta_o = 0, h = 0): F_dry = ((1.55 - 1)/2.55)^2 = 0.046521, R1 = (0.333/2.333)^2
  // = 0.020373, R2 = (0.217/2.883)^2 = 0.005665, R_film = 0.025811: ratio 0.5548. At oblique
  // incidence the per-polarization sums are compared with FilmReflectance above.
  HairOptics dry_optics = Optics(0.3, 0.3, Rgb::Constant(1e4));
  const HairBsdf bsdf(dry_optics);
  EXPECT_NEAR(FilmReflectance(0.0, 1.333, 1.55) / HechtFresnel(1.0, 1.0, 1.55), 0.5548, 1e-4);
  for (double theta_o : {0.0, 30.0, -55.0}) {
    for (double h : {0.0, 0.5, -0.8}) {
      const Vec3 wo = Wo(theta_o * kDeg);
      // wi near the R lobe's peak: mirrored theta, azimuth phi_o + Phi(0, h) = pi/2 - 2 gamma_o.
      const Vec3 wi = Dir(-theta_o * kDeg + 0.07, 0.5 * kPi - 2.0 * std::asin(h));
      FibreHit dry{h, 0.0};
      FibreHit wet{h, 0.0};
      wet.wetness = 1.0;
      const Rgb f_dry = bsdf.Eval(wo, wi, dry);
      const Rgb f_wet = bsdf.Eval(wo, wi, wet);
      ASSERT_GT(f_dry.x(), 1e-3) << theta_o << " " << h;
      const double cos_i = std::cos(theta_o * kDeg) * std::sqrt(1.0 - h * h);
      const double incidence = std::acos(cos_i);
      const double expected =
          FilmReflectance(incidence, 1.333, 1.55) / HechtFresnel(cos_i, 1.0, 1.55);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(f_wet[c] / f_dry[c], expected, 1e-9) << theta_o << " " << h;
      }
      EXPECT_LT(expected, 0.8);  // 0.555 at normal incidence, 0.77 at 70 degrees
      // Half wet: the area-weighted mix of the two.
      FibreHit half{h, 0.0};
      half.wetness = 0.5;
      EXPECT_NEAR(bsdf.Eval(wo, wi, half).x(), 0.5 * (f_dry.x() + f_wet.x()), 1e-12 * f_dry.x());
    }
  }
}

TEST(HairBsdf, WetFibreConservesEnergyAndAbsorbsMore) {
  // White furnace with the film (sigma_a = 0): the integral of f is 1 (the stack is lossless,
  // the lobes' series closes as for a dry fibre). With absorption the integral is the closed
  // form of FurnaceChiangWithAbsorptionIsTheSumOfAttenuations with f = R_film: more light
  // enters the cortex (R_film < F_dry), so more is absorbed than by the dry fibre.
  const Rgb sigma_a(0.2, 0.6, 1.5);
  const double eta = 1.55;
  for (double wetness : {1.0, 0.4}) {
    const HairBsdf white(Optics(0.4, 0.4));
    const HairBsdf brown(Optics(0.4, 0.4, sigma_a));
    for (double theta_o : {-60.0, 10.0, 70.0}) {
      for (double h : {-0.5, 0.3, 0.95}) {
        const double t_o = theta_o * kDeg;
        const Vec3 wo = Wo(t_o);
        FibreHit hit{h, 0.0};
        hit.wetness = wetness;
        const Rgb e_white = SphereIntegral([&](const Vec3& wi) { return white.Eval(wo, wi, hit); },
                                           160, 256);
        const Rgb e = SphereIntegral([&](const Vec3& wi) { return brown.Eval(wo, wi, hit); },
                                     160, 256);
        const Rgb e_dry = SphereIntegral(
            [&](const Vec3& wi) { return brown.Eval(wo, wi, FibreHit{h, 0.0}); }, 160, 256);
        const double cos_i = std::cos(t_o) * std::sqrt(1 - h * h);
        const double f_dry = HechtFresnel(cos_i, 1.0, eta);
        const double f_wet = FilmReflectance(std::acos(cos_i), 1.333, eta);
        const double eta_perp = std::sqrt(eta * eta - std::pow(std::sin(t_o), 2)) / std::cos(t_o);
        const double cos_gt = std::sqrt(1 - h * h / (eta_perp * eta_perp));
        const double cos_tt = std::sqrt(1 - std::pow(std::sin(t_o) / eta, 2));
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(e_white[c], 1.0, 1e-4) << wetness << " " << theta_o << " " << h;
          const double t = std::exp(-sigma_a[c] * 2 * cos_gt / cos_tt);
          auto total = [t](double f) {
            return f + (1 - f) * (1 - f) * t * (1 + f * t + f * f * t * t / (1 - f * t));
          };
          const double expected = (1 - wetness) * total(f_dry) + wetness * total(f_wet);
          EXPECT_NEAR(e[c], expected, 1e-4) << wetness << " " << theta_o << " " << h;
          EXPECT_LT(e[c], e_dry[c]) << wetness << " " << theta_o << " " << h;
        }
      }
    }
  }
}

TEST(HairBsdf, WaterEtaIsChecked) {
  HairOptics optics;
  optics.water_eta = 1.0;
  EXPECT_NE(CheckHairOptics(optics).find("water_eta"), std::string::npos);
}

}  // namespace
}  // namespace ringlet
