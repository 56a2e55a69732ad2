// Closed triangle meshes: validation, angle-weighted pseudo-normals, an AABB tree, and the
// signed distance query (docs/body.md).
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "ringlet/body.h"

namespace ringlet {
namespace {

// A triangle is degenerate when its height over its longest edge is below this ratio
// (|e1 x e2| / L_max^2 = h / L_max, dimensionless): its normal would be noise.
constexpr double kDegenerateRatio = 1e-10;
// Leaves of the hierarchy hold at most this many triangles.
constexpr int kLeafSize = 4;
// Depth limit of the query stack; median splits give a depth of about log2(n / kLeafSize).
constexpr int kMaxDepth = 64;
// Points closer to the surface than this fraction of the mesh's box diagonal count as on the
// surface: the direction x - c is then rounding noise and the pseudo-normal is used instead.
constexpr double kSurfaceTolerance = 1e-12;

std::string IndexText(int index, int base) { return std::to_string(index + base); }

std::string TriangleText(const TriangleMesh::Triangle& t, int base) {
  // Appended piece by piece: "(" + std::string trips GCC 12's -Wrestrict false positive at -O3.
  std::string text = "(";
  text += IndexText(t[0], base);
  text += ", ";
  text += IndexText(t[1], base);
  text += ", ";
  text += IndexText(t[2], base);
  text += ")";
  return text;
}

// The angle between u and v (rad), by atan2 (accurate at 0 and pi, unlike acos of the cosine).
double Angle(const Vec3& u, const Vec3& v) { return std::atan2(u.cross(v).norm(), u.dot(v)); }

// An undirected edge as one 64-bit key.
std::uint64_t EdgeKey(int a, int b) {
  const auto lo = static_cast<std::uint64_t>(std::min(a, b));
  const auto hi = static_cast<std::uint64_t>(std::max(a, b));
  return (lo << 32) | hi;
}
std::uint64_t DirectedKey(int a, int b) {
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint64_t>(b);
}

// One side of an edge: triangle t runs along it from corner k to corner k+1.
struct HalfEdge {
  int a;  // start vertex
  int b;  // end vertex
  int triangle;
  int corner;
};

// x with 6 significant digits.
std::string ShortNumber(double x) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.6g", x);
  return text;
}

// Squared distance from x to the box (0 inside), branch-free: per axis the excess
// max(lo - x, x - hi, 0). Eigen's AlignedBox::squaredExteriorDistance branches per axis, which
// the query's unpredictable boxes make slow.
double BoxDistanceSquared(const Box3& box, const Vec3& x) {
  const Vec3 excess = (box.min() - x).cwiseMax(x - box.max()).cwiseMax(0.0);
  return excess.squaredNorm();
}

bool Fail(const std::string& name, const std::string& message, std::string* error) {
  if (error) *error = name.empty() ? message : name + ": " + message;
  return false;
}

}  // namespace

double SphereSignedDistance(const Sphere& sphere, const Vec3& x, Vec3* gradient) {
  const Vec3 r = x - sphere.center;
  const double norm = r.norm();
  if (gradient) *gradient = norm > 0.0 ? Vec3(r / norm) : Vec3::UnitZ();
  return norm - sphere.radius;
}

Vec3 ClosestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                            TriangleFeature* feature) {
  // Ericson (2005), section 5.1.5: test the Voronoi regions of the corners, then of the edges,
  // with dot products only; what is left is the face, where the barycentric coordinates are
  // ratios of the signed areas va, vb, vc.
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;
  const Vec3 ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) {
    *feature = TriangleFeature::kVertex0;
    return a;
  }
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) {
    *feature = TriangleFeature::kVertex1;
    return b;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    *feature = TriangleFeature::kEdge0;
    return a + (d1 / (d1 - d3)) * ab;
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) {
    *feature = TriangleFeature::kVertex2;
    return c;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    *feature = TriangleFeature::kEdge2;  // edge c -> a
    return a + (d2 / (d2 - d6)) * ac;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    *feature = TriangleFeature::kEdge1;
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  }
  *feature = TriangleFeature::kFace;
  const double denominator = 1.0 / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

bool TriangleMesh::Create(std::vector<Vec3> vertices, std::vector<Triangle> triangles,
                          std::string name, TriangleMesh* mesh, std::string* error,
                          int message_index_base) {
  const int base = message_index_base;
  if (triangles.empty()) return Fail(name, "has no triangles", error);
  if (vertices.size() >= static_cast<size_t>(std::numeric_limits<int>::max()) ||
      triangles.size() >= static_cast<size_t>(std::numeric_limits<int>::max() / 3)) {
    return Fail(name, "has too many vertices or triangles", error);
  }
  const int n = static_cast<int>(vertices.size());

  // Indices in range, finite positions, no repeated index, non-zero area.
  for (const Triangle& t : triangles) {
    for (int index : t) {
      if (index < 0 || index >= n) {
        return Fail(name,
                    "triangle " + TriangleText(t, base) + ": vertex index " +
                        IndexText(index, base) + " out of range (" + std::to_string(n) +
                        " vertices, numbered from " + std::to_string(base) + ")",
                    error);
      }
      if (!vertices[static_cast<size_t>(index)].allFinite()) {
        return Fail(name, "vertex " + IndexText(index, base) + " has a non-finite coordinate",
                    error);
      }
    }
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
      return Fail(name, "triangle " + TriangleText(t, base) + " is degenerate (repeated vertex)",
                  error);
    }
    const Vec3& a = vertices[static_cast<size_t>(t[0])];
    const Vec3& b = vertices[static_cast<size_t>(t[1])];
    const Vec3& c = vertices[static_cast<size_t>(t[2])];
    const double longest =
        std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    if (!((b - a).cross(c - a).norm() > kDegenerateRatio * longest)) {
      return Fail(name, "triangle " + TriangleText(t, base) + " is degenerate (zero area)", error);
    }
  }

  // Closed and consistently oriented: sorted by undirected edge, every edge appears exactly
  // twice, once in each direction.
  std::vector<HalfEdge> half_edges;
  half_edges.reserve(3 * triangles.size());
  for (size_t i = 0; i < triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      half_edges.push_back({triangles[i][static_cast<size_t>(k)],
                            triangles[i][static_cast<size_t>((k + 1) % 3)], static_cast<int>(i),
                            k});
    }
  }
  std::sort(half_edges.begin(), half_edges.end(), [](const HalfEdge& x, const HalfEdge& y) {
    const auto kx = EdgeKey(x.a, x.b), ky = EdgeKey(y.a, y.b);
    return kx != ky ? kx < ky : x.triangle < y.triangle;
  });
  for (size_t i = 0; i < half_edges.size();) {
    size_t j = i;
    while (j < half_edges.size() &&
           EdgeKey(half_edges[j].a, half_edges[j].b) == EdgeKey(half_edges[i].a, half_edges[i].b)) {
      ++j;
    }
    const HalfEdge& e = half_edges[i];
    const std::string edge = "edge (" + IndexText(std::min(e.a, e.b), base) + ", " +
                             IndexText(std::max(e.a, e.b), base) + ")";
    const size_t count = j - i;
    if (count == 1) {
      return Fail(name,
                  edge + " belongs to 1 triangle " +
                      TriangleText(triangles[static_cast<size_t>(e.triangle)], base) +
                      ": the mesh is not closed, so its inside is undefined",
                  error);
    }
    if (count > 2) {
      return Fail(name,
                  edge + " belongs to " + std::to_string(count) +
                      " triangles: the surface is not a manifold",
                  error);
    }
    if (half_edges[i].a == half_edges[i + 1].a) {
      return Fail(
          name,
          edge + " runs in the same direction in triangles " +
              TriangleText(triangles[static_cast<size_t>(half_edges[i].triangle)], base) + " and " +
              TriangleText(triangles[static_cast<size_t>(half_edges[i + 1].triangle)], base) +
              ": inconsistent orientation",
          error);
    }
    i = j;
  }

  // Every vertex a single fan: walking around it across edges comes back after visiting all
  // its triangles (two cones touching at a vertex would not).
  std::unordered_map<std::uint64_t, int> triangle_of_directed_edge;
  triangle_of_directed_edge.reserve(half_edges.size());
  for (const HalfEdge& e : half_edges)
    triangle_of_directed_edge[DirectedKey(e.a, e.b)] = e.triangle;
  std::vector<int> incident(vertices.size(), 0);
  std::vector<int> any_triangle(vertices.size(), -1);
  for (size_t i = 0; i < triangles.size(); ++i) {
    for (int index : triangles[i]) {
      ++incident[static_cast<size_t>(index)];
      any_triangle[static_cast<size_t>(index)] = static_cast<int>(i);
    }
  }
  for (int v = 0; v < n; ++v) {
    const int start = any_triangle[static_cast<size_t>(v)];
    if (start < 0) continue;
    int t = start;
    int steps = 0;
    do {
      // In t = (v, a, b) (rotated), the next triangle around v holds the directed edge v -> b.
      const Triangle& tri = triangles[static_cast<size_t>(t)];
      const int k = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
      const int b = tri[static_cast<size_t>((k + 2) % 3)];
      t = triangle_of_directed_edge.at(DirectedKey(v, b));
      ++steps;
    } while (t != start && steps <= incident[static_cast<size_t>(v)]);
    if (steps != incident[static_cast<size_t>(v)]) {
      return Fail(name,
                  "vertex " + IndexText(v, base) +
                      " is not a manifold vertex (its triangles form several fans)",
                  error);
    }
  }

  // Outward orientation: the enclosed volume, sum of (a . (b x c)) / 6 over the triangles
  // (divergence theorem), is positive.
  double volume = 0.0;
  for (const Triangle& t : triangles) {
    volume += vertices[static_cast<size_t>(t[0])].dot(
                  vertices[static_cast<size_t>(t[1])].cross(vertices[static_cast<size_t>(t[2])])) /
              6.0;
  }
  if (!(volume > 0.0)) {
    return Fail(name,
                "the triangles face inward (enclosed volume " + ShortNumber(volume) +
                    " m^3 <= 0): reverse the order of the vertices of every face",
                error);
  }

  // Drop unused vertices, renumbering the triangles.
  std::vector<int> new_index(vertices.size(), -1);
  std::vector<Vec3> used;
  used.reserve(vertices.size());
  for (Triangle& t : triangles) {
    for (int& index : t) {
      int& mapped = new_index[static_cast<size_t>(index)];
      if (mapped < 0) {
        mapped = static_cast<int>(used.size());
        used.push_back(vertices[static_cast<size_t>(index)]);
      }
      index = mapped;
    }
  }

  TriangleMesh result;
  result.vertices_ = std::move(used);
  result.triangles_ = std::move(triangles);
  result.name_ = std::move(name);
  result.volume_ = volume;
  result.Build();
  *mesh = std::move(result);
  return true;
}

void TriangleMesh::Build() {
  const size_t count = triangles_.size();
  auto corner = [this](size_t t, int k) -> const Vec3& {
    return vertices_[static_cast<size_t>(triangles_[t][static_cast<size_t>(k)])];
  };

  // Pseudo-normals (Baerentzen & Aanaes 2005, section 3): the face normal; for an edge the sum
  // of the two face normals (each with the angle pi); for a vertex the sum of the incident
  // face normals weighted by the incident angles. Only their directions matter.
  face_normals_.resize(count);
  edge_normals_.assign(count, {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  vertex_normals_.assign(vertices_.size(), Vec3::Zero());
  for (size_t t = 0; t < count; ++t) {
    face_normals_[t] =
        (corner(t, 1) - corner(t, 0)).cross(corner(t, 2) - corner(t, 0)).normalized();
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = corner(t, k);
      const double angle = Angle(corner(t, (k + 1) % 3) - p, corner(t, (k + 2) % 3) - p);
      vertex_normals_[static_cast<size_t>(triangles_[t][static_cast<size_t>(k)])] +=
          angle * face_normals_[t];
    }
  }
  std::unordered_map<std::uint64_t, std::pair<int, int>> first_side;  // edge -> (t, k)
  first_side.reserve(3 * count / 2);
  for (size_t t = 0; t < count; ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t key = EdgeKey(triangles_[t][static_cast<size_t>(k)],
                                        triangles_[t][static_cast<size_t>((k + 1) % 3)]);
      const auto [it, inserted] =
          first_side.emplace(key, std::pair<int, int>(static_cast<int>(t), k));
      if (!inserted) {
        // Both sides get the same sum, computed once, so ties between them agree.
        const auto [t0, k0] = it->second;
        const Vec3 sum = face_normals_[static_cast<size_t>(t0)] + face_normals_[t];
        edge_normals_[static_cast<size_t>(t0)][static_cast<size_t>(k0)] = sum;
        edge_normals_[t][static_cast<size_t>(k)] = sum;
      }
    }
  }

  // The hierarchy: top-down, splitting at the median centroid along the longest axis of the
  // centroids' box (nth_element with an index tie-break: deterministic), depth first so that
  // a node's first child is the next node.
  std::vector<int> order(count);
  std::iota(order.begin(), order.end(), 0);
  std::vector<Vec3> centroid(count);
  for (size_t t = 0; t < count; ++t) {
    centroid[t] = (corner(t, 0) + corner(t, 1) + corner(t, 2)) / 3.0;
  }
  nodes_.clear();
  nodes_.reserve(2 * count / kLeafSize + 2);
  BuildNode(0, static_cast<int>(count), centroid, &order);

  packed_.resize(count);
  bounds_ = Box3();
  for (size_t i = 0; i < count; ++i) {
    const size_t t = static_cast<size_t>(order[i]);
    packed_[i].triangle = static_cast<int>(t);
    for (int k = 0; k < 3; ++k) {
      packed_[i].corner[static_cast<size_t>(k)] = corner(t, k);
      bounds_.extend(corner(t, k));
    }
  }
  surface_tolerance_ = kSurfaceTolerance * bounds_.diagonal().norm();
}

int TriangleMesh::BuildNode(int begin, int end, const std::vector<Vec3>& centroid,
                            std::vector<int>* order) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.push_back({});
  Box3 box, centroid_box;
  for (int i = begin; i < end; ++i) {
    const Triangle& t = triangles_[static_cast<size_t>((*order)[static_cast<size_t>(i)])];
    for (int v : t) box.extend(vertices_[static_cast<size_t>(v)]);
    centroid_box.extend(centroid[static_cast<size_t>((*order)[static_cast<size_t>(i)])]);
  }
  nodes_[static_cast<size_t>(index)].box = box;
  if (end - begin <= kLeafSize) {
    nodes_[static_cast<size_t>(index)].first_or_second = begin;
    nodes_[static_cast<size_t>(index)].count = end - begin;
    return index;
  }
  int axis = 0;
  centroid_box.sizes().maxCoeff(&axis);
  const int middle = begin + (end - begin) / 2;
  std::nth_element(order->begin() + begin, order->begin() + middle, order->begin() + end,
                   [&](int x, int y) {
                     const double cx = centroid[static_cast<size_t>(x)](axis);
                     const double cy = centroid[static_cast<size_t>(y)](axis);
                     return cx != cy ? cx < cy : x < y;
                   });
  BuildNode(begin, middle, centroid, order);  // index + 1
  const int second = BuildNode(middle, end, centroid, order);
  nodes_[static_cast<size_t>(index)].first_or_second = second;
  return index;
}

void TriangleMesh::Visit(int begin, int end, const Vec3& x, Candidate* best) const {
  for (int i = begin; i < end; ++i) {
    const PackedTriangle& p = packed_[static_cast<size_t>(i)];
    TriangleFeature feature;
    const Vec3 c = ClosestPointOnTriangle(x, p.corner[0], p.corner[1], p.corner[2], &feature);
    const double d2 = (x - c).squaredNorm();
    // Strictly closer only: on ties the first triangle in hierarchy order wins.
    if (d2 < best->distance_squared) *best = Candidate{d2, c, p.triangle, feature};
  }
}

double TriangleMesh::Finish(const Vec3& x, const Candidate& best, Vec3* gradient,
                            Mat3* hessian) const {
  const size_t t = static_cast<size_t>(best.triangle);
  Vec3 normal;
  switch (best.feature) {
    case TriangleFeature::kFace:
      normal = face_normals_[t];
      break;
    case TriangleFeature::kEdge0:
    case TriangleFeature::kEdge1:
    case TriangleFeature::kEdge2:
      normal = edge_normals_[t][static_cast<size_t>(best.feature) -
                                static_cast<size_t>(TriangleFeature::kEdge0)];
      break;
    default:
      normal = vertex_normals_[static_cast<size_t>(
          triangles_[t][static_cast<size_t>(best.feature) -
                        static_cast<size_t>(TriangleFeature::kVertex0)])];
      break;
  }
  const Vec3 r = x - best.point;
  const double distance = std::sqrt(best.distance_squared);
  // Baerentzen & Aanaes (2005), theorem 1: x is outside iff (x - c) . n > 0, with n the
  // angle-weighted pseudo-normal of the feature holding the closest point c.
  const double sign = r.dot(normal) >= 0.0 ? 1.0 : -1.0;
  if (gradient) {
    *gradient = distance > surface_tolerance_ ? Vec3(sign / distance * r) : normal.normalized();
  }
  if (hessian) {
    // Distance to a plane, a line or a point: its Hessian projects out the directions along
    // which the distance grows linearly (u, and the edge direction e on an edge).
    hessian->setZero();
    if (best.feature != TriangleFeature::kFace && distance > surface_tolerance_) {
      const Vec3 u = r / distance;
      *hessian = Mat3::Identity() - u * u.transpose();
      if (best.feature != TriangleFeature::kVertex0 && best.feature != TriangleFeature::kVertex1 &&
          best.feature != TriangleFeature::kVertex2) {
        const int k = static_cast<int>(best.feature) - static_cast<int>(TriangleFeature::kEdge0);
        const Triangle& tri = triangles_[t];
        const Vec3 e = (vertices_[static_cast<size_t>(tri[static_cast<size_t>((k + 1) % 3)])] -
                        vertices_[static_cast<size_t>(tri[static_cast<size_t>(k)])])
                           .normalized();
        *hessian -= e * e.transpose();
      }
      *hessian *= sign / distance;
    }
  }
  return sign * distance;
}

double TriangleMesh::SignedDistance(const Vec3& x, Vec3* gradient) const {
  return SignedDistanceHessian(x, gradient, nullptr);
}

double TriangleMesh::SignedDistanceHessian(const Vec3& x, Vec3* gradient, Mat3* hessian) const {
  if (nodes_.empty()) {
    if (gradient) *gradient = Vec3::UnitZ();
    if (hessian) hessian->setZero();
    return std::numeric_limits<double>::infinity();
  }
  Candidate best{std::numeric_limits<double>::infinity(), Vec3::Zero(), 0, TriangleFeature::kFace};
  Search(x, &best);
  return Finish(x, best, gradient, hessian);
}

void TriangleMesh::Search(const Vec3& x, Candidate* best_out) const {
  Candidate& best = *best_out;
  // Depth-first traversal, nearer child first, pruning boxes farther than the best so far.
  int stack[kMaxDepth];
  int top = 0;
  int node = 0;
  while (true) {
    const Node& n = nodes_[static_cast<size_t>(node)];
    if (n.count > 0) {
      Visit(n.first_or_second, n.first_or_second + n.count, x, &best);
    } else {
      int near = node + 1;
      int far = n.first_or_second;
      double near_d2 = BoxDistanceSquared(nodes_[static_cast<size_t>(near)].box, x);
      double far_d2 = BoxDistanceSquared(nodes_[static_cast<size_t>(far)].box, x);
      if (far_d2 < near_d2) {
        std::swap(near, far);
        std::swap(near_d2, far_d2);
      }
      if (near_d2 < best.distance_squared) {
        if (far_d2 < best.distance_squared) {
          assert(top < kMaxDepth);
          stack[top++] = far;
        }
        node = near;
        continue;
      }
    }
    // Pop the next box still worth visiting.
    bool found = false;
    while (top > 0) {
      const int candidate = stack[--top];
      if (BoxDistanceSquared(nodes_[static_cast<size_t>(candidate)].box, x) <
          best.distance_squared) {
        node = candidate;
        found = true;
        break;
      }
    }
    if (!found) break;
  }
}

double TriangleMesh::SignedDistanceBruteForce(const Vec3& x, Vec3* gradient) const {
  if (packed_.empty()) {
    if (gradient) *gradient = Vec3::UnitZ();
    return std::numeric_limits<double>::infinity();
  }
  Candidate best{std::numeric_limits<double>::infinity(), Vec3::Zero(), 0, TriangleFeature::kFace};
  Visit(0, static_cast<int>(packed_.size()), x, &best);
  return Finish(x, best, gradient);
}

}  // namespace ringlet
