// Exact targets from ringlet's result files (result_targets.h).
#include "ringlet/result_targets.h"

#include <Eigen/SVD>
#include <cmath>

#include "io/json_reader.h"
#include "ringlet/atomic_file.h"
#include "ringlet/strand_geometry.h"
#include "ringlet/strand_model.h"

namespace ringlet {
namespace {

using internal::Element;
using internal::json;
using internal::Member;
using internal::Show;

// Points must lie on the rebuilt helix within this fraction of the strand length: the file's
// numbers are the shortest round-trip decimals, so the true mismatch is rounding (~1e-16 L).
constexpr double kPointTolerance = 1e-6;

bool Fail(std::string* why, const std::string& message) {
  if (why) *why = message;
  return false;
}

bool ReadTriples(const json& strand, const std::string& path, const char* key, bool required,
                 std::vector<Vec3>* out, std::string* why) {
  out->clear();
  const auto it = strand.find(key);
  if (it == strand.end()) {
    return required ? Fail(why, Member(path, key) + ": missing required field") : true;
  }
  if (!it->is_array()) {
    return Fail(why, Member(path, key) + ": expected an array of [x, y, z] triples, got " +
                         Show(*it));
  }
  for (size_t i = 0; i < it->size(); ++i) {
    const json& t = (*it)[i];
    bool ok = t.is_array() && t.size() == 3;
    Vec3 v;
    for (size_t j = 0; ok && j < 3; ++j) {
      ok = t[j].is_number() && std::isfinite(t[j].get<double>());
      if (ok) v(static_cast<int>(j)) = t[j].get<double>();
    }
    if (!ok) {
      return Fail(why, Element(Member(path, key), i) + ": expected 3 finite numbers, got " +
                           Show(t));
    }
    out->push_back(v);
  }
  return true;
}

bool ParseStrand(const json& strand, const std::string& path, ExactTarget* target,
                 std::string* why) {
  if (!strand.is_object()) {
    return Fail(why, path + ": expected a strand object, got " + Show(strand));
  }
  std::vector<Vec3> points, curvatures, rest;
  if (!ReadTriples(strand, path, "points", true, &points, why) ||
      !ReadTriples(strand, path, "curvatures", true, &curvatures, why) ||
      !ReadTriples(strand, path, "rest_curvatures", false, &rest, why)) {
    return false;
  }
  const int n = static_cast<int>(curvatures.size());
  if (n < 1 || n > kMaxSegments) {
    return Fail(why, Member(path, "curvatures") + ": expected 1 to " +
                         std::to_string(kMaxSegments) + " triples, got " + std::to_string(n));
  }
  const auto lengths = strand.find("segment_lengths");
  if (lengths == strand.end() || !lengths->is_array() ||
      lengths->size() != static_cast<size_t>(n)) {
    return Fail(why, Member(path, "segment_lengths") + ": expected " + std::to_string(n) +
                         " numbers > 0 (m), one per curvature triple");
  }
  StrandModel model;
  for (size_t i = 0; i < lengths->size(); ++i) {
    const json& l = (*lengths)[i];
    if (!l.is_number() || !(std::isfinite(l.get<double>()) && l.get<double>() > 0.0)) {
      return Fail(why, Element(Member(path, "segment_lengths"), i) +
                           ": expected a finite number > 0 (m), got " + Show(l));
    }
    model.segment_lengths.push_back(l.get<double>());
  }
  if (!rest.empty() && rest.size() != static_cast<size_t>(n)) {
    return Fail(why, Member(path, "rest_curvatures") + ": expected " + std::to_string(n) +
                         " triples, got " + std::to_string(rest.size()));
  }
  // points = n k + 1.
  if (points.size() < 2 || (points.size() - 1) % static_cast<size_t>(n) != 0) {
    return Fail(why, Member(path, "points") + ": expected n k + 1 points (n = " +
                         std::to_string(n) + " segments, k >= 1 per segment), got " +
                         std::to_string(points.size()));
  }
  const int k = static_cast<int>((points.size() - 1) / static_cast<size_t>(n));
  VecX q(3 * n);
  for (int i = 0; i < n; ++i) q.segment<3>(3 * i) = curvatures[static_cast<size_t>(i)];

  // The rebuilt centreline with the identity frame at the origin, and the rotation carrying it
  // onto the file's points (Kabsch).
  const std::vector<Vec3> local = SampleCentreline(model, q, k);
  Mat3 cross = Mat3::Zero();
  for (size_t j = 1; j < points.size(); ++j) {
    cross += local[j] * (points[j] - points[0]).transpose();
  }
  Eigen::JacobiSVD<Mat3> svd(cross, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Mat3 u = svd.matrixU(), v = svd.matrixV();
  Mat3 d = Mat3::Identity();
  d(2, 2) = (v * u.transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  Mat3 rotation = v * d * u.transpose();
  const Vec3 s = svd.singularValues();
  target->frame_from_file = s(1) > 1e-9 * s(0);
  if (!target->frame_from_file) {
    // Collinear (straight) strand: only the tangent is defined; keep a frame with that tangent.
    const Vec3 t = (points.back() - points[0]).normalized();
    Mat3 frame;
    const Vec3 helper = std::abs(t.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    frame.col(0) = (helper - t * t.dot(helper)).normalized();
    frame.col(1) = t.cross(frame.col(0));
    frame.col(2) = t;
    rotation = frame;
  }
  const double length = model.Length();
  for (size_t j = 1; j < points.size(); ++j) {
    const double distance = (points[0] + rotation * local[j] - points[j]).norm();
    if (!(distance <= kPointTolerance * length)) {
      return Fail(why, Element(Member(path, "points"), j) +
                           ": does not lie on the helix of the curvatures (" +
                           std::to_string(distance) + " m off, more than 1e-6 L)");
    }
  }
  target->root_position = points[0];
  target->root_frame = rotation;
  target->segment_lengths = std::move(model.segment_lengths);
  target->curvatures = std::move(q);
  target->rest_curvatures.resize(0);
  if (!rest.empty()) {
    target->rest_curvatures.resize(3 * n);
    for (int i = 0; i < n; ++i) {
      target->rest_curvatures.segment<3>(3 * i) = rest[static_cast<size_t>(i)];
    }
  }
  return true;
}

}  // namespace

bool ParseResultTargets(const std::string& text, std::vector<ExactTarget>* targets,
                        std::string* why) {
  json document;
  std::string error;
  if (!internal::ParseJsonText(text, &document, &error)) return Fail(why, error);
  if (!document.is_object() || !document.contains("strands") || !document["strands"].is_array()) {
    return Fail(why, "strands: expected a result document {\"strands\": [...]}");
  }
  const json& strands = document["strands"];
  if (strands.empty()) return Fail(why, "strands: expected at least one strand");
  std::vector<ExactTarget> out(strands.size());
  for (size_t i = 0; i < strands.size(); ++i) {
    if (!ParseStrand(strands[i], Element("strands", i), &out[i], why)) return false;
  }
  *targets = std::move(out);
  return true;
}

bool ReadResultTargets(const std::string& path, std::vector<ExactTarget>* targets,
                       std::string* why) {
  std::string text, error;
  if (!ReadFile(path, &text, &error)) return Fail(why, error);
  if (!ParseResultTargets(text, targets, &error)) return Fail(why, path + ": " + error);
  return true;
}

}  // namespace ringlet
