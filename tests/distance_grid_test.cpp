// The distance grid (src/body/distance_grid.h): accuracy against closed forms and the exact mesh
// distance with tolerances derived from the spacing, sign, derivatives against differences,
// C^1 continuity across cell faces, determinism, options.
#include "body/distance_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "ringlet/body.h"
#include "ringlet/body_json.h"

namespace ringlet {
namespace {

using internal::DistanceGrid;
using Triangle = TriangleMesh::Triangle;

// A subdivided icosahedron of radius r (outward, closed), as in body_test.cpp.
TriangleMesh Icosphere(int level, double r) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> v = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& p : v) p.normalize();
  std::vector<Triangle> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                             {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                             {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                             {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<int, int>, int> midpoint;
    auto middle = [&](int i, int j) {
      const auto key = std::make_pair(std::min(i, j), std::max(i, j));
      const auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      v.push_back((v[static_cast<size_t>(i)] + v[static_cast<size_t>(j)]).normalized());
      return midpoint[key] = static_cast<int>(v.size()) - 1;
    };
    std::vector<Triangle> refined;
    for (const Triangle& a : f) {
      const int ab = middle(a[0], a[1]), bc = middle(a[1], a[2]), ca = middle(a[2], a[0]);
      refined.push_back({a[0], ab, ca});
      refined.push_back({a[1], bc, ab});
      refined.push_back({a[2], ca, bc});
      refined.push_back({ab, bc, ca});
    }
    f = std::move(refined);
  }
  for (Vec3& p : v) p *= r;
  TriangleMesh mesh;
  std::string error;
  EXPECT_TRUE(TriangleMesh::Create(v, f, "sphere", &mesh, &error)) << error;
  return mesh;
}

// Distance from the centre to the nearest face plane: the mesh lies between the spheres of
// this radius and r, so |d_mesh - d_sphere| <= r - inradius.
double Inradius(const TriangleMesh& mesh) {
  double inradius = 1e300;
  for (const Triangle& t : mesh.triangles()) {
    const Vec3& a = mesh.vertices()[static_cast<size_t>(t[0])];
    const Vec3& b = mesh.vertices()[static_cast<size_t>(t[1])];
    const Vec3& c = mesh.vertices()[static_cast<size_t>(t[2])];
    inradius = std::min(inradius, (b - a).cross(c - a).normalized().dot(a));
  }
  return inradius;
}

// Random points of the box.
std::vector<Vec3> RandomPoints(const Box3& box, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> points;
  for (int i = 0; i < count; ++i) {
    points.push_back(box.min() + box.sizes().cwiseProduct(Vec3(u(rng), u(rng), u(rng))));
  }
  return points;
}

constexpr double kR = 0.1;      // m
constexpr double kH = 0.004;    // m, the body files' default spacing
constexpr double kBand = 0.03;  // m
// Rounding of the float node values: |d| <= band, 24-bit mantissa, weights summing to 1.
constexpr double kFloatError = kBand * 1e-7;

// Smooth d: the B-spline's moments give F - d = (h^2/6) sum_a d_aa + O(h^4) (the cubic B-spline
// kernel has variance h^2/3), so |F - d| <= (h^2/2) max |Hessian| over the 4h support; the
// sphere's Hessian is (I - n n^T)/|x - c| <= 1/(R - band - 2 sqrt(3) h) there. Tolerance = that
// bound, not a fitted number; the measured maximum is printed.
TEST(DistanceGrid, SphereWithinSplineErrorBound) {
  const auto sphere = [](const Vec3& x) { return x.norm() - kR; };
  const Box3 box(Vec3::Constant(-kR), Vec3::Constant(kR));
  const DistanceGrid grid = DistanceGrid::Build(sphere, box, kH, kBand);
  const double kappa = 1.0 / (kR - kBand - 2.0 * std::sqrt(3.0) * kH);
  const double tolerance = 0.5 * kH * kH * kappa + kFloatError;
  double worst = 0.0;
  int tested = 0;
  for (const Vec3& x : RandomPoints(Box3(Vec3::Constant(-0.14), Vec3::Constant(0.14)), 20000, 1)) {
    const double d = sphere(x);
    if (std::abs(d) > kBand - 2.0 * std::sqrt(3.0) * kH) continue;  // support holds clamped nodes
    worst = std::max(worst, std::abs(grid.Evaluate(x, nullptr, nullptr) - d));
    ++tested;
  }
  std::printf("sphere, h = %g mm: max |F - d| = %.3g um (bound %.3g um), %d points\n", kH * 1e3,
              worst * 1e6, tolerance * 1e6, tested);
  EXPECT_GT(tested, 1000);
  EXPECT_LE(worst, tolerance);
}

// The icosphere mesh lies within r - inradius of the sphere, and F is linear in the node values
// with weights summing to 1: |F_mesh - d_mesh| <= |F_sphere - d_sphere| + 2 (r - inradius).
TEST(DistanceGrid, MeshWithinBoundOfExactDistanceAndSignCorrect) {
  const TriangleMesh mesh = Icosphere(4, kR);
  const double chordal = kR - Inradius(mesh);
  Body body;
  std::string error;
  MeshDistanceOptions options;
  options.mode = MeshDistanceOptions::Mode::kGrid;
  options.spacing = kH;
  options.band = kBand;
  ASSERT_TRUE(Body::Create({}, {mesh}, &body, &error, 0.0, options)) << error;
  ASSERT_NE(body.distance_grid(), nullptr);
  const double kappa = 1.0 / (kR - kBand - 2.0 * std::sqrt(3.0) * kH);
  const double tolerance = 0.5 * kH * kH * kappa + 2.0 * chordal + kFloatError;
  double worst = 0.0;
  int tested = 0, signs = 0;
  for (const Vec3& x : RandomPoints(Box3(Vec3::Constant(-0.15), Vec3::Constant(0.15)), 20000, 2)) {
    const double d = mesh.SignedDistance(x, nullptr);
    const double f = body.SignedDistance(x, nullptr);
    // Sign: everywhere the exact distance exceeds the error bound (deep points are clamped to
    // -band, far ones to +band: the sign stays).
    if (std::abs(d) > tolerance) {
      EXPECT_EQ(f > 0.0, d > 0.0) << x.transpose();
      ++signs;
    }
    // Beyond the band F is the clamp: a lower bound of |d| with the sign of d.
    if (std::abs(d) > kBand + tolerance) {
      EXPECT_LE(std::abs(f), std::abs(d));
    }
    if (std::abs(d) > kBand - 2.0 * std::sqrt(3.0) * kH) continue;
    worst = std::max(worst, std::abs(f - d));
    ++tested;
  }
  std::printf(
      "icosphere (5120 triangles), h = %g mm: max |F - d| = %.3g um (bound %.3g um, "
      "chordal %.3g um), %d points in the band\n",
      kH * 1e3, worst * 1e6, tolerance * 1e6, chordal * 1e6, tested);
  EXPECT_GT(tested, 1000);
  EXPECT_GT(signs, 10000);
  EXPECT_LE(worst, tolerance);
}

Body MannequinGrid(double spacing, int threads) {
  std::vector<TriangleMesh> meshes;
  std::string error;
  EXPECT_TRUE(
      LoadObjMeshes(std::string(RINGLET_EXAMPLES_DIR) + "/bodies/mannequin.obj", &meshes, &error))
      << error;
  MeshDistanceOptions options;
  options.mode = MeshDistanceOptions::Mode::kGrid;
  options.spacing = spacing;
  options.band = kBand;
  options.threads = threads;
  Body body;
  EXPECT_TRUE(Body::Create({}, std::move(meshes), &body, &error, kDefaultBodyBlend, options))
      << error;
  return body;
}

// Derivatives: gradient against central differences of the value, Hessian against central
// differences of the gradient, at random points of the mannequin's band (the B-spline is a
// cubic polynomial per cell, so the differences are exact up to O(step^2) and rounding).
TEST(DistanceGrid, GradientAndHessianMatchDifferences) {
  const Body body = MannequinGrid(kH, 0);
  const double step = 1e-6;
  int tested = 0;
  double max_gradient_norm = 0.0;
  for (const Vec3& x : RandomPoints(body.Bounds(), 4000, 3)) {
    Vec3 g;
    Mat3 h;
    const double d = body.SignedDistanceHessian(x, &g, &h);
    if (std::abs(d) > 0.02) continue;
    ++tested;
    max_gradient_norm = std::max(max_gradient_norm, g.norm());
    for (int a = 0; a < 3; ++a) {
      const Vec3 e = step * Vec3::Unit(a);
      Vec3 gp, gm;
      const double fd =
          (body.SignedDistance(x + e, &gp) - body.SignedDistance(x - e, &gm)) / (2.0 * step);
      EXPECT_NEAR(g(a), fd, 1e-6) << x.transpose();
      const Vec3 hd = (gp - gm) / (2.0 * step);
      for (int b = 0; b < 3; ++b) {
        EXPECT_NEAR(h(b, a), hd(b), 1e-5 * std::max(1.0, std::abs(hd(b)))) << x.transpose();
      }
    }
  }
  std::printf("mannequin grid: max |grad F| = %.6f within 2 cm of the surface\n",
              max_gradient_norm);
  EXPECT_GT(tested, 200);
  EXPECT_GT(max_gradient_norm, 0.9);  // anti-vacuity: the gradient is the unit normal
  EXPECT_LT(max_gradient_norm, 1.05);
}

// C^1 (indeed C^2): value, gradient and Hessian agree on both sides of a cell face.
TEST(DistanceGrid, GradientContinuousAcrossCellFaces) {
  const Body body = MannequinGrid(kH, 0);
  const DistanceGrid& grid = *body.distance_grid();
  // The grid's origin is the meshes' box min minus band + 3 h; node planes are origin + i h.
  Box3 mesh_box;
  for (const TriangleMesh& m : body.meshes()) mesh_box.extend(m.bounds());
  const Vec3 origin = mesh_box.min() - Vec3::Constant(kBand + 3.0 * kH);
  int tested = 0;
  for (const Vec3& p : RandomPoints(mesh_box, 2000, 4)) {
    if (std::abs(grid.Evaluate(p, nullptr, nullptr)) > 0.02) continue;
    for (int a = 0; a < 3; ++a) {
      Vec3 face = p;
      face(a) = origin(a) + std::round((p(a) - origin(a)) / kH) * kH;
      const Vec3 e = 1e-9 * Vec3::Unit(a);
      Vec3 g0, g1;
      Mat3 h0, h1;
      const double f0 = grid.Evaluate(face - e, &g0, &h0);
      const double f1 = grid.Evaluate(face + e, &g1, &h1);
      EXPECT_NEAR(f0, f1, 1e-8);
      EXPECT_LT((g0 - g1).norm(), 1e-5);  // the Hessian is bounded: jump over 2e-9 m only
      EXPECT_LT((h0 - h1).norm(), 1e-2 * std::max(1.0, h0.norm()));
      ++tested;
    }
  }
  EXPECT_GT(tested, 300);
}

TEST(DistanceGrid, BitIdenticalOnOneAndTwoThreads) {
  const Body one = MannequinGrid(0.008, 1);
  const Body two = MannequinGrid(0.008, 2);
  ASSERT_EQ(one.distance_grid()->values().size(), two.distance_grid()->values().size());
  EXPECT_TRUE(one.distance_grid()->values() == two.distance_grid()->values());
}

// Build time and memory of the mannequin grid at a few spacings (printed for docs/benchmarks.md;
// speed targets live in benchmarks), with the measured error against the exact distance.
TEST(DistanceGrid, MannequinErrorBuildTimeAndMemory) {
  std::vector<TriangleMesh> meshes;
  std::string error;
  ASSERT_TRUE(
      LoadObjMeshes(std::string(RINGLET_EXAMPLES_DIR) + "/bodies/mannequin.obj", &meshes, &error));
  Body exact;
  ASSERT_TRUE(Body::Create({}, meshes, &exact, &error, kDefaultBodyBlend));
  // 2 mm: docs/benchmarks.md (4.6 s to build, too slow for a test).
  for (double h : {0.003, 0.004, 0.005, 0.006, 0.008}) {
    const Body grid = MannequinGrid(h, 0);
    double worst = 0.0, worst_normal = 0.0;
    for (const Vec3& x : RandomPoints(exact.Bounds(), 20000, 5)) {
      Vec3 ge, gg;
      const double d = exact.SignedDistance(x, &ge);
      if (d < 0.0 || d > 0.02) continue;  // the clearance layer outside the body
      worst = std::max(worst, std::abs(grid.SignedDistance(x, &gg) - d));
      worst_normal = std::max(worst_normal, (gg - ge).norm());
    }
    std::printf(
        "mannequin h = %g mm: build %.3f s, %zu queries, %.1f MB, max |F - d| in [0, 2 cm] "
        "= %.3g mm, max |grad F - grad d| = %.3g\n",
        h * 1e3, grid.grid_build_seconds(), grid.distance_grid()->queries(),
        grid.GridMemoryBytes() / 1e6, worst * 1e3, worst_normal);
    // Any 1-Lipschitz d: |F - d| <= sum w |x_i - x| <= sqrt(sum w |x_i - x|^2) = h (Jensen; the
    // B-spline weights' second moment is h^2/3 per axis).
    EXPECT_LE(worst, h + kFloatError);
  }
}

TEST(DistanceGrid, BadOptionsAreOneLineErrors) {
  MeshDistanceOptions options;
  std::string why;
  options.spacing = 0.0;
  EXPECT_FALSE(options.IsValid(&why));
  EXPECT_EQ(why, "spacing: expected a finite number >= 0.0001 (m), got 0");
  options.spacing = 0.004;
  options.band = -1.0;
  EXPECT_FALSE(options.IsValid(&why));
  EXPECT_EQ(why, "band: expected a finite number > 0 (m), got -1");
  Body body;
  EXPECT_FALSE(Body::Create({}, {Icosphere(1, 0.1)}, &body, &why, 0.0, options));
  EXPECT_EQ(why, "mesh_distance.band: expected a finite number > 0 (m), got -1");
  // Too many nodes: a clear message, no allocation attempted.
  options.mode = MeshDistanceOptions::Mode::kGrid;
  options.band = 0.03;
  options.spacing = 1e-4;
  EXPECT_FALSE(Body::Create({}, {Icosphere(1, 0.1)}, &body, &why, 0.0, options));
  EXPECT_EQ(why.rfind("mesh_distance.spacing: 0.0001 m gives ", 0), 0u) << why;
  EXPECT_NE(why.find("use a coarser spacing or exact queries"), std::string::npos) << why;

  const std::string base = std::string(RINGLET_EXAMPLES_DIR) + "/bodies";
  const auto parse = [&](const char* text) {
    std::string message;
    Body b;
    EXPECT_FALSE(ParseBody(nlohmann::json::parse(text), "body", base, &b, &message));
    EXPECT_EQ(message.find('\n'), std::string::npos);
    return message;
  };
  EXPECT_NE(parse(R"({"meshes": [{"obj": "mannequin.obj"}], "mesh_distance": "fast"})")
                .find("body.mesh_distance: expected \"grid\" or \"exact\""),
            std::string::npos);
  EXPECT_NE(parse(R"({"meshes": [{"obj": "mannequin.obj"}], "grid_spacing": 0})")
                .find("body.grid_spacing: expected a finite number >= 0.0001 (m)"),
            std::string::npos);
  EXPECT_NE(parse(R"({"meshes": [{"obj": "mannequin.obj"}], "grid_band": "wide"})")
                .find("body.grid_band: expected a finite number > 0 (m)"),
            std::string::npos);
}

TEST(DistanceGrid, BodyFilesDefaultToTheGridAndAcceptExact) {
  Body grid, exact;
  std::string error;
  const std::string base = std::string(RINGLET_EXAMPLES_DIR) + "/bodies";
  ASSERT_TRUE(ParseBody(nlohmann::json::parse(R"({"meshes": [{"obj": "mannequin.obj"}]})"), "",
                        base, &grid, &error))
      << error;
  ASSERT_TRUE(ParseBody(
      nlohmann::json::parse(R"({"meshes": [{"obj": "mannequin.obj"}], "mesh_distance": "exact"})"),
      "", base, &exact, &error))
      << error;
  ASSERT_NE(grid.distance_grid(), nullptr);
  EXPECT_EQ(grid.mesh_distance().spacing, kDefaultGridSpacing);
  EXPECT_EQ(exact.distance_grid(), nullptr);
  // Near the head's top both agree within the spacing.
  const Vec3 x(0.0, 0.0, 0.105);
  EXPECT_NEAR(grid.SignedDistance(x, nullptr), exact.SignedDistance(x, nullptr),
              kDefaultGridSpacing);
}

}  // namespace
}  // namespace ringlet
