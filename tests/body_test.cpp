// The body (src/body/, src/io/obj_mesh.cpp): sphere and mesh signed distances against closed
// forms, the hierarchy against brute force, gradients against finite differences, unions,
// rejected meshes and OBJ files.
#include "ringlet/body.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "ringlet/body_json.h"
#include "test_util.h"

namespace ringlet {
namespace {

using Triangle = TriangleMesh::Triangle;

// ---------------------------------------------------------------------------------------------
// Meshes and closed forms.

// The box [-h, h]^3 as 8 vertices and 12 outward triangles, each square face split along one
// diagonal. Corners then have 3 to 6 incident triangles, so an unweighted average of face
// normals would tilt the vertex normals: the angle weighting is exercised.
void BoxMesh(const Vec3& h, std::vector<Vec3>* vertices, std::vector<Triangle>* triangles) {
  vertices->clear();
  for (int i = 0; i < 8; ++i) {
    vertices->emplace_back((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(),
                           (i & 4) ? h.z() : -h.z());
  }
  // Faces as quads (counter-clockwise seen from outside), split into (0,1,2) and (0,2,3).
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  triangles->clear();
  for (const auto& q : quads) {
    triangles->push_back({q[0], q[1], q[2]});
    triangles->push_back({q[0], q[2], q[3]});
  }
}

TriangleMesh MustCreate(std::vector<Vec3> vertices, std::vector<Triangle> triangles) {
  TriangleMesh mesh;
  std::string error;
  EXPECT_TRUE(
      TriangleMesh::Create(std::move(vertices), std::move(triangles), "test", &mesh, &error))
      << error;
  return mesh;
}

TriangleMesh Box(const Vec3& h) {
  std::vector<Vec3> v;
  std::vector<Triangle> t;
  BoxMesh(h, &v, &t);
  return MustCreate(v, t);
}

// Exact signed distance to the box [-h, h]^3 (the standard closed form, e.g. Quilez, "distance
// functions"): with q = |p| - h componentwise, |max(q, 0)| outside plus min(max_i q_i, 0)
// inside.
double BoxDistance(const Vec3& p, const Vec3& h) {
  const Vec3 q = p.cwiseAbs() - h;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

// A unit icosahedron subdivided `level` times (edge midpoints pushed to the sphere), scaled
// to radius r: every vertex on the sphere, triangles outward.
void Icosphere(int level, double r, std::vector<Vec3>* vertices, std::vector<Triangle>* triangles) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  *vertices = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
               {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& v : *vertices) v.normalize();
  *triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<int, int>, int> midpoint;
    auto middle = [&](int i, int j) {
      const auto key = std::make_pair(std::min(i, j), std::max(i, j));
      const auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      vertices->push_back(
          ((*vertices)[static_cast<size_t>(i)] + (*vertices)[static_cast<size_t>(j)]).normalized());
      return midpoint[key] = static_cast<int>(vertices->size()) - 1;
    };
    std::vector<Triangle> refined;
    for (const Triangle& f : *triangles) {
      const int ab = middle(f[0], f[1]), bc = middle(f[1], f[2]), ca = middle(f[2], f[0]);
      refined.push_back({f[0], ab, ca});
      refined.push_back({f[1], bc, ab});
      refined.push_back({f[2], ca, bc});
      refined.push_back({ab, bc, ca});
    }
    *triangles = std::move(refined);
  }
  for (Vec3& v : *vertices) v *= r;
}

std::string Examples() { return RINGLET_EXAMPLES_DIR; }

const TriangleMesh* FindMesh(const Body& body, const std::string& name) {
  for (const TriangleMesh& m : body.meshes()) {
    if (m.name() == name) return &m;
  }
  return nullptr;
}

// A fresh empty directory for file tests, removed by the destructor.
class TempDirectory {
 public:
  TempDirectory() {
    std::string pattern = ::testing::TempDir() + "ringlet_body_XXXXXX";
    path_ = ::mkdtemp(pattern.data()) ? pattern : std::string();
  }
  ~TempDirectory() {
    std::error_code ec;
    if (!path_.empty()) std::filesystem::remove_all(path_, ec);
  }
  std::string Write(const std::string& name, const std::string& contents) const {
    const std::string file = path_ + "/" + name;
    std::ofstream(file) << contents;
    return file;
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// The box [-1, 1]^3 as an OBJ file with 6 quads.
const char* kBoxObj = R"(# a cube
o box
v -1 -1 -1
v  1 -1 -1
v -1  1 -1
v  1  1 -1
v -1 -1  1
v  1 -1  1
v -1  1  1
v  1  1  1
f 1 3 4 2
f 5 6 8 7
f 1 2 6 5
f 3 7 8 4
f 1 5 7 3
f 2 4 8 6
)";

// ---------------------------------------------------------------------------------------------
// Spheres.

TEST(Sphere, DistanceAndGradientExact) {
  const Sphere s{Vec3(0.1, -0.2, 0.3), 0.05, "s"};
  // x = c + rho u with u = (1, 2, 2)/3 a unit vector: d = rho - r, gradient u (by hand).
  const Vec3 u = Vec3(1.0, 2.0, 2.0) / 3.0;
  for (double rho : {0.0, 0.01, 0.05, 0.07, 1.0}) {
    Vec3 g;
    const double d = SphereSignedDistance(s, s.center + rho * u, &g);
    EXPECT_NEAR(d, rho - 0.05, 1e-15) << rho;
    if (rho > 0.0) {
      EXPECT_LT((g - u).norm(), 1e-14) << rho;
    }
  }
  // At the centre: depth r, gradient the documented +z.
  Vec3 g;
  EXPECT_EQ(SphereSignedDistance(s, s.center, &g), -0.05);
  EXPECT_EQ(g, Vec3::UnitZ());

  // The same through a body of one sphere.
  Body body;
  std::string error;
  ASSERT_TRUE(Body::Create({s}, {}, &body, &error)) << error;
  EXPECT_NEAR(body.SignedDistance(s.center + 0.07 * u, &g), 0.02, 1e-15);
  EXPECT_LT((g - u).norm(), 1e-14);
  EXPECT_TRUE(
      body.Bounds().isApprox(Box3(Vec3(0.05, -0.25, 0.25), Vec3(0.15, -0.15, 0.35)), 1e-15));
}

// ---------------------------------------------------------------------------------------------
// Closest point on a triangle.

TEST(ClosestPointOnTriangle, AgreesWithDenseSampling) {
  // Independent reference: the minimum distance over a fine barycentric grid (spacing 1/400 of
  // the edges) is within the grid's covering radius of the exact minimum, and never below it.
  const Vec3 a(0.0, 0.0, 0.0), b(1.0, 0.2, 0.1), c(0.3, 0.9, -0.2);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 2.0);
  const int n = 400;
  const double covering = 1.5 / n;  // longest edge (about 1.05) / n, generously
  for (int trial = 0; trial < 40; ++trial) {
    const Vec3 p(u(rng), u(rng), u(rng));
    TriangleFeature feature;
    const double exact = (p - ClosestPointOnTriangle(p, a, b, c, &feature)).norm();
    double sampled = 1e300;
    for (int i = 0; i <= n; ++i) {
      for (int j = 0; i + j <= n; ++j) {
        const Vec3 q = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
        sampled = std::min(sampled, (p - q).norm());
      }
    }
    EXPECT_LE(exact, sampled + 1e-14) << trial;
    EXPECT_GE(exact, sampled - covering) << trial;
  }
  // Each region once, by construction: above the face, beyond each edge, beyond each corner.
  TriangleFeature f;
  const Vec3 A(0, 0, 0), B(1, 0, 0), C(0, 1, 0);
  EXPECT_LT((ClosestPointOnTriangle(Vec3(0.2, 0.2, 1), A, B, C, &f) - Vec3(0.2, 0.2, 0)).norm(),
            1e-16);
  EXPECT_EQ(f, TriangleFeature::kFace);
  EXPECT_EQ(ClosestPointOnTriangle(Vec3(0.5, -1, 1), A, B, C, &f), Vec3(0.5, 0, 0));
  EXPECT_EQ(f, TriangleFeature::kEdge0);
  EXPECT_TRUE(ClosestPointOnTriangle(Vec3(1, 1, 0), A, B, C, &f).isApprox(Vec3(0.5, 0.5, 0)));
  EXPECT_EQ(f, TriangleFeature::kEdge1);
  EXPECT_EQ(ClosestPointOnTriangle(Vec3(-1, 0.5, 0), A, B, C, &f), Vec3(0, 0.5, 0));
  EXPECT_EQ(f, TriangleFeature::kEdge2);
  EXPECT_EQ(ClosestPointOnTriangle(Vec3(-1, -1, 0), A, B, C, &f), A);
  EXPECT_EQ(f, TriangleFeature::kVertex0);
  EXPECT_EQ(ClosestPointOnTriangle(Vec3(2, -0.5, 0), A, B, C, &f), B);
  EXPECT_EQ(f, TriangleFeature::kVertex1);
  EXPECT_EQ(ClosestPointOnTriangle(Vec3(-0.5, 2, 0), A, B, C, &f), C);
  EXPECT_EQ(f, TriangleFeature::kVertex2);
}

// ---------------------------------------------------------------------------------------------
// Mesh signed distance.

// Coordinates just inside and outside the faces, edges and corners of the box, where the
// closest feature is a vertex or an edge and a wrong pseudo-normal flips the sign.
std::vector<double> NearBoundaryCoordinates(double h) {
  std::vector<double> values = {0.0, 0.3 * h, -0.7 * h};
  for (double delta : {1e-3 * h, 1e-7 * h, 0.3 * h}) {
    for (double sign : {-1.0, 1.0}) {
      values.push_back(sign * (h + delta));
      values.push_back(sign * (h - delta));
    }
  }
  return values;
}

TEST(TriangleMesh, BoxMatchesClosedFormNearEdgesAndCorners) {
  const Vec3 h(0.1, 0.15, 0.2);
  const TriangleMesh box = Box(h);
  EXPECT_NEAR(box.volume(), 8.0 * h.prod(), 1e-15);  // 8 h_x h_y h_z
  const std::vector<double> xs = NearBoundaryCoordinates(h.x());
  const std::vector<double> ys = NearBoundaryCoordinates(h.y());
  const std::vector<double> zs = NearBoundaryCoordinates(h.z());
  int inside = 0, outside = 0;
  for (double x : xs) {
    for (double y : ys) {
      for (double z : zs) {
        const Vec3 p(x, y, z);
        const double expected = BoxDistance(p, h);
        const double d = box.SignedDistance(p, nullptr);
        // Rounding only: the inputs are O(0.2 m), so a few ulps of 0.2 (1e-16 each).
        ASSERT_NEAR(d, expected, 1e-15) << p.transpose();
        (expected < 0.0 ? inside : outside) += 1;
      }
    }
  }
  EXPECT_GT(inside, 100);
  EXPECT_GT(outside, 1000);
}

TEST(TriangleMesh, SharpPyramidSignNearApexAndEdges) {
  // The box cannot tell a wrong pseudo-normal from a right one: at its right-angled edges and
  // corners any positive combination of the face normals gives the right sign. A tall, thin
  // pyramid can: its side edges are sharp (interior dihedral angle 60 deg) and its apex is a
  // narrow cone, so the edge normal must mix both faces and the apex normal must be close to
  // the axis. One side face is split into 12 thin triangles fanning from the apex, which tilts
  // an unweighted average of face normals (not the angle-weighted one) toward that face.
  // Reference: the pyramid is convex, so x is inside iff it is below every face plane, and
  // its depth inside is the smallest distance to a face plane; outside, the distance is the
  // smallest over triangles (ClosestPointOnTriangle, tested above).
  const double r = 0.05, height = 1.0;
  const int splits = 12;
  std::vector<Vec3> v;
  for (int k = 0; k < 3; ++k) {
    const double angle = 2.0 * M_PI * k / 3.0;
    v.emplace_back(r * std::cos(angle), r * std::sin(angle), 0.0);  // base corners 0, 1, 2
  }
  v.emplace_back(0.0, 0.0, height);  // apex 3
  std::vector<int> edge01 = {0};     // base edge 0 -> 1 with splits - 1 points inside
  for (int i = 1; i < splits; ++i) {
    v.push_back(v[0] + (v[1] - v[0]) * (double(i) / splits));
    edge01.push_back(static_cast<int>(v.size()) - 1);
  }
  edge01.push_back(1);
  std::vector<Triangle> t = {{1, 2, 3}, {2, 0, 3}};
  for (int i = 0; i < splits; ++i) {
    t.push_back({edge01[static_cast<size_t>(i)], edge01[static_cast<size_t>(i) + 1], 3});
    t.push_back({2, edge01[static_cast<size_t>(i) + 1], edge01[static_cast<size_t>(i)]});
  }
  const TriangleMesh pyramid = MustCreate(v, t);
  // Face planes (outward unit normal n, offset n . point) of the three sides and the base.
  std::vector<std::pair<Vec3, double>> planes;
  for (const Triangle& f :
       {Triangle{0, 1, 3}, Triangle{1, 2, 3}, Triangle{2, 0, 3}, Triangle{0, 2, 1}}) {
    const Vec3 n = (v[static_cast<size_t>(f[1])] - v[static_cast<size_t>(f[0])])
                       .cross(v[static_cast<size_t>(f[2])] - v[static_cast<size_t>(f[0])])
                       .normalized();
    planes.emplace_back(n, n.dot(v[static_cast<size_t>(f[0])]));
  }
  std::mt19937_64 rng(17);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int inside = 0, outside = 0;
  for (int i = 0; i < 20000; ++i) {
    // Around the apex, or around a point of a side edge, at distances from 1e-6 to 1e-2.
    const Vec3 anchor_point = i % 2 == 0 ? v[3]
                                         : Vec3(v[static_cast<size_t>(i % 3)] +
                                                unit(rng) * (v[3] - v[static_cast<size_t>(i % 3)]));
    const Vec3 p = anchor_point + std::pow(10.0, -6.0 + 4.0 * unit(rng)) *
                                      Vec3(gauss(rng), gauss(rng), gauss(rng)).normalized();
    double plane_max = -1e300;
    for (const auto& [n, offset] : planes) plane_max = std::max(plane_max, n.dot(p) - offset);
    const double d = pyramid.SignedDistance(p, nullptr);
    if (plane_max < -1e-12) {
      ASSERT_NEAR(d, plane_max, 1e-12) << p.transpose();
      ++inside;
    } else if (plane_max > 1e-12) {
      ASSERT_GT(d, 0.0) << p.transpose();
      ASSERT_NEAR(d, pyramid.SignedDistanceBruteForce(p, nullptr), 1e-15);
      ++outside;
    }
  }
  EXPECT_GT(inside, 1000);
  EXPECT_GT(outside, 10000);
}

TEST(TriangleMesh, RotatedBoxMatchesClosedFormAtRandomPoints) {
  // A rigid motion of the box must not change distances: mesh = R * box + t, queried at
  // R * p + t, against the closed form at p.
  const Vec3 h(0.05, 0.08, 0.12);
  const Mat3 rotation = testing::RandomRotation(11);
  const Vec3 translation(0.3, -0.1, 0.7);
  std::vector<Vec3> v;
  std::vector<Triangle> t;
  BoxMesh(h, &v, &t);
  for (Vec3& x : v) x = rotation * x + translation;
  const TriangleMesh box = MustCreate(v, t);
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  for (int i = 0; i < 5000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    Vec3 g;
    const double d = box.SignedDistance(rotation * p + translation, &g);
    ASSERT_NEAR(d, BoxDistance(p, h), 1e-14) << p.transpose();
    ASSERT_NEAR(g.norm(), 1.0, 1e-12);
  }
}

TEST(TriangleMesh, IcosphereWithinChordalErrorOfSphere) {
  // Every vertex lies on the sphere of radius R, so the convex mesh K lies between the balls
  // B(R - s) and B(R), where s = R - min over faces of the distance from the centre to the
  // face's plane (the chordal error, the sagitta of the largest face: R - sqrt(R^2 - rho^2)
  // for circumradius rho). The signed distance is monotone under inclusion (A in B implies
  // d_B <= d_A), hence |x| - R <= d_K(x) <= |x| - R + s everywhere.
  const double r = 0.1;
  std::vector<Vec3> v;
  std::vector<Triangle> t;
  Icosphere(3, r, &v, &t);
  double min_plane = r;
  for (const Triangle& f : t) {
    const Vec3& a = v[static_cast<size_t>(f[0])];
    const Vec3 n = (v[static_cast<size_t>(f[1])] - a).cross(v[static_cast<size_t>(f[2])] - a);
    min_plane = std::min(min_plane, n.normalized().dot(a));
  }
  const double s = r - min_plane;
  // Level 3: edges of about 0.15 R, so s ~ rho^2 / (2R) ~ 0.4% of R (a meaningful bound).
  EXPECT_GT(s, 1e-4 * r);
  EXPECT_LT(s, 1e-2 * r);
  const TriangleMesh sphere = MustCreate(v, t);
  EXPECT_EQ(sphere.triangles().size(), 1280u);

  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-2.0 * r, 2.0 * r);
  double largest_gap = 0.0;
  for (int i = 0; i < 5000; ++i) {
    Vec3 p(u(rng), u(rng), u(rng));
    if (i % 2 == 0) p = p.normalized() * r * (1.0 + 0.02 * (u(rng) / r));  // near the surface
    const double exact = p.norm() - r;
    const double d = sphere.SignedDistance(p, nullptr);
    ASSERT_GE(d, exact - 1e-15) << p.transpose();
    ASSERT_LE(d, exact + s + 1e-15) << p.transpose();
    largest_gap = std::max(largest_gap, d - exact);
  }
  // Anti-vacuity: the gap does come close to s (near face centres).
  EXPECT_GT(largest_gap, 0.5 * s);
}

// The mesh mannequin's meshes (examples/bodies/mannequin_mesh.json's) without its distance grid:
// TriangleMesh's own queries do not use the grid, and building it took most of these tests' time
// under the sanitizers (45-55 s each).
bool LoadMannequinMeshesExact(Body* body, std::string* error) {
  return ParseBody(
      nlohmann::json::parse(R"({"meshes": [{"obj": "mannequin.obj"}], "mesh_distance": "exact"})"),
      "", Examples() + "/bodies", body, error);
}

TEST(TriangleMesh, HierarchyEqualsBruteForce) {
  Body body;
  std::string error;
  ASSERT_TRUE(LoadMannequinMeshesExact(&body, &error)) << error;
  ASSERT_EQ(body.meshes().size(), 3u);
  std::mt19937_64 rng(5);
  for (const TriangleMesh& mesh : body.meshes()) {
    const Box3 box = mesh.bounds();
    std::uniform_real_distribution<double> ux(box.min().x() - 0.05, box.max().x() + 0.05);
    std::uniform_real_distribution<double> uy(box.min().y() - 0.05, box.max().y() + 0.05);
    std::uniform_real_distribution<double> uz(box.min().z() - 0.05, box.max().z() + 0.05);
    std::uniform_real_distribution<double> offset(-0.003, 0.003);
    std::uniform_int_distribution<size_t> vertex(0, mesh.vertices().size() - 1);
    for (int i = 0; i < 1500; ++i) {
      // Two thirds in the box around the mesh, one third within 3 mm of a vertex.
      const Vec3 p =
          i % 3 == 0
              ? Vec3(mesh.vertices()[vertex(rng)] + Vec3(offset(rng), offset(rng), offset(rng)))
              : Vec3(ux(rng), uy(rng), uz(rng));
      Vec3 g_tree, g_brute;
      const double d_tree = mesh.SignedDistance(p, &g_tree);
      const double d_brute = mesh.SignedDistanceBruteForce(p, &g_brute);
      // Equal up to rounding: on ties (a shared edge or vertex) the two searches may take the
      // closest point from different triangles.
      ASSERT_NEAR(d_tree, d_brute, 1e-15) << mesh.name() << " " << p.transpose();
      ASSERT_LT((g_tree - g_brute).norm(), 1e-9) << mesh.name() << " " << p.transpose();
    }
  }
}

TEST(TriangleMesh, GradientMatchesCentralDifferences) {
  // Away from the medial axis the signed distance is differentiable with gradient the unit
  // (signed) direction to the closest point. Points: outside the convex icosphere (no medial
  // axis there), and inside the box where the nearest face is unique by a margin.
  std::vector<Vec3> v;
  std::vector<Triangle> t;
  Icosphere(2, 0.1, &v, &t);
  const TriangleMesh sphere = MustCreate(v, t);
  const Vec3 h(0.1, 0.15, 0.2);
  const TriangleMesh box = Box(h);
  const double step = 1e-6;
  auto check = [&](const TriangleMesh& mesh, const Vec3& p) {
    Vec3 g;
    mesh.SignedDistance(p, &g);
    ASSERT_NEAR(g.norm(), 1.0, 1e-12);
    for (int i = 0; i < 3; ++i) {
      Vec3 plus = p, minus = p;
      plus(i) += step;
      minus(i) -= step;
      const double fd =
          (mesh.SignedDistance(plus, nullptr) - mesh.SignedDistance(minus, nullptr)) / (2 * step);
      // Truncation h^2 |d'''| (curvature radius >= 1 cm: ~1e-8) plus rounding 1e-16 / h.
      EXPECT_NEAR(g(i), fd, 1e-7) << p.transpose() << " axis " << i;
    }
  };
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  int checked_inside = 0;
  for (int i = 0; i < 300; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    if (p.norm() > 0.12) check(sphere, p);
    const Vec3 q = p.cwiseProduct(h) / 0.3;  // inside the box
    Vec3 gaps = q.cwiseAbs() - h;            // -(distance to each pair of faces)
    std::sort(gaps.data(), gaps.data() + 3);
    if (gaps(2) - gaps(1) > 1e-3) {
      check(box, q);
      ++checked_inside;
    }
  }
  EXPECT_GT(checked_inside, 100);
}

TEST(TriangleMesh, ClosestPointProjectionAndLipschitz) {
  // x - d(x) grad d(x) is the closest surface point, so its distance is zero (anywhere, medial
  // axis included); and |d(x) - d(y)| <= |x - y| (1-Lipschitz).
  Body body;
  std::string error;
  ASSERT_TRUE(LoadMannequinMeshesExact(&body, &error)) << error;
  const TriangleMesh& head = *FindMesh(body, "head");
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(-0.15, 0.15);
  std::uniform_real_distribution<double> small(-0.01, 0.01);
  int inside = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 x(u(rng), u(rng), u(rng));
    Vec3 g;
    const double d = head.SignedDistance(x, &g);
    if (d < 0.0) ++inside;
    EXPECT_NEAR(head.SignedDistance(x - d * g, nullptr), 0.0, 1e-12) << x.transpose();
    const Vec3 y = x + Vec3(small(rng), small(rng), small(rng));
    EXPECT_LE(std::abs(head.SignedDistance(y, nullptr) - d), (y - x).norm() * (1 + 1e-12) + 1e-15);
  }
  EXPECT_GT(inside, 200);
}

TEST(TriangleMesh, EmptyMeshIsFarAway) {
  const TriangleMesh empty;
  Vec3 g;
  EXPECT_EQ(empty.SignedDistance(Vec3::Zero(), &g), std::numeric_limits<double>::infinity());
  EXPECT_EQ(g, Vec3::UnitZ());
}

// ---------------------------------------------------------------------------------------------
// Bodies: unions.

TEST(Body, UnionOfSphereAndBoxIsTheMinimum) {
  const Vec3 h(0.1, 0.1, 0.1);
  const Sphere sphere{Vec3(0.1, 0.1, 0.1), 0.08, "ball"};  // centred on a corner: overlapping
  Body body;
  std::string error;
  ASSERT_TRUE(Body::Create({sphere}, {Box(h)}, &body, &error)) << error;
  EXPECT_TRUE(body.Bounds().isApprox(Box3(Vec3(-0.1, -0.1, -0.1), Vec3(0.18, 0.18, 0.18)), 1e-15));
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  int from_sphere = 0, from_box = 0;
  for (int i = 0; i < 3000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const double ds = (p - sphere.center).norm() - sphere.radius;
    const double db = BoxDistance(p, h);
    Vec3 g;
    const double d = body.SignedDistance(p, &g);
    ASSERT_NEAR(d, std::min(ds, db), 1e-14) << p.transpose();
    if (ds < db - 1e-9) {
      ++from_sphere;
      ASSERT_LT((g - (p - sphere.center).normalized()).norm(), 1e-12);
    } else if (db < ds - 1e-9) {
      ++from_box;
    }
  }
  EXPECT_GT(from_sphere, 100);
  EXPECT_GT(from_box, 100);
  EXPECT_EQ(body.FindSphere("ball"), &body.spheres()[0]);
  EXPECT_EQ(body.FindSphere("head"), nullptr);
  EXPECT_EQ(body.FindSphere(""), nullptr);
}

TEST(Body, EmptyBodyIsFarAway) {
  const Body body;
  Vec3 g;
  EXPECT_EQ(body.SignedDistance(Vec3::Zero(), &g), std::numeric_limits<double>::infinity());
  EXPECT_EQ(g, Vec3::UnitZ());
  EXPECT_TRUE(body.Bounds().isEmpty());
}

TEST(Body, RejectsBadSpheres) {
  Body body;
  std::string error;
  EXPECT_FALSE(Body::Create({Sphere{Vec3::Zero(), -0.1, "a"}}, {}, &body, &error));
  EXPECT_EQ(error, "spheres[0].radius: expected a finite number > 0 (m), got -0.1");
  EXPECT_FALSE(Body::Create({Sphere{Vec3(0, NAN, 0), 0.1, "a"}}, {}, &body, &error));
  EXPECT_EQ(error, "spheres[0].center: expected 3 finite numbers (m)");
  EXPECT_FALSE(Body::Create({Sphere{Vec3::Zero(), 0.1, "a"}, Sphere{Vec3::Zero(), 0.2, "a"}}, {},
                            &body, &error));
  EXPECT_EQ(error, "spheres[1].name: \"a\" is already the name of another sphere");
  EXPECT_FALSE(Body::Create({}, {TriangleMesh()}, &body, &error));
  EXPECT_EQ(error, "meshes[0]: the mesh is empty");
}

// ---------------------------------------------------------------------------------------------
// Rejected meshes.

std::string CreateError(std::vector<Vec3> v, std::vector<Triangle> t) {
  TriangleMesh mesh;
  std::string error;
  EXPECT_FALSE(TriangleMesh::Create(std::move(v), std::move(t), "m", &mesh, &error));
  EXPECT_TRUE(mesh.triangles().empty());  // untouched
  return error;
}

TEST(TriangleMesh, RejectsOpenMesh) {
  std::vector<Vec3> v;
  std::vector<Triangle> t;
  BoxMesh(Vec3(1, 1, 1), &v, &t);
  t.pop_back();  // {1, 7, 5}: edges (1, 7), (5, 7), (1, 5) lose a side
  EXPECT_EQ(CreateError(v, t),
            "m: edge (1, 5) belongs to 1 triangle (0, 1, 5): the mesh is not closed, so its "
            "inside is undefined");
}

TEST(TriangleMesh, RejectsDegenerateTriangles) {
  std::vector<Vec3> v;
  std::vector<Triangle> t;
  BoxMesh(Vec3(1, 1, 1), &v, &t);
  auto repeated = t;
  repeated[3] = {2, 2, 7};
  EXPECT_EQ(CreateError(v, repeated), "m: triangle (2, 2, 7) is degenerate (repeated vertex)");
  // Vertex 8 on the segment from 0 to 1: a zero-area triangle.
  auto flat_vertices = v;
  flat_vertices.push_back((v[0] + v[1]) / 2);
  auto flat = t;
  flat.push_back({0, 8, 1});
  EXPECT_EQ(CreateError(flat_vertices, flat), "m: triangle (0, 8, 1) is degenerate (zero area)");
}

TEST(TriangleMesh, RejectsBadIndicesOrientationAndTopology) {
  std::vector<Vec3> v;
  std::vector<Triangle> t;
  BoxMesh(Vec3(1, 1, 1), &v, &t);
  auto out_of_range = t;
  out_of_range[0][1] = 8;
  EXPECT_EQ(CreateError(v, out_of_range),
            "m: triangle (0, 8, 3): vertex index 8 out of range (8 vertices, numbered from 0)");

  auto flipped_one = t;
  std::swap(flipped_one[0][1], flipped_one[0][2]);
  EXPECT_NE(CreateError(v, flipped_one).find("inconsistent orientation"), std::string::npos);

  auto inward = t;
  for (Triangle& f : inward) std::swap(f[1], f[2]);
  EXPECT_EQ(CreateError(v, inward),
            "m: the triangles face inward (enclosed volume -8 m^3 <= 0): reverse the "
            "order of the vertices of every face");

  // Two boxes sharing only the corner 7 of the first: closed, consistently oriented, but
  // vertex 7 has two separate fans.
  std::vector<Vec3> v2;
  std::vector<Triangle> t2;
  BoxMesh(Vec3(1, 1, 1), &v2, &t2);
  auto vertices = v;
  auto triangles = t;
  for (int i = 0; i < 8; ++i) vertices.push_back(v2[static_cast<size_t>(i)] + Vec3(2, 2, 2));
  for (Triangle f : t2) {
    for (int& index : f) index = index == 0 ? 7 : index + 8;  // its corner 0 is our corner 7
    triangles.push_back(f);
  }
  EXPECT_EQ(CreateError(vertices, triangles),
            "m: vertex 7 is not a manifold vertex (its triangles form several fans)");

  EXPECT_EQ(CreateError(v, {}), "m: has no triangles");
}

// ---------------------------------------------------------------------------------------------
// OBJ files.

TEST(LoadObjMeshes, QuadBoxLoadsAndMatchesClosedForm) {
  TempDirectory dir;
  const std::string path = dir.Write("box.obj", kBoxObj);
  std::vector<TriangleMesh> meshes;
  std::string error;
  ASSERT_TRUE(LoadObjMeshes(path, &meshes, &error)) << error;
  ASSERT_EQ(meshes.size(), 1u);
  EXPECT_EQ(meshes[0].name(), "box");
  EXPECT_EQ(meshes[0].triangles().size(), 12u);
  EXPECT_NEAR(meshes[0].volume(), 8.0, 1e-14);
  for (const Vec3& p : {Vec3(0, 0, 0), Vec3(1.5, 1.2, -1.1), Vec3(0.99, 0.98, 0.5)}) {
    EXPECT_NEAR(meshes[0].SignedDistance(p, nullptr), BoxDistance(p, Vec3::Ones()), 1e-15);
  }
}

TEST(LoadObjMeshes, NonConvexFacesAndSharedVertices) {
  // An L-shaped prism (three unit squares in the plane, extruded by 1): its two L faces are
  // non-convex hexagons, so a fan would put a triangle outside the polygon; the volume (3 m^3)
  // and the distance at the notch check the ear clipping. A second object ("lid", a
  // tetrahedron) reuses vertex 1: shared vertices are fine.
  const char* obj = R"(o ell
v 0 0 0
v 2 0 0
v 2 1 0
v 1 1 0
v 1 2 0
v 0 2 0
v 0 0 1
v 2 0 1
v 2 1 1
v 1 1 1
v 1 2 1
v 0 2 1
v -1 -1 -1
v -1 -2 -1
v -2 -1 -1
f 6 5 4 3 2 1
f 7 8 9 10 11 12
f 1 2 8 7
f 2 3 9 8
f 3 4 10 9
f 4 5 11 10
f 5 6 12 11
f 6 1 7 12
o lid
f 1 14 13
f 1 15 14
f 1 13 15
f 13 14 15
)";
  TempDirectory dir;
  std::vector<TriangleMesh> meshes;
  std::string error;
  ASSERT_TRUE(LoadObjMeshes(dir.Write("ell.obj", obj), &meshes, &error)) << error;
  ASSERT_EQ(meshes.size(), 2u);
  EXPECT_NEAR(meshes[0].volume(), 3.0, 1e-14);
  EXPECT_EQ(meshes[0].triangles().size(), 2u * 4u + 6u * 2u);
  // In the notch, (1.2, 1.2, z) is 0.2 from the faces y = 1 (x in [1, 2]) and x = 1; above the
  // top face, (1.2, 1.2, 1.1) is sqrt(0.2^2 + 0.1^2) from the edge (x, 1, 1). A fan from the
  // first vertex would have covered the notch with a triangle at 0.1.
  EXPECT_NEAR(meshes[0].SignedDistance(Vec3(1.2, 1.2, 0.5), nullptr), 0.2, 1e-15);
  EXPECT_NEAR(meshes[0].SignedDistance(Vec3(1.2, 1.2, 1.1), nullptr), std::sqrt(0.05), 1e-15);
  EXPECT_NEAR(meshes[0].SignedDistance(Vec3(0.5, 0.5, 0.5), nullptr), -0.5, 1e-15);
  EXPECT_EQ(meshes[1].name(), "lid");
  EXPECT_EQ(meshes[1].vertices().size(), 4u);  // only the vertices it uses
}

TEST(LoadObjMeshes, RejectsBadFiles) {
  TempDirectory dir;
  std::vector<TriangleMesh> meshes;
  std::string error;
  auto load = [&](const std::string& name, const std::string& text) {
    error.clear();
    EXPECT_FALSE(LoadObjMeshes(dir.Write(name, text), &meshes, &error)) << name;
    return error;
  };
  const std::string missing = dir.path() + "/missing.obj";
  EXPECT_FALSE(LoadObjMeshes(missing, &meshes, &error));
  EXPECT_EQ(error, missing + ": cannot open: No such file or directory");

  // A zero index is refused by ringlet's own line check (issue 16), before tinyobjloader.
  EXPECT_EQ(load("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n"),
            dir.path() +
                "/zero.obj: line 4: face: expected vertex references v, v/vt, v//vn or v/vt/vn "
                "(non-zero integers), got \"0\"");
  EXPECT_EQ(load("points.obj", "v 0 0 0\nv 1 0 0\n"), dir.path() +
                                                          "/points.obj: no faces "
                                                          "(a body mesh needs closed "
                                                          "triangle surfaces)");
  EXPECT_EQ(load("range.obj", "o t\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"),
            dir.path() + "/range.obj: t: face 1 uses vertex 9, out of range (3 vertices)");
  // An open head: the box without its last quad; vertex numbers as in the file (1-based).
  std::string open = kBoxObj;
  open = open.substr(0, open.rfind("f 2 4 8 6"));
  const std::string head = "o head" + open.substr(open.find('\n', open.find("o box")));
  EXPECT_EQ(load("head.obj", head),
            dir.path() +
                "/head.obj: head: edge (2, 4) belongs to 1 triangle (3, 4, 2): the "
                "mesh is not closed, so its inside is undefined");
  meshes.clear();
  EXPECT_TRUE(meshes.empty());
}

// ---------------------------------------------------------------------------------------------
// The shipped mannequin.

TEST(Mannequin, MeshHasClosedComponentsAndTheHeadTopOnTheSurface) {
  Body body;
  std::string error;
  ASSERT_TRUE(LoadBody(Examples() + "/bodies/mannequin_mesh.json", &body, &error)) << error;
  size_t triangles = 0;
  for (const TriangleMesh& m : body.meshes()) triangles += m.triangles().size();
  EXPECT_GE(triangles, 2000u);
  EXPECT_LE(triangles, 20000u);
  ASSERT_NE(FindMesh(body, "head"), nullptr);
  ASSERT_NE(FindMesh(body, "neck"), nullptr);
  ASSERT_NE(FindMesh(body, "torso"), nullptr);
  // The head is the ellipsoid with semi-axes (0.08, 0.1, 0.1) m about the origin
  // (scripts/make_mannequin.py); the top (0, 0, 0.1) is on the ellipsoid, so within the
  // chordal error of the mesh (level-4 icosphere, edges ~ 8 mm: sagitta ~ e^2/(8R) < 0.1 mm).
  // The file's body uses the distance grid (band 3 cm, error < 0.2 mm on the head: tests/
  // distance_grid_test.cpp); the same meshes with exact queries give the far values too.
  Body exact;
  ASSERT_TRUE(ParseBody(
      nlohmann::json::parse(R"({"meshes": [{"obj": "mannequin.obj"}], "mesh_distance": "exact"})"),
      "", Examples() + "/bodies", &exact, &error))
      << error;
  ASSERT_NE(body.distance_grid(), nullptr);
  for (const Body* b : {&exact, &body}) {
    const double tolerance = b == &exact ? 2e-4 : 4e-4;
    Vec3 g;
    EXPECT_NEAR(b->SignedDistance(Vec3(0, 0, 0.1), &g), 0.0, tolerance);
    EXPECT_GT(g.z(), 0.99);
    // Inside the head, 2 cm below its top; the face (+y) at y = 0.1.
    EXPECT_NEAR(b->SignedDistance(Vec3(0, 0, 0.08), nullptr), -0.02, tolerance);
    EXPECT_NEAR(b->SignedDistance(Vec3(0, 0.12, 0), nullptr), 0.02, tolerance);
    // The shoulders at x = +-0.15 are near z = -0.224.
    EXPECT_NEAR(b->SignedDistance(Vec3(0.15, -0.01, -0.224), nullptr), 0.0, 2e-3);
    EXPECT_NEAR(b->SignedDistance(Vec3(-0.15, -0.01, -0.224), nullptr), 0.0, 2e-3);
  }
  Vec3 g;
  EXPECT_NEAR(exact.SignedDistance(Vec3(0, 0, 0.15), &g), 0.05, 2e-4);
  EXPECT_GT(g.z(), 0.99);
  // The neck is inside the union.
  EXPECT_LT(exact.SignedDistance(Vec3(0, -0.01, -0.15), nullptr), -0.04);
  // Beyond the band the grid is the clamp, a lower bound of |d| with its sign.
  EXPECT_DOUBLE_EQ(body.SignedDistance(Vec3(0, 0, 0.15), nullptr), 0.03);
  EXPECT_FLOAT_EQ(body.SignedDistance(Vec3(0, -0.01, -0.15), nullptr), -0.03);
}

}  // namespace
}  // namespace ringlet

namespace ringlet {
namespace {

// The smooth union (Body::Create's blend): exact away from creases, at most k/4 below the exact
// minimum on them, continuous gradient across them, 1-Lipschitz.
TEST(BodyBlend, SmoothUnionOfTwoSpheres) {
  const double k = 0.01;
  std::vector<Sphere> spheres = {{Vec3(-0.05, 0, 0), 0.06, "a"}, {Vec3(0.05, 0, 0), 0.06, "b"}};
  Body exact, smooth;
  std::string error;
  ASSERT_TRUE(Body::Create(spheres, {}, &exact, &error)) << error;
  ASSERT_TRUE(Body::Create(spheres, {}, &smooth, &error, k)) << error;
  EXPECT_EQ(smooth.blend(), k);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-0.15, 0.15);
  int on_crease = 0;
  for (int i = 0; i < 5000; ++i) {
    const Vec3 x(u(rng), u(rng), u(rng));
    const double da = (x - spheres[0].center).norm() - 0.06;
    const double db = (x - spheres[1].center).norm() - 0.06;
    const double d = smooth.SignedDistance(x, nullptr);
    const double m = std::min(da, db);
    EXPECT_LE(d, m + 1e-15);
    EXPECT_GE(d, m - k / 4 - 1e-15);
    if (std::abs(da - db) >= k) {
      EXPECT_NEAR(d, m, 1e-15);
    } else {
      ++on_crease;
      // Closed form of the quadratic smooth minimum, independent of the fold's code path.
      const double h = std::clamp(0.5 + 0.5 * (db - da) / k, 0.0, 1.0);
      EXPECT_NEAR(d, db + h * (da - db) - k * h * (1.0 - h), 1e-15);
    }
  }
  EXPECT_GT(on_crease, 50);
  // Across the crease plane x = 0 (in the valley above the seam) the gradient is continuous:
  // central differences match it, and its two one-sided values agree.
  for (double y : {0.03, 0.05, 0.07}) {
    for (double x0 : {-2e-3, -1e-9, 0.0, 1e-9, 2e-3}) {
      const Vec3 x(x0, y, 0.01);
      Vec3 g;
      smooth.SignedDistance(x, &g);
      EXPECT_LE(g.norm(), 1.0 + 1e-12);
      for (int c = 0; c < 3; ++c) {
        Vec3 e = Vec3::Zero();
        e(c) = 1e-7;
        const double fd =
            (smooth.SignedDistance(x + e, nullptr) - smooth.SignedDistance(x - e, nullptr)) / 2e-7;
        EXPECT_NEAR(g(c), fd, 1e-6) << "y " << y << " x " << x0 << " component " << c;
      }
    }
  }
  std::string why;
  EXPECT_FALSE(Body::Create(spheres, {}, &smooth, &why, -1.0));
  EXPECT_NE(why.find("blend"), std::string::npos);
}

}  // namespace
}  // namespace ringlet
