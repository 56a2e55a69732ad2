#include "render/embree_scene.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

#include "groom/random.h"
#include "render/sampler.h"

namespace ringlet::render {
namespace {

// The shading normal of each triangle corner (3 per triangle, unit): the area-weighted mean of
// the normals of the faces around the corner's vertex that turn by at most kSmoothAngle from
// the triangle's own, so that a tessellated smooth surface shades smoothly while a crease
// sharper than that (a box's edge) stays sharp. A degenerate triangle's corners get zero (the
// hit then shades with its geometric normal).
constexpr double kSmoothAngle = 60.0 * std::numbers::pi / 180.0;

std::vector<Vec3> CornerNormals(const TriangleMesh& mesh) {
  const auto& v = mesh.vertices();
  const auto& triangles = mesh.triangles();
  const size_t count = triangles.size();
  std::vector<Vec3> area(count), unit(count);  // cross products (2 x area) and unit normals
  std::vector<std::uint32_t> start(v.size() + 1, 0), faces(3 * count);
  for (size_t t = 0; t < count; ++t) {
    const Vec3& a = v[triangles[t][0]];
    area[t] = (v[triangles[t][1]] - a).cross(v[triangles[t][2]] - a);
    const double norm = area[t].norm();
    unit[t] = norm > 0.0 ? Vec3(area[t] / norm) : Vec3::Zero();
    for (int c = 0; c < 3; ++c) ++start[static_cast<size_t>(triangles[t][c]) + 1];
  }
  for (size_t i = 0; i < v.size(); ++i) start[i + 1] += start[i];
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (size_t t = 0; t < count; ++t) {
    for (int c = 0; c < 3; ++c) {
      faces[fill[static_cast<size_t>(triangles[t][c])]++] = static_cast<std::uint32_t>(t);
    }
  }
  const double min_cos = std::cos(kSmoothAngle);
  std::vector<Vec3> corners(3 * count, Vec3::Zero());
  for (size_t t = 0; t < count; ++t) {
    if (unit[t].isZero()) continue;
    for (int c = 0; c < 3; ++c) {
      const size_t vertex = static_cast<size_t>(triangles[t][c]);
      Vec3 sum = Vec3::Zero();
      for (std::uint32_t k = start[vertex]; k < start[vertex + 1]; ++k) {
        if (unit[faces[k]].dot(unit[t]) >= min_cos) sum += area[faces[k]];
      }
      corners[3 * t + static_cast<size_t>(c)] = sum.normalized();
    }
  }
  return corners;
}

// The first error Embree reports on a device (its error callback may run on any thread during
// a build; the first message is kept).
struct ErrorSink {
  std::string message;
};

void OnEmbreeError(void* user, RTCError code, const char* text) {
  auto* sink = static_cast<ErrorSink*>(user);
  if (sink->message.empty()) {
    sink->message = "Embree error " + std::to_string(static_cast<int>(code)) + ": " +
                    (text != nullptr ? text : "(no message)");
  }
}

// Embree's context extended with what the hair filter must skip (the pattern of Embree's
// tutorials: the context is the first member, so the filter can cast back).
struct RayContext {
  RTCIntersectContext context;
  const RayIgnore* ignore;
};

// Rejects the hits a RayIgnore names. Embree calls it for every candidate hit on the hair
// geometry, with the candidate's distance in the ray's tfar.
void HairFilter(const RTCFilterFunctionNArguments* args) {
  const auto* context = reinterpret_cast<const RayContext*>(args->context);
  const RayIgnore& ignore = *context->ignore;
  if (ignore.segment == kNoSegment) return;
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
    if (prim == ignore.segment ||
        (prim >= ignore.first_neighbour && prim <= ignore.last_neighbour &&
         RTCRayN_tfar(args->ray, args->N, i) < ignore.neighbour_t)) {
      args->valid[i] = 0;
    }
  }
}

RTCRay MakeRay(const Vec3& org, const Vec3& dir, double tnear, double tfar) {
  RTCRay ray;
  ray.org_x = static_cast<float>(org.x());
  ray.org_y = static_cast<float>(org.y());
  ray.org_z = static_cast<float>(org.z());
  ray.tnear = static_cast<float>(tnear);
  ray.dir_x = static_cast<float>(dir.x());
  ray.dir_y = static_cast<float>(dir.y());
  ray.dir_z = static_cast<float>(dir.z());
  ray.time = 0.0f;
  ray.tfar = std::isfinite(tfar) ? static_cast<float>(tfar) : std::numeric_limits<float>::infinity();
  ray.mask = ~0u;
  ray.id = 0;
  ray.flags = 0;
  return ray;
}

}  // namespace

std::unique_ptr<EmbreeScene> EmbreeScene::Create(const HairCurves* hair, const Body* body,
                                                 std::string* error) {
  ErrorSink sink;  // declared first: it outlives the device on every return path
  std::unique_ptr<EmbreeScene> out(new EmbreeScene);
  out->hair_ = hair;
  out->body_ = body;
  auto fail = [&](const std::string& what) {
    *error = !sink.message.empty() ? what + ": " + sink.message : what + ": Embree failed";
    return nullptr;
  };
  out->device_ = rtcNewDevice("verbose=0");
  if (out->device_ == nullptr) {
    *error = "Embree: cannot create a device (error " +
             std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")";
    return nullptr;
  }
  rtcSetDeviceErrorFunction(out->device_, OnEmbreeError, &sink);
  out->scene_ = rtcNewScene(out->device_);
  if (out->scene_ == nullptr) return fail("Embree scene");

  // Hair: one round linear curve geometry (cones with spherical joints, Embree 3 manual,
  // RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE): float4 vertices (x, y, z, radius = width / 2), and
  // one index per segment, its first vertex. 16 + 4 bytes per point, nothing per segment else.
  if (hair != nullptr && hair->NumStrands() > 0) {
    const size_t num_points = hair->points.size();
    size_t num_segments = 0;
    for (std::uint32_t count : hair->point_counts) num_segments += count - 1;
    RTCGeometry geometry = rtcNewGeometry(out->device_, RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE);
    if (geometry == nullptr) return fail("Embree hair geometry");
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), num_points));
    auto* indices = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, sizeof(std::uint32_t), num_segments));
    if (vertices == nullptr || indices == nullptr) {
      rtcReleaseGeometry(geometry);
      return fail("Embree hair buffers (" + std::to_string(num_points) + " points)");
    }
    for (size_t i = 0; i < num_points; ++i) {
      const Vec3f& p = hair->points[i];
      vertices[4 * i + 0] = p.x();
      vertices[4 * i + 1] = p.y();
      vertices[4 * i + 2] = p.z();
      vertices[4 * i + 3] = 0.5f * hair->widths[i];
    }
    out->strand_first_segment_.reserve(hair->point_counts.size() + 1);
    std::uint32_t point = 0;
    std::uint32_t segment = 0;
    for (std::uint32_t count : hair->point_counts) {
      out->strand_first_segment_.push_back(segment);
      for (std::uint32_t j = 0; j + 1 < count; ++j) indices[segment++] = point + j;
      point += count;
    }
    out->strand_first_segment_.push_back(segment);
    rtcSetGeometryIntersectFilterFunction(geometry, HairFilter);
    rtcSetGeometryOccludedFilterFunction(geometry, HairFilter);
    rtcCommitGeometry(geometry);
    out->hair_geometry_ = rtcAttachGeometry(out->scene_, geometry);
    rtcReleaseGeometry(geometry);
    out->hair_segments_ = static_cast<int>(num_segments);
  }

  // Body spheres: one sphere-point geometry (true spheres, not tessellated). The body's smooth
  // union (Body::blend) only rounds the creases of the contact distance; the renderer shows
  // the exact union of the components.
  if (body != nullptr && !body->spheres().empty()) {
    const auto& spheres = body->spheres();
    RTCGeometry geometry = rtcNewGeometry(out->device_, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    if (geometry == nullptr) return fail("Embree sphere geometry");
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float),
        spheres.size()));
    if (vertices == nullptr) {
      rtcReleaseGeometry(geometry);
      return fail("Embree sphere buffer");
    }
    for (size_t i = 0; i < spheres.size(); ++i) {
      vertices[4 * i + 0] = static_cast<float>(spheres[i].center.x());
      vertices[4 * i + 1] = static_cast<float>(spheres[i].center.y());
      vertices[4 * i + 2] = static_cast<float>(spheres[i].center.z());
      vertices[4 * i + 3] = static_cast<float>(spheres[i].radius);
    }
    rtcCommitGeometry(geometry);
    out->sphere_geometry_ = rtcAttachGeometry(out->scene_, geometry);
    rtcReleaseGeometry(geometry);
    out->body_primitives_ += static_cast<int>(spheres.size());
  }
  // Body meshes: one triangle geometry each (float3 vertices, uint3 triangles).
  if (body != nullptr) {
    for (size_t m = 0; m < body->meshes().size(); ++m) {
      const TriangleMesh& mesh = body->meshes()[m];
      if (mesh.triangles().empty()) continue;
      RTCGeometry geometry = rtcNewGeometry(out->device_, RTC_GEOMETRY_TYPE_TRIANGLE);
      if (geometry == nullptr) return fail("Embree mesh geometry");
      auto* vertices = static_cast<float*>(
          rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                  3 * sizeof(float), mesh.vertices().size()));
      auto* indices = static_cast<std::uint32_t*>(
          rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                  3 * sizeof(std::uint32_t), mesh.triangles().size()));
      if (vertices == nullptr || indices == nullptr) {
        rtcReleaseGeometry(geometry);
        return fail("Embree mesh buffers");
      }
      for (size_t i = 0; i < mesh.vertices().size(); ++i) {
        for (int c = 0; c < 3; ++c) vertices[3 * i + c] = static_cast<float>(mesh.vertices()[i](c));
      }
      for (size_t i = 0; i < mesh.triangles().size(); ++i) {
        for (int c = 0; c < 3; ++c) {
          indices[3 * i + c] = static_cast<std::uint32_t>(mesh.triangles()[i][c]);
        }
      }
      rtcCommitGeometry(geometry);
      const unsigned id = rtcAttachGeometry(out->scene_, geometry);
      rtcReleaseGeometry(geometry);
      if (out->mesh_of_geometry_.size() <= id) out->mesh_of_geometry_.resize(id + 1, -1);
      out->mesh_of_geometry_[id] = static_cast<int>(m);
      out->corner_normals_.resize(body->meshes().size());
      out->corner_normals_[m] = CornerNormals(mesh);
      out->body_primitives_ += static_cast<int>(mesh.triangles().size());
    }
  }

  // Build the hierarchy (Embree's TBB tasks run in the caller's task arena).
  rtcCommitScene(out->scene_);
  if (rtcGetDeviceError(out->device_) != RTC_ERROR_NONE || !sink.message.empty()) {
    return fail("Embree scene build");
  }
  RTCBounds bounds;
  rtcGetSceneBounds(out->scene_, &bounds);
  double size = 0.0;
  if (bounds.lower_x <= bounds.upper_x) {
    const Vec3 lower(bounds.lower_x, bounds.lower_y, bounds.lower_z);
    const Vec3 upper(bounds.upper_x, bounds.upper_y, bounds.upper_z);
    size = std::max((upper - lower).norm(), std::max(lower.cwiseAbs().maxCoeff(),
                                                     upper.cwiseAbs().maxCoeff()));
  }
  out->body_offset_ = 1e-5 * std::max(size, 1e-3);
  // From here on errors are programmer errors; the sink dies with this function.
  rtcSetDeviceErrorFunction(out->device_, nullptr, nullptr);
  return out;
}

EmbreeScene::~EmbreeScene() {
  if (scene_ != nullptr) rtcReleaseScene(scene_);
  if (device_ != nullptr) rtcReleaseDevice(device_);
}

int EmbreeScene::StrandOfSegment(std::uint32_t segment) const {
  const auto it = std::upper_bound(strand_first_segment_.begin(), strand_first_segment_.end(),
                                   segment);
  return static_cast<int>(it - strand_first_segment_.begin()) - 1;
}

SurfaceHit EmbreeScene::Intersect(const Vec3& org, const Vec3& dir, double tnear, double tfar,
                                  const RayIgnore& ignore) const {
  RayContext context;
  rtcInitIntersectContext(&context.context);
  context.ignore = &ignore;
  RTCRayHit rayhit;
  rayhit.ray = MakeRay(org, dir, tnear, tfar);
  rayhit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rayhit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &context.context, &rayhit);

  SurfaceHit hit;
  if (rayhit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return hit;
  hit.t = rayhit.ray.tfar;
  hit.p = org + hit.t * dir;
  const unsigned geometry = rayhit.hit.geomID;
  const unsigned prim = rayhit.hit.primID;
  if (geometry == hair_geometry_) {
    // The segment's axis from the float data Embree intersected: p_axis is the closest point
    // of the axis segment to the hit (a point of a joint cap projects onto the segment's end).
    hit.kind = HitKind::kHair;
    hit.segment = prim;
    hit.strand = StrandOfSegment(prim);
    const std::uint32_t first_point = prim + static_cast<std::uint32_t>(hit.strand);
    const Vec3 p0 = hair_->points[first_point].cast<double>();
    const Vec3 p1 = hair_->points[first_point + 1].cast<double>();
    const double r0 = 0.5 * hair_->widths[first_point];
    const double r1 = 0.5 * hair_->widths[first_point + 1];
    const Vec3 axis = p1 - p0;
    const double length_squared = axis.squaredNorm();
    double s = 0.0;
    if (length_squared > 0.0) {
      s = std::clamp((hit.p - p0).dot(axis) / length_squared, 0.0, 1.0);
      hit.tangent = axis / std::sqrt(length_squared);
    } else {
      // A zero-length segment is a sphere: any tangent normal to the ray will do.
      hit.tangent = Frame(dir).s;
    }
    hit.axis_point = p0 + s * axis;
    if (!hair_->major_axes.empty()) {
      hit.major_axis = (1.0 - s) * hair_->major_axes[first_point].cast<double>() +
                       s * hair_->major_axes[first_point + 1].cast<double>();
    }
    hit.radius = (1.0 - s) * r0 + s * r1;
    if (!hair_->wetness.empty()) hit.wetness = hair_->wetness[static_cast<size_t>(hit.strand)];
    return hit;
  }
  hit.kind = HitKind::kBody;
  if (geometry == sphere_geometry_) {
    const Sphere& sphere = body_->spheres()[prim];
    hit.normal = (hit.p - sphere.center).normalized();
    hit.shading_normal = hit.normal;
  } else {
    const int m = mesh_of_geometry_[geometry];
    const TriangleMesh& mesh = body_->meshes()[static_cast<size_t>(m)];
    const auto& triangle = mesh.triangles()[prim];
    const Vec3& a = mesh.vertices()[triangle[0]];
    const Vec3& b = mesh.vertices()[triangle[1]];
    const Vec3& c = mesh.vertices()[triangle[2]];
    hit.normal = (b - a).cross(c - a).normalized();  // outward (TriangleMesh's orientation)
    // Phong normal: Embree's barycentrics (u, v) weight corners 1 and 2.
    const Vec3* n = &corner_normals_[static_cast<size_t>(m)][3 * static_cast<size_t>(prim)];
    const double u = rayhit.hit.u, w = rayhit.hit.v;
    const Vec3 shading = (1.0 - u - w) * n[0] + u * n[1] + w * n[2];
    const double norm = shading.norm();
    hit.shading_normal = norm > 0.0 && std::isfinite(norm) ? Vec3(shading / norm) : hit.normal;
  }
  return hit;
}

bool EmbreeScene::Occluded(const Vec3& org, const Vec3& dir, double tnear, double tfar,
                           const RayIgnore& ignore) const {
  RayContext context;
  rtcInitIntersectContext(&context.context);
  context.ignore = &ignore;
  RTCRay ray = MakeRay(org, dir, tnear, tfar);
  rtcOccluded1(scene_, &context.context, &ray);
  return ray.tfar < 0.0f;  // Embree sets tfar = -inf when something blocks
}

RayIgnore EmbreeScene::IgnoreFor(const SurfaceHit& hit) const {
  RayIgnore ignore;
  if (hit.kind != HitKind::kHair) return ignore;
  ignore.segment = hit.segment;
  const std::uint32_t first = strand_first_segment_[hit.strand];
  const std::uint32_t last = strand_first_segment_[hit.strand + 1] - 1;
  ignore.first_neighbour = hit.segment > first ? hit.segment - 1 : first;
  ignore.last_neighbour = hit.segment < last ? hit.segment + 1 : last;
  // A ray from the surface of a joint crosses the neighbour's cap within 2 r; 4 r is safe and
  // far below the length of any real segment.
  ignore.neighbour_t = static_cast<float>(4.0 * hit.radius);
  return ignore;
}

FibreFrame MakeFibreFrame(const SurfaceHit& hit, const Vec3& wo, std::uint64_t orientation_seed) {
  FibreFrame frame;
  frame.x = hit.tangent;
  Vec3 z = wo - wo.dot(frame.x) * frame.x;
  const double z_norm = z.norm();
  // wo along the fibre: the normal plane direction is arbitrary (a measure-zero case).
  frame.z = z_norm > 1e-12 ? Vec3(z / z_norm) : Frame(frame.x).s;
  frame.y = frame.z.cross(frame.x);
  const double h = hit.radius > 0.0 ? (hit.p - hit.axis_point).dot(frame.y) / hit.radius : 0.0;
  frame.hit.h = std::clamp(h, -1.0, 1.0);
  frame.hit.wetness = hit.wetness;
  // The ellipse's orientation: the given major axis seen in the normal plane (y, z), folded into
  // [0, pi); without one (or with one along the fibre), a random angle per strand.
  const double axis_y = hit.major_axis.dot(frame.y);
  const double axis_z = hit.major_axis.dot(frame.z);
  if (std::hypot(axis_y, axis_z) > 1e-6 * hit.major_axis.norm() && hit.major_axis.norm() > 0.0) {
    double angle = std::atan2(axis_z, axis_y);  // (-pi, pi]
    if (angle < 0.0) angle += std::numbers::pi;
    if (angle >= std::numbers::pi) angle -= std::numbers::pi;
    frame.hit.major_axis_angle = angle;
  } else {
    groom::SplitMix64 rng(
        groom::StreamSeed(orientation_seed, static_cast<std::uint64_t>(hit.strand)));
    frame.hit.major_axis_angle = std::numbers::pi * rng.Uniform();
  }
  return frame;
}

Rgb ShadowTransmittance(const EmbreeScene& scene, const FibreScattering& fibre,
                        std::uint64_t orientation_seed, const Vec3& org, const Vec3& dir,
                        double tnear, double tfar, const RayIgnore& ignore, std::int64_t* rays,
                        int max_crossings, double min_throughput) {
  Rgb throughput = Rgb::Ones();
  Vec3 origin = org;
  double t_start = tnear;
  double t_left = tfar;
  RayIgnore skip = ignore;
  // Each crossing restarts the ray at the fibre's entry point, skipping that fibre: a ray
  // crosses a straight fibre (convex) once, and its neighbours' joints within a few radii.
  for (int crossing = 0; crossing <= max_crossings; ++crossing) {
    if (rays != nullptr) ++*rays;
    const SurfaceHit hit = scene.Intersect(origin, dir, t_start, t_left, skip);
    if (hit.kind == HitKind::kNone) return throughput;
    if (hit.kind == HitKind::kBody || crossing == max_crossings) return Rgb::Zero();
    const FibreFrame frame = MakeFibreFrame(hit, -dir, orientation_seed);
    throughput = throughput.cwiseProduct(fibre.Transmittance(frame.ToLocal(-dir), frame.hit));
    if (throughput.maxCoeff() < min_throughput) return Rgb::Zero();
    origin = hit.p;
    if (std::isfinite(t_left)) t_left -= hit.t;
    t_start = 0.0;
    skip = scene.IgnoreFor(hit);
  }
  return Rgb::Zero();
}

}  // namespace ringlet::render
