// Unsymmetric bending of an elliptic section: a horizontal cantilever (t = +x, e = 0.8) whose
// principal axes are rotated by psi about the tangent, against linear beam theory. Prints the
// markdown table of docs/validation.md ("Unsymmetric bending of an elliptic section"); the
// conventions and the derivation are at the top of tests/unsymmetric_bending_test.cpp.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "ringlet/statics.h"
#include "ringlet/strand_geometry.h"

int main() {
  using namespace ringlet;
  constexpr int kSegments = 10;
  const double discretization = 1.0 - 1.0 / (3.0 * kSegments * kSegments);
  std::printf(
      "| psi (deg) | load w L^3 / (E I1) | predicted lateral, vertical tip (w L^4 / (8 E I1)) | "
      "measured, n = %d | measured / predicted - (1 - 1/(3n^2)), lateral, vertical | total twist, "
      "measured / predicted | max tau / max kappa |\n",
      kSegments);
  std::printf("|---:|---:|---:|---:|---:|---:|---:|\n");
  for (double degrees : {0.0, 30.0, 45.0, 60.0, 90.0, -30.0, -60.0}) {
    for (double lambda : {1e-3, 1e-2}) {
      const double psi = degrees * std::numbers::pi / 180.0;
      const double c = std::cos(psi), s = std::sin(psi);
      StrandModel m;
      m.section = SectionFromEccentricity(50e-6, 0.8);
      // n1 = -cos(psi) y - sin(psi) z, n2 = sin(psi) y - cos(psi) z, t = +x.
      m.root_frame.col(0) = Vec3(0.0, -c, -s);
      m.root_frame.col(1) = Vec3(0.0, s, -c);
      m.root_frame.col(2) = Vec3(1.0, 0.0, 0.0);
      const double e_modulus = m.material.young_modulus;
      const double i1 = m.section.I1(), i2 = m.section.I2();
      const double w = m.WeightPerLength().norm();
      const double length = std::cbrt(lambda * e_modulus * i1 / w);
      m.segment_lengths = UniformSegments(length, kSegments);
      const StrandSolution solution = SolveStrand(m);
      const Vec3 tip = ComputeGeometry(m, solution.curvatures).points.back();
      // Linear theory, in units of w L^4 / (8 E I1).
      const double unit = w * std::pow(length, 4) / (8.0 * e_modulus * i1);
      const double lateral = s * c * (1.0 - i1 / i2);
      const double vertical = -(c * c + s * s * i1 / i2);
      // Second-order twist: int tau ds = -w A L^6 / (120 mu J), A = (w / E) s c (1/I1 - 1/I2).
      const double a = w / e_modulus * s * c * (1.0 / i1 - 1.0 / i2);
      const double twist_predicted = -w * a * std::pow(length, 6) / (120.0 * m.Stiffness()(2));
      double twist = 0.0, max_tau = 0.0, max_kappa = 0.0;
      for (int i = 0; i < kSegments; ++i) {
        twist += solution.curvatures(3 * i + 2) * m.segment_lengths[i];
        max_tau = std::max(max_tau, std::abs(solution.curvatures(3 * i + 2)));
        max_kappa = std::max(max_kappa, solution.curvatures.segment<2>(3 * i).norm());
      }
      const bool symmetric = std::abs(s * c) < 1e-12;
      char lateral_error[32], twist_ratio[32];
      if (symmetric) {
        std::snprintf(lateral_error, sizeof lateral_error, "(y = %.0e)", std::abs(tip.y()) / unit);
        std::snprintf(twist_ratio, sizeof twist_ratio, "0 (%.0e rad)", twist);
      } else {
        std::snprintf(lateral_error, sizeof lateral_error, "%+.1e",
                      tip.y() / unit / lateral - discretization);
        std::snprintf(twist_ratio, sizeof twist_ratio, "%.4f", twist / twist_predicted);
      }
      std::printf("| %.0f | %.0e | %+.4f, %+.4f | %+.6f, %+.6f | %s, %+.1e | %s | %.1e |\n",
                  degrees, lambda, symmetric ? 0.0 : lateral, vertical, tip.y() / unit,
                  tip.z() / unit, lateral_error, tip.z() / unit / vertical - discretization,
                  twist_ratio, max_tau / max_kappa);
    }
  }
  return 0;
}
