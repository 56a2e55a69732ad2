// Wisp generation for a whole head (issue 4, item 5): 1,000 masters of 20 segments, 100 children
// each, 32 points per child (100,000 strands, 3.2 million points). Target: <= 0.5 s on the 2-core
// machine of docs/benchmarks.md. Build with -DRINGLET_BUILD_BENCHMARKS=ON.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "ringlet/strand_geometry.h"
#include "ringlet/wisp.h"

namespace ringlet {
namespace {

// 1,000 curly 20-cm masters in their natural shape (kappa in [30, 80] 1/m, tau in [5, 20] 1/m),
// roots spread over a 16 cm x 16 cm patch, tangents tilted differently; each sampled at 4 points
// per segment (81 samples).
std::vector<FramedCentreline> Masters(int count, int segments) {
  std::vector<FramedCentreline> masters;
  masters.reserve(count);
  for (int i = 0; i < count; ++i) {
    StrandModel m;
    m.segment_lengths = UniformSegments(0.2, segments);
    m.section = SectionFromEccentricity(40e-6, 0.3);
    m.natural_curvature = Vec3(30.0 + 50.0 * (i % 11) / 10.0, 0.0, 5.0 + 15.0 * (i % 7) / 6.0);
    m.root_position = Vec3(0.005 * (i % 32), 0.005 * (i / 32), 0.0);
    const double a = 0.1 * (i % 13);
    Mat3 frame;
    std::string why;
    RootFrameFromTangentNormal(Vec3(std::sin(a), 0.0, -std::cos(a)), Vec3(std::cos(a), 0.0, std::sin(a)),
                               &frame, &why);
    m.root_frame = frame;
    masters.push_back(SampleFramedCentreline(m, m.NaturalCurvatures(), 4));
  }
  return masters;
}

void BM_GenerateWisps(benchmark::State& state) {
  const std::vector<FramedCentreline> masters = Masters(1000, 20);
  const std::vector<CrossSection> sections = {SectionFromEccentricity(40e-6, 0.3)};
  WispOptions o;
  o.strands_per_wisp = 100;
  o.points_per_strand = 32;
  if (state.range(0) != 0) {  // all variations on
    o.jitter = 2e-4;
    o.frizz_amplitude = 1e-4;
    o.tip_taper = 0.2;
  }
  size_t points = 0;
  for (auto _ : state) {
    const HairCurves curves = GenerateWisps(masters, sections, o, 7);
    points = curves.points.size();
    benchmark::DoNotOptimize(curves.points.data());
  }
  state.counters["strands"] = 1000.0 * o.strands_per_wisp;
  state.counters["points"] = static_cast<double>(points);
  state.counters["time_per_point"] = benchmark::Counter(
      static_cast<double>(points), benchmark::Counter::kIsIterationInvariantRate |
                                       benchmark::Counter::kInvert);
}
BENCHMARK(BM_GenerateWisps)->Arg(0)->Arg(1)->ArgName("jitter_frizz")->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace ringlet
BENCHMARK_MAIN();
