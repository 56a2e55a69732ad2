// Elliptic section: area kept, moments of inertia, torsion constant, the two shape measures.
#include "ringlet/cross_section.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "ringlet/material.h"

namespace ringlet {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(CrossSection, CircleHasPolarMomentAsTorsionConstant) {
  const double r = 40e-6;
  const CrossSection c = SectionFromEccentricity(r, 0.0);
  EXPECT_DOUBLE_EQ(c.a, r);
  EXPECT_DOUBLE_EQ(c.b, r);
  // Circle: I = pi r^4 / 4 and J = polar moment pi r^4 / 2 (textbook values).
  EXPECT_NEAR(c.I1(), kPi * std::pow(r, 4) / 4, 1e-15 * std::pow(r, 4));
  EXPECT_NEAR(c.I2(), c.I1(), 1e-30);
  EXPECT_NEAR(c.J(), kPi * std::pow(r, 4) / 2, 1e-15 * std::pow(r, 4));
}

TEST(CrossSection, EccentricityKeepsAreaAndOrdersMoments) {
  const double r = 50e-6;
  for (double e : {0.1, 0.5, 0.9, 0.99}) {
    const CrossSection c = SectionFromEccentricity(r, e);
    EXPECT_NEAR(c.Area(), kPi * r * r, 1e-14 * r * r) << e;
    EXPECT_NEAR(c.Eccentricity(), e, 1e-12);
    EXPECT_NEAR(c.b / c.a, std::sqrt(1 - e * e), 1e-14);
    // Soft about n1 (the major axis): I1 = pi a b^3/4 < I2 = pi a^3 b/4, ratio (b/a)^2 = 1 - e^2.
    EXPECT_LT(c.I1(), c.I2());
    EXPECT_NEAR(c.I1() / c.I2(), 1 - e * e, 1e-12);
    // Saint-Venant: J = 4 I1 I2 / (I1 + I2) for the ellipse (pi a^3 b^3 / (a^2 + b^2)).
    EXPECT_NEAR(c.J(), 4 * c.I1() * c.I2() / (c.I1() + c.I2()), 1e-12 * c.J());
    EXPECT_LT(c.J(), c.I1() + c.I2());  // torsion constant below the polar moment off the circle
  }
}

TEST(CrossSection, EllipticityMatchesDermatologyRatios) {
  // Diameter ratios: ~1.3 Asian, ~1.4 Caucasian, ~1.7 African hair (issue 2; Robbins 2002).
  for (double ratio : {1.0, 1.3, 1.4, 1.7}) {
    const CrossSection c = SectionFromEllipticity(35e-6, ratio);
    EXPECT_NEAR(c.Ellipticity(), ratio, 1e-14);
    EXPECT_NEAR(c.MeanRadius(), 35e-6, 1e-19);
    // The same section from its eccentricity.
    const CrossSection d = SectionFromEccentricity(35e-6, c.Eccentricity());
    EXPECT_NEAR(d.a, c.a, 1e-18);
    EXPECT_NEAR(d.b, c.b, 1e-18);
  }
}

TEST(CrossSection, ValidationNamesTheProblem) {
  std::string why;
  EXPECT_TRUE(IsValid(SectionFromEccentricity(1e-5, 0.3), &why));
  EXPECT_FALSE(IsValid(CrossSection{1e-5, 2e-5}, &why));  // a < b
  EXPECT_FALSE(IsValid(CrossSection{1e-5, 0.0}, &why));
  EXPECT_FALSE(IsValid(CrossSection{std::nan(""), 1e-5}, &why));
  EXPECT_NE(why.find("semi-axes"), std::string::npos);
}

TEST(Material, PaperDefaultsAndShearModulus) {
  const Material m;
  EXPECT_EQ(m.young_modulus, 10e9);
  EXPECT_EQ(m.poisson_ratio, 0.3);
  EXPECT_EQ(m.density, 1300.0);
  EXPECT_DOUBLE_EQ(m.ShearModulus(), 10e9 / 2.6);  // E / (2 (1 + sigma)), paper footnote 2
  std::string why;
  EXPECT_TRUE(IsValid(m, &why));
  Material bad = m;
  bad.young_modulus = -1;
  EXPECT_FALSE(IsValid(bad, &why));
  EXPECT_NE(why.find("young_modulus"), std::string::npos);
  bad = m;
  bad.poisson_ratio = 0.7;
  EXPECT_FALSE(IsValid(bad, &why));
  EXPECT_NE(why.find("poisson_ratio"), std::string::npos);
}

}  // namespace
}  // namespace ringlet
