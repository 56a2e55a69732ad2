// Strand dynamics (issue 27, item 7; docs/benchmarks.md "Hair in motion"): one implicit step per
// film frame (h = 1/24 s) for a whole head of masters with body contact, and the cost of one step
// against the segment count.
//
//   cmake -S . -B build-bench -G Ninja -DCMAKE_BUILD_TYPE=Release -DRINGLET_BUILD_BENCHMARKS=ON
//   cmake --build build-bench --target ringlet_dynamics_bench
//   ./build-bench/bench/ringlet_dynamics_bench --benchmark_filter=Head
//
// BM_HeadStep/<style>/<masters>/<segments>/<mass points, 0 = default>/<inexact steps' model tolerance
// in thousandths, 0 = Newton to the tolerance (default)> (and BM_HeadStep10k, 6 frames): the
// masters of an example hairstyle on the sphere
// mannequin (BuildMasters: roots on the scalp, hair type, graded segments, body contact), started
// at rest on their static equilibrium (SolveStrands), then the head shakes: the roots turn about
// the head's up axis through its centre by 0.5 sin(2 pi t) rad (1 Hz, +-29 degrees), the inertial
// terms of the moving clamp included (StrandDynamics::SetClampMotion), and the body moves as
// `ringlet simulate` moves it: its head part (head and jaw spheres) turns with the roots, its torso
// (neck, chest, shoulders, arms, back) stays (SplitBody; docs/body.md). One benchmark iteration is
// one frame: every master advanced by one StrandDynamics::Step, TBB over masters (one task per
// master, as SolveStrands; all hardware threads). The strands are independent, so the results do
// not depend on the thread count. Wall time and the process's CPU time (both threads) are
// reported; Newton iterations and halvings per master-step as counters.
//
// BM_StrandStep/<n>: one curly strand (50 cm, Gamma = 460) released horizontally, n segments,
// one step per frame for the first second: the cost per step and per Newton iteration against n
// (single thread).
#include <benchmark/benchmark.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "ringlet/cross_section.h"
#include "ringlet/dynamics.h"
#include "ringlet/hairstyle.h"
#include "ringlet/hairstyle_json.h"
#include "ringlet/solve_strands.h"
#include "ringlet/split_body.h"
#include "ringlet/strand_geometry.h"

namespace ringlet {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kFrame = 1.0 / 24.0;

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

// Rotation by `angle` about the unit axis `axis` (Rodrigues).
Mat3 AxisRotation(const Vec3& axis, double angle) {
  const Mat3 k = Hat(axis);
  return Mat3::Identity() + std::sin(angle) * k + (1.0 - std::cos(angle)) * (k * k);
}

// The benchmark's shake for one master: its root turned about the head's up axis through the
// head's centre by 0.5 sin(2 pi t) rad, the body carried: with a split body (a torso part) its
// head part turns and its torso stays, as ringlet simulate places it. The rigid motion is
// x -> R x + c with c = centre - R centre, so the torso's translation c - centre + R centre = 0.
ClampMotion ShakeClamp(const StrandModel& m, const HeadFrame& head,
                       const std::shared_ptr<const SplitBody>& split) {
  const Vec3 up = head.up.normalized();
  const Vec3 arm = m.root_position - head.centre;
  const Vec3 centre = head.centre;
  const Mat3 frame = m.root_frame;
  ClampMotion clamp;
  clamp.position = [=](double t) {
    return Vec3(centre + AxisRotation(up, 0.5 * std::sin(2 * kPi * t)) * arm);
  };
  clamp.frame = [=](double t) {
    return Mat3(AxisRotation(up, 0.5 * std::sin(2 * kPi * t)) * frame);
  };
  clamp.carries_obstacle = true;
  if (split) {
    clamp.move_obstacle = [split, centre](const Mat3& rotation, const Vec3& translation) {
      return split->Place(rotation, translation, translation - centre + rotation * centre);
    };
  }
  return clamp;
}

// The body of a hairstyle split into head and torso parts, or null when it has no torso part
// (then it moves rigidly with the head).
std::shared_ptr<const SplitBody> SplitOf(const Hairstyle& style) {
  return style.body && style.body->HasTorsoPart() ? SplitBody::Create(style.body) : nullptr;
}

void BM_HeadStep(benchmark::State& state) {
  Hairstyle style = LoadStyle(static_cast<int>(state.range(0)));
  style.roots.count = static_cast<int>(state.range(1));
  style.segments = static_cast<int>(state.range(2));
  HairstyleMasters masters;
  std::string error;
  if (!BuildMasters(style, &masters, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    std::abort();
  }
  const std::vector<StrandSolution> rest = SolveStrands(masters.models, style.solver);
  const HeadFrame head = std::get<SphereScalp>(style.scalp).head;
  // The body as ringlet simulate places it: the head part turns, the torso stays.
  const std::shared_ptr<const SplitBody> split = SplitOf(style);
  const size_t count = masters.models.size();
  std::vector<std::unique_ptr<StrandDynamics>> strands(count);
  for (size_t i = 0; i < count; ++i) {
    const StrandModel& m = masters.models[i];
    const VecX& q = rest[i].curvatures;
    DynamicsOptions options;
    if (state.range(3) > 0) options.mass_points = static_cast<int>(state.range(3));
    options.model_tolerance = 1e-3 * static_cast<double>(state.range(4));
    strands[i] = std::make_unique<StrandDynamics>(m, options,
                                                  StrandState{q, VecX::Zero(q.size()), 0.0});
    strands[i]->SetClampMotion(ShakeClamp(m, head, split));
  }
  std::vector<StepReport> reports(count);
  long iterations = 0, factorizations = 0, steps = 0;
  int halved = 0, failed = 0;
  for (auto _ : state) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1),
                      [&](const tbb::blocked_range<size_t>& r) {
                        for (size_t i = r.begin(); i != r.end(); ++i) reports[i] = strands[i]->Step();
                      });
    for (const StepReport& report : reports) {
      iterations += report.newton_iterations;
      factorizations += report.factorizations;
      halved += report.halvings > 0;
      failed += !report.converged;
      ++steps;
    }
  }
  state.SetLabel(kStyles[state.range(0)]);
  state.counters["masters"] = static_cast<double>(count);
  state.counters["newton_per_step"] = static_cast<double>(iterations) / static_cast<double>(steps);
  state.counters["factor_per_step"] =
      static_cast<double>(factorizations) / static_cast<double>(steps);
  state.counters["halved"] = halved;
  state.counters["failed"] = failed;
}

// The first second of the shake (24 frames), 1,000 masters for every style: the default step
// (Newton to the tolerance, 6 mass points) and the inexact one (model tolerance 0.03, 2 points).
void HeadArguments(benchmark::internal::Benchmark* b) {
  for (const auto& [points, model] : {std::pair{0, 0}, std::pair{2, 30}}) {
    for (int segments : {15, 20}) {
      for (int style = 0; style < 4; ++style) b->Args({style, 1000, segments, points, model});
    }
  }
}
BENCHMARK(BM_HeadStep)->Apply(HeadArguments)->Unit(benchmark::kMillisecond)->UseRealTime()
    ->MeasureProcessCPUTime()->Iterations(24);
// 10,000 masters: the first quarter second of the shake (6 frames, the fastest head motion).
BENCHMARK(BM_HeadStep)->Args({2, 10000, 15, 0, 0})->Args({2, 10000, 20, 0, 0})
    ->Args({0, 10000, 20, 0, 0})->Args({2, 10000, 15, 2, 30})->Args({2, 10000, 20, 2, 30})
    ->Args({0, 10000, 20, 2, 30})->Name("BM_HeadStep10k")->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime()
    ->Iterations(6);

// A small head for profiling (100 masters, curly, 20 segments), and its cost against the mass
// samples per segment (DynamicsOptions::mass_points; 0 = the default, 6).
BENCHMARK(BM_HeadStep)->Args({2, 100, 20, 0, 0})->Args({0, 100, 20, 0, 0})->Args({2, 100, 20, 2, 0})
    ->Args({2, 100, 20, 3, 0})->Args({2, 100, 20, 4, 0})->Args({2, 100, 20, 2, 30})
    ->Args({0, 100, 20, 2, 30})->Name("BM_HeadStepSmall")->Unit(benchmark::kMillisecond)
    ->UseRealTime()->MeasureProcessCPUTime()->Iterations(24);

// The results do not depend on the thread count: 100 curly masters shaken for 6 frames on 1 and on
// 2 threads give the same bits (counter bits_equal = 1). Not a timing.
void BM_HeadThreadsAgree(benchmark::State& state) {
  Hairstyle style = LoadStyle(2);
  style.roots.count = 100;
  HairstyleMasters masters;
  std::string error;
  if (!BuildMasters(style, &masters, &error)) std::abort();
  const std::vector<StrandSolution> rest = SolveStrands(masters.models, style.solver);
  const HeadFrame head = std::get<SphereScalp>(style.scalp).head;
  const std::shared_ptr<const SplitBody> split = SplitOf(style);
  auto run = [&](int threads) {
    const size_t count = masters.models.size();
    std::vector<std::unique_ptr<StrandDynamics>> strands(count);
    for (size_t i = 0; i < count; ++i) {
      const StrandModel& m = masters.models[i];
      strands[i] = std::make_unique<StrandDynamics>(
          m, DynamicsOptions{}, StrandState{rest[i].curvatures, VecX::Zero(rest[i].curvatures.size()), 0.0});
      strands[i]->SetClampMotion(ShakeClamp(m, head, split));
    }
    tbb::task_arena arena(threads);
    for (int k = 0; k < 6; ++k) {
      arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1),
                          [&](const tbb::blocked_range<size_t>& r) {
                            for (size_t i = r.begin(); i != r.end(); ++i) strands[i]->Step();
                          });
      });
    }
    std::vector<VecX> out;
    for (const auto& s : strands) out.push_back(s->state().curvatures);
    return out;
  };
  bool equal = true;
  for (auto _ : state) equal = run(1) == run(2);
  state.counters["bits_equal"] = equal;
}
BENCHMARK(BM_HeadThreadsAgree)->Iterations(1)->Unit(benchmark::kMillisecond);

void BM_StrandStep(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  StrandModel m;
  m.segment_lengths = UniformSegments(0.5, n);
  m.section = SectionFromEccentricity(40e-6, 0.5);
  m.natural_curvature = Vec3(60.0, 0.0, 20.0);
  Mat3 frame;  // horizontal: tangent +x, n1 up
  frame.col(0) = Vec3(0, 0, 1);
  frame.col(1) = Vec3(0, -1, 0);
  frame.col(2) = Vec3(1, 0, 0);
  m.root_frame = frame;
  long iterations = 0, steps = 0;
  int halved = 0;
  for (auto _ : state) {
    state.PauseTiming();
    StrandDynamics dynamics(m, {}, {m.NaturalCurvatures(), VecX::Zero(3 * n), 0.0});
    state.ResumeTiming();
    for (int k = 0; k < 24; ++k) {
      const StepReport report = dynamics.Step();
      iterations += report.newton_iterations;
      halved += report.halvings > 0;
      ++steps;
    }
  }
  state.SetItemsProcessed(steps);  // items/s = steps per second
  state.counters["newton_per_step"] = static_cast<double>(iterations) / static_cast<double>(steps);
  state.counters["us_per_step"] = benchmark::Counter(
      static_cast<double>(steps), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["us_per_newton"] = benchmark::Counter(
      static_cast<double>(iterations), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["halved"] = halved;
}
BENCHMARK(BM_StrandStep)->Arg(5)->Arg(10)->Arg(15)->Arg(20)->Arg(30)->Arg(40)->Arg(60)->Arg(80)
    ->Unit(benchmark::kMillisecond)->MinTime(1.0);

}  // namespace
}  // namespace ringlet

BENCHMARK_MAIN();
