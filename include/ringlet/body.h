// The body hair rests on: a union of spheres (the paper's approach, section 3.1) and closed
// triangle meshes, seen by the contact energy through its signed distance (docs/body.md).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ringlet/math.h"
#include "ringlet/obstacle.h"

namespace ringlet {

/// An axis-aligned box (m); Eigen's default-constructed box is empty.
using Box3 = Eigen::AlignedBox3d;

/// The part of the body a component moves with when the head moves (docs/body.md, "Head and
/// torso"; docs/dynamics.md, "Head motion"): the head part follows the head's whole rigid motion
/// (rotation about the pivot and translation), the torso part only its translation (a walk's
/// bounce), never its rotation: a head turns and nods on a still torso.
enum class BodyPart : std::uint8_t {
  kHead,
  kTorso,
};

/// "head" or "torso".
const char* BodyPartName(BodyPart part);

/// The part of a component by its name, when the body file does not say: kHead when a word of the
/// name (the runs of ASCII letters, case ignored, split at camelCase humps) is a word of a head or
/// of what is worn on one, whole, or with a plural s or es (head, skull, face, eyebrow, ear,
/// earring, jaw, lip, hat, glasses, ...: docs/body.md, "Head and torso"; "head", "jaw",
/// "ear_left", "leftEar", "Nose2"), and for an unnamed component (an anonymous body is the head
/// the strands grow on); kTorso for every other name ("neck", "chest", "shoulder_left", "torso",
/// "brown_coat").
BodyPart DefaultBodyPart(std::string_view name);

/// A solid sphere of the body.
struct Sphere {
  /// Centre (m, world coordinates).
  Vec3 center = Vec3::Zero();
  /// Radius (m), finite and > 0.
  double radius = 0.0;
  /// Name used to find the sphere (e.g. "head"); may be empty; unique within a body otherwise.
  std::string name;
  /// The part it moves with; unset: DefaultBodyPart(name).
  std::optional<BodyPart> moves_with = std::nullopt;
};

/// Signed distance to a sphere (m): |x - c| - r, exact. If gradient is not null it receives the
/// outward unit normal (x - c)/|x - c| (+z at the centre, where it is not differentiable).
double SphereSignedDistance(const Sphere& sphere, const Vec3& x, Vec3* gradient);

/// The closest feature of a triangle to a point: its interior, one of its edges (edge k joins
/// corner k to corner (k+1) mod 3) or one of its corners.
enum class TriangleFeature : std::uint8_t {
  kFace,
  kEdge0,
  kEdge1,
  kEdge2,
  kVertex0,
  kVertex1,
  kVertex2,
};

/// The closest point of the triangle (a, b, c) to p (m) and the feature it lies on, by the
/// Voronoi regions of the triangle (Ericson, Real-Time Collision Detection, 2005, section 5.1.5).
/// The triangle must not be degenerate.
Vec3 ClosestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                            TriangleFeature* feature);

/// A closed, consistently and outward oriented triangle mesh (one solid, possibly with several
/// shells) with a bounding-volume hierarchy for closest-point queries. Immutable once created;
/// queries are thread-safe (no mutable state, no allocation) and the signed distance is
/// 1-Lipschitz (it is the exact signed Euclidean distance to a closed surface).
class TriangleMesh {
 public:
  /// Three vertex indices, counter-clockwise seen from outside (right-hand rule: the normal
  /// (b - a) x (c - a) points out of the solid).
  using Triangle = std::array<int, 3>;

  /// An empty mesh (no triangles); use Create to build a real one.
  TriangleMesh() = default;

  /// Validates and builds a mesh: every index in range; no degenerate triangle (repeated index
  /// or zero area, relative to the longest edge); closed and consistently oriented (every edge
  /// belongs to exactly two triangles which run along it in opposite directions); every vertex
  /// a manifold fan; positive enclosed volume (outward normals). A non-closed mesh is an error:
  /// its inside is undefined. Vertices used by no triangle are dropped. Self-intersections are
  /// not detected. name starts the error messages ("head: edge (12, 40) belongs to 1 triangle
  /// ..."), where message_index_base is added to the vertex indices (1 for OBJ files). On
  /// failure *mesh is untouched, *error receives one line and the function returns false.
  /// Never throws.
  static bool Create(std::vector<Vec3> vertices, std::vector<Triangle> triangles, std::string name,
                     TriangleMesh* mesh, std::string* error, int message_index_base = 0);

  /// Signed distance from x (m) to the surface (m): negative inside. The sign is that of
  /// (x - c) . n, where c is the closest surface point and n the angle-weighted pseudo-normal of
  /// the feature (face, edge or vertex) c lies on (Baerentzen & Aanaes, "Signed distance
  /// computation using the angle weighted pseudonormal", IEEE TVCG 11(3), 2005). If gradient is
  /// not null it receives the unit vector sign * (x - c)/|x - c|, or the unit pseudo-normal of
  /// the feature (the face normal inside a face) when x is on the surface. O(log n) with the
  /// hierarchy for points near the mesh. An empty mesh returns +infinity and gradient +z.
  double SignedDistance(const Vec3& x, Vec3* gradient) const;

  /// SignedDistance with its Hessian (1/m), exact away from the surface: 0 when the closest
  /// point is inside a face; sign (I - u u^T - e e^T) / |x - c| on an edge of unit direction e;
  /// sign (I - u u^T) / |x - c| at a vertex, with u = (x - c)/|x - c| (the Hessian of the distance
  /// to a line and to a point). 0 on the surface itself. gradient and hessian may be null.
  double SignedDistanceHessian(const Vec3& x, Vec3* gradient, Mat3* hessian) const;

  /// The same result by testing every triangle, O(n): the reference for tests.
  double SignedDistanceBruteForce(const Vec3& x, Vec3* gradient) const;

  /// Vertex positions (m): those given to Create that some triangle uses, in order of first use.
  const std::vector<Vec3>& vertices() const { return vertices_; }
  /// Triangles, as given to Create, renumbered to vertices().
  const std::vector<Triangle>& triangles() const { return triangles_; }
  /// The name given to Create (e.g. the OBJ object's name).
  const std::string& name() const { return name_; }
  /// Box around the triangles (m); empty for an empty mesh.
  const Box3& bounds() const { return bounds_; }
  /// Volume enclosed by the surface (m^3), > 0 (divergence theorem).
  double volume() const { return volume_; }

 private:
  // A node of the hierarchy: a box and either two children (count == 0: the first child is
  // the next node, the second at first_or_second) or a leaf of `count` packed triangles from
  // first_or_second.
  struct Node {
    Box3 box;
    int first_or_second = 0;
    int count = 0;
  };
  // A triangle's corners in hierarchy order, and its index in triangles_.
  struct PackedTriangle {
    std::array<Vec3, 3> corner;
    int triangle = 0;
  };

  // The closest point found so far.
  struct Candidate {
    double distance_squared;  // m^2
    Vec3 point;               // m
    int triangle;             // index in triangles_
    TriangleFeature feature;
  };

  // Computes the pseudo-normals and builds the hierarchy (Create, after validation).
  void Build();
  // Builds the subtree of the triangles order[begin, end) and returns its node index.
  int BuildNode(int begin, int end, const std::vector<Vec3>& centroid, std::vector<int>* order);
  // Tests the packed triangles [begin, end) against *best.
  void Visit(int begin, int end, const Vec3& x, Candidate* best) const;
  // The signed distance and gradient from the closest point.
  double Finish(const Vec3& x, const Candidate& best, Vec3* gradient,
                Mat3* hessian = nullptr) const;
  void Search(const Vec3& x, Candidate* best) const;

  std::vector<Vec3> vertices_;
  std::vector<Triangle> triangles_;
  std::string name_;
  Box3 bounds_;
  double volume_ = 0.0;
  std::vector<Node> nodes_;
  std::vector<PackedTriangle> packed_;
  // Pseudo-normals (Baerentzen & Aanaes 2005): unit face normals per triangle; per triangle
  // edge k (corner k to k+1), the sum of the two adjacent face normals (angle pi each); per
  // vertex, the sum of the incident face normals weighted by the incident angles.
  std::vector<Vec3> face_normals_;
  std::vector<std::array<Vec3, 3>> edge_normals_;
  std::vector<Vec3> vertex_normals_;
  // Below this distance (m) x counts as on the surface for the gradient.
  double surface_tolerance_ = 0.0;
};

/// Reads the closed triangle meshes of a Wavefront OBJ file (m): each object or group ("o" or
/// "g", a tinyobjloader shape) with faces becomes one TriangleMesh named after it, its polygons
/// triangulated (ear clipping, orientation kept). Vertices may be shared between objects;
/// normals, texture coordinates and materials are ignored. Errors name the file and the
/// problem ("head.obj: cannot open: No such file or directory", "m.obj: invalid OBJ: ...",
/// "m.obj: no faces", "m.obj: head: edge (12, 40) belongs to 1 triangle ...", vertex numbers
/// 1-based as in the file); on failure *meshes is untouched. Never throws.
bool LoadObjMeshes(const std::string& path, std::vector<TriangleMesh>* meshes, std::string* error);

/// LoadObjMeshes on OBJ text already in memory (at most kMaxObjFileBytes, atomic_file.h): the
/// same checks and messages, without the file name (the fuzz harnesses' entry point).
bool ParseObjMeshes(std::string_view text, std::vector<TriangleMesh>* meshes, std::string* error);

namespace internal {
class DistanceGrid;
}  // namespace internal

/// How a Body evaluates the signed distance of its meshes (docs/body.md, "Distance grid").
struct MeshDistanceOptions {
  enum class Mode : std::uint8_t {
    /// Closest-point queries on the meshes' trees at every call: exact, ~1 us, gradient kinks
    /// on the faceted surface.
    kExact,
    /// A grid of exact distances built once (Body::Create) and interpolated by a uniform tricubic
    /// B-spline: C^2, ~0.1 us, within ~h^2/6 |Laplacian d| of the exact distance where
    /// |d| < band - 2 h, clamped to +-band (a lower bound of |d|) beyond.
    kGrid,
  };
  /// The mode; exact by default in the C++ API (body files default to the grid).
  Mode mode = Mode::kExact;
  /// Grid spacing h (m), finite, > 0 and >= 1e-4.
  double spacing = 0.005;
  /// Half-width of the exact band (m), finite and > 0: node values are clamped to [-band, band].
  /// Must exceed the largest contact clearance plus half a segment for the contact broad phase
  /// to skip segments.
  double band = 0.03;
  /// Threads building the grid; <= 0: all cores. The grid does not depend on it.
  int threads = 0;
  /// True if the options are usable; otherwise *why names the field ("spacing: ...").
  bool IsValid(std::string* why) const;
};

/// The union of spheres and closed triangle meshes a strand may touch (paper, section 3.1: "the
/// body is approximated by a set of spheres"). Immutable once created; queries are thread-safe.
class Body final : public Obstacle {
 public:
  /// An empty body: SignedDistance is +infinity everywhere.
  Body() = default;

  /// Builds a body from spheres (finite centres, finite radii > 0, non-empty names unique) and
  /// valid meshes (TriangleMesh::Create). On failure *body is untouched, *error receives one
  /// line ("spheres[2].radius: expected a finite number > 0 (m), got -0.1") and the function
  /// returns false. Never throws.
  ///
  /// blend (m, >= 0) rounds the creases where components meet (a smooth union): with blend k > 0
  /// the components are folded with the quadratic smooth minimum (Quilez, "Smooth minimum",
  /// iquilezles.org, 2013)
  ///   smin(a, b) = b + h (a - b) - k h (1 - h),  h = clamp(1/2 + (b - a) / (2 k), 0, 1),
  /// whose gradient h grad a + (1 - h) grad b is continuous: the contact penalty then has a
  /// continuous gradient in the valleys between spheres, where the exact minimum has a kink that
  /// stalls the line search. smin equals the exact minimum where the two distances differ by more
  /// than k, is below it by at most k/4 on the crease (so contact is felt a little early), and
  /// stays 1-Lipschitz (its gradient is a convex combination of unit vectors). 0 = exact minimum.
  ///
  /// mesh_distance chooses exact mesh queries or a distance grid of the meshes' (blended) union,
  /// built here once (MeshDistanceOptions); spheres stay exact and are folded with it.
  ///
  /// mesh_moves_with gives the part of each mesh (empty, or one entry per mesh; an unset entry:
  /// DefaultBodyPart of the mesh's name); spheres carry theirs (Sphere::moves_with).
  static bool Create(std::vector<Sphere> spheres, std::vector<TriangleMesh> meshes, Body* body,
                     std::string* error, double blend = 0.0,
                     const MeshDistanceOptions& mesh_distance = {},
                     const std::vector<std::optional<BodyPart>>& mesh_moves_with = {});

  /// The mesh distance options given to Create.
  const MeshDistanceOptions& mesh_distance() const { return mesh_distance_; }
  /// The distance grid of the meshes (null in exact mode or without meshes).
  const internal::DistanceGrid* distance_grid() const { return grid_.get(); }
  /// Seconds Body::Create spent building the grid (0 without one).
  double grid_build_seconds() const { return grid_build_seconds_; }
  /// Bytes of the grid's node values (0 without one).
  std::size_t GridMemoryBytes() const;

  /// The crease-rounding radius given to Create (m).
  double blend() const { return blend_; }

  /// Minimum of the signed distances of the components (m). Outside every component this is
  /// the exact distance to the union; inside, where components overlap, it is -max of the
  /// depths, a lower bound of the true depth in the union, which is what a penalty needs (the
  /// push-out direction is that of the deepest component). It is 1-Lipschitz (a minimum of
  /// 1-Lipschitz functions). The gradient is that of the minimizing component (the first one in
  /// sphere-then-mesh order on ties). Spheres cost one square root each and no allocation;
  /// meshes are skipped when x is farther from their box than the best distance so far. With a
  /// distance grid (MeshDistanceOptions::kGrid) the meshes' part is the grid's B-spline: within
  /// the grid spacing h of the exact value near the surface (measured 0.9 mm on the mannequin at
  /// h = 5 mm), clamped to +-band beyond, each partial derivative bounded by 1 (measured
  /// |gradient| <= 1.006), C^2; one grid query (~65 ns) replaces the tree queries.
  double SignedDistance(const Vec3& x, Vec3* gradient) const override;

  /// SignedDistance with its exact Hessian (1/m): (I - n n^T)/|x - c| for a sphere, the mesh's
  /// TriangleMesh::SignedDistanceHessian, and for the smooth union (blend k > 0) the Hessian of
  /// the quadratic smooth minimum, h H_a + (1 - h) H_b - (g_a - g_b)(g_a - g_b)^T / (2k) while
  /// the two distances are within k.
  double SignedDistanceHessian(const Vec3& x, Vec3* gradient, Mat3* hessian) const override;

  /// 1 without a distance grid (a minimum, or smooth minimum, of 1-Lipschitz distances); 1.75
  /// with one: each partial derivative of the grid's B-spline is a convex combination of node
  /// differences over h, at most 1 up to the nodes' float rounding, so |gradient| <= sqrt(3).
  double LipschitzBound() const override { return grid_ ? 1.75 : 1.0; }

  /// Box around all the components (m); empty for an empty body.
  const Box3& Bounds() const { return bounds_; }

  /// The spheres, in the order given to Create.
  const std::vector<Sphere>& spheres() const { return spheres_; }
  /// The meshes, in the order given to Create.
  const std::vector<TriangleMesh>& meshes() const { return meshes_; }

  /// The sphere with this (non-empty) name, or null.
  const Sphere* FindSphere(std::string_view name) const;

  /// The part sphere i moves with (its moves_with, or DefaultBodyPart of its name).
  BodyPart sphere_part(size_t i) const { return sphere_parts_[i]; }
  /// The part mesh i moves with (Create's mesh_moves_with, or DefaultBodyPart of its name).
  BodyPart mesh_part(size_t i) const { return mesh_parts_[i]; }
  /// Whether some component moves with the torso (otherwise the whole body moves with the head,
  /// rigidly, and SplitBody is not needed).
  bool HasTorsoPart() const;

 private:
  std::vector<Sphere> spheres_;
  std::vector<BodyPart> sphere_parts_;
  std::vector<BodyPart> mesh_parts_;
  // The spheres packed for the query loop: (cx, cy, cz, r).
  std::vector<Eigen::Vector4d> packed_spheres_;
  std::vector<TriangleMesh> meshes_;
  Box3 bounds_;
  double blend_ = 0.0;
  MeshDistanceOptions mesh_distance_;
  // Shared between copies of the body: immutable once built.
  std::shared_ptr<const internal::DistanceGrid> grid_;
  double grid_build_seconds_ = 0.0;
};

}  // namespace ringlet
