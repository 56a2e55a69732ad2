// Strand model: segment layouts, root frame, stiffness and validation.
#include "ringlet/strand_model.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numeric>

namespace ringlet {

double StrandModel::Length() const {
  return std::accumulate(segment_lengths.begin(), segment_lengths.end(), 0.0);
}

Vec3 StrandModel::Stiffness() const {
  const double e = material.young_modulus;
  return Vec3(e * section.I1(), e * section.I2(), material.ShearModulus() * section.J());
}

Vec3 StrandModel::WeightPerLength() const {
  return material.density * section.Area() * gravity;
}

VecX StrandModel::NaturalCurvatures() const {
  if (HasRestShape()) return rest_curvatures;
  VecX q(3 * NumSegments());
  for (int i = 0; i < NumSegments(); ++i) q.segment<3>(3 * i) = natural_curvature;
  return q;
}

double StrandModel::GravityParameter() const {
  const double l = Length();
  return WeightPerLength().norm() * l * l * l / Stiffness()(0);
}

double StrandModel::ContactStiffness() const {
  return contact.stiffness > 0.0 ? contact.stiffness : DefaultContactStiffness(*this);
}

double DefaultContactStiffness(const StrandModel& model) {
  const double length = model.Length();
  const double load = std::max(model.WeightPerLength().norm(), model.Stiffness()(0) / (length * length * length));
  return kContactLoadFactor * load / (kContactPenetration * length);
}

std::vector<double> UniformSegments(double length, int segments) {
  return std::vector<double>(static_cast<size_t>(segments), length / segments);
}

std::vector<double> GradedSegments(double length, int segments, double ratio) {
  if (segments == 1 || ratio == 1.0) return UniformSegments(length, segments);
  // l_i = l_0 q^i with q^(n-1) = ratio; sum = l_0 (q^n - 1)/(q - 1) = L.
  const double q = std::pow(ratio, 1.0 / (segments - 1));
  const double first = length * (q - 1.0) / (std::pow(q, segments) - 1.0);
  std::vector<double> lengths(static_cast<size_t>(segments));
  double sum = 0.0;
  for (int i = 0; i < segments; ++i) {
    lengths[i] = first * std::pow(q, i);
    sum += lengths[i];
  }
  // Remove the rounding so that the lengths sum to L.
  for (double& l : lengths) l *= length / sum;
  return lengths;
}

double RecommendedGradingRatio(double gravity_parameter) {
  return 1.0 + gravity_parameter / (2.0 * std::sqrt(1.0 + gravity_parameter / 64.0));
}

bool RootFrameFromTangentNormal(const Vec3& tangent, const Vec3& normal, Mat3* frame,
                                std::string* why) {
  const double t_norm = tangent.norm();
  if (!std::isfinite(t_norm) || t_norm == 0.0) {
    if (why) *why = "tangent must be a finite, non-zero vector";
    return false;
  }
  const Vec3 t = tangent / t_norm;
  const double n_norm = normal.norm();
  if (!std::isfinite(n_norm) || n_norm == 0.0) {
    if (why) *why = "normal must be a finite, non-zero vector";
    return false;
  }
  // Gram-Schmidt; reject normals within ~0.06 degrees of the tangent, where n1 is ill-defined.
  const Vec3 n_perp = normal / n_norm - t * t.dot(normal / n_norm);
  if (n_perp.norm() < 1e-3) {
    if (why) *why = "normal must not be parallel to the tangent";
    return false;
  }
  const Vec3 n1 = n_perp.normalized();
  const Vec3 n2 = t.cross(n1);
  frame->col(0) = n1;
  frame->col(1) = n2;
  frame->col(2) = t;
  return true;
}

double NaturalTurning(const StrandModel& model) {
  if (model.rest_curvatures.size() == 0) return model.natural_curvature.norm() * model.Length();
  double turning = 0.0;
  for (int i = 0; i < model.NumSegments() && 3 * i + 2 < model.rest_curvatures.size(); ++i) {
    turning += model.rest_curvatures.segment<3>(3 * i).norm() * model.segment_lengths[i];
  }
  return turning;
}

bool IsValid(const StrandModel& model, std::string* why) {
  const int n = model.NumSegments();
  if (n < 1 || n > kMaxSegments) {
    if (why) *why = "segments must be between 1 and " + std::to_string(kMaxSegments);
    return false;
  }
  for (double l : model.segment_lengths) {
    if (!(std::isfinite(l) && l > 0.0)) {
      if (why) *why = "segment lengths must be finite and > 0 (m)";
      return false;
    }
  }
  if (!IsValid(model.section, why)) return false;
  if (!IsValid(model.material, why)) return false;
  if (!model.natural_curvature.allFinite()) {
    if (why) *why = "natural curvature and twist must be finite (1/m)";
    return false;
  }
  if (model.rest_curvatures.size() != 0) {
    if (model.rest_curvatures.size() != 3 * static_cast<Eigen::Index>(n)) {
      if (why) {
        *why = "rest curvatures must be empty or 3 per segment (" + std::to_string(3 * n) +
               " numbers), got " + std::to_string(model.rest_curvatures.size());
      }
      return false;
    }
    for (Eigen::Index j = 0; j < model.rest_curvatures.size(); ++j) {
      if (!std::isfinite(model.rest_curvatures(j))) {
        if (why) {
          *why = "rest curvatures of segment " + std::to_string(j / 3) + " must be finite (1/m)";
        }
        return false;
      }
    }
  }
  if (!(NaturalTurning(model) <= kMaxNaturalTurning)) {
    if (why) {
      *why = "natural curvature and twist times length must be at most " +
             std::to_string(static_cast<long>(kMaxNaturalTurning)) + " rad, got " +
             std::to_string(NaturalTurning(model)) + " rad";
    }
    return false;
  }
  if (!model.root_position.allFinite()) {
    if (why) *why = "root position must be finite (m)";
    return false;
  }
  if (!model.gravity.allFinite()) {
    if (why) *why = "gravity must be finite (m/s^2)";
    return false;
  }
  const Mat3& q = model.root_frame;
  if (!q.allFinite() || (q.transpose() * q - Mat3::Identity()).norm() > 1e-9 ||
      q.determinant() < 0.0) {
    if (why) *why = "root frame must be a proper rotation (n1 x n2 = t)";
    return false;
  }
  const ContactModel& c = model.contact;
  if (!(std::isfinite(c.clearance) && c.clearance >= 0.0)) {
    if (why) *why = "contact clearance must be finite and >= 0 (m)";
    return false;
  }
  if (!(std::isfinite(c.stiffness) && c.stiffness >= 0.0)) {
    if (why) *why = "contact stiffness must be finite and >= 0 (N/m^2; 0 = default)";
    return false;
  }
  if (c.samples_per_segment < 1 || c.samples_per_segment > 64) {
    if (why) *why = "contact samples per segment must be between 1 and 64";
    return false;
  }
  if (!c.support_offsets.empty()) {
    const size_t samples =
        static_cast<size_t>(model.NumSegments()) * static_cast<size_t>(c.samples_per_segment);
    if (c.support_offsets.size() != samples) {
      if (why) {
        *why = "contact support offsets: expected " + std::to_string(samples) +
               " (one per contact sample) or none, got " + std::to_string(c.support_offsets.size());
      }
      return false;
    }
    for (double x : c.support_offsets) {
      if (!std::isfinite(x)) {
        if (why) *why = "contact support offsets must be finite (m)";
        return false;
      }
    }
  }
  return true;
}

}  // namespace ringlet
