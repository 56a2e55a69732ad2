// Micro benchmarks of one strand: energy+gradient evaluation and full solves (issue 2, item 9).
// Build with -DRINGLET_BUILD_BENCHMARKS=ON; results and machine in docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <Eigen/Cholesky>

#include "ringlet/energy.h"
#include "ringlet/statics.h"
#include "ringlet/strand_hessian.h"

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
    ->ArgsProduct({{15, 30, 60, 100, 120}, {0, 1}})
    ->ArgNames({"n", "curly"})
    ->Unit(benchmark::kMicrosecond);
// The default: L-BFGS followed by the stability certificate (exact Hessian, O(n) factorization
// and a few steps of inverse iteration for the smallest eigenvalue).
BENCHMARK(BM_Solve<Method::kLbfgs, true>)
    ->Name("BM_Solve/lbfgs+stability")
    ->ArgsProduct({{15, 30, 60, 100, 120}, {0, 1}})
    ->ArgNames({"n", "curly"})
    ->Unit(benchmark::kMicrosecond);

// The stability certificate alone at the curly strand's equilibrium: the exact Hessian
// (strand_hessian.h) and its O(n) block factorization, against the former certificate, central
// differences of the exact gradient (6n evaluations) and a dense Cholesky (what SolveStrand did
// before the exact Hessian; reproduced here with the public API).
template <bool kExact>
void BM_Certificate(benchmark::State& state) {
  const StrandModel m = Hair(static_cast<int>(state.range(0)), true);
  SolveOptions options;
  options.check_stability = false;
  const VecX q = SolveStrand(m, options).curvatures;
  const int n = static_cast<int>(q.size());
  StrandHessian hessian;
  StrandHessianFactor factor;
  StrandEnergy energy(m);
  MatX dense(n, n);
  VecX gp, gm, x = q;
  for (auto _ : state) {
    if (kExact) {
      ComputeStrandHessian(m, q, &hessian);
      benchmark::DoNotOptimize(factor.Factor(hessian, 0.0));
    } else {
      for (int j = 0; j < n; ++j) {
        const double h = 1e-5 / m.Length();
        x(j) = q(j) + h;
        energy.Evaluate(x, &gp);
        x(j) = q(j) - h;
        energy.Evaluate(x, &gm);
        x(j) = q(j);
        dense.col(j) = (gp - gm) / (2.0 * h);
      }
      const Eigen::LLT<MatX> llt(0.5 * (dense + dense.transpose()));
      benchmark::DoNotOptimize(llt.info());
    }
    benchmark::ClobberMemory();
  }
}
BENCHMARK(BM_Certificate<true>)
    ->Name("BM_Certificate/exact")
    ->Arg(15)->Arg(30)->Arg(60)->Arg(100)->Arg(300)->Arg(1000)
    ->ArgName("n")
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Certificate<false>)
    ->Name("BM_Certificate/finite_difference")
    ->Arg(15)->Arg(30)->Arg(60)->Arg(100)
    ->ArgName("n")
    ->Unit(benchmark::kMicrosecond);

// Heavy curly hair (issue 11): a curly strand (kappa^0 = 50 1/m, tau^0 = 10 1/m) of length L
// hanging from a horizontal root, w L^3 / EI = 2040 L^3: 441 at 0.6 m, 1488 at 0.9 m; graded
// segments with the recommended ratio. Arguments: length in mm, segments.
template <Method kMethod>
void BM_HeavyCurly(benchmark::State& state) {
  const double length = 1e-3 * static_cast<double>(state.range(0));
  const int segments = static_cast<int>(state.range(1));
  StrandModel m = Hair(segments, true);
  m.segment_lengths = UniformSegments(length, segments);
  m.segment_lengths =
      GradedSegments(length, segments, RecommendedGradingRatio(m.GravityParameter()));
  SolveOptions options;
  options.method = kMethod;
  options.check_stability = true;
  int iterations = 0;
  bool stable = false;
  for (auto _ : state) {
    const StrandSolution s = SolveStrand(m, options);
    if (!s.summary.Converged()) state.SkipWithError("not converged");
    iterations = s.summary.iterations;
    stable = s.summary.stable;
    benchmark::DoNotOptimize(s.curvatures.data());
  }
  state.counters["iterations"] = iterations;
  state.counters["stable"] = stable ? 1 : 0;
  state.counters["load"] = m.GravityParameter();
}
BENCHMARK(BM_HeavyCurly<Method::kLbfgs>)
    ->Name("BM_HeavyCurly/lbfgs")
    ->ArgsProduct({{300, 450, 600, 900}, {30, 60}})
    ->ArgNames({"L_mm", "n"})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_HeavyCurly<Method::kNewton>)
    ->Name("BM_HeavyCurly/newton")
    ->ArgsProduct({{300, 450, 600, 900}, {30, 60}})
    ->ArgNames({"L_mm", "n"})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_HeavyCurly<Method::kBfgs>)
    ->Name("BM_HeavyCurly/bfgs")
    ->ArgsProduct({{300, 450, 600, 900}, {30, 60}})
    ->ArgNames({"L_mm", "n"})
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace ringlet

BENCHMARK_MAIN();
