// Greenhill's self-buckling: a strand clamped pointing up, loads around w L^3 / EI = 7.8373.
// Prints the markdown tables of docs/validation.md ("Greenhill's self-buckling"): what the solver
// does around the threshold; the critical load of the planar reference (tests/reference/
// greenhill.h) and the discrete critical loads implied by the scaled Hessian; the post-buckling
// branch, reference against the 3D solver for n = 15, 30, 60.
#include <cmath>
#include <cstdio>
#include <numbers>

#include "../tests/reference/greenhill.h"
#include "ringlet/statics.h"
#include "ringlet/strand_geometry.h"

namespace {

using namespace ringlet;

constexpr double kGreenhill = 7.8373;  // critical w L^3 / EI (Greenhill 1881), as published
constexpr double kDegrees = 180.0 / std::numbers::pi;
constexpr int kSegments[] = {15, 30, 60};

// A 5-cm strand of circular section pointing up (t = +z), n uniform segments, the load
// w L^3 / EI set through the density.
StrandModel StandingStrand(double load, int n) {
  StrandModel m;
  m.segment_lengths = UniformSegments(0.05, n);
  m.section = SectionFromEccentricity(50e-6, 0.0);
  m.root_frame = Mat3::Identity();  // tangent +z: pointing up
  const double ei = m.Stiffness()(0), l = m.Length();
  m.material.density = load * ei / (l * l * l * m.section.Area() * m.gravity.norm());
  return m;
}

// Angle of the tip tangent from the upward vertical (rad).
double TipAngle(const StrandModel& m, const VecX& curvatures) {
  const Vec3 t = ComputeGeometry(m, curvatures).frames.back().col(2);
  return std::atan2(t.head<2>().norm(), t.z());
}

// The critical load of the n-segment strand: at the straight state the scaled Hessian is
// I + lambda G, so its smallest eigenvalue mu gives lambda_c(n) = lambda / (1 - mu). Evaluated
// above threshold, where the eigenvalue is the eigensolver's (not the inverse-iteration estimate).
double DiscreteCriticalLoad(int n) {
  const StrandModel m = StandingStrand(1.1 * kGreenhill, n);
  const double mu = MinScaledHessianEigenvalue(m, VecX::Zero(3 * n));
  return m.GravityParameter() / (1.0 - mu);
}

void SolverTable() {
  std::printf(
      "| load / 7.8373 | n | termination | stable | restarts | min eigenvalue | tip angle from "
      "vertical (deg) |\n");
  std::printf("|---:|---:|---|---|---:|---:|---:|\n");
  for (double factor : {0.9, 0.98, 1.02, 1.1, 1.35, 2.0}) {
    for (int n : kSegments) {
      const StrandModel m = StandingStrand(factor * kGreenhill, n);
      const StrandSolution s = SolveStrand(m);
      std::printf("| %.2f | %d | %s | %s | %d | %.4f | %.2f |\n", factor, n,
                  TerminationName(s.summary.termination), s.summary.stable ? "yes" : "no",
                  s.summary.stability_restarts, s.summary.min_eigenvalue,
                  TipAngle(m, s.curvatures) * kDegrees);
    }
  }
}

void CriticalLoadTable() {
  const double series = reference::GreenhillCriticalLoadSeries();
  const double shooting = reference::GreenhillCriticalLoadByShooting();
  std::printf(
      "\nReference critical load: series %.10f, shooting on the linearized ODE %.10f "
      "(published %.4f).\n",
      series, shooting, kGreenhill);
  const double c = reference::GreenhillPitchforkCoefficient();
  std::printf(
      "Pitchfork: tip angle^2 / (load / critical - 1) -> %.5f (perturbation theory); "
      "reference branch:",
      c);
  for (double eps : {1e-4, 1e-3, 1e-2}) {
    const auto s = reference::SolveGreenhillBuckled(series * (1.0 + eps));
    std::printf(" %.5f (eps %.0e)", s.tip_angle * s.tip_angle / eps, eps);
  }
  std::printf("\n\n| n | critical load from the scaled Hessian | relative error | error x n^2 |\n");
  std::printf("|---:|---:|---:|---:|\n");
  double previous = 0.0, last = 0.0;
  for (int n : {15, 30, 60, 120}) {
    const double discrete = DiscreteCriticalLoad(n);
    std::printf("| %d | %.6f | %.3e | %.4f |\n", n, discrete, discrete / series - 1.0,
                (discrete / series - 1.0) * n * n);
    previous = last;
    last = discrete;
  }
  std::printf("\nRichardson from n = 60 and 120: %.8f\n", (4.0 * last - previous) / 3.0);
}

void BranchTable() {
  const double series = reference::GreenhillCriticalLoadSeries();
  std::printf(
      "\n| load / 7.8373 | reference tip angle (deg) | reference tip offset / L | 3D tip angle, n "
      "= 15 / 30 / 60 (deg) | error (deg) | error x n^2 (rad) | error vs reference at load x "
      "critical / critical(n) (deg) | tip position error x n^2 (L), n = 60 |\n");
  std::printf("|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (double factor : {1.02, 1.1, 1.35, 2.0}) {
    const double load = factor * kGreenhill;
    const reference::GreenhillSolution ref = reference::SolveGreenhillBuckled(load);
    double angle[3], shifted[3], position_error = 0.0;
    for (int i = 0; i < 3; ++i) {
      const int n = kSegments[i];
      const StrandModel m = StandingStrand(load, n);
      const VecX curvatures = SolveStrand(m).curvatures;
      angle[i] = TipAngle(m, curvatures);
      const Vec3 tip = ComputeGeometry(m, curvatures).points.back() / m.Length();
      position_error = std::hypot(tip.head<2>().norm() - ref.tip_x, tip.z() - ref.tip_z) * n * n;
      const auto s = reference::SolveGreenhillBuckled(load * series / DiscreteCriticalLoad(n));
      shifted[i] = angle[i] - s.tip_angle;
    }
    std::printf(
        "| %.2f | %.4f | %.5f | %.3f / %.3f / %.3f | %.4f / %.4f / %.4f | %.2f / %.2f / %.2f "
        "| %.4f / %.4f / %.4f | %.2f |\n",
        factor, ref.tip_angle * kDegrees, ref.tip_x, angle[0] * kDegrees, angle[1] * kDegrees,
        angle[2] * kDegrees, (angle[0] - ref.tip_angle) * kDegrees,
        (angle[1] - ref.tip_angle) * kDegrees, (angle[2] - ref.tip_angle) * kDegrees,
        (angle[0] - ref.tip_angle) * 15 * 15, (angle[1] - ref.tip_angle) * 30 * 30,
        (angle[2] - ref.tip_angle) * 60 * 60, shifted[0] * kDegrees, shifted[1] * kDegrees,
        shifted[2] * kDegrees, position_error);
  }
}

}  // namespace

int main() {
  SolverTable();
  CriticalLoadTable();
  BranchTable();
  return 0;
}
