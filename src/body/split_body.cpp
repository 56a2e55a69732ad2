// A body whose head turns on a still torso (split_body.h; docs/body.md, "Head and torso").
#include "ringlet/split_body.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "body/body_fold.h"

namespace ringlet {

using internal::NearestSphere;
using internal::SmoothFold;
using internal::SmoothFoldHessian;
using internal::SphereHessian;

// The split body placed: spheres moved, the parts' meshes queried in their frames.
class PlacedSplitBody final : public Obstacle {
 public:
  PlacedSplitBody(std::shared_ptr<const SplitBody> split, const Mat3& head_rotation,
                  const Vec3& head_translation, const Vec3& torso_translation)
      : split_(std::move(split)),
        rotation_(head_rotation),
        head_translation_(head_translation),
        torso_translation_(torso_translation) {
    const size_t count = split_->spheres_.size();
    spheres_.resize(count);
    for (size_t i = 0; i < count; ++i) {
      const Eigen::Vector4d& s = split_->spheres_[i];
      const Vec3 c = s.head<3>();
      const Vec3 moved =
          split_->sphere_torso_[i] ? Vec3(c + torso_translation) : Vec3(head_rotation * c + head_translation);
      spheres_[i] << moved, s(3);
    }
  }

  double SignedDistance(const Vec3& x, Vec3* gradient) const override {
    return Evaluate(x, gradient, nullptr);
  }
  double SignedDistanceHessian(const Vec3& x, Vec3* gradient, Mat3* hessian) const override {
    return Evaluate(x, gradient, hessian);
  }
  double LipschitzBound() const override { return split_->lipschitz_; }

 private:
  // A part's meshes at x (world): d(local), gradient and Hessian turned back to the world.
  double Part(bool head, const Vec3& x, Vec3* g, Mat3* h) const {
    const Body& part = head ? *split_->head_meshes_ : *split_->torso_meshes_;
    const Vec3 local = head ? Vec3(rotation_.transpose() * (x - head_translation_))
                            : Vec3(x - torso_translation_);
    Vec3 gl = Vec3::UnitZ();
    Mat3 hl = Mat3::Zero();
    const double d = h ? part.SignedDistanceHessian(local, &gl, &hl)
                       : part.SignedDistance(local, g ? &gl : nullptr);
    if (g) *g = head ? Vec3(rotation_ * gl) : gl;
    if (h) *h = head ? Mat3(rotation_ * hl * rotation_.transpose()) : hl;
    return d;
  }

  // Whether a part's meshes can be skipped: with blend 0, when x lies outside the part's box by
  // at least best (the distance to the box bounds the part's distance from below).
  bool SkipPart(bool head, const Vec3& x, double best) const {
    const Body& part = head ? *split_->head_meshes_ : *split_->torso_meshes_;
    if (part.distance_grid()) return false;  // a grid query is cheaper than the box test's worth
    const Vec3 local = head ? Vec3(rotation_.transpose() * (x - head_translation_))
                            : Vec3(x - torso_translation_);
    const double box_distance = std::sqrt(part.Bounds().squaredExteriorDistance(local));
    return box_distance > 0.0 && box_distance >= best;
  }

  double Evaluate(const Vec3& x, Vec3* gradient, Mat3* hessian) const {
    const double k = split_->blend_;
    const bool parts[2] = {split_->head_meshes_ != nullptr, split_->torso_meshes_ != nullptr};
    double best = std::numeric_limits<double>::infinity();
    Vec3 best_gradient = Vec3::UnitZ();
    Mat3 best_hessian = Mat3::Zero();
    const bool want_gradient = gradient || hessian;
    if (k > 0.0) {
      // The smooth union, folded in the body's order (Body::SignedDistance).
      for (const Eigen::Vector4d& s : spheres_) {
        const Vec3 r = x - s.head<3>();
        const double reach = s(3) + best + k;
        if (reach > 0.0 && r.squaredNorm() >= reach * reach) continue;
        const double norm = r.norm();
        const Vec3 n = norm > 0.0 ? Vec3(r / norm) : Vec3::UnitZ();
        if (hessian) {
          SmoothFoldHessian(norm - s(3), n, SphereHessian(r, norm), k, &best, &best_gradient,
                            &best_hessian);
        } else {
          SmoothFold(norm - s(3), n, k, &best, &best_gradient);
        }
      }
      for (int p = 0; p < 2; ++p) {
        if (!parts[p]) continue;
        Vec3 g;
        Mat3 h;
        const double d = Part(p == 0, x, &g, hessian ? &h : nullptr);
        if (hessian) {
          SmoothFoldHessian(d, g, h, k, &best, &best_gradient, &best_hessian);
        } else {
          SmoothFold(d, g, k, &best, &best_gradient);
        }
      }
    } else {
      // The exact minimum: the first minimizing component in sphere-then-mesh order.
      const int nearest = NearestSphere(spheres_, x, &best);
      if (nearest >= 0 && want_gradient) {
        const Vec3 r = x - spheres_[static_cast<size_t>(nearest)].head<3>();
        const double norm = r.norm();
        best_gradient = norm > 0.0 ? Vec3(r / norm) : Vec3::UnitZ();
        if (hessian) best_hessian = SphereHessian(r, norm);
      }
      for (int p = 0; p < 2; ++p) {
        if (!parts[p] || SkipPart(p == 0, x, best)) continue;
        Vec3 g;
        Mat3 h;
        const double d =
            Part(p == 0, x, want_gradient ? &g : nullptr, hessian ? &h : nullptr);
        if (d < best) {
          best = d;
          if (want_gradient) best_gradient = g;
          if (hessian) best_hessian = h;
        }
      }
    }
    if (gradient) *gradient = best_gradient;
    if (hessian) *hessian = best_hessian;
    return best;
  }

  std::shared_ptr<const SplitBody> split_;
  Mat3 rotation_;
  Vec3 head_translation_;
  Vec3 torso_translation_;
  std::vector<Eigen::Vector4d> spheres_;  // moved
};

std::shared_ptr<const SplitBody> SplitBody::Create(std::shared_ptr<const Body> body) {
  if (!body) throw std::invalid_argument("SplitBody: no body");
  if (!body->HasTorsoPart()) return nullptr;
  std::shared_ptr<SplitBody> split(new SplitBody());
  split->blend_ = body->blend();
  for (size_t i = 0; i < body->spheres().size(); ++i) {
    const Sphere& s = body->spheres()[i];
    split->spheres_.emplace_back(s.center.x(), s.center.y(), s.center.z(), s.radius);
    split->sphere_torso_.push_back(body->sphere_part(i) == BodyPart::kTorso ? 1 : 0);
  }
  std::vector<TriangleMesh> head, torso;
  for (size_t i = 0; i < body->meshes().size(); ++i) {
    (body->mesh_part(i) == BodyPart::kTorso ? torso : head).push_back(body->meshes()[i]);
  }
  for (auto* part : {&head, &torso}) {
    if (part->empty()) continue;
    auto meshes = std::make_shared<Body>();
    std::string error;
    if (!Body::Create({}, std::move(*part), meshes.get(), &error, body->blend(),
                      body->mesh_distance())) {
      throw std::invalid_argument("SplitBody: " + error);
    }
    split->grid_build_seconds_ += meshes->grid_build_seconds();
    split->lipschitz_ = std::max(split->lipschitz_, meshes->LipschitzBound());
    (part == &head ? split->head_meshes_ : split->torso_meshes_) = std::move(meshes);
  }
  split->body_ = std::move(body);
  return split;
}

std::shared_ptr<const Obstacle> SplitBody::Place(const Mat3& head_rotation,
                                                 const Vec3& head_translation,
                                                 const Vec3& torso_translation) const {
  return std::make_shared<PlacedSplitBody>(shared_from_this(), head_rotation, head_translation,
                                           torso_translation);
}

bool MoveBodyParts(const Body& body, const Mat3& head_rotation, const Vec3& head_translation,
                   const Mat3& torso_rotation, const Vec3& torso_translation, Body* moved,
                   std::string* error) {
  auto place = [&](BodyPart part, const Vec3& x) -> Vec3 {
    return part == BodyPart::kTorso ? Vec3(torso_rotation * x + torso_translation)
                                    : Vec3(head_rotation * x + head_translation);
  };
  std::vector<Sphere> spheres = body.spheres();
  for (size_t i = 0; i < spheres.size(); ++i) {
    spheres[i].center = place(body.sphere_part(i), spheres[i].center);
    spheres[i].moves_with = body.sphere_part(i);
  }
  std::vector<TriangleMesh> meshes;
  std::vector<std::optional<BodyPart>> parts;
  for (size_t i = 0; i < body.meshes().size(); ++i) {
    const TriangleMesh& mesh = body.meshes()[i];
    const bool torso = body.mesh_part(i) == BodyPart::kTorso;
    if ((torso ? torso_rotation : head_rotation) == Mat3::Identity() &&
        (torso ? torso_translation : head_translation) == Vec3::Zero()) {
      meshes.push_back(mesh);  // not moved: no need to build it again
      parts.emplace_back(body.mesh_part(i));
      continue;
    }
    std::vector<Vec3> vertices = mesh.vertices();
    for (Vec3& v : vertices) v = place(body.mesh_part(i), v);
    TriangleMesh m;
    if (!TriangleMesh::Create(std::move(vertices), mesh.triangles(), mesh.name(), &m, error)) {
      return false;
    }
    meshes.push_back(std::move(m));
    parts.emplace_back(body.mesh_part(i));
  }
  return Body::Create(std::move(spheres), std::move(meshes), moved, error, body.blend(), {},
                      parts);
}

}  // namespace ringlet
