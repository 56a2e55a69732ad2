// Hanging curls (docs/validation.md, "Hanging curls"): a naturally curly strand clamped pointing
// straight down, swept over natural curvature, weight and eccentricity. Writes CSV files to the
// directory given on the command line and prints the tables of docs/validation.md; progress on
// stderr. Regenerate everything (CSV, tables, the three images):
//
//   cmake --build build --target hanging_curl_study && ./build/tools/hanging_curl_study docs/data/hanging_curls && /usr/bin/python3 scripts/plot_hanging_curls.py docs/data/hanging_curls docs/images
//
// Files: phase_diagram.csv (Miller et al.'s planar natural curl over (kappa0 L, w L^3/EI)),
// shapes.csv (centrelines of the pictured cases), profile.csv (local curvature along a stretched
// helix against the local helical-spring prediction), scaling.csv (curled length against weight
// and natural curvature), regularity.csv (curl irregularity against eccentricity).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "../tests/hanging_curl_measures.h"
#include "../tests/reference/helical_spring.h"
#include "ringlet/statics.h"
#include "ringlet/strand_geometry.h"

namespace {

using namespace ringlet;

constexpr double kLength = 0.25;       // m
constexpr double kRadius = 50e-6;      // mean fibre radius (m), the paper's hair
constexpr int kSegments = 100;         // uniform; the curled length moves < 0.1% from n = 50 to 200

// Root frame pointing down: t = -z, n1 = +x, n2 = t x n1 = -y.
Mat3 DownFrame() {
  Mat3 q;
  q.col(0) = Vec3(1, 0, 0);
  q.col(1) = Vec3(0, -1, 0);
  q.col(2) = Vec3(0, 0, -1);
  return q;
}

// A strand of the paper's material hanging from the origin, natural (kappa0, 0, tau0), its weight
// set through the density so that w L^3 / (E I1) = load.
StrandModel Hanging(double kappa0, double tau0, double load, double eccentricity = 0.0) {
  StrandModel m;
  m.segment_lengths = UniformSegments(kLength, kSegments);
  m.section = SectionFromEccentricity(kRadius, eccentricity);
  m.natural_curvature = Vec3(kappa0, 0.0, tau0);
  m.root_frame = DownFrame();
  const double l = m.Length();
  m.material.density = load * m.Stiffness()(0) / (l * l * l * m.section.Area() * m.gravity.norm());
  return m;
}

// Natural (kappa0, tau0) of a helix of radius r0 and pitch p0 (m).
Vec3 HelixCurvature(double r0, double p0) {
  const double h = p0 / (2.0 * std::numbers::pi);
  const double d = r0 * r0 + h * h;
  return Vec3(r0 / d, 0.0, h / d);
}

reference::HelicalSpring Spring(const StrandModel& m) {
  return {m.Stiffness()(0), m.Stiffness()(2), m.natural_curvature.head<2>().norm(),
          m.natural_curvature(2)};
}

// Curled length predicted by the local helical spring: the weight below carries the tension at
// which the curvature is half the natural one (tests/reference/helical_spring.h) (m).
double SpringCurledLength(const StrandModel& m) {
  const reference::HelicalSpring spring = Spring(m);
  return spring.Tension(0.5 * spring.kappa0) / m.WeightPerLength().norm();
}

// Smallest distance between centreline points more than half a natural turn apart (m): < 2 r
// means the strand passes through itself (ringlet has no self-contact).
double SelfDistance(const StrandModel& m, const VecX& q) {
  const int k = 4;
  const std::vector<Vec3> x = SampleCentreline(m, q, k);
  const double ds = m.Length() / (static_cast<double>(x.size()) - 1.0);
  const double omega0 = m.natural_curvature.norm();
  const int gap = static_cast<int>(std::ceil(std::numbers::pi / omega0 / ds));
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < x.size(); ++i)
    for (size_t j = i + gap; j < x.size(); ++j) best = std::min(best, (x[i] - x[j]).norm());
  return best;
}

struct Measured {
  StrandSolution solution;
  curls::CurlProfile profile;
  double stretched_fraction = 0.0;
  double out_of_plane = 0.0;
  curls::CurlRegime regime = curls::CurlRegime::kPlanar;
};

Measured Solve(const StrandModel& m) {
  Measured r;
  SolveOptions options;
  options.max_iterations = 5000;  // heavy planar curls at w L^3/EI = 10^4 need ~1500
  r.solution = SolveStrand(m, options);
  r.profile = curls::MeasureCurl(m, r.solution.curvatures);
  const double kappa0 = m.natural_curvature.head<2>().norm();
  r.stretched_fraction = curls::StretchedLength(r.profile, kappa0) / m.Length();
  r.out_of_plane = curls::OutOfPlaneDeviation(m, r.solution.curvatures);
  r.regime = curls::Classify(r.out_of_plane, r.stretched_fraction);
  return r;
}

void WriteShape(std::ofstream& out, const std::string& name, const StrandModel& m,
                const Measured& r) {
  const std::vector<Vec3> x = SampleCentreline(m, r.solution.curvatures, 6);
  for (const Vec3& p : x)
    out << name << ',' << p.x() / m.Length() << ',' << p.y() / m.Length() << ','
        << p.z() / m.Length() << '\n';
}

// Least-squares slope of log y against log x.
double LogSlope(const std::vector<double>& x, const std::vector<double>& y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(x.size());
  for (size_t i = 0; i < x.size(); ++i) {
    const double a = std::log(x[i]), b = std::log(y[i]);
    sx += a, sy += b, sxx += a * a, sxy += a * b;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: hanging_curl_study OUTPUT_DIRECTORY\n");
    return 1;
  }
  const std::filesystem::path dir = argv[1];
  std::error_code error;
  std::filesystem::create_directories(dir, error);
  if (error) {
    std::fprintf(stderr, "error: cannot create output directory '%s': %s\n", argv[1],
                 error.message().c_str());
    return 1;
  }
  const auto start = std::chrono::steady_clock::now();
  const auto open = [&](const char* name) {
    std::ofstream out(dir / name);
    if (!out) {
      std::fprintf(stderr, "error: cannot write '%s'\n", (dir / name).c_str());
      std::exit(1);
    }
    return out;
  };

  // 1. Phase diagram, Miller et al.'s rod: circular section, planar natural curl (tau0 = 0).
  {
    std::ofstream out = open("phase_diagram.csv");
    out << "kappa0_L,load,kappa0_lgb,out_of_plane,stretched_fraction,spring_curled_fraction,"
           "self_distance_over_diameter,regime,termination,restarts,min_eigenvalue\n";
    const std::vector<double> curvatures = {1, 2, 3, 5, 7, 10, 14, 20, 28, 40, 56, 80};
    const std::vector<double> loads = {1, 3, 10, 30, 100, 300, 1000, 3000, 10000};
    int done = 0;
    for (double k : curvatures) {
      for (double load : loads) {
        const StrandModel m = Hanging(k / kLength, 0.0, load);
        const Measured r = Solve(m);
        const double self = SelfDistance(m, r.solution.curvatures) / (2.0 * kRadius);
        char line[512];
        std::snprintf(line, sizeof line, "%g,%g,%.6g,%.6g,%.6g,%.6g,%.6g,%s,%s,%d,%.6g\n", k, load,
                      k / std::cbrt(load), r.out_of_plane, r.stretched_fraction,
                      SpringCurledLength(m) / kLength, self, curls::RegimeName(r.regime),
                      TerminationName(r.solution.summary.termination),
                      r.solution.summary.stability_restarts, r.solution.summary.min_eigenvalue);
        out << line;
        std::fprintf(stderr, "\rphase diagram %3d/%zu", ++done, curvatures.size() * loads.size());
      }
    }
    std::fprintf(stderr, "\n");
  }

  // 2. Pictured shapes and the stretched-helix profile.
  {
    std::ofstream shapes = open("shapes.csv");
    shapes << "case,x_over_L,y_over_L,z_over_L\n";
    struct Case {
      const char* name;
      double kappa0, tau0, load;
    };
    const Vec3 small = HelixCurvature(0.005, 0.005);
    const Case cases[] = {
        {"planar curl (k0L=5; wL3/EI=1000)", 5 / kLength, 0.0, 1000},
        {"localized helix (k0L=20; wL3/EI=1000)", 20 / kLength, 0.0, 1000},
        {"global helix (k0L=20; wL3/EI=100)", 20 / kLength, 0.0, 100},
        {"natural helix R0=p0=5mm; wL3/EI=6000", small(0), small(2), 6000},
    };
    std::printf("\n| case | regime | out of plane / L | stretched part / L | curled part / L, "
                "helical-spring prediction |\n|---|---|---:|---:|---:|\n");
    for (const Case& c : cases) {
      const StrandModel m = Hanging(c.kappa0, c.tau0, c.load);
      const Measured r = Solve(m);
      WriteShape(shapes, c.name, m, r);
      std::printf("| %s | %s | %.2e | %.3f | %.3f, %.3f |\n", c.name, curls::RegimeName(r.regime),
                  r.out_of_plane, r.stretched_fraction, 1.0 - r.stretched_fraction,
                  SpringCurledLength(m) / kLength);
      if (c.tau0 > 0) {
        std::ofstream profile = open("profile.csv");
        profile << "s_over_L,kappa_over_kappa0,spring_kappa_over_kappa0,radius_over_R0,descent\n";
        const reference::HelicalSpring spring = Spring(m);
        const double w = m.WeightPerLength().norm();
        const double r0 = 0.005;
        for (size_t i = 0; i < r.profile.s.size(); ++i) {
          const double s = r.profile.s[i];
          profile << s / kLength << ',' << r.profile.curvature[i] / spring.kappa0 << ','
                  << spring.CurvatureAtTension(w * (kLength - s)) / spring.kappa0 << ','
                  << r.profile.radius[i] / r0 << ',' << r.profile.descent[i] << '\n';
        }
      }
    }
  }

  // 3. Scaling of the curled length: weight sweep and natural-curvature sweep (same helix shape,
  // pitch = radius, scaled), natural helix, circular section.
  {
    std::ofstream out = open("scaling.csv");
    out << "sweep,omega0_L,load,curled_fraction,spring_curled_fraction\n";
    std::printf("\n| sweep | values | fitted exponent of the curled length | helical spring "
                "(exact in the slowly varying limit) | curled length / prediction |\n"
                "|---|---|---:|---:|---:|\n");
    for (int sweep = 0; sweep < 2; ++sweep) {
      std::vector<double> x, y;
      double worst = 1.0;
      const std::vector<double> values = sweep == 0 ? std::vector<double>{3000, 4000, 5333, 7111}
                                                    : std::vector<double>{0.0045, 0.005, 0.0055, 0.006};
      for (double v : values) {
        const Vec3 omega0 = HelixCurvature(sweep == 0 ? 0.005 : v, sweep == 0 ? 0.005 : v);
        const double load = sweep == 0 ? v : 4000;
        const StrandModel m = Hanging(omega0(0), omega0(2), load);
        const Measured r = Solve(m);
        const double curled = 1.0 - r.stretched_fraction;
        const double predicted = SpringCurledLength(m) / kLength;
        out << (sweep == 0 ? "weight" : "curvature") << ',' << omega0.norm() * kLength << ','
            << load << ',' << curled << ',' << predicted << '\n';
        x.push_back(sweep == 0 ? load : omega0.norm());
        y.push_back(curled);
        if (std::abs(curled / predicted - 1.0) > std::abs(worst - 1.0)) worst = curled / predicted;
      }
      std::printf("| %s | %s | %.3f | %s | worst %.3f |\n",
                  sweep == 0 ? "weight w L^3/EI" : "natural curvature |Omega0| (R0 = p0)",
                  sweep == 0 ? "3000, 4000, 5333, 7111 (R0 = p0 = 5 mm)" : "R0 = p0 = 4.5, 5, 5.5, 6 mm (w L^3/EI = 4000)",
                  LogSlope(x, y), sweep == 0 ? "-1" : "+2", worst);
    }
  }

  // 4. Regularity against eccentricity (Bertails et al. 2005, Fig. 2 left): a natural helix of
  // radius and pitch 1 cm, 25 cm long, curvature about the soft axis n1. "same fibre": the
  // density and mean radius are fixed, so the load w L^3/(E I1) grows as 1/sqrt(1 - e^2);
  // "same load": the density is adjusted to keep w L^3/(E I1).
  {
    std::ofstream out = open("regularity.csv");
    out << "series,base_load,eccentricity,load,irregularity_lower_half,irregularity_whole,"
           "stretched_fraction\n";
    std::printf("\n| series | w L^3/(E I) at e = 0 | irregularity (lower half), e = 0 / 0.3 / "
                "0.6 / 0.8 / 0.9 |\n|---|---:|---|\n");
    const Vec3 omega0 = HelixCurvature(0.01, 0.01);
    for (int same_load = 0; same_load < 2; ++same_load) {
      for (double base : {30.0, 300.0, 1000.0}) {
        std::string row;
        for (double e : {0.0, 0.3, 0.6, 0.8, 0.9}) {
          StrandModel m = Hanging(omega0(0), omega0(2), base, e);
          if (!same_load) {
            // Same fibre: the density of the circular strand at this base load.
            const StrandModel circle = Hanging(omega0(0), omega0(2), base, 0.0);
            m.material.density = circle.material.density;
          }
          const Measured r = Solve(m);
          const double lower = curls::CurlIrregularity(r.profile, omega0.norm(), kLength / 2, kLength);
          const double whole = curls::CurlIrregularity(r.profile, omega0.norm(), 0.0, kLength);
          char line[256];
          std::snprintf(line, sizeof line, "%s,%g,%g,%.6g,%.6g,%.6g,%.6g\n",
                        same_load ? "same load" : "same fibre", base, e, m.GravityParameter(), lower,
                        whole, r.stretched_fraction);
          out << line;
          char cell[32];
          std::snprintf(cell, sizeof cell, "%s%.4f", row.empty() ? "" : " / ", lower);
          row += cell;
          std::fprintf(stderr, "\rregularity %s base %g e %.1f", same_load ? "same load " : "same fibre",
                       base, e);
        }
        std::printf("| %s | %g | %s |\n", same_load ? "same load" : "same fibre", base, row.c_str());
      }
    }
    std::fprintf(stderr, "\n");
  }
  std::fprintf(stderr, "done in %.1f s\n",
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return 0;
}
