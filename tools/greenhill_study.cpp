// Greenhill's self-buckling: a strand clamped pointing up, loads around w L^3 / EI = 7.8373.
// Prints the markdown table of docs/validation.md ("Greenhill's self-buckling").
#include <cmath>
#include <cstdio>
#include <numbers>

#include "ringlet/statics.h"
#include "ringlet/strand_geometry.h"

int main() {
  using namespace ringlet;
  constexpr double kGreenhill = 7.8373;  // critical w L^3 / EI (Greenhill 1881)
  std::printf("| load / 7.8373 | n | termination | stable | restarts | min eigenvalue | tip angle from vertical (deg) |\n");
  std::printf("|---:|---:|---|---|---:|---:|---:|\n");
  for (double factor : {0.9, 0.98, 1.02, 1.1, 1.35, 2.0}) {
    for (int n : {15, 30, 60}) {
      StrandModel m;
      m.segment_lengths = UniformSegments(0.05, n);
      m.section = SectionFromEccentricity(50e-6, 0.0);
      m.root_frame = Mat3::Identity();  // tangent +z: pointing up
      const double ei = m.Stiffness()(0), l = m.Length();
      m.material.density = factor * kGreenhill * ei / (l * l * l * m.section.Area() * 9.81);
      const StrandSolution s = SolveStrand(m);
      const StrandGeometry g = ComputeGeometry(m, s.curvatures);
      const Vec3 t = g.frames[n].col(2);
      const double angle = std::atan2(t.head<2>().norm(), t.z()) * 180.0 / std::numbers::pi;
      std::printf("| %.2f | %d | %s | %s | %d | %.4f | %.2f |\n", factor, n,
                  TerminationName(s.summary.termination), s.summary.stable ? "yes" : "no",
                  s.summary.stability_restarts, s.summary.min_eigenvalue, angle);
    }
  }
  return 0;
}
