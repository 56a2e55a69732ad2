// Convergence of the 3D strand solver to the planar heavy elastica: tip error against the
// independent shooting reference (tests/reference/heavy_elastica.h) for a horizontally clamped,
// straight strand of circular section, over loads w L^3 / EI and segment counts, with uniform and
// graded segments (tests/reference/grading_rule.h).
//
//   convergence_study OUTPUT.csv
//
// writes one CSV row per (load, grading, n) and prints markdown tables: the errors, and per load
// the n needed for a tip error of 1e-4 L and the observed order of convergence. docs/validation.md
// shows the result; scripts/plot_convergence.py plots the CSV.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <system_error>
#include <vector>

#include "../tests/reference/grading_rule.h"
#include "../tests/reference/heavy_elastica.h"
#include "ringlet/statics.h"
#include "ringlet/strand_geometry.h"
#include "ringlet/strand_model.h"

namespace {

using ringlet::Mat3;
using ringlet::StrandModel;
using ringlet::Vec3;

constexpr double kLoads[] = {0.5, 10.0, 100.0, 1000.0};
constexpr int kSegments[] = {5, 10, 15, 20, 30, 50, 80, 120};
// The target tip error (units of L).
constexpr double kTarget = 1e-4;
// Orders are fitted on n >= this (the smallest n are pre-asymptotic).
constexpr int kMinFitSegments = 10;

struct Row {
  double load = 0.0;
  bool graded = false;
  int n = 0;
  double ratio = 1.0;
  double tip_error = 0.0;  // |tip - reference tip| / L
  int iterations = 0;
  double seconds = 0.0;
  bool converged = false;
};

// A horizontally clamped strand (t = +x, n1 = +z, n2 = -y: bending in the x-z plane is bending
// about n2) of radius 50 um with the paper's material, its length chosen for the load.
StrandModel MakeModel(double load, int n, double ratio) {
  StrandModel m;
  m.section = ringlet::SectionFromEccentricity(50e-6, 0.0);
  m.root_frame.col(0) = Vec3(0, 0, 1);
  m.root_frame.col(1) = Vec3(0, -1, 0);
  m.root_frame.col(2) = Vec3(1, 0, 0);
  const double stiffness = m.material.young_modulus * m.section.I2();
  const double weight = m.material.density * m.section.Area() * m.gravity.norm();
  const double length = std::cbrt(load * stiffness / weight);
  m.segment_lengths = ringlet::GradedSegments(length, n, ratio);
  return m;
}

// Least-squares slope of log(error) against log(n), negated: the observed order.
double FitOrder(const std::vector<Row>& rows) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int count = 0;
  for (const Row& r : rows) {
    if (r.n < kMinFitSegments || !(r.tip_error > 0.0)) continue;
    const double x = std::log(r.n), y = std::log(r.tip_error);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    ++count;
  }
  if (count < 2) return std::nan("");
  return -(count * sxy - sx * sy) / (count * sxx - sx * sx);
}

// The smallest n of the study reaching the target, or 0.
int SmallestReaching(const std::vector<Row>& rows) {
  for (const Row& r : rows) {
    if (r.converged && r.tip_error <= kTarget) return r.n;
  }
  return 0;
}

// n for the target from the fitted power law error = C n^-p: n = (C / target)^(1/p), with C the
// least-squares intercept for the given order p.
double EstimatedNeeded(const std::vector<Row>& rows, double order) {
  double sum = 0.0;
  int count = 0;
  for (const Row& r : rows) {
    if (r.n < kMinFitSegments || !(r.tip_error > 0.0)) continue;
    sum += std::log(r.tip_error) + order * std::log(r.n);
    ++count;
  }
  if (count == 0) return std::nan("");
  const double log_c = sum / count;
  return std::exp((log_c - std::log(kTarget)) / order);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUTPUT.csv\n", argv[0]);
    return 1;
  }
  const std::filesystem::path output = argv[1];

  std::vector<Row> rows;
  for (double load : kLoads) {
    const ringlet::reference::HeavyElasticaSolution reference =
        ringlet::reference::SolveHeavyElastica({load, 0.0, 0.0});
    if (!reference.converged || !reference.stable) {
      std::fprintf(stderr, "reference failed at load %g: %s\n", load, reference.message.c_str());
      return 2;
    }
    for (bool graded : {false, true}) {
      const double ratio = graded ? ringlet::reference::SuggestedGradingRatio(load) : 1.0;
      for (int n : kSegments) {
        const StrandModel model = MakeModel(load, n, ratio);
        const auto start = std::chrono::steady_clock::now();
        const ringlet::StrandSolution solution = ringlet::SolveStrand(model);
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const Vec3 tip = ringlet::ComputeGeometry(model, solution.curvatures).points.back();
        const double length = model.Length();
        Row row;
        row.load = load;
        row.graded = graded;
        row.n = n;
        row.ratio = ratio;
        row.tip_error = std::hypot(tip.x() / length - reference.tip_x, tip.y() / length,
                                   tip.z() / length - reference.tip_z);
        row.iterations = solution.summary.iterations;
        row.seconds = seconds;
        row.converged = solution.summary.Converged();
        if (!row.converged) {
          std::fprintf(stderr, "warning: load %g, %s, n = %d: %s\n", load,
                       graded ? "graded" : "uniform", n, solution.summary.message.c_str());
        }
        rows.push_back(row);
      }
    }
  }

  // CSV, written to a temporary file and renamed: nothing half-written.
  std::filesystem::path temporary = output;
  temporary += ".tmp";
  {
    std::ofstream csv(temporary);
    if (!csv) {
      std::fprintf(stderr, "cannot write %s\n", temporary.c_str());
      return 1;
    }
    csv << "load,grading,n,ratio,tip_error_over_L,iterations,seconds,converged\n";
    char line[256];
    for (const Row& r : rows) {
      std::snprintf(line, sizeof(line), "%g,%s,%d,%.6g,%.6e,%d,%.6e,%d\n", r.load,
                    r.graded ? "graded" : "uniform", r.n, r.ratio, r.tip_error, r.iterations,
                    r.seconds, r.converged ? 1 : 0);
      csv << line;
    }
    if (!csv.flush()) {
      std::fprintf(stderr, "cannot write %s\n", temporary.c_str());
      return 1;
    }
  }
  std::error_code error;
  std::filesystem::rename(temporary, output, error);
  if (error) {
    std::fprintf(stderr, "cannot rename %s to %s: %s\n", temporary.c_str(), output.c_str(),
                 error.message().c_str());
    return 1;
  }

  // The errors, one line per (load, n).
  std::printf(
      "| wL^3/EI | n | uniform: tip error / L | iterations | graded (ratio): tip error / L "
      "| iterations |\n|---|---|---|---|---|---|\n");
  for (double load : kLoads) {
    for (int n : kSegments) {
      const Row* u = nullptr;
      const Row* g = nullptr;
      for (const Row& r : rows) {
        if (r.load == load && r.n == n) (r.graded ? g : u) = &r;
      }
      std::printf("| %g | %d | %.2e | %d | %.2e (%.3g) | %d |\n", load, n, u->tip_error,
                  u->iterations, g->tip_error, g->ratio, g->iterations);
    }
  }
  // Per load: n needed for the target and the observed order.
  std::printf(
      "\n| wL^3/EI | graded ratio | n for 1e-4 L, uniform (fit) | n for 1e-4 L, graded (fit) "
      "| order, uniform | order, graded |\n|---|---|---|---|---|---|\n");
  for (double load : kLoads) {
    std::vector<Row> uniform, graded;
    for (const Row& r : rows) {
      if (r.load == load) (r.graded ? graded : uniform).push_back(r);
    }
    const double p_u = FitOrder(uniform), p_g = FitOrder(graded);
    const int n_u = SmallestReaching(uniform), n_g = SmallestReaching(graded);
    const std::string more = "> " + std::to_string(kSegments[std::size(kSegments) - 1]);
    const std::string su = n_u > 0 ? std::to_string(n_u) : more;
    const std::string sg = n_g > 0 ? std::to_string(n_g) : more;
    std::printf("| %g | %.3g | %s (%.0f) | %s (%.0f) | %.2f | %.2f |\n", load, graded[0].ratio,
                su.c_str(), std::ceil(EstimatedNeeded(uniform, p_u)), sg.c_str(),
                std::ceil(EstimatedNeeded(graded, p_g)), p_u, p_g);
  }
  return 0;
}
