// Micro benchmarks of one strand: energy+gradient evaluation and full solves (issue 2, item 9).
// Build with -DRINGLET_BUILD_BENCHMARKS=ON; results and machine in docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include "ringlet/energy.h"
#include "ringlet/statics.h"

namespace ringlet {
namespace {

// A 20-cm hair of radius 50 um with the paper's material, clamped horizontally (tangent +x,
// n1 = +z): straight, or curly with kappa^0 = 50 1/m, tau^0 = 10 1/m.
StrandModel Hair(int segments, bool curly) {
  StrandModel m;
  m.segment_lengths = UniformSegments(0.2, segments);
  m.section = SectionFromEccentricity(50e-6, 0.0);
  if (curly) m.natural_curvature = Vec3(50.0, 0.0, 10.0);
  m.root_frame.col(0) = Vec3(0, 0, 1);
  m.root_frame.col(1) = Vec3(0, -1, 0);
  m.root_frame.col(2) = Vec3(1, 0, 0);
  return m;
}

void BM_EnergyGradient(benchmark::State& state) {
  const StrandModel m = Hair(static_cast<int>(state.range(0)), state.range(1) != 0);
  StrandEnergy energy(m);
  VecX q = m.NaturalCurvatures();
  q(1) += 1.0;
  VecX g;
  for (auto _ : state) {
    benchmark::DoNotOptimize(energy.Evaluate(q, &g));
    benchmark::ClobberMemory();
  }
  state.counters["segments"] = static_cast<double>(state.range(0));
}
BENCHMARK(BM_EnergyGradient)
    ->ArgsProduct({{15, 30, 60, 100, 120}, {0, 1}})
    ->ArgNames({"n", "curly"});

template <Method kMethod, bool kCheck>
void BM_Solve(benchmark::State& state) {
  const StrandModel m = Hair(static_cast<int>(state.range(0)), state.range(1) != 0);
  SolveOptions options;
  options.method = kMethod;
  options.check_stability = kCheck;
  int iterations = 0;
  for (auto _ : state) {
    const StrandSolution s = SolveStrand(m, options);
    if (!s.summary.Converged()) state.SkipWithError("not converged");
    iterations = s.summary.iterations;
    benchmark::DoNotOptimize(s.curvatures.data());
  }
  state.counters["iterations"] = iterations;
}
BENCHMARK(BM_Solve<Method::kLbfgs, false>)
    ->Name("BM_Solve/lbfgs")
    ->ArgsProduct({{15, 30, 60, 100, 120}, {0, 1}})
    ->ArgNames({"n", "curly"})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Solve<Method::kBfgs, false>)
    ->Name("BM_Solve/bfgs")
    ->ArgsProduct({{15, 30, 60, 100, 120}, {0, 1}})
    ->ArgNames({"n", "curly"})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Solve<Method::kNewton, false>)
    ->Name("BM_Solve/newton")
    ->ArgsProduct({{15, 30, 60}, {0, 1}})
    ->ArgNames({"n", "curly"})
    ->Unit(benchmark::kMicrosecond);
// The default: L-BFGS followed by the stability certificate (finite-difference Hessian and its
// smallest eigenvalue).
BENCHMARK(BM_Solve<Method::kLbfgs, true>)
    ->Name("BM_Solve/lbfgs+stability")
    ->ArgsProduct({{15, 30, 60, 100, 120}, {0, 1}})
    ->ArgNames({"n", "curly"})
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace ringlet

BENCHMARK_MAIN();
