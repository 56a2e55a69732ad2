// The body: a union of spheres and closed meshes, queried by the contact energy (docs/body.md).
#include "ringlet/body.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "body/body_fold.h"
#include "body/distance_grid.h"

namespace ringlet {

using internal::NearestSphere;
using internal::SmoothFold;
using internal::SmoothFoldHessian;
using internal::SphereHessian;

namespace {

// Largest distance grid Body::Create builds: 4 bytes per node, 256 MB.
constexpr double kMaxGridNodes = 64e6;

// A number as quoted in messages: the shortest %g form that reads back exactly (-0.1, not
// -0.10000000000000001).
std::string NumberText(double x) {
  char text[32];
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(text, sizeof(text), "%.*g", digits, x);
    if (std::strtod(text, nullptr) == x) break;
  }
  return text;
}

}  // namespace

bool MeshDistanceOptions::IsValid(std::string* why) const {
  if (mode != Mode::kExact && mode != Mode::kGrid) {
    if (why) *why = "mode: expected exact or grid";
    return false;
  }
  if (!(std::isfinite(spacing) && spacing >= 1e-4)) {
    if (why) *why = "spacing: expected a finite number >= 0.0001 (m), got " + NumberText(spacing);
    return false;
  }
  if (!(std::isfinite(band) && band > 0.0)) {
    if (why) *why = "band: expected a finite number > 0 (m), got " + NumberText(band);
    return false;
  }
  return true;
}

std::size_t Body::GridMemoryBytes() const { return grid_ ? grid_->MemoryBytes() : 0; }

const char* BodyPartName(BodyPart part) { return part == BodyPart::kTorso ? "torso" : "head"; }

BodyPart DefaultBodyPart(std::string_view name) {
  if (name.empty()) return BodyPart::kHead;
  // Whole words only (a prefix rule read "brown_coat" as a brow and "earth" as an ear): the
  // parts of a head and what is worn on it, each also with a plural s or es.
  static constexpr std::string_view kHeadWords[] = {
      "head",    "skull",    "cranium", "crania",   "scalp",    "face",      "forehead",
      "brow",    "eyebrow",  "eye",     "eyelid",   "eyelash",  "ear",       "earlobe",
      "earring", "nose",     "nostril", "cheek",    "cheekbone", "jaw",      "jawbone",
      "jawline", "chin",     "mouth",   "lip",      "tooth",    "teeth",     "tongue",
      "hat",     "cap",      "helmet",  "headband", "glasses",  "spectacles"};
  auto is_head_word = [](std::string_view word) {
    for (std::string_view head : kHeadWords) {
      if (word == head) return true;
      if (word.size() == head.size() + 1 && word.back() == 's' && word.starts_with(head)) {
        return true;
      }
      if (word.size() == head.size() + 2 && word.ends_with("es") && word.starts_with(head)) {
        return true;
      }
    }
    return false;
  };
  auto lower = [](char c) { return c >= 'a' && c <= 'z'; };
  auto upper = [](char c) { return c >= 'A' && c <= 'Z'; };
  size_t i = 0;
  while (i < name.size()) {
    // The next word: a run of ASCII letters, lower-cased, that also ends where a lower-case
    // letter is followed by an upper-case one (camelCase: "leftEar" is "left" and "ear").
    while (i < name.size() && !lower(name[i]) && !upper(name[i])) ++i;
    std::string word;
    while (i < name.size() && (lower(name[i]) || upper(name[i]))) {
      if (!word.empty() && upper(name[i]) && lower(name[i - 1])) break;
      const char c = name[i++];
      word.push_back(upper(c) ? static_cast<char>(c - 'A' + 'a') : c);
    }
    if (!word.empty() && is_head_word(word)) return BodyPart::kHead;
  }
  return BodyPart::kTorso;
}

bool Body::HasTorsoPart() const {
  for (BodyPart p : sphere_parts_) {
    if (p == BodyPart::kTorso) return true;
  }
  for (BodyPart p : mesh_parts_) {
    if (p == BodyPart::kTorso) return true;
  }
  return false;
}

bool Body::Create(std::vector<Sphere> spheres, std::vector<TriangleMesh> meshes, Body* body,
                  std::string* error, double blend, const MeshDistanceOptions& mesh_distance,
                  const std::vector<std::optional<BodyPart>>& mesh_moves_with) {
  if (!(std::isfinite(blend) && blend >= 0.0)) {
    if (error) *error = "blend: expected a finite number >= 0 (m)";
    return false;
  }
  std::string why;
  if (!mesh_distance.IsValid(&why)) {
    if (error) *error = "mesh_distance." + why;
    return false;
  }
  std::set<std::string> names;
  for (size_t i = 0; i < spheres.size(); ++i) {
    const Sphere& s = spheres[i];
    const std::string path = "spheres[" + std::to_string(i) + "]";
    if (!s.center.allFinite()) {
      if (error) *error = path + ".center: expected 3 finite numbers (m)";
      return false;
    }
    if (!(std::isfinite(s.radius) && s.radius > 0.0)) {
      if (error) {
        *error = path + ".radius: expected a finite number > 0 (m), got " + NumberText(s.radius);
      }
      return false;
    }
    if (!s.name.empty() && !names.insert(s.name).second) {
      if (error) *error = path + ".name: \"" + s.name + "\" is already the name of another sphere";
      return false;
    }
    if (s.moves_with && *s.moves_with != BodyPart::kHead && *s.moves_with != BodyPart::kTorso) {
      if (error) *error = path + ".moves_with: expected head or torso";
      return false;
    }
  }
  if (!mesh_moves_with.empty() && mesh_moves_with.size() != meshes.size()) {
    if (error) {
      *error = "mesh_moves_with: expected one entry per mesh (" + std::to_string(meshes.size()) +
               ") or none, got " + std::to_string(mesh_moves_with.size());
    }
    return false;
  }
  for (size_t i = 0; i < mesh_moves_with.size(); ++i) {
    const std::optional<BodyPart>& p = mesh_moves_with[i];
    if (p && *p != BodyPart::kHead && *p != BodyPart::kTorso) {
      if (error) *error = "mesh_moves_with[" + std::to_string(i) + "]: expected head or torso";
      return false;
    }
  }
  for (size_t i = 0; i < meshes.size(); ++i) {
    if (meshes[i].triangles().empty()) {
      if (error) *error = "meshes[" + std::to_string(i) + "]: the mesh is empty";
      return false;
    }
  }

  Body result;
  result.packed_spheres_.reserve(spheres.size());
  for (const Sphere& s : spheres) {
    result.packed_spheres_.emplace_back(s.center.x(), s.center.y(), s.center.z(), s.radius);
    result.bounds_.extend(s.center - Vec3::Constant(s.radius));
    result.bounds_.extend(s.center + Vec3::Constant(s.radius));
  }
  for (const TriangleMesh& m : meshes) result.bounds_.extend(m.bounds());
  for (const Sphere& s : spheres) {
    result.sphere_parts_.push_back(s.moves_with ? *s.moves_with : DefaultBodyPart(s.name));
  }
  for (size_t i = 0; i < meshes.size(); ++i) {
    result.mesh_parts_.push_back(!mesh_moves_with.empty() && mesh_moves_with[i]
                                     ? *mesh_moves_with[i]
                                     : DefaultBodyPart(meshes[i].name()));
  }
  result.spheres_ = std::move(spheres);
  result.meshes_ = std::move(meshes);
  result.blend_ = blend;
  result.mesh_distance_ = mesh_distance;
  if (mesh_distance.mode == MeshDistanceOptions::Mode::kGrid && !result.meshes_.empty()) {
    // The grid samples the meshes' union alone (the same fold as the exact queries); spheres
    // stay exact and are folded with the grid's value at query time.
    Box3 mesh_box;
    for (const TriangleMesh& m : result.meshes_) mesh_box.extend(m.bounds());
    const std::vector<TriangleMesh>& all = result.meshes_;
    const auto exact = [&all, blend](const Vec3& x) {
      double best = std::numeric_limits<double>::infinity();
      Vec3 best_gradient = Vec3::UnitZ();
      for (const TriangleMesh& m : all) {
        const double box_distance = std::sqrt(m.bounds().squaredExteriorDistance(x));
        if (box_distance > 0.0 && box_distance >= best + blend) continue;
        Vec3 g = Vec3::UnitZ();
        const double d = m.SignedDistance(x, &g);
        if (blend > 0.0) {
          SmoothFold(d, g, blend, &best, &best_gradient);
        } else {
          best = std::min(best, d);
        }
      }
      return best;
    };
    // Memory guard: the node count of the box enlarged by band + 3 h at this spacing.
    const Vec3 nodes =
        ((mesh_box.sizes().array() + 2.0 * (mesh_distance.band + 3.0 * mesh_distance.spacing)) /
             mesh_distance.spacing +
         2.0)
            .matrix();
    if (nodes.prod() > kMaxGridNodes) {
      if (error) {
        *error = "mesh_distance.spacing: " + NumberText(mesh_distance.spacing) + " m gives " +
                 NumberText(std::round(nodes.prod() / 1e6)) +
                 " million grid nodes over the meshes' box (at most " +
                 NumberText(kMaxGridNodes / 1e6) +
                 " million): use a coarser spacing or exact queries";
      }
      return false;
    }
    const auto start = std::chrono::steady_clock::now();
    result.grid_ = std::make_shared<const internal::DistanceGrid>(internal::DistanceGrid::Build(
        exact, mesh_box, mesh_distance.spacing, mesh_distance.band, mesh_distance.threads));
    result.grid_build_seconds_ =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  *body = std::move(result);
  return true;
}

double Body::SignedDistance(const Vec3& x, Vec3* gradient) const {
  if (blend_ > 0.0) {
    // Smooth union: every component within blend of the running minimum contributes.
    double best = std::numeric_limits<double>::infinity();
    Vec3 best_gradient = Vec3::UnitZ();
    for (const Eigen::Vector4d& s : packed_spheres_) {
      const Vec3 r = x - s.head<3>();
      // Spheres farther than best + blend do not change the fold: skip them without a root.
      const double reach = s(3) + best + blend_;
      if (reach > 0.0 && r.squaredNorm() >= reach * reach) continue;
      const double norm = r.norm();
      SmoothFold(norm - s(3), norm > 0.0 ? Vec3(r / norm) : Vec3::UnitZ(), blend_, &best,
                 &best_gradient);
    }
    if (grid_) {
      Vec3 g;
      const double d = grid_->Evaluate(x, &g, nullptr);
      SmoothFold(d, g, blend_, &best, &best_gradient);
    } else {
      for (const TriangleMesh& m : meshes_) {
        const double box_distance = std::sqrt(m.bounds().squaredExteriorDistance(x));
        if (box_distance > 0.0 && box_distance >= best + blend_) continue;
        Vec3 g = Vec3::UnitZ();
        const double d = m.SignedDistance(x, &g);
        SmoothFold(d, g, blend_, &best, &best_gradient);
      }
    }
    if (gradient) *gradient = best_gradient;
    return best;
  }
  // Spheres: min |x - c| - r, no allocation, no virtual call.
  double best = std::numeric_limits<double>::infinity();
  const int best_sphere = NearestSphere(packed_spheres_, x, &best);
  // Meshes: skipped when x is outside the mesh's box by more than the best distance (the
  // distance to the box is then a lower bound of the mesh's signed distance).
  int best_mesh = -1;
  Vec3 mesh_gradient = Vec3::UnitZ();
  if (grid_) {
    Vec3 g;
    const double d = grid_->Evaluate(x, gradient ? &g : nullptr, nullptr);
    if (d < best) {
      best = d;
      best_mesh = 0;
      if (gradient) mesh_gradient = g;
    }
  }
  for (size_t m = 0; !grid_ && m < meshes_.size(); ++m) {
    const double box_distance = std::sqrt(meshes_[m].bounds().squaredExteriorDistance(x));
    if (box_distance > 0.0 && box_distance >= best) continue;
    Vec3 g;
    const double d = meshes_[m].SignedDistance(x, gradient ? &g : nullptr);
    if (d < best) {
      best = d;
      best_mesh = static_cast<int>(m);
      if (gradient) mesh_gradient = g;
    }
  }
  if (gradient) {
    if (best_mesh >= 0) {
      *gradient = mesh_gradient;
    } else if (best_sphere >= 0) {
      const Eigen::Vector4d& s = packed_spheres_[static_cast<size_t>(best_sphere)];
      const Vec3 r = x - s.head<3>();
      const double norm = r.norm();
      *gradient = norm > 0.0 ? Vec3(r / norm) : Vec3::UnitZ();
    } else {
      *gradient = Vec3::UnitZ();
    }
  }
  return best;
}

double Body::SignedDistanceHessian(const Vec3& x, Vec3* gradient, Mat3* hessian) const {
  if (!hessian) return SignedDistance(x, gradient);
  double best = std::numeric_limits<double>::infinity();
  Vec3 best_gradient = Vec3::UnitZ();
  Mat3 best_hessian = Mat3::Zero();
  if (blend_ > 0.0) {
    // The same components and the same fold as SignedDistance, with their Hessians.
    for (const Eigen::Vector4d& s : packed_spheres_) {
      const Vec3 r = x - s.head<3>();
      const double reach = s(3) + best + blend_;
      if (reach > 0.0 && r.squaredNorm() >= reach * reach) continue;
      const double norm = r.norm();
      SmoothFoldHessian(norm - s(3), norm > 0.0 ? Vec3(r / norm) : Vec3::UnitZ(),
                        SphereHessian(r, norm), blend_, &best, &best_gradient, &best_hessian);
    }
    if (grid_) {
      Vec3 g;
      Mat3 hm;
      const double d = grid_->Evaluate(x, &g, &hm);
      SmoothFoldHessian(d, g, hm, blend_, &best, &best_gradient, &best_hessian);
    }
    for (size_t i = 0; !grid_ && i < meshes_.size(); ++i) {
      const TriangleMesh& m = meshes_[i];
      const double box_distance = std::sqrt(m.bounds().squaredExteriorDistance(x));
      if (box_distance > 0.0 && box_distance >= best + blend_) continue;
      Vec3 g = Vec3::UnitZ();
      Mat3 hm;
      const double d = m.SignedDistanceHessian(x, &g, &hm);
      SmoothFoldHessian(d, g, hm, blend_, &best, &best_gradient, &best_hessian);
    }
  } else {
    // The exact minimum: the Hessian of the minimizing component (ties as in SignedDistance).
    const int best_sphere = NearestSphere(packed_spheres_, x, &best);
    if (best_sphere >= 0) {
      const Vec3 r = x - packed_spheres_[static_cast<size_t>(best_sphere)].head<3>();
      const double norm = r.norm();
      best_gradient = norm > 0.0 ? Vec3(r / norm) : Vec3::UnitZ();
      best_hessian = SphereHessian(r, norm);
    }
    if (grid_) {
      Vec3 g;
      Mat3 hm;
      const double d = grid_->Evaluate(x, &g, &hm);
      if (d < best) {
        best = d;
        best_gradient = g;
        best_hessian = hm;
      }
    }
    for (size_t i = 0; !grid_ && i < meshes_.size(); ++i) {
      const TriangleMesh& m = meshes_[i];
      const double box_distance = std::sqrt(m.bounds().squaredExteriorDistance(x));
      if (box_distance > 0.0 && box_distance >= best) continue;
      Vec3 g;
      Mat3 hm;
      const double d = m.SignedDistanceHessian(x, &g, &hm);
      if (d < best) {
        best = d;
        best_gradient = g;
        best_hessian = hm;
      }
    }
  }
  if (gradient) *gradient = best_gradient;
  *hessian = best_hessian;
  return best;
}

const Sphere* Body::FindSphere(std::string_view name) const {
  if (name.empty()) return nullptr;
  for (const Sphere& s : spheres_) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

}  // namespace ringlet
