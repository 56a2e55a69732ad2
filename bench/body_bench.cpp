// Micro benchmarks of the body's signed distance, the contact energy's inner query (issue 4).
// Build with -DRINGLET_BUILD_BENCHMARKS=ON; results and machine in docs/benchmarks.md.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "ringlet/body.h"
#include "ringlet/body_json.h"

namespace ringlet {
namespace {

// Query points where hair is: within `shell` (m) of the body's box, seeded. Points far inside
// the box are as likely as points near the surface; the mix is that of hair over a head.
std::vector<Vec3> Points(const Body& body, double shell, int count) {
  const Box3 box = body.Bounds();
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> points;
  points.reserve(static_cast<size_t>(count));
  const Vec3 lo = box.min() - Vec3::Constant(shell);
  const Vec3 size = box.sizes() + Vec3::Constant(2.0 * shell);
  for (int i = 0; i < count; ++i) {
    points.push_back(lo + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(size));
  }
  return points;
}

// Points above the scalp at distances in [0, offset] (m) from the body's own surface: the
// typical contact query of a strand lying on the head. A direction from the head's centre picks
// the point at 0.1 m, which is moved to the closest surface point x - d grad d, then out along
// the normal.
std::vector<Vec3> NearHead(const Body& body, double offset, int count) {
  std::mt19937_64 rng(2);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> u(0.0, offset);
  std::vector<Vec3> points;
  while (points.size() < static_cast<size_t>(count)) {
    Vec3 direction(gauss(rng), gauss(rng), gauss(rng));
    direction.normalize();
    if (direction.z() < -0.2) continue;  // the scalp, not the face's underside
    const Vec3 p = 0.1 * direction;
    Vec3 g;
    const double d = body.SignedDistance(p, &g);
    points.push_back(p - d * g + u(rng) * g);
  }
  return points;
}

Body Load(const std::string& name) {
  Body body;
  std::string error;
  if (!LoadBody(std::string(RINGLET_EXAMPLES_DIR) + "/bodies/" + name, &body, &error)) {
    std::abort();
  }
  return body;
}

// The same body with exact mesh queries (body files default to the distance grid).
Body Exact(const Body& body) {
  Body exact;
  std::string error;
  if (!Body::Create(body.spheres(), body.meshes(), &exact, &error, body.blend())) std::abort();
  return exact;
}

void Run(benchmark::State& state, const Body& body, const std::vector<Vec3>& points) {
  const Obstacle& obstacle = body;  // through the virtual interface, as the contact energy
  size_t i = 0;
  Vec3 g;
  for (auto _ : state) {
    benchmark::DoNotOptimize(obstacle.SignedDistance(points[i], &g));
    benchmark::DoNotOptimize(g);
    i = (i + 1) & (points.size() - 1);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
}

constexpr int kPoints = 4096;  // a power of two

void BM_SpheresNearHead(benchmark::State& state) {
  static const Body body = Load("mannequin.json");
  const std::vector<Vec3> points =
      NearHead(body, 1e-3 * static_cast<double>(state.range(0)), kPoints);
  Run(state, body, points);
  state.counters["spheres"] = static_cast<double>(body.spheres().size());
}
BENCHMARK(BM_SpheresNearHead)->Arg(2)->Arg(50)->ArgName("offset_mm");

void BM_MeshNearHead(benchmark::State& state) {
  static const Body body = Exact(Load("mannequin_mesh.json"));
  const std::vector<Vec3> points =
      NearHead(body, 1e-3 * static_cast<double>(state.range(0)), kPoints);
  Run(state, body, points);
}
BENCHMARK(BM_MeshNearHead)->Arg(2)->Arg(10)->Arg(50)->ArgName("offset_mm");

void BM_HeadMeshOnly(benchmark::State& state) {
  // The head component alone (5120 triangles), without the body's loop over components.
  static const Body body = Load("mannequin_mesh.json");
  const std::vector<Vec3> points =
      NearHead(body, 1e-3 * static_cast<double>(state.range(0)), kPoints);
  const TriangleMesh& head = body.meshes()[0];
  size_t i = 0;
  Vec3 g;
  for (auto _ : state) {
    benchmark::DoNotOptimize(head.SignedDistance(points[i], &g));
    i = (i + 1) & (points.size() - 1);
  }
}
BENCHMARK(BM_HeadMeshOnly)->Arg(2)->Arg(10)->Arg(50)->ArgName("offset_mm");

void BM_MeshInBox(benchmark::State& state) {
  static const Body body = Exact(Load("mannequin_mesh.json"));
  static const std::vector<Vec3> points = Points(body, 0.1, kPoints);
  Run(state, body, points);
}
BENCHMARK(BM_MeshInBox);

// The body file's default: the distance grid (docs/body.md, "Distance grid").
void BM_MeshGridNearHead(benchmark::State& state) {
  static const Body body = Load("mannequin_mesh.json");
  const std::vector<Vec3> points =
      NearHead(body, 1e-3 * static_cast<double>(state.range(0)), kPoints);
  Run(state, body, points);
}
BENCHMARK(BM_MeshGridNearHead)->Arg(2)->Arg(10)->Arg(50)->ArgName("offset_mm");

void BM_MeshGridInBox(benchmark::State& state) {
  static const Body body = Load("mannequin_mesh.json");
  static const std::vector<Vec3> points = Points(body, 0.1, kPoints);
  Run(state, body, points);
}
BENCHMARK(BM_MeshGridInBox);

// Value, gradient and Hessian (the stability certificate's query).
void BM_MeshGridHessianNearHead(benchmark::State& state) {
  static const Body body = Load("mannequin_mesh.json");
  const std::vector<Vec3> points = NearHead(body, 0.01, kPoints);
  const Obstacle& obstacle = body;
  size_t i = 0;
  Vec3 g;
  Mat3 h;
  for (auto _ : state) {
    benchmark::DoNotOptimize(obstacle.SignedDistanceHessian(points[i], &g, &h));
    benchmark::DoNotOptimize(h);
    i = (i + 1) & (points.size() - 1);
  }
}
BENCHMARK(BM_MeshGridHessianNearHead);

void BM_MeshBruteForceNearHead(benchmark::State& state) {
  // The reference without the hierarchy: one mesh component (the head), every triangle.
  static const Body body = Load("mannequin_mesh.json");
  static const std::vector<Vec3> points = NearHead(body, 0.05, kPoints);
  const TriangleMesh& head = body.meshes()[0];
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(head.SignedDistanceBruteForce(points[i], nullptr));
    i = (i + 1) & (points.size() - 1);
  }
  state.counters["triangles"] = static_cast<double>(head.triangles().size());
}
BENCHMARK(BM_MeshBruteForceNearHead);

}  // namespace
}  // namespace ringlet

BENCHMARK_MAIN();
