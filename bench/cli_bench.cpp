// Where `ringlet solve` spends its time per strand (issue 11): the library's SolveStrand of the
// 15-segment curly strand of examples/vertical_curly.json, and each stage of the command on a
// scene of N copies of it (parse, solve, result geometry, JSON text, file write), so that the
// command's CPU time per strand (docs/benchmarks.md, "CLI overhead") can be split into its parts.
//
//   cmake -S . -B build-bench -G Ninja -DCMAKE_BUILD_TYPE=Release -DRINGLET_BUILD_BENCHMARKS=ON
//   cmake --build build-bench --target ringlet_cli_bench
//   ./build-bench/bench/ringlet_cli_bench --benchmark_repetitions=5
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "io/json_reader.h"
#include "ringlet/atomic_file.h"
#include "ringlet/kirchhoff.h"
#include "ringlet/result_json.h"
#include "ringlet/scene_json.h"
#include "ringlet/solve_strands.h"
#include "ringlet/statics.h"
#include "ringlet/strand_geometry.h"

namespace ringlet {
namespace {

// Strands per scene in the per-stage benchmarks: enough that per-file costs are amortized.
constexpr int kStrands = 1000;

// The text of examples/vertical_curly.json.
std::string ExampleText() {
  std::string text;
  std::string error;
  if (!ReadFile(std::string(RINGLET_EXAMPLES_DIR) + "/vertical_curly.json", &text, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    std::abort();
  }
  return text;
}

// The text of a scene of `count` copies of the example's strand on a 1-cm grid of roots (what
// scripts/make_many_strands.py writes), with the stability check on or off.
std::string ManyStrandsText(int count, bool check_stability) {
  nlohmann::json scene = nlohmann::json::parse(ExampleText());
  const nlohmann::json strand = scene["strands"][0];
  scene["strands"] = nlohmann::json::array();
  int side = 1;
  while (side * side < count) ++side;
  for (int i = 0; i < count; ++i) {
    nlohmann::json s = strand;
    s["root"]["position"] = {0.01 * (i % side), 0.01 * (i / side), 0.0};
    scene["strands"].push_back(std::move(s));
  }
  scene["solver"]["check_stability"] = check_stability;
  return scene.dump(1);
}

Scene MustParse(const std::string& text) {
  Scene scene;
  std::string error;
  if (!ParseSceneText(text, &scene, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    std::abort();
  }
  return scene;
}

void PerStrand(benchmark::State& state, int strands) {
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * strands);
  state.counters["us_per_strand"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * strands * 1e-6,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// The library: one SolveStrand of the example's strand, stability check off (0) or on (1).
void BM_LibrarySolveStrand(benchmark::State& state) {
  const Scene scene = MustParse(ExampleText());
  SolveOptions options = scene.solver;
  options.check_stability = state.range(0) != 0;
  int iterations = 0;
  for (auto _ : state) {
    const StrandSolution s = SolveStrand(scene.strands[0], options);
    if (!s.summary.Converged()) state.SkipWithError("not converged");
    iterations = s.summary.iterations;
    benchmark::DoNotOptimize(s.curvatures.data());
  }
  state.counters["iterations"] = iterations;
}
BENCHMARK(BM_LibrarySolveStrand)
    ->ArgName("stability")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMicrosecond);

// Stage 1: the scene text -> validated models (JSON parse with duplicate check + field checks).
void BM_ParseScene(benchmark::State& state) {
  const std::string text = ManyStrandsText(kStrands, false);
  for (auto _ : state) {
    Scene scene;
    std::string error;
    if (!ParseSceneText(text, &scene, &error)) state.SkipWithError(error.c_str());
    benchmark::DoNotOptimize(scene.strands.data());
  }
  PerStrand(state, kStrands);
  state.counters["bytes_per_strand"] = static_cast<double>(text.size()) / kStrands;
}
BENCHMARK(BM_ParseScene)->Unit(benchmark::kMillisecond);

// The JSON syntax alone (nlohmann's parse, no duplicate check, no field checks), for comparison.
void BM_ParseJsonOnly(benchmark::State& state) {
  const std::string text = ManyStrandsText(kStrands, false);
  for (auto _ : state) {
    const nlohmann::json document = nlohmann::json::parse(text);
    benchmark::DoNotOptimize(&document);
  }
  PerStrand(state, kStrands);
}
BENCHMARK(BM_ParseJsonOnly)->Unit(benchmark::kMillisecond);

// The readers' own parse of the same text (io/json_reader.h: simdjson, replayed into the same
// nlohmann document with the duplicate and depth checks), what BM_ParseScene spends before the
// conversion to models.
void BM_ParseJsonText(benchmark::State& state) {
  const std::string text = ManyStrandsText(kStrands, false);
  for (auto _ : state) {
    nlohmann::json document;
    std::string error;
    if (!internal::ParseJsonText(text, &document, &error)) state.SkipWithError(error.c_str());
    benchmark::DoNotOptimize(&document);
  }
  PerStrand(state, kStrands);
}
BENCHMARK(BM_ParseJsonText)->Unit(benchmark::kMillisecond);

// Stage 2 is BM_LibrarySolveStrand. Stage 3: MakeStrandResult (centreline samples, the Kirchhoff
// certificate, the non-finite rule), and its two costly parts alone.
void BM_MakeStrandResult(benchmark::State& state) {
  const Scene scene = MustParse(ExampleText());
  SolveOptions options = scene.solver;
  options.check_stability = false;
  const StrandSolution solution = SolveStrand(scene.strands[0], options);
  for (auto _ : state) {
    const StrandResult r = MakeStrandResult(scene.strands[0], solution, 1);
    benchmark::DoNotOptimize(r.points.data());
  }
}
BENCHMARK(BM_MakeStrandResult)->Unit(benchmark::kMicrosecond);

void BM_KirchhoffResidual(benchmark::State& state) {
  const Scene scene = MustParse(ExampleText());
  SolveOptions options = scene.solver;
  options.check_stability = false;
  const StrandSolution solution = SolveStrand(scene.strands[0], options);
  for (auto _ : state) {
    benchmark::DoNotOptimize(KirchhoffResidual(scene.strands[0], solution.curvatures));
  }
}
BENCHMARK(BM_KirchhoffResidual)->Unit(benchmark::kMicrosecond);

void BM_SampleCentreline(benchmark::State& state) {
  const Scene scene = MustParse(ExampleText());
  SolveOptions options = scene.solver;
  options.check_stability = false;
  const StrandSolution solution = SolveStrand(scene.strands[0], options);
  for (auto _ : state) {
    const std::vector<Vec3> points = SampleCentreline(scene.strands[0], solution.curvatures, 1);
    benchmark::DoNotOptimize(points.data());
  }
}
BENCHMARK(BM_SampleCentreline)->Unit(benchmark::kMicrosecond);

// kStrands solved results, as the command holds them before writing.
std::vector<StrandResult> SolvedResults() {
  const Scene scene = MustParse(ManyStrandsText(kStrands, false));
  std::vector<StrandResult> results;
  for (const StrandModel& model : scene.strands) {
    results.push_back(MakeStrandResult(model, SolveStrand(model, scene.solver), 1));
  }
  return results;
}

// Stage 4: the result text (what the command writes).
void BM_ResultToString(benchmark::State& state) {
  const std::vector<StrandResult> results = SolvedResults();
  size_t bytes = 0;
  for (auto _ : state) {
    const std::string text = ResultToString(results, 1.0);
    bytes = text.size();
    benchmark::DoNotOptimize(text.data());
  }
  PerStrand(state, kStrands);
  state.counters["bytes_per_strand"] = static_cast<double>(bytes) / kStrands;
}
BENCHMARK(BM_ResultToString)->Unit(benchmark::kMillisecond);

// The nlohmann tree of the same document (used by groom and style, which add members to it).
void BM_ResultToJson(benchmark::State& state) {
  const std::vector<StrandResult> results = SolvedResults();
  for (auto _ : state) {
    const nlohmann::ordered_json document = ResultToJson(results, 1.0);
    benchmark::DoNotOptimize(&document);
  }
  PerStrand(state, kStrands);
}
BENCHMARK(BM_ResultToJson)->Unit(benchmark::kMillisecond);

// Stage 5: writing the text to a file (temporary file, fsync, rename).
void BM_WriteFileAtomically(benchmark::State& state) {
  const std::string text = ResultToString(SolvedResults(), 1.0);
  const std::string path =
      (std::filesystem::temp_directory_path() / "ringlet_cli_bench_result.json").string();
  for (auto _ : state) {
    std::string error;
    if (!WriteFileAtomically(path, text, true, &error)) state.SkipWithError(error.c_str());
  }
  std::filesystem::remove(path);
  PerStrand(state, kStrands);
}
BENCHMARK(BM_WriteFileAtomically)->Unit(benchmark::kMillisecond)->UseRealTime();

// All the stages in one process, as `ringlet solve --threads 1 --quiet` runs them on the scene
// text (scene file read and process start-up excluded): what the stages above should add up to.
void BM_SolvePipeline(benchmark::State& state) {
  const std::string text = ManyStrandsText(kStrands, state.range(0) != 0);
  const std::string path =
      (std::filesystem::temp_directory_path() / "ringlet_cli_bench_pipeline.json").string();
  BatchOptions batch;
  batch.threads = 1;
  for (auto _ : state) {
    const Scene scene = MustParse(text);
    const std::vector<StrandSolution> solutions = SolveStrands(scene.strands, scene.solver, batch);
    const std::vector<StrandResult> results = MakeStrandResults(scene.strands, solutions, 1, 1);
    std::string error;
    if (!WriteFileAtomically(path, ResultToString(results, 1.0), true, &error)) {
      state.SkipWithError(error.c_str());
    }
  }
  std::filesystem::remove(path);
  PerStrand(state, kStrands);
}
BENCHMARK(BM_SolvePipeline)->ArgName("stability")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ringlet

BENCHMARK_MAIN();
