// Scene files: JSON -> validated StrandModels and SolveOptions (docs/scene-format.md).
//
// Every field is checked where it is read, so that an error names the field, what was expected
// and what was found, in one line: "strands[2].radius: expected a finite number > 0 (metres),
// got -1". The model's own IsValid runs last as a safety net.
#include "ringlet/scene_json.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <set>
#include <utility>

#include "ringlet/atomic_file.h"
#include "ringlet/cross_section.h"
#include "ringlet/material.h"
#include "io/body_member.h"
#include "io/json_reader.h"

namespace ringlet {
namespace {

using nlohmann::json;
using internal::Member;
using internal::Element;
using internal::Show;
using internal::NumberRule;
using internal::Reader;

// Largest iteration budget a scene may ask for; more is almost certainly a typo.
constexpr int kMaxIterationsLimit = 1000000000;
// The scene's minimization methods, by their names in scene files.
struct MethodEntry {
  const char* name;
  Method method;
};
constexpr MethodEntry kMethods[] = {
    {"bfgs", Method::kBfgs},
    {"lbfgs", Method::kLbfgs},
    {"newton", Method::kNewton},
    {"auto", Method::kAuto},
};

// ---------------------------------------------------------------------------------------------
// Typed field readers. Each returns false after recording "path: message" in the reader.

constexpr NumberRule kLengthRule{"a finite number > 0 (metres)", [](double x) { return x > 0.0; }};
constexpr NumberRule kModulusRule{"a finite number > 0 (pascals)",
                                  [](double x) { return x > 0.0; }};
constexpr NumberRule kPoissonRule{"a finite number in (-1, 0.5]",
                                  [](double x) { return x > -1.0 && x <= 0.5; }};
constexpr NumberRule kDensityRule{"a finite number >= 0 (kg/m^3)",
                                  [](double x) { return x >= 0.0; }};
constexpr NumberRule kEccentricityRule{"a finite number in [0, 1)",
                                       [](double x) { return x >= 0.0 && x < 1.0; }};
constexpr NumberRule kEllipticityRule{"a finite number >= 1 (the ratio a/b of the semi-axes)",
                                      [](double x) { return x >= 1.0; }};
constexpr NumberRule kTwistRule{"a finite number (1/metre)", [](double) { return true; }};
constexpr NumberRule kGradingRule{"a finite number >= 1 (last/first segment length) or \"auto\"",
                                  [](double x) { return x >= 1.0; }};
constexpr NumberRule kToleranceRule{"a finite number in (0, 1)",
                                    [](double x) { return x > 0.0 && x < 1.0; }};

// ---------------------------------------------------------------------------------------------
// The scene's objects.

// root: {"position", "tangent", "normal"}, all required; n1 is the normal orthogonalized
// against the tangent.
bool ParseRoot(Reader& reader, const json& strand, const std::string& strand_path,
               StrandModel* model) {
  const std::string path = Member(strand_path, "root");
  const char* expected = "an object with position, tangent and normal";
  const auto it = strand.find("root");
  if (it == strand.end()) return reader.Missing(path, expected);
  const json& root = *it;
  if (!root.is_object()) return reader.Expected(path, expected, root);
  if (!reader.CheckFields(root, path, {"position", "tangent", "normal"})) return false;

  Vec3 position, tangent, normal;
  if (!reader.ReadVector<3>(root, path, "position", "metres", true, &position)) return false;
  if (!reader.ReadVector<3>(root, path, "tangent", "any length", true, &tangent)) return false;
  if (!reader.ReadVector<3>(root, path, "normal", "any length", true, &normal)) return false;
  // Each vector must have a finite, non-zero length (norm() can overflow for huge entries).
  const double tangent_norm = tangent.norm();
  if (!(std::isfinite(tangent_norm) && tangent_norm > 0.0)) {
    return reader.Expected(Member(path, "tangent"), "a non-zero vector of finite length",
                           root["tangent"]);
  }
  const double normal_norm = normal.norm();
  if (!(std::isfinite(normal_norm) && normal_norm > 0.0)) {
    return reader.Expected(Member(path, "normal"), "a non-zero vector of finite length",
                           root["normal"]);
  }
  std::string why;
  if (!RootFrameFromTangentNormal(tangent, normal, &model->root_frame, &why)) {
    // The tangent has passed its checks: what is left is the normal against the tangent.
    return reader.Fail(Member(path, "normal"), why + " (normal " + Show(root["normal"]) +
                                                   ", tangent " + Show(root["tangent"]) + ")");
  }
  model->root_position = position;
  return true;
}

// The optional per-segment rest shape (issue 13, StrandModel::rest_curvatures): one triple
// [kappa1^0, kappa2^0, tau^0] (1/m) per segment, after the segment layout is known.
bool ParseRestCurvatures(Reader& reader, const json& strand, const std::string& path,
                         StrandModel* model) {
  const int n = model->NumSegments();
  const std::string expected = "an array of " + std::to_string(n) +
                               " triples [kappa1, kappa2, tau] (1/metre), one per segment";
  const json* rest = nullptr;
  if (!reader.ReadArray(strand, path, "rest_curvatures", expected.c_str(), &rest)) return false;
  if (!rest) return true;
  const std::string field = Member(path, "rest_curvatures");
  if (rest->size() != static_cast<size_t>(n)) {
    return reader.Fail(field, "has " + std::to_string(rest->size()) + " entries, expected " +
                                  std::to_string(n) + " (one triple per segment)");
  }
  VecX values(3 * n);
  for (int i = 0; i < n; ++i) {
    const json& triple = (*rest)[static_cast<size_t>(i)];
    const char* triple_expected = "an array of 3 finite numbers [kappa1, kappa2, tau] (1/metre)";
    if (!triple.is_array() || triple.size() != 3) {
      return reader.Expected(Element(field, static_cast<size_t>(i)), triple_expected, triple);
    }
    for (int j = 0; j < 3; ++j) {
      const json& x = triple[static_cast<size_t>(j)];
      if (!x.is_number() || !std::isfinite(x.get<double>())) {
        return reader.Expected(Element(field, static_cast<size_t>(i)), triple_expected, triple);
      }
      values(3 * i + j) = x.get<double>();
    }
  }
  model->rest_curvatures = std::move(values);
  return true;
}
// What the scene still allows: segments left of kMaxTotalSegments, and the method (whose
// own limit, kMaxBfgsSegments for dense BFGS, holds per strand).
struct SegmentBudget {
  long remaining = kMaxTotalSegments;
  Method method = Method::kAuto;
};

// The segment layout: explicit segment_lengths, or `segments` graded by `grading` (uniform by
// default).
bool ParseSegments(Reader& reader, const json& strand, const std::string& path, double length,
                   const SegmentBudget& budget, StrandModel* model) {
  int segments = kDefaultSegments;
  bool has_segments = false;
  if (!reader.ReadInteger(strand, path, "segments", 1, kMaxSegments, &segments, &has_segments)) {
    return false;
  }
  // The limits on products, before anything is allocated for the segments: the method's limit
  // (dense BFGS) and the scene's total.
  const auto explicit_lengths = strand.find("segment_lengths");
  if (!has_segments && explicit_lengths != strand.end() && explicit_lengths->is_array() &&
      !explicit_lengths->empty()) {
    segments = static_cast<int>(std::min<size_t>(explicit_lengths->size(), kMaxSegments + 1));
  }
  const std::string segments_field =
      Member(path, has_segments || explicit_lengths == strand.end() ? "segments"
                                                                    : "segment_lengths");
  std::string why;
  if (segments <= kMaxSegments && !CheckMethodSegments(segments, budget.method, &why)) {
    return reader.Fail(segments_field, why);
  }
  if (static_cast<long>(segments) > budget.remaining) {
    return reader.Fail(segments_field,
                       std::to_string(segments) + " more segments would take the scene beyond " +
                           "its limit of " + std::to_string(kMaxTotalSegments) +
                           " segments in all strands");
  }
  double grading = 1.0;
  bool has_grading = false;
  const auto grading_it = strand.find("grading");
  if (grading_it != strand.end() && grading_it->is_string() && *grading_it == "auto") {
    // RecommendedGradingRatio from the load w L^3 / (E I1); section, material and gravity are
    // parsed before the segments for this.
    has_grading = true;
    const double ei = model->material.young_modulus * model->section.I1();
    const double w = model->material.density * model->section.Area() * model->gravity.norm();
    grading = RecommendedGradingRatio(w * length * length * length / ei);
  } else if (!reader.ReadNumber(strand, path, "grading", kGradingRule, false, &grading,
                                &has_grading)) {
    return false;
  }

  const auto it = strand.find("segment_lengths");
  if (it == strand.end()) {
    model->segment_lengths = GradedSegments(length, segments, grading);
    // An extreme grading, or a tiny length, can make a segment length underflow. The field to
    // blame is the grading when there is one, the length otherwise (read through find: an
    // absent member must never be indexed).
    for (double l : model->segment_lengths) {
      if (!(std::isfinite(l) && l > 0.0)) {
        const std::string counted = " for " + std::to_string(segments) +
                                    " segments: some segment lengths are not representable, got ";
        if (has_grading) {
          return reader.Fail(Member(path, "grading"),
                             "is too large" + counted + Show(*strand.find("grading")));
        }
        return reader.Fail(Member(path, "length"),
                           "is too small" + counted + Show(*strand.find("length")));
      }
    }
    return true;
  }

  const std::string field = Member(path, "segment_lengths");
  if (has_grading) {
    return reader.Fail(Member(path, "grading"),
                       "cannot be combined with segment_lengths (give one of them)");
  }
  const json& lengths = *it;
  const char* expected = "a non-empty array of finite numbers > 0 (metres)";
  if (!lengths.is_array() || lengths.empty()) return reader.Expected(field, expected, lengths);
  if (lengths.size() > static_cast<size_t>(kMaxSegments)) {
    return reader.Fail(field, "has " + std::to_string(lengths.size()) +
                                  " entries, more than the limit of " +
                                  std::to_string(kMaxSegments) + " segments");
  }
  std::vector<double> values;
  values.reserve(lengths.size());
  double sum = 0.0;
  for (size_t i = 0; i < lengths.size(); ++i) {
    const json& l = lengths[i];
    if (!l.is_number() || !std::isfinite(l.get<double>()) || !(l.get<double>() > 0.0)) {
      return reader.Expected(Element(field, i), kLengthRule.expected, l);
    }
    values.push_back(l.get<double>());
    sum += values.back();
  }
  if (has_segments && values.size() != static_cast<size_t>(segments)) {
    return reader.Fail(field, "has " + std::to_string(values.size()) + " entries but segments is " +
                                  std::to_string(segments));
  }
  if (!(std::abs(sum - length) <= kSegmentLengthSumTolerance * length)) {
    return reader.Fail(field, "sum to " + json(sum).dump() + " m but length is " +
                                  json(length).dump() +
                                  " m (they must agree within 1e-9 relative)");
  }
  model->segment_lengths = std::move(values);
  return true;
}

bool ParseStrand(Reader& reader, const json& strand, const std::string& path, const Vec3& gravity,
                 const SegmentBudget& budget, StrandModel* out) {
  if (!strand.is_object()) return reader.Expected(path, "a strand object", strand);
  if (!reader.CheckFields(strand, path,
                          {"length", "segments", "grading", "segment_lengths", "radius",
                           "eccentricity", "ellipticity", "young_modulus", "poisson_ratio",
                           "density", "natural_curvature", "natural_twist", "rest_curvatures",
                           "root"})) {
    return false;
  }
  StrandModel model;
  model.gravity = gravity;

  // Length (the segment layout comes after the material: "grading": "auto" needs the load).
  double length = 0.0;
  if (!reader.ReadNumber(strand, path, "length", kLengthRule, true, &length)) return false;

  // Cross-section: mean radius and one of eccentricity or ellipticity (circular by default).
  double radius = kDefaultRadius;
  double eccentricity = 0.0;
  double ellipticity = 1.0;
  bool has_eccentricity = false;
  bool has_ellipticity = false;
  if (!reader.ReadNumber(strand, path, "radius", kLengthRule, false, &radius) ||
      !reader.ReadNumber(strand, path, "eccentricity", kEccentricityRule, false, &eccentricity,
                         &has_eccentricity) ||
      !reader.ReadNumber(strand, path, "ellipticity", kEllipticityRule, false, &ellipticity,
                         &has_ellipticity)) {
    return false;
  }
  if (has_eccentricity && has_ellipticity) {
    return reader.Fail(Member(path, "ellipticity"),
                       "cannot be combined with eccentricity (give one of them)");
  }
  model.section = has_ellipticity ? SectionFromEllipticity(radius, ellipticity)
                                  : SectionFromEccentricity(radius, eccentricity);

  // Material (defaults are Material's: the paper's values).
  if (!reader.ReadNumber(strand, path, "young_modulus", kModulusRule, false,
                         &model.material.young_modulus) ||
      !reader.ReadNumber(strand, path, "poisson_ratio", kPoissonRule, false,
                         &model.material.poisson_ratio) ||
      !reader.ReadNumber(strand, path, "density", kDensityRule, false, &model.material.density)) {
    return false;
  }

  // Natural shape: (kappa1^0, kappa2^0) and tau^0.
  Eigen::Vector2d natural_curvature = Eigen::Vector2d::Zero();
  double natural_twist = 0.0;
  if (!reader.ReadVector<2>(strand, path, "natural_curvature", "1/metre", false,
                            &natural_curvature) ||
      !reader.ReadNumber(strand, path, "natural_twist", kTwistRule, false, &natural_twist)) {
    return false;
  }
  model.natural_curvature = Vec3(natural_curvature(0), natural_curvature(1), natural_twist);

  // Segment layout: uniform, graded (a ratio or "auto") or explicit lengths.
  if (!ParseSegments(reader, strand, path, length, budget, &model)) return false;
  // The natural turning bounds the Kirchhoff certificate's work (strand_model.h).
  const double turning = model.natural_curvature.norm() * length;
  if (!(turning <= kMaxNaturalTurning)) {
    char number[32];
    std::snprintf(number, sizeof(number), "%.6g", turning);  // "1e+06", "inf"
    return reader.Fail(Member(path, "natural_curvature"),
                       std::string("with natural_twist, turns the strand by ") + number +
                           " rad over its length, more than the limit of 1e+05 rad (|(kappa1, "
                           "kappa2, tau)| x length)");
  }

  if (!ParseRoot(reader, strand, path, &model)) return false;
  if (!ParseRestCurvatures(reader, strand, path, &model)) return false;

  // Safety net: whatever the field checks above missed, the model's own validation catches.
  std::string why;
  if (!IsValid(model, &why)) return reader.Fail(path, why);
  *out = std::move(model);
  return true;
}

// "contact": {"clearance": m}, only with a body (the penalty of contact.h).
constexpr internal::NumberRule kClearanceRule{"a finite number in [0, 0.1) (m)",
                                              [](double x) { return x >= 0.0 && x < 0.1; }};

bool ParseSceneDocument(Reader& reader, const json& document, const std::string& base_directory,
                        Scene* out) {
  if (!document.is_object()) {
    return reader.Expected("", "a JSON object {\"strands\": [...]} at the top level", document);
  }
  if (!reader.CheckFields(document, "", {"gravity", "strands", "solver", "body", "contact"})) {
    return false;
  }

  Vec3 gravity(0.0, 0.0, -9.81);
  if (!reader.ReadVector<3>(document, "", "gravity", "metres per second squared", false,
                            &gravity)) {
    return false;
  }

  const char* expected = "a non-empty array of strand objects";
  const auto strands = document.find("strands");
  if (strands == document.end()) return reader.Missing("strands", expected);
  if (!strands->is_array() || strands->empty()) {
    return reader.Expected("strands", expected, *strands);
  }
  Scene scene;
  // The body (optional) and its contact clearance.
  if (!internal::ParseBodyMember(reader, document, base_directory, false, &scene.body)) {
    return false;
  }
  double clearance = 0.0;
  const json* contact = nullptr;
  if (!internal::OptionalObject(reader, document, "", "contact", &contact)) return false;
  if (contact) {
    if (!scene.body) {
      return reader.Fail("contact", "needs a \"body\" to touch (docs/scene-format.md)");
    }
    if (!reader.CheckFields(*contact, "contact", {"clearance"}) ||
        !reader.ReadNumber(*contact, "contact", "clearance", kClearanceRule, false, &clearance)) {
      return false;
    }
  }
  // The solver first: its method limits the segments of every strand.
  if (!internal::ParseSolverObject(reader, document, "", &scene.solver)) return false;
  SegmentBudget budget;
  budget.method = scene.solver.method;
  // One model per strand as it is read, not strands->size() of them up front: a 64-MiB file of
  // "{}," would otherwise ask for 22 million models (~8 GB) before the first error.
  for (size_t i = 0; i < strands->size(); ++i) {
    StrandModel model;
    if (!ParseStrand(reader, (*strands)[i], Element("strands", i), gravity, budget, &model)) {
      return false;
    }
    budget.remaining -= model.NumSegments();
    if (scene.body) {
      model.contact.obstacle = scene.body;
      model.contact.clearance = clearance;
    }
    scene.strands.push_back(std::move(model));
  }
  *out = std::move(scene);
  return true;
}

}  // namespace

namespace internal {

bool ParseSolverObject(Reader& reader, const json& parent, const std::string& parent_path,
                       SolveOptions* options) {
  const auto it = parent.find("solver");
  if (it == parent.end()) return true;
  const std::string path = Member(parent_path, "solver");
  const json& solver = *it;
  if (!solver.is_object()) return reader.Expected(path, "an object", solver);
  if (!reader.CheckFields(solver, path,
                          {"method", "tolerance", "max_iterations", "check_stability"})) {
    return false;
  }
  const auto method = solver.find("method");
  if (method != solver.end()) {
    std::string names;
    for (const MethodEntry& entry : kMethods) {
      names += std::string(names.empty() ? "" : ", ") + "\"" + entry.name + "\"";
    }
    if (!method->is_string())
      return reader.Expected(Member(path, "method"), "one of " + names, *method);
    const auto entry = std::find_if(std::begin(kMethods), std::end(kMethods),
                                    [&](const MethodEntry& e) { return *method == e.name; });
    if (entry == std::end(kMethods)) {
      return reader.Expected(Member(path, "method"), "one of " + names, *method);
    }
    options->method = entry->method;
  }
  if (!reader.ReadNumber(solver, path, "tolerance", kToleranceRule, false, &options->tolerance) ||
      !reader.ReadInteger(solver, path, "max_iterations", 1, kMaxIterationsLimit,
                          &options->max_iterations) ||
      !reader.ReadBool(solver, path, "check_stability", &options->check_stability)) {
    return false;
  }
  std::string why;
  if (!options->IsValid(&why)) return reader.Fail(path, why);
  return true;
}

}  // namespace internal

const char* MethodName(Method method) {
  for (const MethodEntry& entry : kMethods) {
    if (entry.method == method) return entry.name;
  }
  return "unknown";
}

bool ParseScene(const nlohmann::json& document, Scene* scene, std::string* error) {
  return ParseScene(document, std::string(), scene, error);
}

bool ParseScene(const nlohmann::json& document, const std::string& base_directory, Scene* scene,
                std::string* error) {
  Reader reader;
  try {
    if (ParseSceneDocument(reader, document, base_directory, scene)) return true;
  } catch (const std::exception& e) {
    // Not expected (every access is type-checked first), but the library never throws.
    reader.Fail("", std::string("cannot read the scene: ") + e.what());
  }
  if (error) *error = reader.error();
  return false;
}

bool ParseSceneText(const std::string& text, Scene* scene, std::string* error) {
  json document;
  if (!internal::ParseJsonText(text, &document, error)) return false;
  return ParseScene(document, scene, error);
}

bool LoadScene(const std::string& path, Scene* scene, std::string* error) {
  std::string text;
  if (!ReadFile(path, &text, error)) return false;
  std::string why;
  json document;
  const std::string base = std::filesystem::path(path).parent_path().string();
  if (!internal::ParseJsonText(text, &document, &why) ||
      !ParseScene(document, base, scene, &why)) {
    if (error) *error = path + ": " + why;
    return false;
  }
  return true;
}

}  // namespace ringlet
