// Validation studies of the strand dynamics (issue 27, items 4 and 7; docs/validation.md
// "Dynamics", docs/benchmarks.md "Hair in motion"): heavier than the unit tests, so their numbers
// live in the docs and their CSVs in docs/data/dynamics/ (plotted by scripts/plot_dynamics.py).
//
//   ./build/tools/dynamics_study [OUTDIR]      (default docs/data/dynamics)
//
// 1. rotating_clamp.csv: a straight rod on a clamp turning at constant Omega about a vertical
//    axis, simulated until it rests in the turning frame, against an independent reference: the
//    planar rod equations of the relative equilibrium (centrifugal load rho S Omega^2 x, gravity)
//    integrated by RK4 and shot on the tip conditions (PlanarRotatingRod below; no ringlet code).
// 2. time_convergence.csv: the error at t = 0.5 s of a horizontal curly strand released under
//    gravity, against a fine-step reference, for h = T/12 .. T/768 and both schemes.
// 3. energy.csv / energy_summary.csv: total energy over 10^4 undamped steps per scheme (h = 1 ms
//    and h = 1/24 s), and with the hair's damping at film frames (rises counted).
// 4. stable_steps.csv: per example hair type (12 presets, 30 cm on a spherical head with contact,
//    20 and 50 segments): the explicit limit 2/omega_max from the modal analysis (all modes, and
//    the bending modes only) against the largest implicit step of the ladder 1/24 .. 1 s that runs
//    3 s with every step converged, none halved and the energy never rising.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "ringlet/body.h"
#include "ringlet/contact.h"
#include "ringlet/cross_section.h"
#include "ringlet/dynamics.h"
#include "ringlet/hair_type.h"
#include "ringlet/statics.h"
#include "ringlet/strand_geometry.h"
#include "reference/rotating_rod.h"

namespace ringlet {
namespace {

using reference::PlanarRotatingRod;

constexpr double kPi = 3.14159265358979323846;

Mat3 HorizontalFrame() {  // t = +x, n1 = +z, n2 = -y
  Mat3 q;
  q.col(0) = Vec3(0, 0, 1);
  q.col(1) = Vec3(0, -1, 0);
  q.col(2) = Vec3(1, 0, 0);
  return q;
}

Mat3 RotationZ(double angle) {
  Mat3 r;
  r << std::cos(angle), -std::sin(angle), 0.0, std::sin(angle), std::cos(angle), 0.0, 0.0, 0.0, 1.0;
  return r;
}

std::FILE* Open(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) {
    std::fprintf(stderr, "cannot write %s\n", path.c_str());
    std::exit(1);
  }
  return f;
}

// ---------------------------------------------------------------------------------------------
// 1. The rotating clamp.

void RotatingClamp(const std::string& dir) {
  std::FILE* out = Open(dir + "/rotating_clamp.csv");
  std::fprintf(out, "scheme,segments,omega,h,in_plane_error_L,out_of_plane_L,static_error_L,"
                    "deflection_from_static_L,tip_x,tip_z,ref_tip_x,ref_tip_z,last_change_L\n");
  std::FILE* shapes = Open(dir + "/rotating_clamp_shapes.csv");
  std::fprintf(shapes, "curve,s,x,y,z\n");
  const double length = 0.15, radius_of_clamp = 0.05, omega = 10.0;
  struct Run {
    Integrator integrator;
    int segments;
    double h;
  };
  const Run runs[] = {{Integrator::kBdf2, 10, 1.0 / 480.0},  {Integrator::kBdf2, 20, 1.0 / 480.0},
                      {Integrator::kBdf2, 40, 1.0 / 480.0},  {Integrator::kBackwardEuler, 40, 1.0 / 480.0},
                      {Integrator::kBackwardEuler, 40, 1.0 / 960.0}, {Integrator::kBdf2, 40, 1.0 / 960.0}};
  for (const Run& run : runs) {
    const int n = run.segments;
    const double h = run.h;
    StrandModel m;
    m.segment_lengths = UniformSegments(length, n);
    m.section = SectionFromEccentricity(50e-6, 0.0);
    m.natural_curvature = Vec3::Zero();
    m.root_frame = HorizontalFrame();
    m.root_position = Vec3(radius_of_clamp, 0.0, 0.0);
    const double rho_s = m.material.density * m.section.Area();
    const double ei = m.material.young_modulus * m.section.I1();
    const StrandSolution rest = SolveStrand(m);
    DynamicsOptions options;
    options.time_step = h;
    options.integrator = run.integrator;
    options.air_drag = 0.0;            // still air would drag the turning strand out of its plane
    options.internal_friction = 1e-8;  // settles the relative motion in ~0.2 s (not the shape)
    StrandDynamics dynamics(m, options, {rest.curvatures, VecX::Zero(3 * n), 0.0});
    const Vec3 arm = m.root_position;
    const Mat3 frame = m.root_frame;
    dynamics.SetClampMotion({[=](double t) { return Vec3(RotationZ(omega * t) * arm); },
                             [=](double t) { return Mat3(RotationZ(omega * t) * frame); }});
    VecX last = rest.curvatures;
    const int steps = static_cast<int>(std::lround(3.0 / h));  // 3 s
    for (int k = 0; k < steps; ++k) {
      last = dynamics.state().curvatures;
      const StepReport report = dynamics.Step();
      if (!report.converged) {
        std::fprintf(stderr, "rotating clamp: %s\n", report.message.c_str());
        std::exit(1);
      }
    }
    // The shape in the turning frame: the model with the root back where it was at t = 0.
    std::vector<double> arcs;
    const int points = 60;
    for (int j = 0; j <= points; ++j) arcs.push_back(length * j / points);
    const std::vector<Vec3> simulated = SampleCentrelineAt(m, dynamics.state().curvatures, arcs);
    const std::vector<Vec3> previous = SampleCentrelineAt(m, last, arcs);
    const std::vector<Vec3> statics = SampleCentrelineAt(m, rest.curvatures, arcs);
    PlanarRotatingRod rod{length, radius_of_clamp, omega, rho_s, ei, -m.gravity.z()};
    rod.steps = 6000;
    const std::vector<PlanarRotatingRod::State> reference = rod.Solve();
    PlanarRotatingRod still = rod;
    still.omega = 0.0;
    const std::vector<PlanarRotatingRod::State> reference_still = still.Solve();
    double in_plane = 0.0, out_of_plane = 0.0, static_error = 0.0, change = 0.0, deflection = 0.0;
    for (int j = 0; j <= points; ++j) {
      const size_t sj = static_cast<size_t>(j);
      const PlanarRotatingRod::State& y = reference[static_cast<size_t>(j * rod.steps / points)];
      const PlanarRotatingRod::State& y0 = reference_still[static_cast<size_t>(j * rod.steps / points)];
      in_plane = std::max(in_plane, std::hypot(simulated[sj].x() - y[0], simulated[sj].z() - y[1]) / length);
      out_of_plane = std::max(out_of_plane, std::abs(simulated[sj].y()) / length);
      static_error = std::max(static_error, (statics[sj] - Vec3(y0[0], 0.0, y0[1])).norm() / length);
      change = std::max(change, (simulated[sj] - previous[sj]).norm() / length);
      deflection = std::max(deflection, (simulated[sj] - statics[sj]).norm() / length);
    }
    const char* name = run.integrator == Integrator::kBdf2 ? "bdf2" : "backward_euler";
    const PlanarRotatingRod::State& tip = reference.back();
    std::fprintf(out, "%s,%d,%.6g,%.6g,%.6e,%.6e,%.6e,%.6e,%.9f,%.9f,%.9f,%.9f,%.3e\n", name, n, omega,
                 h, in_plane, out_of_plane, static_error, deflection, simulated.back().x(),
                 simulated.back().z(), tip[0], tip[1], change);
    std::printf("rotating clamp %s n = %d h = %.4g: in-plane error %.3e L, out of plane %.3e L "
                "(at rest: %.3e L); the turning moved the shape by %.3e L; last step %.1e L\n",
                name, n, h, in_plane, out_of_plane, static_error, deflection, change);
    if (n == 40 && run.integrator == Integrator::kBdf2 && h > 1.5e-3) {
      for (int j = 0; j <= points; ++j) {
        const size_t sj = static_cast<size_t>(j);
        const PlanarRotatingRod::State& y = reference[static_cast<size_t>(j * rod.steps / points)];
        std::fprintf(shapes, "reference,%.6f,%.9f,0,%.9f\n", arcs[sj], y[0], y[1]);
        std::fprintf(shapes, "simulated,%.6f,%.9f,%.9f,%.9f\n", arcs[sj], simulated[sj].x(),
                     simulated[sj].y(), simulated[sj].z());
        std::fprintf(shapes, "static,%.6f,%.9f,%.9f,%.9f\n", arcs[sj], statics[sj].x(),
                     statics[sj].y(), statics[sj].z());
      }
    }
  }
  std::fclose(out);
  std::fclose(shapes);
}

// ---------------------------------------------------------------------------------------------
// 2. Convergence in h.

StrandModel CurlySwing() {
  StrandModel m;
  m.segment_lengths = UniformSegments(0.2, 10);
  m.section = SectionFromEccentricity(40e-6, 0.3);
  m.natural_curvature = Vec3(40.0, 0.0, 10.0);
  m.root_frame = HorizontalFrame();
  return m;
}

std::vector<Vec3> RunSwing(Integrator integrator, int steps, double duration) {
  const StrandModel m = CurlySwing();
  DynamicsOptions options;
  options.integrator = integrator;
  options.max_halvings = 0;  // a halving would change the scheme's step; none is expected
  StrandDynamics dynamics(m, options, {m.NaturalCurvatures(), VecX::Zero(3 * m.NumSegments()), 0.0});
  const double h = duration / steps;
  for (int k = 0; k < steps; ++k) {
    const StepReport report = dynamics.Step(h);
    if (!report.converged) {
      std::fprintf(stderr, "swing: %s\n", report.message.c_str());
      std::exit(1);
    }
  }
  return SampleCentreline(m, dynamics.state().curvatures, 4);
}

void TimeConvergence(const std::string& dir) {
  std::FILE* out = Open(dir + "/time_convergence.csv");
  std::fprintf(out, "scheme,steps,h,error_L,order\n");
  const double duration = 0.5, length = 0.2;
  const std::vector<Vec3> reference = RunSwing(Integrator::kBdf2, 12288, duration);
  // The swing's size: how far the tip moved.
  const std::vector<Vec3> start = RunSwing(Integrator::kBdf2, 1, 1e-9);
  std::printf("swing: the tip moved %.3f L in %.2f s\n", (reference.back() - start.back()).norm() / length, duration);
  for (Integrator integrator : {Integrator::kBackwardEuler, Integrator::kBdf2}) {
    const char* name = integrator == Integrator::kBdf2 ? "bdf2" : "backward_euler";
    double previous = 0.0;
    for (int steps : {12, 24, 48, 96, 192, 384, 768}) {
      const std::vector<Vec3> r = RunSwing(integrator, steps, duration);
      double error = 0.0;
      for (size_t j = 0; j < r.size(); ++j) error = std::max(error, (r[j] - reference[j]).norm() / length);
      const double order = previous > 0.0 ? std::log2(previous / error) : std::nan("");
      std::fprintf(out, "%s,%d,%.6e,%.6e,%.4f\n", name, steps, duration / steps, error, order);
      std::printf("swing %s h = %.3e s: error %.3e L, order %.2f\n", name, duration / steps, error, order);
      previous = error;
    }
  }
  std::fclose(out);
}

// ---------------------------------------------------------------------------------------------
// 3. Energy.

void Energy(const std::string& dir) {
  std::FILE* series = Open(dir + "/energy.csv");
  std::fprintf(series, "case,step,time,energy_above_equilibrium_rel\n");
  std::FILE* summary = Open(dir + "/energy_summary.csv");
  std::fprintf(summary, "case,steps,h,lost_percent,highest_above_start_rel,rises,largest_rise_rel,rises_before_settled,settled_step\n");
  // The unit test's strand (tests/dynamics_test.cpp, UndampedEnergyIsBoundedOverTenThousandSteps).
  StrandModel m;
  m.segment_lengths = UniformSegments(0.1, 6);
  m.section = SectionFromEccentricity(50e-6, 0.0);
  m.natural_curvature = Vec3(30.0, 0.0, 0.0);
  m.root_frame = HorizontalFrame();
  const double equilibrium = SolveStrand(m).summary.energy.total;
  struct Case {
    const char* name;
    Integrator integrator;
    double h;
    bool damped;
  };
  const Case cases[] = {{"backward_euler_1ms", Integrator::kBackwardEuler, 1e-3, false},
                        {"bdf2_1ms", Integrator::kBdf2, 1e-3, false},
                        {"backward_euler_frame", Integrator::kBackwardEuler, 1.0 / 24.0, false},
                        {"bdf2_frame", Integrator::kBdf2, 1.0 / 24.0, false},
                        {"backward_euler_frame_damped", Integrator::kBackwardEuler, 1.0 / 24.0, true},
                        {"bdf2_frame_damped", Integrator::kBdf2, 1.0 / 24.0, true}};
  for (const Case& c : cases) {
    DynamicsOptions options;
    options.integrator = c.integrator;
    options.time_step = c.h;
    options.mass_points = 3;
    if (!c.damped) {
      options.internal_friction = 0.0;
      options.air_drag = 0.0;
    }
    StrandDynamics dynamics(m, options, {m.NaturalCurvatures(), VecX::Zero(18), 0.0});
    const double initial = dynamics.Potential().total + dynamics.Kinetic();
    const double range = initial - equilibrium;
    double energy = initial, highest = initial, largest_rise = 0.0;
    int rises = 0, early_rises = 0, settled = -1;
    const int steps = 10000;
    std::fprintf(series, "%s,0,0,1\n", c.name);
    for (int k = 1; k <= steps; ++k) {
      const StepReport report = dynamics.Step();
      if (!report.converged || report.halvings > 0) {
        std::fprintf(stderr, "energy %s: step %d %s\n", c.name, k, report.message.c_str());
      }
      const double next = report.potential.total + report.kinetic;
      const bool rise = next > energy + 1e-12 * std::abs(initial);
      rises += rise;
      // Settled: within 1e-6 of the range above the equilibrium (rounding of the total energy,
      // ~1e-16 |E|, is then a visible part of what is left).
      if (settled < 0 && next - equilibrium < 1e-6 * range) settled = k;
      early_rises += rise && settled < 0;
      largest_rise = std::max(largest_rise, (next - energy) / range);
      energy = next;
      highest = std::max(highest, energy);
      if (k * c.h <= 10.0 + 1e-9 && (k % 20 == 0 || k < 100)) {  // the plotted 10 s
        std::fprintf(series, "%s,%d,%.6g,%.9e\n", c.name, k, k * c.h, (energy - equilibrium) / range);
      }
    }
    std::fprintf(summary, "%s,%d,%.6g,%.4f,%.3e,%d,%.3e,%d,%d\n", c.name, steps, c.h,
                 100.0 * (initial - energy) / range, (highest - initial) / range, rises,
                 largest_rise, early_rises, settled);
    std::printf("energy %s: %.4f%% lost over %d steps, highest %.2e above the start, %d rises "
                "(%d before it settled at step %d), largest rise %.2e of the range\n",
                c.name, 100.0 * (initial - energy) / range, steps, (highest - initial) / range, rises,
                early_rises, settled, largest_rise);
  }
  std::fclose(series);
  std::fclose(summary);
}

// ---------------------------------------------------------------------------------------------
// 4. The largest stable step per hair type against the explicit limit.

void StableSteps(const std::string& dir) {
  std::FILE* out = Open(dir + "/stable_steps.csv");
  std::fprintf(out, "origin,curl,segments,omega_max,h_explicit_all,omega_max_bending,"
                    "h_explicit_bending,h_explicit_bending_no_contact,largest_stable_h,"
                    "ratio_to_explicit_bending\n");
  Body head;
  std::string error;
  if (!Body::Create({Sphere{Vec3::Zero(), 0.1, "head"}}, {}, &head, &error)) std::exit(1);
  const auto obstacle = std::make_shared<const Body>(std::move(head));
  const double ladder[] = {1.0 / 24.0, 1.0 / 12.0, 1.0 / 6.0, 1.0 / 3.0, 0.5, 1.0};
  for (int segments : {20, 50}) {
    for (std::string_view origin : HairOrigins()) {
      for (std::string_view curl : CurlTypes()) {
        HairType type;
        if (!FindHairType(origin, curl, &type, &error)) std::exit(1);
        const StrandParameters p = SampleStrand(type, 1, 0);
        // The film-frame test's strand (tests/dynamics_test.cpp, EveryHairType...).
        StrandModel m;
        m.section = p.section;
        m.material = p.material;
        m.natural_curvature = p.natural_curvature;
        m.segment_lengths = UniformSegments(0.3, segments);
        const double angle = 1.2;
        const Vec3 normal(std::cos(angle), 0.0, std::sin(angle));
        const Vec3 down_the_scalp(std::sin(angle), 0.0, -std::cos(angle));
        m.root_position = 0.1 * normal;
        Mat3 frame;
        if (!RootFrameFromTangentNormal(0.5 * normal + down_the_scalp, Vec3(0, 1, 0), &frame, &error)) std::exit(1);
        m.root_frame = frame;
        m.contact.obstacle = obstacle;
        m.contact.clearance = 1e-3;
        // Modes at the static equilibrium (contact stiffness included).
        const StrandSolution rest = SolveStrand(m);
        const Modes modes = ComputeModes(m, rest.curvatures);
        DynamicsOptions no_rotation;
        no_rotation.rotational_inertia = false;
        const MatX mass = ComputeMassMatrix(m, rest.curvatures).Dense();
        const MatX translational = ComputeMassMatrix(m, rest.curvatures, no_rotation).Dense();
        const MatX rotational = mass - translational;
        double omega_all = 0.0, omega_bending = 0.0;
        for (Eigen::Index j = 0; j < modes.omega_squared.size(); ++j) {
          const double w = std::sqrt(std::max(0.0, modes.omega_squared(j)));
          omega_all = std::max(omega_all, w);
          const VecX v = modes.shapes.col(j);
          // Bending: most of the mode's kinetic energy (v^T M v = 1) is the centreline's.
          if (v.dot(rotational * v) < 0.5) omega_bending = std::max(omega_bending, w);
        }
        // The same without the body: the hanging equilibrium's bending modes (the contact penalty
        // adds stiff modes of its own).
        double omega_free = 0.0;
        {
          StrandModel free = m;
          free.contact.obstacle = nullptr;
          const VecX q = SolveStrand(free).curvatures;
          const Modes free_modes = ComputeModes(free, q);
          const MatX rotational_free = ComputeMassMatrix(free, q).Dense() -
                                       ComputeMassMatrix(free, q, no_rotation).Dense();
          for (Eigen::Index j = 0; j < free_modes.omega_squared.size(); ++j) {
            const VecX v = free_modes.shapes.col(j);
            if (v.dot(rotational_free * v) < 0.5) {
              omega_free = std::max(omega_free, std::sqrt(std::max(0.0, free_modes.omega_squared(j))));
            }
          }
        }
        double largest = 0.0;
        for (double h : ladder) {
          DynamicsOptions options;
          options.time_step = h;
          options.max_halvings = 0;
          StrandDynamics dynamics(m, options, {m.NaturalCurvatures(), VecX::Zero(3 * segments), 0.0});
          double energy = dynamics.Potential().total + dynamics.Kinetic();
          const double scale = std::abs(energy);
          bool ok = true;
          for (int k = 0; k < static_cast<int>(std::lround(3.0 / h)) && ok; ++k) {
            const StepReport report = dynamics.Step();
            const double next = report.potential.total + report.kinetic;
            ok = report.converged && next <= energy + 1e-9 * scale;
            energy = next;
          }
          if (!ok) break;
          largest = h;
        }
        const double h_all = 2.0 / omega_all, h_bending = 2.0 / omega_bending;
        std::fprintf(out, "%s,%s,%d,%.6e,%.6e,%.6e,%.6e,%.6e,%.6g,%.4g\n", std::string(origin).c_str(),
                     std::string(curl).c_str(), segments, omega_all, h_all, omega_bending, h_bending,
                     2.0 / omega_free, largest, largest / h_bending);
        std::printf("%s %s n = %d: explicit limit %.2e s (all modes), %.2e s (bending), %.2e s "
                    "(bending, no body); largest implicit step %.4g s (%.0fx)\n",
                    std::string(origin).c_str(), std::string(curl).c_str(), segments, h_all, h_bending,
                    2.0 / omega_free, largest, largest / h_bending);
      }
    }
  }
  std::fclose(out);
}

}  // namespace
}  // namespace ringlet

int main(int argc, char** argv) {
  const std::string dir = argc > 1 ? argv[1] : "docs/data/dynamics";
  const std::string only = argc > 2 ? argv[2] : "";
  std::filesystem::create_directories(dir);
  if (only.empty() || only == "clamp") ringlet::RotatingClamp(dir);
  if (only.empty() || only == "convergence") ringlet::TimeConvergence(dir);
  if (only.empty() || only == "energy") ringlet::Energy(dir);
  if (only.empty() || only == "stable") ringlet::StableSteps(dir);
  return 0;
}
