// Hair type presets, helix <-> curvature conversions, per-strand sampling (hair_type.h).
#include "ringlet/hair_type.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <vector>

#include "ringlet/helix.h"

namespace ringlet {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Curvature and torsion of the parametric helix r(t) = (R cos t, R sin t, c t), c = p / (2 pi),
// from the general formulas kappa = |r' x r''| / |r'|^3, tau = (r' x r'') . r''' / |r' x r''|^2
// (do Carmo, section 1-6), evaluated at an arbitrary t: independent of CurvatureFromHelix.
HelixCurvature ParametricHelixCurvature(double radius, double pitch) {
  const double c = pitch / (2 * kPi), t = 0.7;
  const Vec3 d1(-radius * std::sin(t), radius * std::cos(t), c);
  const Vec3 d2(-radius * std::cos(t), -radius * std::sin(t), 0);
  const Vec3 d3(radius * std::sin(t), -radius * std::cos(t), 0);
  const Vec3 b = d1.cross(d2);
  return HelixCurvature{b.norm() / std::pow(d1.norm(), 3), b.dot(d3) / b.squaredNorm()};
}

// Radius and pitch measured on the centreline of the rod with constant Omega = (kappa, 0, tau):
// its axis is Omega / |Omega|; one turn takes arc length 2 pi / |Omega|; the axial advance over a
// turn is the pitch and half the chord across half a turn, perpendicular to the axis, the radius.
// Uses the closed-form helix kinematics of helix.h: independent of HelixFromCurvature.
HelixShape MeasuredHelix(double kappa, double tau) {
  const Vec3 omega(kappa, 0, tau);
  const double w = omega.norm();
  const Vec3 axis = omega / w;
  const Vec3 turn = HelixChord(omega, 2 * kPi / w);
  const Vec3 half = HelixChord(omega, kPi / w);
  return HelixShape{(half - axis * axis.dot(half)).norm() / 2, turn.dot(axis)};
}

TEST(HelixConversion, MatchesTheParametricHelix) {
  for (double radius : {0.002, 0.012, 0.044}) {
    for (double pitch : {-0.05, 0.001, 0.01, 0.2}) {
      const HelixCurvature k = CurvatureFromHelix(radius, pitch);
      const HelixCurvature ref = ParametricHelixCurvature(radius, pitch);
      EXPECT_NEAR(k.curvature, ref.curvature, 1e-12 * ref.curvature);
      EXPECT_NEAR(k.torsion, ref.torsion, 1e-12 * std::abs(ref.torsion));
    }
  }
}

TEST(HelixConversion, InverseMatchesTheRodCentreline) {
  for (double kappa : {5.0, 80.0, 400.0}) {
    for (double tau : {-30.0, 0.5, 20.0, 300.0}) {
      const HelixShape h = HelixFromCurvature(kappa, tau);
      const HelixShape ref = MeasuredHelix(kappa, tau);
      EXPECT_NEAR(h.radius, ref.radius, 1e-10 * ref.radius) << kappa << " " << tau;
      EXPECT_NEAR(h.pitch, ref.pitch, 1e-10 * std::abs(ref.pitch) + 1e-15) << kappa << " " << tau;
    }
  }
}

TEST(HelixConversion, RoundTrips) {
  for (double radius : {1e-4, 0.002, 0.044, 3.0}) {
    for (double pitch : {-0.3, -1e-3, 0.0, 1e-3, 0.3}) {
      const HelixCurvature k = CurvatureFromHelix(radius, pitch);
      const HelixShape h = HelixFromCurvature(k.curvature, k.torsion);
      EXPECT_NEAR(h.radius, radius, 1e-13 * radius);
      EXPECT_NEAR(h.pitch, pitch, 1e-13 * std::max(std::abs(pitch), radius));
      const HelixCurvature back = CurvatureFromHelix(h.radius, h.pitch);
      EXPECT_NEAR(back.curvature, k.curvature, 1e-13 * k.curvature);
    }
  }
}

TEST(HelixConversion, Limits) {
  // ZeroCurvature: a straight, untwisted line.
  const HelixShape line = HelixFromCurvature(0, 0);
  EXPECT_EQ(line.radius, kInf);
  const HelixCurvature k = CurvatureFromHelix(kInf, 0.1);
  EXPECT_EQ(k.curvature, 0.0);
  EXPECT_EQ(k.torsion, 0.0);
  // ZeroRadius: a straight twisted rod, tau = 2 pi / p.
  const HelixCurvature twisted = CurvatureFromHelix(0.0, 0.01);
  EXPECT_EQ(twisted.curvature, 0.0);
  EXPECT_NEAR(twisted.torsion, 2 * kPi / 0.01, 1e-12);
  EXPECT_EQ(HelixFromCurvature(0.0, 2 * kPi / 0.01).radius, 0.0);
  // ZeroTwist: a planar circle of radius 1 / kappa.
  const HelixShape circle = HelixFromCurvature(50, 0);
  EXPECT_DOUBLE_EQ(circle.radius, 0.02);
  EXPECT_EQ(circle.pitch, 0.0);
  EXPECT_TRUE(std::isnan(CurvatureFromHelix(0, 0).curvature));
}

HairType Find(std::string_view origin, std::string_view curl) {
  HairType t;
  std::string why;
  EXPECT_TRUE(FindHairType(origin, curl, &t, &why)) << why;
  return t;
}

TEST(HairType, SectionsMatchTheCitedTable) {
  // docs/hair-types.md, from Franbourg et al. 2003: r = sqrt(A / pi), SD_r = SD_A / (2 pi r),
  // SD = CI sqrt(n) / 1.96; values computed by hand (python) from the published A, CI, n.
  struct Row {
    const char* origin;
    double r_um, r_sd_um, ellipticity, ellipticity_sd;
  };
  for (const Row& row : {Row{"asian", 40.1448, 4.7622, 1.29, 0.20132},
                         Row{"caucasian", 36.0331, 5.0097, 1.41, 0.20015},
                         Row{"african", 36.6072, 4.2874, 1.66, 0.16166}}) {
    for (std::string_view curl : CurlTypes()) {
      const HairType t = Find(row.origin, curl);
      EXPECT_NEAR(t.mean_radius * 1e6, row.r_um, 1e-4) << row.origin;
      EXPECT_NEAR(t.mean_radius_std * 1e6, row.r_sd_um, 1e-4) << row.origin;
      EXPECT_EQ(t.ellipticity, row.ellipticity);
      EXPECT_NEAR(t.ellipticity_std, row.ellipticity_sd, 1e-5);
      // The paper's material (section 4): E = 10 GPa, Poisson 0.3, rho = 1300 kg/m^3.
      EXPECT_EQ(t.material.young_modulus, 10e9);
      EXPECT_EQ(t.material.poisson_ratio, 0.3);
      EXPECT_EQ(t.material.density, 1300.0);
      std::string why;
      EXPECT_TRUE(IsValid(t, &why)) << why;
    }
  }
}

TEST(HairType, CurlsMatchTheCitedTable) {
  // docs/hair-types.md: wavy R = 4.4 +- 2.3 cm (Nagase et al. 2008); curly 1.2 +- 0.45 cm and
  // kinky 2 +- 0.6 mm (chosen, see the table); pitch = 2 pi R * (1, 0.5, 0.25).
  const HairType straight = Find("asian", "straight");
  EXPECT_TRUE(straight.IsStraight());
  EXPECT_EQ(straight.MeanNaturalCurvature(), Vec3::Zero());
  EXPECT_NEAR(straight.straight_curvature_std, 6.25, 1e-12);
  struct Row {
    const char* curl;
    double radius, radius_sd, pitch;
  };
  for (const Row& row : {Row{"wavy", 0.044, 0.023, 2 * kPi * 0.044},
                         Row{"curly", 0.012, 0.0045, 2 * kPi * 0.012 * 0.5},
                         Row{"kinky", 0.002, 0.0006, 2 * kPi * 0.002 * 0.25}}) {
    const HairType t = Find("caucasian", row.curl);
    EXPECT_EQ(t.curl_radius, row.radius);
    EXPECT_EQ(t.curl_radius_std, row.radius_sd);
    EXPECT_NEAR(t.curl_pitch, row.pitch, 1e-15);
    // The mean natural curvature is the helix's: kappa = R / (R^2 + c^2), tau = c / (R^2 + c^2).
    const double c = row.pitch / (2 * kPi);
    const Vec3 k = t.MeanNaturalCurvature();
    EXPECT_NEAR(k.x(), row.radius / (row.radius * row.radius + c * c), 1e-9);
    EXPECT_EQ(k.y(), 0.0);
    EXPECT_NEAR(k.z(), c / (row.radius * row.radius + c * c), 1e-9);
  }
  // Kinky kappa ~ 1/(R (1 + 0.0625)) = 470.6 1/m: far tighter than wavy's ~11.4 1/m.
  EXPECT_NEAR(Find("african", "kinky").MeanNaturalCurvature().x(), 1 / (0.002 * 1.0625), 1e-9);
}

TEST(HairType, DefaultCurlPairing) {
  EXPECT_EQ(DefaultCurl("asian"), "straight");
  EXPECT_EQ(DefaultCurl("caucasian"), "wavy");
  EXPECT_EQ(DefaultCurl("african"), "kinky");
  EXPECT_EQ(Find("african", "").curl, "kinky");
  EXPECT_EQ(Find("asian", "").curl, "straight");
}

TEST(HairType, UnknownNamesListTheValidOnes) {
  HairType t;
  std::string why;
  EXPECT_FALSE(FindHairType("martian", "wavy", &t, &why));
  EXPECT_NE(why.find("hair_type.origin"), std::string::npos);
  for (std::string_view name : HairOrigins()) EXPECT_NE(why.find(name), std::string::npos);
  EXPECT_FALSE(FindHairType("asian", "frizzy", &t, &why));
  EXPECT_NE(why.find("hair_type.curl"), std::string::npos);
  EXPECT_NE(why.find("\"frizzy\""), std::string::npos);
  for (std::string_view name : CurlTypes()) EXPECT_NE(why.find(name), std::string::npos);
  EXPECT_FALSE(FindHairType("Asian", "", &t, &why));  // names are lower case
}

TEST(HairType, ValidationNamesTheField) {
  HairType t = Find("caucasian", "wavy");
  std::string why;
  t.ellipticity = 0.9;
  EXPECT_FALSE(IsValid(t, &why));
  EXPECT_NE(why.find("hair_type.ellipticity"), std::string::npos);
  t = Find("caucasian", "wavy");
  t.curl_radius = -1;
  EXPECT_FALSE(IsValid(t, &why));
  EXPECT_NE(why.find("hair_type.curl_radius"), std::string::npos);
  t = Find("caucasian", "wavy");
  t.material.young_modulus = 0;
  EXPECT_FALSE(IsValid(t, &why));
  EXPECT_NE(why.find("hair_type.material"), std::string::npos);
}

// Mean and standard deviation of f over strands 0..n-1.
void Moments(int n, const std::function<double(uint64_t)>& f, double* mean, double* sd) {
  double s = 0, s2 = 0;
  for (int i = 0; i < n; ++i) {
    const double x = f(static_cast<uint64_t>(i));
    s += x;
    s2 += x * x;
  }
  *mean = s / n;
  *sd = std::sqrt(std::max(0.0, s2 / n - *mean * *mean) * n / (n - 1));
}

// Sample moments against the type's parameters: the mean within 5 standard errors
// (sd / sqrt(n)); the standard deviation within 10% (its standard error for these log-normals,
// of kurtosis <= 12, is below 1.3% at n = 20000, so 10% is a > 7-sigma bound).
void ExpectMoments(const char* what, int n, const std::function<double(uint64_t)>& f,
                   double mean, double sd) {
  double m = 0, s = 0;
  Moments(n, f, &m, &s);
  EXPECT_NEAR(m, mean, 5 * sd / std::sqrt(n) + 1e-15 * std::abs(mean)) << what;
  EXPECT_NEAR(s, sd, 0.1 * sd + 1e-300) << what;
}

TEST(SampleStrand, MomentsMatchTheHairType) {
  const int n = 20000;
  for (auto [origin, curl] : {std::pair{"asian", "straight"}, std::pair{"caucasian", "wavy"},
                              std::pair{"african", "kinky"}, std::pair{"african", "curly"}}) {
    const HairType t = Find(origin, curl);
    const uint64_t seed = 2024;
    auto sample = [&](uint64_t i) { return SampleStrand(t, seed, i); };
    ExpectMoments("mean radius", n, [&](uint64_t i) { return sample(i).section.MeanRadius(); },
                  t.mean_radius, t.mean_radius_std);
    ExpectMoments("ellipticity", n, [&](uint64_t i) { return sample(i).section.Ellipticity(); },
                  t.ellipticity, t.ellipticity_std);
    ExpectMoments("length factor", n, [&](uint64_t i) { return sample(i).length_factor; }, 1.0,
                  t.length_factor_std);
    if (t.IsStraight()) {
      ExpectMoments("straight kappa1", n,
                    [&](uint64_t i) { return sample(i).natural_curvature.x(); }, 0.0,
                    t.straight_curvature_std);
    } else {
      ExpectMoments("curl radius", n, [&](uint64_t i) { return sample(i).helix.radius; },
                    t.curl_radius, t.curl_radius_std);
      // |pitch| = R * ratio * factor with independent R and factor: mean curl_pitch, and
      // Var = E[R^2] E[f^2] ratio^2 - curl_pitch^2 with E[f^2] = 1 + rel_sd^2.
      const double ratio = t.curl_pitch / t.curl_radius;
      const double pitch_sd = std::sqrt(
          (t.curl_radius * t.curl_radius + t.curl_radius_std * t.curl_radius_std) *
              (1 + t.curl_pitch_rel_std * t.curl_pitch_rel_std) * ratio * ratio -
          t.curl_pitch * t.curl_pitch);
      ExpectMoments("pitch", n, [&](uint64_t i) { return std::abs(sample(i).helix.pitch); },
                    t.curl_pitch, pitch_sd);
    }
  }
}

TEST(SampleStrand, EachStrandIsConsistent) {
  const HairType t = Find("african", "kinky");
  int left = 0;
  const int n = 4000;
  for (int i = 0; i < n; ++i) {
    const StrandParameters p = SampleStrand(t, 5, i);
    std::string why;
    ASSERT_TRUE(IsValid(p.section, &why)) << why;
    EXPECT_GE(p.section.Ellipticity(), 1.0);
    // The natural curvature is the sampled helix's, bending about n1.
    const HelixShape h = HelixFromCurvature(p.natural_curvature.x(), p.natural_curvature.z());
    EXPECT_NEAR(h.radius, p.helix.radius, 1e-12 * p.helix.radius);
    EXPECT_NEAR(h.pitch, p.helix.pitch, 1e-12 * std::abs(p.helix.pitch));
    EXPECT_EQ(p.natural_curvature.y(), 0.0);
    EXPECT_GT(p.length_factor, 0.0);
    left += p.natural_curvature.z() < 0;
  }
  // Random handedness: Binomial(4000, 1/2) has sd 31.6; allow 5 sd.
  EXPECT_NEAR(left, n / 2, 160);
  HairType right = t;
  right.handedness = 1;
  for (int i = 0; i < 100; ++i) EXPECT_GT(SampleStrand(right, 5, i).natural_curvature.z(), 0);
}

TEST(SampleStrand, DeterministicPerSeedAndIndexInAnyOrder) {
  const HairType t = Find("caucasian", "curly");
  std::vector<StrandParameters> forward, backward(50);
  for (int i = 0; i < 50; ++i) forward.push_back(SampleStrand(t, 77, i));
  for (int i = 49; i >= 0; --i) backward[i] = SampleStrand(t, 77, i);
  for (int i = 0; i < 50; ++i) {
    EXPECT_EQ(forward[i].natural_curvature, backward[i].natural_curvature);  // bit-identical
    EXPECT_EQ(forward[i].section.a, backward[i].section.a);
    EXPECT_EQ(forward[i].length_factor, backward[i].length_factor);
  }
  EXPECT_NE(SampleStrand(t, 77, 0).natural_curvature, SampleStrand(t, 77, 1).natural_curvature);
  EXPECT_NE(SampleStrand(t, 77, 0).natural_curvature, SampleStrand(t, 78, 0).natural_curvature);
  EXPECT_NE(SampleStrand(t, 77, 0).section.a, SampleStrand(t, 78, 0).section.a);
}

}  // namespace
}  // namespace ringlet
