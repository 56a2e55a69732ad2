// Hanging curls (docs/validation.md, "Hanging curls"): a naturally curly strand clamped pointing
// straight down. References:
// - the local helical spring (tests/reference/helical_spring.h): a uniform helix of natural
//   curvature and twist pulled along its axis by F with no axial torque has curvature kappa(F)
//   given in closed form by Kirchhoff's equations; hanging, F = w (L - s). It predicts the curled
//   length at the tip, l_h = F_half / w with F_half ~ E I |Omega0|^2: the scaling of Miller,
//   Lazarus, Audoly & Reis, "Shapes of a suspended curly hair", PRL 112, 068103 (2014) (the helix
//   is opened where the tension exceeds ~E I kappa0^2, so l_h ~ E I kappa0^2 / w).
// - Miller et al.'s three regimes (planar curl, localized helix, global helix), classified by the
//   rule of tests/hanging_curl_measures.h.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "hanging_curl_measures.h"
#include "reference/helical_spring.h"
#include "ringlet/statics.h"

namespace ringlet {
namespace {

constexpr double kLength = 0.25;  // m
constexpr int kSegments = 50;

Mat3 DownFrame() {  // t = -z, n1 = +x, n2 = t x n1 = -y
  Mat3 q;
  q.col(0) = Vec3(1, 0, 0);
  q.col(1) = Vec3(0, -1, 0);
  q.col(2) = Vec3(0, 0, -1);
  return q;
}

// Paper's material, radius 50 um, circular; weight set through the density so that
// w L^3 / (E I) = load.
StrandModel Hanging(double kappa0, double tau0, double load) {
  StrandModel m;
  m.segment_lengths = UniformSegments(kLength, kSegments);
  m.section = SectionFromEccentricity(50e-6, 0.0);
  m.natural_curvature = Vec3(kappa0, 0.0, tau0);
  m.root_frame = DownFrame();
  m.material.density = load * m.Stiffness()(0) /
                       (kLength * kLength * kLength * m.section.Area() * m.gravity.norm());
  return m;
}

// Natural helix of radius r0 and pitch p0 (m): kappa0 = r0 / (r0^2 + h^2), tau0 = h / (r0^2 + h^2),
// h = p0 / (2 pi).
Vec3 HelixCurvature(double r0, double p0) {
  const double h = p0 / (2.0 * std::numbers::pi), d = r0 * r0 + h * h;
  return Vec3(r0 / d, 0.0, h / d);
}

reference::HelicalSpring Spring(const StrandModel& m) {
  return {m.Stiffness()(0), m.Stiffness()(2), m.natural_curvature(0), m.natural_curvature(2)};
}

double CurledLength(const StrandModel& m, const StrandSolution& solution) {
  const curls::CurlProfile p = curls::MeasureCurl(m, solution.curvatures);
  return m.Length() - curls::StretchedLength(p, m.natural_curvature(0));
}

double SpringCurledLength(const StrandModel& m) {
  const reference::HelicalSpring spring = Spring(m);
  return spring.Tension(0.5 * spring.kappa0) / m.WeightPerLength().norm();
}

double LogSlope(const std::vector<double>& x, const std::vector<double>& y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(x.size());
  for (size_t i = 0; i < x.size(); ++i) {
    const double a = std::log(x[i]), b = std::log(y[i]);
    sx += a, sy += b, sxx += a * a, sxy += a * b;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

TEST(HelicalSpringReference, EndsAndMonotonicity) {
  // Natural state carries no force; the helix opens monotonically as the force grows; tau0 = 0
  // caps the force at B^2 kappa0^2 / C (the kappa -> 0 limit of eq. (3)).
  const reference::HelicalSpring spring{2.0, 1.5, 100.0, 20.0};
  EXPECT_NEAR(spring.Tension(100.0), 0.0, 1e-12);
  EXPECT_NEAR(spring.Twist(100.0), 20.0, 1e-12);
  double previous = 0.0;
  for (double k = 99.0; k > 1.0; k -= 7.0) {
    EXPECT_GT(spring.Tension(k), previous);
    previous = spring.Tension(k);
  }
  EXPECT_NEAR(spring.CurvatureAtTension(spring.Tension(37.0)), 37.0, 1e-9);
  const reference::HelicalSpring planar{2.0, 1.5, 100.0, 0.0};
  EXPECT_NEAR(planar.Tension(1e-6), 4.0 * 1e4 / 1.5, 1e-2);
  EXPECT_EQ(planar.CurvatureAtTension(1.01 * 4.0 * 1e4 / 1.5), 0.0);
}

TEST(HangingCurlMeasures, NaturalHelixIsRegularAndUnstretched) {
  // Without gravity the equilibrium is the natural helix: every segment has the natural radius
  // and pitch, nothing is stretched and the irregularity is zero (anti-vacuity for the measures).
  const Vec3 omega0 = HelixCurvature(0.005, 0.005);
  StrandModel m = Hanging(omega0(0), omega0(2), 100.0);
  m.gravity = Vec3::Zero();
  const StrandSolution solution = SolveStrand(m);
  const curls::CurlProfile p = curls::MeasureCurl(m, solution.curvatures);
  for (size_t i = 0; i < p.s.size(); ++i) {
    EXPECT_NEAR(p.radius[i], 0.005, 1e-12);
    EXPECT_NEAR(p.pitch[i], 0.005, 1e-12);
  }
  EXPECT_EQ(curls::StretchedLength(p, omega0(0)), 0.0);
  EXPECT_NEAR(curls::CurlIrregularity(p, omega0.norm(), 0.0, kLength), 0.0, 1e-12);
  EXPECT_GT(curls::OutOfPlaneDeviation(m, solution.curvatures), 1e-3);  // a helix is not planar
  // StretchedLength interpolates: one crossing half-way between two midpoints.
  curls::CurlProfile two;
  two.s = {0.25, 0.75};
  two.curvature = {0.0, 2.0};
  two.length = 1.0;
  EXPECT_NEAR(curls::StretchedLength(two, 2.0), 0.25 + 0.25, 1e-15);
}

TEST(HangingCurl, StretchedNearRootTightNearTip) {
  // Natural helix R0 = p0 = 5 mm (|Omega0| L = 49), w L^3 / EI = 6000: the weight is 190 times a
  // real hair's (w L^3 / EI = 32 at L = 25 cm), so that the curls open over the upper part of the
  // strand; at the real weight the spring predicts a curled length of 16 m (a global helix).
  const Vec3 omega0 = HelixCurvature(0.005, 0.005);
  const StrandModel m = Hanging(omega0(0), omega0(2), 6000.0);
  const StrandSolution solution = SolveStrand(m);
  ASSERT_TRUE(solution.summary.Converged()) << solution.summary.message;
  EXPECT_TRUE(solution.summary.stable);
  const curls::CurlProfile p = curls::MeasureCurl(m, solution.curvatures);
  const int n = kSegments;
  // Tip: unloaded, the natural curl (last segment; its midpoint carries the weight of L/(2n)).
  EXPECT_NEAR(p.curvature[n - 1] / omega0(0), 1.0, 0.03);
  EXPECT_NEAR(p.radius[n - 1] / 0.005, 1.0, 0.05);
  // Root quarter: opened (measured kappa <= 0.089 kappa0, radius 0.40-0.51 R0 after the first
  // segment, descent >= 0.978: the tangent within 12 degrees of the vertical). The first segment
  // lies in the clamp's boundary layer (width ~L / sqrt(w L^3 / EI) = L / 77): kappa = 0.089
  // kappa0 but tau is small too, so its helix radius is 1.7 R0, a helix of very long pitch.
  for (int i = 0; i < n / 4; ++i) {
    EXPECT_LT(p.curvature[i] / omega0(0), 0.1) << "segment " << i;
    if (i > 0) {
      EXPECT_LT(p.radius[i] / 0.005, 0.6) << "segment " << i;
    }
    EXPECT_GT(p.descent[i], 0.97) << "segment " << i;
  }
  // Everywhere the local curvature follows the helical spring under the weight below, except in
  // the unloaded last turn and the clamp's boundary layer (first segment). Measured: max
  // deviation 0.0092 kappa0 (n = 50); 0.028 in the last turn, 0.050 in the first segment.
  const reference::HelicalSpring spring = Spring(m);
  const double w = m.WeightPerLength().norm();
  const double turn = 2.0 * std::numbers::pi / omega0.norm();
  for (int i = 1; i < n; ++i) {
    if (p.s[i] > kLength - turn) break;
    const double predicted = spring.CurvatureAtTension(w * (kLength - p.s[i]));
    EXPECT_NEAR(p.curvature[i] / omega0(0), predicted / omega0(0), 0.015) << "s = " << p.s[i];
  }
  // The curled length agrees with the spring prediction (measured 0.3373 L against 0.3387 L).
  EXPECT_NEAR(CurledLength(m, solution) / SpringCurledLength(m), 1.0, 0.02);
}

TEST(HangingCurl, CurledLengthScalesWithCurvatureSquaredOverWeight) {
  // l_h ~ E I |Omega0|^2 / w (Miller et al. 2014; exact for the local spring): fit the exponents
  // over a weight sweep (fixed helix) and a curvature sweep (helix shape fixed, R0 = p0 scaled),
  // each keeping 2-6 turns in the curled part. Measured (n = 50): exponents -1.004 and 2.013;
  // curled lengths 0.071-0.169 m, each within 3% of the spring's (docs/validation.md).
  std::vector<double> loads, curled_w, omegas, curled_k;
  for (double load : {3000.0, 4000.0, 5333.0, 7111.0}) {
    const Vec3 omega0 = HelixCurvature(0.005, 0.005);
    const StrandModel m = Hanging(omega0(0), omega0(2), load);
    const StrandSolution solution = SolveStrand(m);
    ASSERT_TRUE(solution.summary.Converged());
    loads.push_back(load);
    curled_w.push_back(CurledLength(m, solution));
    EXPECT_NEAR(curled_w.back() / SpringCurledLength(m), 1.0, 0.03) << "load " << load;
  }
  for (double r0 : {0.0045, 0.005, 0.0055, 0.006}) {
    const Vec3 omega0 = HelixCurvature(r0, r0);
    const StrandModel m = Hanging(omega0(0), omega0(2), 4000.0);
    const StrandSolution solution = SolveStrand(m);
    ASSERT_TRUE(solution.summary.Converged());
    omegas.push_back(omega0.norm());
    curled_k.push_back(CurledLength(m, solution));
    EXPECT_NEAR(curled_k.back() / SpringCurledLength(m), 1.0, 0.03) << "r0 " << r0;
  }
  EXPECT_NEAR(LogSlope(loads, curled_w), -1.0, 0.05);
  EXPECT_NEAR(LogSlope(omegas, curled_k), 2.0, 0.1);
  // Stretched length L - l_h grows with the weight and shrinks with the natural curvature.
  EXPECT_GT(curled_w.front(), curled_w.back());
  EXPECT_GT(curled_k.front(), curled_k.back());  // r0 = 4.5 mm curls more than r0 = 6 mm
}

TEST(HangingCurl, ThreeRegimesOfMillerEtAl) {
  // Miller et al.'s naturally planar curl (tau0 = 0), circular section, three well-separated
  // points of the (kappa0 L, w L^3 / EI) plane (docs/images/hanging_curl_phase_diagram.png).
  struct Point {
    double kappa0_l, load;
    curls::CurlRegime expected;
  };
  const Point points[] = {
      {5.0, 1000.0, curls::CurlRegime::kPlanar},            // kappa0 l_gb = 0.5: heavy, tip curl
      {20.0, 1000.0, curls::CurlRegime::kLocalizedHelix},   // kappa0 l_gb = 2.0
      {20.0, 100.0, curls::CurlRegime::kGlobalHelix},       // kappa0 l_gb = 4.3, light
  };
  for (const Point& point : points) {
    const StrandModel m = Hanging(point.kappa0_l / kLength, 0.0, point.load);
    const StrandSolution solution = SolveStrand(m);
    ASSERT_TRUE(solution.summary.Converged()) << solution.summary.message;
    const curls::CurlProfile p = curls::MeasureCurl(m, solution.curvatures);
    const double stretched = curls::StretchedLength(p, m.natural_curvature(0)) / kLength;
    const double planar = curls::OutOfPlaneDeviation(m, solution.curvatures);
    EXPECT_EQ(curls::RegimeName(curls::Classify(planar, stretched)),
              curls::RegimeName(point.expected))
        << "kappa0 L = " << point.kappa0_l << ", load " << point.load << ": out of plane "
        << planar << ", stretched " << stretched;
    if (point.expected == curls::CurlRegime::kLocalizedHelix) {
      // Measured 0.286 L against the spring's 0.306 L (n = 100: the same).
      EXPECT_NEAR((1.0 - stretched) * kLength / SpringCurledLength(m), 1.0, 0.1);
    }
    if (point.expected == curls::CurlRegime::kGlobalHelix) {
      EXPECT_GT(SpringCurledLength(m), kLength);  // the spring cannot open it anywhere
    }
  }
}

}  // namespace
}  // namespace ringlet
