// Encoding a full head of hair to the export formats (issue 4, item 8): 100,000 strands of 32
// points (3.2 million points), to .hair bytes and .usda / .obj text in memory (no disk I/O).
// Build with -DRINGLET_BUILD_BENCHMARKS=ON; results and machine in docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <random>

#include "ringlet/hair_file.h"
#include "ringlet/obj_export.h"
#include "ringlet/usd_export.h"

namespace ringlet {
namespace {

// 100,000 strands x 32 points within a 30-cm box, widths 40-120 um, one colour per strand.
const HairCurves& Head() {
  static const HairCurves curves = [] {
    constexpr int kStrands = 100000;
    constexpr int kPoints = 32;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> pos(-0.15f, 0.15f), width(40e-6f, 120e-6f),
        rgb(0.0f, 1.0f);
    HairCurves c;
    c.point_counts.assign(kStrands, kPoints);
    c.points.reserve(kStrands * kPoints);
    c.widths.reserve(kStrands * kPoints);
    for (int k = 0; k < kStrands; ++k) {
      for (int i = 0; i < kPoints; ++i) {
        c.points.emplace_back(pos(rng), pos(rng), pos(rng));
        c.widths.push_back(width(rng));
      }
      c.colors.emplace_back(rgb(rng), rgb(rng), rgb(rng));
    }
    return c;
  }();
  return curves;
}

void Report(benchmark::State& state, size_t bytes) {
  state.counters["MB"] = static_cast<double>(bytes) / 1e6;
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(bytes));
  state.counters["points"] = static_cast<double>(Head().points.size());
}

void BM_EncodeHairFile(benchmark::State& state) {
  HairFileOptions options;
  options.store_colors = state.range(0) != 0;
  std::string bytes, error;
  for (auto _ : state) {
    if (!EncodeHairFile(Head(), options, &bytes, &error)) state.SkipWithError(error.c_str());
    benchmark::DoNotOptimize(bytes.data());
  }
  Report(state, bytes.size());
}
BENCHMARK(BM_EncodeHairFile)->Arg(0)->Arg(1)->ArgName("colors")->Unit(benchmark::kMillisecond);

void BM_DecodeHairFile(benchmark::State& state) {
  std::string bytes, error;
  EncodeHairFile(Head(), HairFileOptions(), &bytes, &error);
  HairCurves back;
  for (auto _ : state) {
    if (!DecodeHairFile(bytes, &back, &error)) state.SkipWithError(error.c_str());
    benchmark::DoNotOptimize(back.points.data());
  }
  Report(state, bytes.size());
}
BENCHMARK(BM_DecodeHairFile)->Unit(benchmark::kMillisecond);

void BM_EncodeUsda(benchmark::State& state) {
  std::string text, error;
  for (auto _ : state) {
    if (!EncodeUsda(Head(), UsdExportOptions(), &text, &error)) {
      state.SkipWithError(error.c_str());
    }
    benchmark::DoNotOptimize(text.data());
  }
  Report(state, text.size());
}
BENCHMARK(BM_EncodeUsda)->Unit(benchmark::kMillisecond);

void BM_EncodeObj(benchmark::State& state) {
  std::string text, error;
  for (auto _ : state) {
    if (!EncodeObj(Head(), &text, &error)) state.SkipWithError(error.c_str());
    benchmark::DoNotOptimize(text.data());
  }
  Report(state, text.size());
}
BENCHMARK(BM_EncodeObj)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ringlet

BENCHMARK_MAIN();
