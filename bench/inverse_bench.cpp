// Inverse statics on a full head (issue 13, item 9; docs/benchmarks.md): 10,000 target strands
// of 50 segments fitted, inverted and verified, and the inversion alone. Targets: the equilibria
// of the wavy example hairstyle with 10,000 masters of 50 segments (body contact), written as
// float polylines without frames, as a .hair file holds them: (0) 4 points per segment (201
// points, the breaks at points, what `ringlet groom` writes) and (1) 100 points equally spaced
// in arc length (no point on most breaks: the fit is approximate; the 2024 paper's strands have
// 100 vertices). Compare: "Rest shape optimization for sag-free discrete elastic rods" (2024),
// 11.2 s for 1.9K strands x 100 vertices. Wall time (UseRealTime): the work is TBB-parallel.
//
//   cmake -S . -B build-bench -G Ninja -DCMAKE_BUILD_TYPE=Release -DRINGLET_BUILD_BENCHMARKS=ON
//   cmake --build build-bench --target ringlet_inverse_bench
//   ./build-bench/bench/ringlet_inverse_bench
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "ringlet/hairstyle.h"
#include "ringlet/hairstyle_json.h"
#include "ringlet/helix.h"
#include "ringlet/inverse.h"
#include "ringlet/solve_strands.h"
#include "ringlet/strand_geometry.h"

namespace ringlet {
namespace {

constexpr int kStrands = 10000;
constexpr int kSegments = 50;

// The exact centreline of (model, q) at arc lengths s (ascending, within [0, L]).
std::vector<Vec3> PointsAtArcLengths(const StrandModel& model, const VecX& q,
                                     const std::vector<double>& s) {
  std::vector<Vec3> out;
  Mat3 frame = model.root_frame;
  Vec3 r = model.root_position;
  double start = 0.0;
  size_t k = 0;
  for (int i = 0; i < model.NumSegments(); ++i) {
    const Vec3 omega = q.segment<3>(3 * i);
    const double l = model.segment_lengths[static_cast<size_t>(i)];
    const bool last = i + 1 == model.NumSegments();
    while (k < s.size() && (s[k] <= start + l || last)) {
      out.push_back(r + frame * HelixChord(omega, std::min(s[k] - start, l)));
      ++k;
    }
    const HelixSegment seg = EvaluateHelixSegment(omega, l);
    r += frame * seg.chord;
    frame = frame * seg.rotation;
    start += l;
  }
  return out;
}

struct Head {
  std::vector<StrandModel> models;  // the masters: section, material, contact
  std::vector<std::vector<Vec3>> polylines[2];
  double setup_seconds = 0.0;
};

const Head& GetHead() {
  static const Head head = [] {
    const auto start = std::chrono::steady_clock::now();
    Head h;
    Hairstyle style;
    std::string error;
    if (!LoadHairstyle(std::string(RINGLET_EXAMPLES_DIR) + "/hairstyles/wavy_mannequin.json", &style,
                       &error)) {
      std::fprintf(stderr, "%s\n", error.c_str());
      std::abort();
    }
    style.roots.count = kStrands;
    style.segments = kSegments;
    HairstyleMasters masters;
    if (!BuildMasters(style, &masters, &error)) {
      std::fprintf(stderr, "%s\n", error.c_str());
      std::abort();
    }
    const std::vector<StrandSolution> solutions = SolveStrands(masters.models, style.solver);
    for (size_t i = 0; i < solutions.size(); ++i) {
      const StrandModel& m = masters.models[i];
      const VecX& q = solutions[i].curvatures;
      std::vector<Vec3> points = SampleCentreline(m, q, 4);
      std::vector<double> s(100);
      for (int j = 0; j < 100; ++j) s[static_cast<size_t>(j)] = m.Length() * j / 99.0;
      std::vector<Vec3> uniform = PointsAtArcLengths(m, q, s);
      for (auto* p : {&points, &uniform}) {
        for (Vec3& x : *p) x = x.cast<float>().cast<double>();  // as a file holds them
      }
      h.models.push_back(m);
      h.polylines[0].push_back(std::move(points));
      h.polylines[1].push_back(std::move(uniform));
    }
    std::chrono::duration<double> d = std::chrono::steady_clock::now() - start;
    h.setup_seconds = d.count();
    std::fprintf(stderr, "setup: %zu masters of %d segments solved and sampled in %.1f s\n",
                 h.models.size(), kSegments, h.setup_seconds);
    return h;
  }();
  return head;
}

FitOptions Fit50() {
  FitOptions o;
  o.segments = kSegments;
  return o;
}

// The models of the fitted targets: the masters' physics, the fits' geometry.
std::vector<StrandModel> FittedModels(const Head& head, const std::vector<HelixFit>& fits,
                                      std::vector<VecX>* targets) {
  std::vector<StrandModel> models = head.models;
  targets->clear();
  for (size_t i = 0; i < models.size(); ++i) {
    models[i].segment_lengths = fits[i].segment_lengths;
    models[i].root_position = fits[i].root_position;
    models[i].root_frame = fits[i].root_frame;
    models[i].rest_curvatures.resize(0);
    targets->push_back(fits[i].curvatures);
  }
  return models;
}

void FitCounters(benchmark::State& state, const std::vector<HelixFit>& fits) {
  double worst = 0.0, iterations = 0.0;
  for (const HelixFit& f : fits) {
    worst = std::max(worst, f.max_distance / f.length);
    iterations += f.iterations;
  }
  state.counters["fit_max_per_L"] = worst;
  state.counters["fit_iterations_per_strand"] = iterations / static_cast<double>(fits.size());
}

void InverseCounters(benchmark::State& state, const std::vector<StrandModel>& models,
                     const std::vector<InverseResult>& results) {
  int unstable = 0, fallbacks = 0;
  double worst = 0.0, worst_stable = 0.0;
  for (size_t i = 0; i < results.size(); ++i) {
    unstable += results[i].stable ? 0 : 1;
    fallbacks += results[i].support_fallback ? 1 : 0;
    const double d = results[i].deviation / models[i].Length();
    worst = std::max(worst, d);
    if (results[i].stable) worst_stable = std::max(worst_stable, d);
  }
  state.counters["unstable"] = unstable;
  state.counters["support_fallbacks"] = fallbacks;
  // All targets (an unstable one moves to the closest stable equilibrium), and the stable ones.
  state.counters["deviation_max_per_L"] = worst;
  state.counters["deviation_stable_max_per_L"] = worst_stable;
}

// The fit alone: 10,000 polylines, 50 segments each, no root frames.
void BM_Fit(benchmark::State& state) {
  const Head& head = GetHead();
  const auto& polylines = head.polylines[state.range(0)];
  std::vector<HelixFit> fits;
  for (auto _ : state) {
    std::string why;
    if (!FitPiecewiseHelices(polylines, Fit50(), 0, &fits, nullptr, &why)) std::abort();
    benchmark::DoNotOptimize(fits.data());
  }
  FitCounters(state, fits);
  state.SetLabel(state.range(0) == 0 ? "4 points per segment" : "100 points");
}
BENCHMARK(BM_Fit)->DenseRange(0, 1)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

// The inversion alone: rest shapes (the closed form) and the stability certificate (the exact
// Hessian's block LDL^T), Kirchhoff's residual; no forward solve.
void BM_Invert(benchmark::State& state) {
  const Head& head = GetHead();
  std::vector<HelixFit> fits;
  std::string why;
  if (!FitPiecewiseHelices(head.polylines[0], Fit50(), 0, &fits, nullptr, &why)) std::abort();
  std::vector<VecX> targets;
  const std::vector<StrandModel> models = FittedModels(head, fits, &targets);
  InverseOptions options;
  options.verify = false;
  options.naive = false;
  std::vector<InverseResult> results;
  for (auto _ : state) {
    results = InvertStrands(models, targets, options);
    benchmark::DoNotOptimize(results.data());
  }
  InverseCounters(state, models, results);
}
BENCHMARK(BM_Invert)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// Everything (the 10 s target): fit, inversion, certificate and the forward verification from
// the target (no naive comparison).
void BM_FitInvertVerify(benchmark::State& state) {
  const Head& head = GetHead();
  const auto& polylines = head.polylines[state.range(0)];
  InverseOptions options;
  options.naive = false;
  std::vector<HelixFit> fits;
  std::vector<StrandModel> models;
  std::vector<InverseResult> results;
  for (auto _ : state) {
    std::string why;
    if (!FitPiecewiseHelices(polylines, Fit50(), 0, &fits, nullptr, &why)) std::abort();
    std::vector<VecX> targets;
    models = FittedModels(head, fits, &targets);
    results = InvertStrands(models, targets, options);
    benchmark::DoNotOptimize(results.data());
  }
  FitCounters(state, fits);
  InverseCounters(state, models, results);
  state.SetLabel(state.range(0) == 0 ? "4 points per segment" : "100 points");
}
BENCHMARK(BM_FitInvertVerify)->DenseRange(0, 1)->Unit(benchmark::kMillisecond)->UseRealTime()
    ->Iterations(1);

}  // namespace
}  // namespace ringlet

BENCHMARK_MAIN();
