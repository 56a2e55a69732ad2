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
