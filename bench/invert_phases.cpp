// Where `ringlet invert --body` spends its time, phase by phase (issue 25, item 10;
// docs/benchmarks.md, "Inverse statics of the full head with body contact"). A scene benchmark,
// not a Google Benchmark: one run of each phase on every strand of a .hair file (or every k-th),
// with the body of a body file, as `ringlet invert TARGET --body BODY` does:
//
//   body     LoadBody (the meshes' distance grid)
//   fit      FitPiecewiseHelices (automatic segment count, tolerance 1e-3 L)
//   invert   InvertStrands without verification or naive solve: support forces (NNLS), the
//            closed form, the stability certificate and its smallest eigenvalue
//   verify   the same with the verification (Kirchhoff residual, forward solve from the target);
//            the phase's time is the difference
//   naive    the same with the naive rest shape's forward solve too (the default of invert)
//   compare  verification and naive solve by L-BFGS and by Newton, strand by strand: how far
//            apart their equilibria are (the change of InverseOptions::solver, docs/benchmarks.md)
//
// BODY "-": no body. --method auto|lbfgs|newton|bfgs: the forward solves' method (default: the
// InverseOptions default, Newton). --dump FILE: every fit's segment count and distances.
// --against FILE: compare the fits with an earlier --dump of the same strands (another build):
// how many segment counts differ, and the ratios of the largest and RMS distances.
// Prints, per phase, wall and process CPU seconds (user + system, all threads) and per-strand
// counters (forward and naive iterations, unstable, unconverged, fallbacks).
//
//   ./build/bench/ringlet_invert_phases_bench /tmp/wavy/strands.hair examples/bodies/head.json
//       [--step K] [--threads N] [--phases fit,invert,verify,naive] [--dump F] [--against F]
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "ringlet/body.h"
#include "ringlet/body_json.h"
#include "ringlet/hair_type.h"
#include "ringlet/inverse.h"
#include "ringlet/strand_targets.h"

namespace ringlet {
namespace {

double CpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

struct Clock {
  std::chrono::steady_clock::time_point wall = std::chrono::steady_clock::now();
  double cpu = CpuSeconds();
  void Report(const char* phase, size_t strands) const {
    const double w = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count();
    const double c = CpuSeconds() - cpu;
    std::printf("%-8s wall %8.2f s  cpu %8.2f s  (%.3f ms cpu per strand)\n", phase, w, c,
                1e3 * c / static_cast<double>(std::max<size_t>(strands, 1)));
    std::fflush(stdout);
  }
};

void Counters(const char* phase, const std::vector<InverseResult>& results) {
  long forward = 0, naive = 0, forward_evaluations = 0, naive_evaluations = 0;
  int unstable = 0, unconverged = 0, fallbacks = 0, supported = 0;
  for (const InverseResult& r : results) {
    forward += r.forward.iterations;
    naive += r.naive_forward.iterations;
    forward_evaluations += r.forward.evaluations;
    naive_evaluations += r.naive_forward.evaluations;
    unstable += r.stable ? 0 : 1;
    unconverged += r.stable && !r.forward.Converged() && r.forward.iterations > 0 ? 1 : 0;
    fallbacks += r.support_fallback ? 1 : 0;
    supported += r.supported_samples > 0 ? 1 : 0;
  }
  const double n = static_cast<double>(std::max<size_t>(results.size(), 1));
  std::vector<int> e;
  for (const InverseResult& r : results) e.push_back(r.naive_forward.evaluations);
  std::sort(e.begin(), e.end());
  if (!e.empty()) {
    std::printf("         naive evaluations: median %d, 90%% %d, 99%% %d, max %d; sum of top 10%% %.0f%%\n",
                e[e.size() / 2], e[e.size() * 9 / 10], e[e.size() * 99 / 100], e.back(),
                100.0 * [&] { long t = 0, a = 0; for (size_t i = 0; i < e.size(); ++i) { a += e[i]; if (i >= e.size() * 9 / 10) t += e[i]; } return a ? double(t) / double(a) : 0.0; }());
  }
  std::printf(
      "         %s: forward %.1f iterations (%.1f evaluations), naive %.1f (%.1f) per strand; "
      "%d unstable, %d stable but unconverged, %d fallbacks, %d with supports\n",
      phase, static_cast<double>(forward) / n, static_cast<double>(forward_evaluations) / n,
      static_cast<double>(naive) / n, static_cast<double>(naive_evaluations) / n, unstable,
      unconverged, fallbacks, supported);
}

int Main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s TARGET.hair BODY.json|- [--step K] [--threads N] "
                         "[--phases fit,invert,verify,naive,compare] [--method M] [--dump FILE]\n",
                 argv[0]);
    return 1;
  }
  int step = 1, threads = 0;
  std::string phases = "fit,invert,verify,naive";
  std::string method;  // empty: InverseOptions' default
  std::string dump;  // per strand: segments, fit max and RMS distance (m), one line each
  std::string against;  // an earlier dump to compare with
  for (int a = 3; a + 1 < argc; a += 2) {
    if (!std::strcmp(argv[a], "--step")) step = std::max(1, std::atoi(argv[a + 1]));
    if (!std::strcmp(argv[a], "--threads")) threads = std::atoi(argv[a + 1]);
    if (!std::strcmp(argv[a], "--phases")) phases = argv[a + 1];
    if (!std::strcmp(argv[a], "--method")) method = argv[a + 1];
    if (!std::strcmp(argv[a], "--dump")) dump = argv[a + 1];
    if (!std::strcmp(argv[a], "--against")) against = argv[a + 1];
  }
  const auto has = [&phases](const char* p) { return phases.find(p) != std::string::npos; };
  std::string error;

  Clock body_clock;
  // "-": no body (the fit alone, or inversion without contact).
  std::shared_ptr<Body> body = std::strcmp(argv[2], "-") ? std::make_shared<Body>() : nullptr;
  if (body && !LoadBody(argv[2], body.get(), &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  body_clock.Report("body", 1);

  HairCurves curves;
  if (!ReadStrandTargets(argv[1], StrandTargetOptions{}, &curves, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  std::vector<std::vector<Vec3>> polylines;
  size_t offset = 0;
  for (size_t k = 0; k < curves.point_counts.size(); ++k) {
    if (k % static_cast<size_t>(step) == 0) {
      std::vector<Vec3> p;
      for (uint32_t j = 0; j < curves.point_counts[k]; ++j) {
        p.push_back(curves.points[offset + j].cast<double>());
      }
      polylines.push_back(std::move(p));
    }
    offset += curves.point_counts[k];
  }
  const size_t count = polylines.size();
  std::printf("%zu strands (every %d-th of %s), %d threads\n", count, step, argv[1], threads);

  Clock fit_clock;
  std::vector<HelixFit> fits;
  if (!FitPiecewiseHelices(polylines, FitOptions{}, threads, &fits, nullptr, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    return 1;
  }
  if (has("fit")) fit_clock.Report("fit", count);
  if (!dump.empty()) {
    FILE* f = std::fopen(dump.c_str(), "w");
    for (const HelixFit& fit : fits) {
      std::fprintf(f, "%d %.17g %.17g\n", fit.NumSegments(), fit.max_distance, fit.rms_distance);
    }
    std::fclose(f);
  }
  {
    // The fits: segment counts, largest and mean RMS distance (units of each strand's length).
    std::vector<int> histogram(kMaxSegments + 1, 0);
    double worst = 0.0, rms = 0.0;
    for (const HelixFit& fit : fits) {
      ++histogram[static_cast<size_t>(fit.NumSegments())];
      worst = std::max(worst, fit.max_distance / fit.length);
      rms += fit.rms_distance / fit.length / static_cast<double>(count);
    }
    std::printf("         fits: largest distance %.4g L, mean RMS %.4g L; segments:", worst, rms);
    for (size_t n = 0; n < histogram.size(); ++n) {
      if (histogram[n] > 0) std::printf(" %zu x %d", n, histogram[n]);
    }
    std::printf("\n");
  }
  if (!against.empty()) {
    FILE* f = std::fopen(against.c_str(), "r");
    if (!f) {
      std::fprintf(stderr, "--against %s: cannot open\n", against.c_str());
      return 1;
    }
    int differ = 0, fewer = 0, compared = 0;
    double max_ratio = 0.0, min_ratio = 1e300, rms_ratio = 0.0;
    std::vector<double> ratios;
    for (const HelixFit& fit : fits) {
      int n = 0;
      double max_distance = 0.0, rms_distance = 0.0;
      if (std::fscanf(f, "%d %lf %lf", &n, &max_distance, &rms_distance) != 3) {
        std::fprintf(stderr, "--against %s: fewer strands than fitted\n", against.c_str());
        std::fclose(f);
        return 1;
      }
      if (n != fit.NumSegments()) {
        ++differ;
        fewer += fit.NumSegments() < n ? 1 : 0;
        continue;
      }
      if (!(max_distance > 0.0 && rms_distance > 0.0)) continue;
      const double r = fit.max_distance / max_distance;
      ratios.push_back(r);
      max_ratio = std::max(max_ratio, r);
      min_ratio = std::min(min_ratio, r);
      rms_ratio += fit.rms_distance / rms_distance;
      ++compared;
    }
    std::fclose(f);
    std::sort(ratios.begin(), ratios.end());
    std::printf("against %s: %d segment counts differ (%d fewer); same counts: largest distance "
                "ratio median %.4f, %.3f to %.3f; mean RMS ratio %.4f\n",
                against.c_str(), differ, fewer, ratios.empty() ? 0.0 : ratios[ratios.size() / 2],
                min_ratio, max_ratio, compared ? rms_ratio / compared : 0.0);
  }
  long segments = 0;
  std::vector<StrandModel> models(count);
  std::vector<VecX> targets(count);
  for (size_t i = 0; i < count; ++i) {
    StrandModel& m = models[i];
    m.segment_lengths = fits[i].segment_lengths;
    m.root_position = fits[i].root_position;
    m.root_frame = fits[i].root_frame;
    if (!ApplyInverseHairType("", i, &m, &error)) return 1;
    m.contact.obstacle = body;
    targets[i] = fits[i].curvatures;
    segments += m.NumSegments();
  }
  std::printf("         %.2f segments per strand\n",
              static_cast<double>(segments) / static_cast<double>(count));

  InverseOptions options;
  options.verify = false;
  options.naive = false;
  if (method == "auto") options.solver.method = Method::kAuto;
  if (method == "newton") options.solver.method = Method::kNewton;
  if (method == "lbfgs") options.solver.method = Method::kLbfgs;
  if (method == "bfgs") options.solver.method = Method::kBfgs;
  if (has("invert")) {
    Clock c;
    const std::vector<InverseResult> r = InvertStrands(models, targets, options, threads);
    c.Report("invert", count);
    Counters("invert", r);
  }
  options.verify = true;
  if (has("verify")) {
    Clock c;
    const std::vector<InverseResult> r = InvertStrands(models, targets, options, threads);
    c.Report("+verify", count);
    Counters("verify", r);
  }
  options.naive = true;
  if (has("naive")) {
    Clock c;
    const std::vector<InverseResult> r = InvertStrands(models, targets, options, threads);
    c.Report("+naive", count);
    Counters("naive", r);
  }
  if (has("compare")) {
    // The equilibria of both methods, strand by strand: how far apart (units of L).
    InverseOptions a = options, b = options;
    a.solver.method = Method::kLbfgs;
    b.solver.method = Method::kNewton;
    Clock ca;
    const std::vector<InverseResult> ra = InvertStrands(models, targets, a, threads);
    ca.Report("lbfgs", count);
    Clock cb;
    const std::vector<InverseResult> rb = InvertStrands(models, targets, b, threads);
    cb.Report("newton", count);
    double worst_naive = 0.0, worst_forward = 0.0, worst_dev = 0.0;
    int differ = 0;
    for (size_t i = 0; i < count; ++i) {
      const double l = models[i].Length();
      const double dn = CentrelineDeviation(models[i], ra[i].naive_equilibrium,
                                            rb[i].naive_equilibrium, 4) / l;
      const double df = CentrelineDeviation(models[i], ra[i].equilibrium, rb[i].equilibrium, 4) / l;
      worst_naive = std::max(worst_naive, dn);
      worst_forward = std::max(worst_forward, df);
      worst_dev = std::max(worst_dev, std::abs(ra[i].naive_deviation - rb[i].naive_deviation) / l);
      if (dn > 1e-6 || df > 1e-6) {
        ++differ;
        std::printf("  strand %zu: naive %.3g L (lbfgs %s %d it, newton %s %d it; sag %.3g / %.3g L), "
                    "forward %.3g L (stable %d)\n", i, dn,
                    TerminationName(ra[i].naive_forward.termination), ra[i].naive_forward.iterations,
                    TerminationName(rb[i].naive_forward.termination), rb[i].naive_forward.iterations,
                    ra[i].naive_deviation / l, rb[i].naive_deviation / l, df, ra[i].stable ? 1 : 0);
      }
    }
    std::printf("compare: naive equilibria differ by %.3g L at most, forward %.3g L, naive "
                "deviation %.3g L; %d strands differ by > 1e-6 L\n",
                worst_naive, worst_forward, worst_dev, differ);
  }
  return 0;
}

}  // namespace
}  // namespace ringlet

int main(int argc, char** argv) { return ringlet::Main(argc, argv); }
