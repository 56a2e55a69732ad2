// Scene benchmarks of full hairstyles (issue 4): the master solve of a whole head (1,000 masters
// of 20 segments with body contact, TBB across both cores) and the whole groom (masters + 50,000
// wisp strands), for the four example styles. Wall time (UseRealTime): the work is parallel.
//
//   cmake -S . -B build-bench -G Ninja -DCMAKE_BUILD_TYPE=Release -DRINGLET_BUILD_BENCHMARKS=ON
//   cmake --build build-bench --target ringlet_groom_bench && ./build-bench/bench/ringlet_groom_bench
#include <benchmark/benchmark.h>

#include <cstdio>
#include <string>

#include "ringlet/hairstyle.h"
#include "ringlet/hairstyle_json.h"
#include "ringlet/solve_strands.h"

namespace ringlet {
namespace {

// The four examples on the sphere mannequin (the numbers of docs/benchmarks.md).
const char* const kStyles[] = {"straight_mannequin", "wavy_mannequin", "curly_mannequin",
                               "african_mannequin"};

Hairstyle LoadStyle(int index) {
  Hairstyle style;
  std::string error;
  const std::string path =
      std::string(RINGLET_EXAMPLES_DIR) + "/hairstyles/" + kStyles[index] + ".json";
  if (!LoadHairstyle(path, &style, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    std::abort();
  }
  return style;
}

// The physics of a head: SolveStrands over the 1,000 masters (roots and models built once).
void BM_SolveMasters(benchmark::State& state) {
  const Hairstyle style = LoadStyle(static_cast<int>(state.range(0)));
  HairstyleMasters masters;
  std::string error;
  if (!BuildMasters(style, &masters, &error)) std::abort();
  long iterations = 0;
  int unconverged = 0;
  for (auto _ : state) {
    const std::vector<StrandSolution> solutions = SolveStrands(masters.models, style.solver);
    iterations = 0;
    unconverged = 0;
    for (const StrandSolution& s : solutions) {
      iterations += s.summary.iterations;
      unconverged += !s.summary.Converged();
    }
    benchmark::DoNotOptimize(solutions.data());
  }
  state.SetLabel(kStyles[state.range(0)]);
  state.counters["masters"] = static_cast<double>(masters.models.size());
  state.counters["iterations_per_master"] =
      static_cast<double>(iterations) / static_cast<double>(masters.models.size());
  state.counters["unconverged"] = unconverged;
}
BENCHMARK(BM_SolveMasters)->DenseRange(0, 3)->Unit(benchmark::kMillisecond)->UseRealTime()
    ->Iterations(3);

// Everything but the files: roots, masters, solve, 50,000 wisp strands.
void BM_Groom(benchmark::State& state) {
  const Hairstyle style = LoadStyle(static_cast<int>(state.range(0)));
  int strands = 0;
  for (auto _ : state) {
    Groom groom;
    std::string error;
    if (!GroomHairstyle(style, BatchOptions{}, &groom, &error)) std::abort();
    strands = groom.summary.strands;
    benchmark::DoNotOptimize(groom.strands.points.data());
  }
  state.SetLabel(kStyles[state.range(0)]);
  state.counters["strands"] = strands;
}
BENCHMARK(BM_Groom)->DenseRange(0, 3)->Unit(benchmark::kMillisecond)->UseRealTime()
    ->Iterations(3);

}  // namespace
}  // namespace ringlet

BENCHMARK_MAIN();
