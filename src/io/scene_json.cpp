// Scene files: JSON -> validated StrandModels and SolveOptions (docs/scene-format.md).
//
// Every field is checked where it is read, so that an error names the field, what was expected
// and what was found, in one line: "strands[2].radius: expected a finite number > 0 (metres),
// got -1". The model's own IsValid runs last as a safety net.
#include "ringlet/scene_json.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <set>
#include <utility>

#include "ringlet/atomic_file.h"
#include "ringlet/cross_section.h"
#include "ringlet/material.h"

namespace ringlet {
namespace {

using nlohmann::json;

// Values quoted in error messages are cut to this many characters.
constexpr size_t kMaxShownCharacters = 60;
// nlohmann's own messages (which quote the text read) are cut to this many characters.
constexpr size_t kMaxMessage = 200;
// Largest iteration budget a scene may ask for; more is almost certainly a typo.
constexpr int kMaxIterationsLimit = 1000000000;
// Unknown fields this close (edit distance) to a known one get a "did you mean" hint.
constexpr size_t kSuggestionDistance = 2;

// The scene's minimization methods, by their names in scene files.
struct MethodEntry {
  const char* name;
  Method method;
};
constexpr MethodEntry kMethods[] = {
    {"bfgs", Method::kBfgs},
    {"lbfgs", Method::kLbfgs},
    {"newton", Method::kNewton},
};

// ---------------------------------------------------------------------------------------------
// Paths and values in messages.

// Keys made of letters, digits and underscores are shown bare; others are quoted.
bool IsPlainKey(const std::string& key) {
  if (key.empty()) return false;
  return std::all_of(key.begin(), key.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  });
}

// The path of a member: "strands[0]" + "radius" -> "strands[0].radius"; odd keys are quoted
// (escaped, ASCII only) so that a message always stays on one line: strands[0]["a\nb"].
std::string Member(const std::string& path, const std::string& key) {
  if (IsPlainKey(key)) return path.empty() ? key : path + "." + key;
  return path + "[" + json(key).dump(-1, ' ', true, json::error_handler_t::replace) + "]";
}

// The path of an array element: "strands" + 2 -> "strands[2]".
std::string Element(const std::string& path, size_t index) {
  return path + "[" + std::to_string(index) + "]";
}

// text cut to at most max_bytes, at a UTF-8 character boundary, marked with "...".
std::string Truncate(std::string text, size_t max_bytes) {
  if (text.size() <= max_bytes) return text;
  size_t cut = max_bytes - 3;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;
  return text.substr(0, cut) + "...";
}

// A value as quoted in a message: compact JSON, ASCII only (control characters escaped), cut to
// kMaxShownCharacters.
std::string Show(const json& value) {
  return Truncate(value.dump(-1, ' ', true, json::error_handler_t::replace), kMaxShownCharacters);
}

// Levenshtein distance, for "did you mean" hints on misspelt fields.
size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t substitution = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      diagonal = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitution});
    }
  }
  return row[b.size()];
}

// 1-based line and column (in characters, not bytes) of the character at 1-based byte position
// byte (nlohmann's parse_error::byte: the last byte read, the one that broke the parse).
void LineColumn(const std::string& text, size_t byte, size_t* line, size_t* column) {
  const size_t index = std::min(byte == 0 ? 0 : byte - 1, text.size());
  *line = 1;
  size_t line_start = 0;
  for (size_t i = 0; i < index; ++i) {
    if (text[i] == '\n') {
      ++*line;
      line_start = i + 1;
    }
  }
  // UTF-8 continuation bytes (10xxxxxx) do not start a character.
  *column = 1;
  for (size_t i = line_start; i < index; ++i) {
    if ((static_cast<unsigned char>(text[i]) & 0xC0) != 0x80) ++*column;
  }
}

std::string LineColumnText(const std::string& text, size_t byte) {
  size_t line = 0, column = 0;
  LineColumn(text, byte, &line, &column);
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

// ---------------------------------------------------------------------------------------------
// Typed field readers. Each returns false after recording "path: message" in the reader.

// What a number field accepts: always finite, and in range by accepts(); expected describes
// both, with the unit, for messages ("a finite number > 0 (metres)").
struct NumberRule {
  const char* expected;
  bool (*accepts)(double);
};

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

class Reader {
 public:
  const std::string& error() const { return error_; }

  // Records "path: message" (or just message at the top level) and returns false.
  bool Fail(const std::string& path, const std::string& message) {
    error_ = path.empty() ? message : path + ": " + message;
    return false;
  }

  // Every member of object must be one of known.
  bool CheckFields(const json& object, const std::string& path,
                   std::initializer_list<const char*> known) {
    for (const auto& item : object.items()) {
      const std::string& key = item.key();
      if (std::any_of(known.begin(), known.end(), [&](const char* k) { return key == k; })) {
        continue;
      }
      std::string hint;
      size_t best = kSuggestionDistance + 1;
      for (const char* k : known) {
        const size_t d = EditDistance(key, k);
        if (d < best) {
          best = d;
          hint = std::string(" (did you mean \"") + k + "\"?)";
        }
      }
      if (hint.empty()) {
        hint = " (known fields: ";
        for (const char* k : known) hint += std::string(k == *known.begin() ? "" : ", ") + k;
        hint += ")";
      }
      return Fail(Member(path, key), "unknown field" + hint);
    }
    return true;
  }

  // A number field; when absent, required is an error and otherwise *out keeps its default.
  bool ReadNumber(const json& object, const std::string& path, const char* key,
                  const NumberRule& rule, bool required, double* out, bool* present = nullptr) {
    if (present) *present = false;
    const auto it = object.find(key);
    const std::string field = Member(path, key);
    if (it == object.end()) {
      if (required) return Missing(field, rule.expected);
      return true;
    }
    if (!it->is_number()) return Expected(field, rule.expected, *it);
    const double x = it->get<double>();
    if (!std::isfinite(x) || !rule.accepts(x)) return Expected(field, rule.expected, *it);
    *out = x;
    if (present) *present = true;
    return true;
  }

  // An integer field in [min, max]; 15 and 15.0 are both accepted, 15.5 is not.
  bool ReadInteger(const json& object, const std::string& path, const char* key, int min, int max,
                   int* out, bool* present = nullptr) {
    if (present) *present = false;
    const auto it = object.find(key);
    const std::string field = Member(path, key);
    const std::string expected =
        "an integer between " + std::to_string(min) + " and " + std::to_string(max);
    if (it == object.end()) return true;
    if (!it->is_number()) return Expected(field, expected, *it);
    const double x = it->get<double>();
    if (!std::isfinite(x) || x != std::floor(x) || x < min || x > max) {
      return Expected(field, expected, *it);
    }
    *out = static_cast<int>(x);
    if (present) *present = true;
    return true;
  }

  bool ReadBool(const json& object, const std::string& path, const char* key, bool* out) {
    const auto it = object.find(key);
    if (it == object.end()) return true;
    if (!it->is_boolean()) return Expected(Member(path, key), "true or false", *it);
    *out = it->get<bool>();
    return true;
  }

  // A fixed-size array of finite numbers.
  template <int N>
  bool ReadVector(const json& object, const std::string& path, const char* key, const char* unit,
                  bool required, Eigen::Matrix<double, N, 1>* out) {
    const auto it = object.find(key);
    const std::string field = Member(path, key);
    const std::string expected =
        "an array of " + std::to_string(N) + " finite numbers (" + unit + ")";
    if (it == object.end()) {
      if (required) return Missing(field, expected);
      return true;
    }
    if (!it->is_array() || it->size() != static_cast<size_t>(N)) {
      return Expected(field, expected, *it);
    }
    Eigen::Matrix<double, N, 1> v;
    for (int i = 0; i < N; ++i) {
      const json& element = (*it)[static_cast<size_t>(i)];
      if (!element.is_number() || !std::isfinite(element.get<double>())) {
        return Expected(field, expected, *it);
      }
      v(i) = element.get<double>();
    }
    *out = v;
    return true;
  }

  bool Missing(const std::string& field, const std::string& expected) {
    return Fail(field, "missing required field (expected " + expected + ")");
  }

  bool Expected(const std::string& field, const std::string& expected, const json& got) {
    return Fail(field, "expected " + expected + ", got " + Show(got));
  }

 private:
  std::string error_;
};

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

// The segment layout: explicit segment_lengths, or `segments` graded by `grading` (uniform by
// default).
bool ParseSegments(Reader& reader, const json& strand, const std::string& path, double length,
                   StrandModel* model) {
  int segments = kDefaultSegments;
  bool has_segments = false;
  if (!reader.ReadInteger(strand, path, "segments", 1, kMaxSegments, &segments, &has_segments)) {
    return false;
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
    // An extreme grading can make the first segment underflow.
    for (double l : model->segment_lengths) {
      if (!(std::isfinite(l) && l > 0.0)) {
        return reader.Fail(Member(path, "grading"),
                           "is too large for " + std::to_string(segments) +
                               " segments: some segment lengths are not representable, got " +
                               Show(strand["grading"]));
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
                 StrandModel* out) {
  if (!strand.is_object()) return reader.Expected(path, "a strand object", strand);
  if (!reader.CheckFields(strand, path,
                          {"length", "segments", "grading", "segment_lengths", "radius",
                           "eccentricity", "ellipticity", "young_modulus", "poisson_ratio",
                           "density", "natural_curvature", "natural_twist", "root"})) {
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
  if (!ParseSegments(reader, strand, path, length, &model)) return false;

  if (!ParseRoot(reader, strand, path, &model)) return false;

  // Safety net: whatever the field checks above missed, the model's own validation catches.
  std::string why;
  if (!IsValid(model, &why)) return reader.Fail(path, why);
  *out = std::move(model);
  return true;
}

bool ParseSolver(Reader& reader, const json& document, SolveOptions* options) {
  const auto it = document.find("solver");
  if (it == document.end()) return true;
  const std::string path = "solver";
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

bool ParseSceneDocument(Reader& reader, const json& document, Scene* out) {
  if (!document.is_object()) {
    return reader.Expected("", "a JSON object {\"strands\": [...]} at the top level", document);
  }
  if (!reader.CheckFields(document, "", {"gravity", "strands", "solver"})) return false;

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
  scene.strands.resize(strands->size());
  for (size_t i = 0; i < strands->size(); ++i) {
    if (!ParseStrand(reader, (*strands)[i], Element("strands", i), gravity, &scene.strands[i])) {
      return false;
    }
  }
  if (!ParseSolver(reader, document, &scene.solver)) return false;
  *out = std::move(scene);
  return true;
}

// The path of the first duplicate member in a document, found while parsing (nlohmann keeps the
// last of duplicate members silently; a scene must not).
class DuplicateFinder {
 public:
  bool OnEvent(json::parse_event_t event, const json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
        BeginElement();
        stack_.push_back(Frame{false, 0, {}, {}});
        break;
      case json::parse_event_t::array_start:
        BeginElement();
        stack_.push_back(Frame{true, 0, {}, {}});
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        if (!stack_.empty()) stack_.pop_back();
        break;
      case json::parse_event_t::key:
        if (!stack_.empty() && parsed.is_string()) {
          Frame& top = stack_.back();
          top.key = parsed.get<std::string>();
          if (!top.keys.insert(top.key).second && duplicate_.empty()) duplicate_ = Path();
        }
        break;
      case json::parse_event_t::value:
        BeginElement();
        break;
    }
    return true;  // keep every value
  }

  // Empty when there is no duplicate.
  const std::string& duplicate() const { return duplicate_; }

  // The path of the value being parsed when the parse stopped: the member after the last key,
  // or the next element of an array.
  std::string PendingPath() const {
    std::string path;
    for (size_t i = 0; i < stack_.size(); ++i) {
      const Frame& frame = stack_[i];
      const bool last = i + 1 == stack_.size();
      path = frame.is_array ? Element(path, frame.next_index - (last ? 0 : 1))
                            : Member(path, frame.key);
    }
    return path;
  }

 private:
  struct Frame {
    bool is_array;
    size_t next_index;  // arrays: index of the next element
    std::string key;    // objects: the current member
    std::set<std::string> keys;
  };

  void BeginElement() {
    if (!stack_.empty() && stack_.back().is_array) ++stack_.back().next_index;
  }

  std::string Path() const {
    std::string path;
    for (const Frame& frame : stack_) {
      path = frame.is_array ? Element(path, frame.next_index - 1) : Member(path, frame.key);
    }
    return path;
  }

  std::vector<Frame> stack_;
  std::string duplicate_;
};

}  // namespace

const char* MethodName(Method method) {
  for (const MethodEntry& entry : kMethods) {
    if (entry.method == method) return entry.name;
  }
  return "unknown";
}

bool ParseScene(const nlohmann::json& document, Scene* scene, std::string* error) {
  Reader reader;
  try {
    if (ParseSceneDocument(reader, document, scene)) return true;
  } catch (const std::exception& e) {
    // Not expected (every access is type-checked first), but the library never throws.
    reader.Fail("", std::string("cannot read the scene: ") + e.what());
  }
  if (error) *error = reader.error();
  return false;
}

bool ParseSceneText(const std::string& text, Scene* scene, std::string* error) {
  json document;
  DuplicateFinder duplicates;
  try {
    document = json::parse(
        text,
        [&duplicates](int /*depth*/, json::parse_event_t event, json& parsed) {
          return duplicates.OnEvent(event, parsed);
        },
        /*allow_exceptions=*/true, /*ignore_comments=*/false);
  } catch (const json::parse_error& e) {
    // nlohmann's text is "[json.exception.parse_error.101] parse error at line 2, column 0:
    // syntax error ..."; keep the part after the position, which is recomputed from the byte
    // offset (nlohmann counts a newline as column 0 of the next line).
    std::string what = e.what();
    const size_t column = what.find("column ");
    const size_t colon = column == std::string::npos ? what.find("] ") : what.find(": ", column);
    if (colon != std::string::npos) what = what.substr(colon + 2);
    if (error) {
      *error = LineColumnText(text, e.byte) + ": invalid JSON: " + Truncate(what, kMaxMessage);
    }
    return false;
  } catch (const json::exception& e) {
    // Number overflow (out_of_range.406: "number overflow parsing '1e999'") carries no position:
    // the field is the value being parsed, the position that of the literal in the text.
    std::string what = e.what();
    const size_t bracket = what.find("] ");
    if (bracket != std::string::npos) what = what.substr(bracket + 2);
    const size_t open = what.find('\'');
    const size_t close = open == std::string::npos ? open : what.find('\'', open + 1);
    if (e.id != 406 || close == std::string::npos) {
      if (error) *error = "invalid JSON: " + Truncate(what, kMaxMessage);
      return false;
    }
    const std::string literal = what.substr(open + 1, close - open - 1);
    std::string message = "expected a finite number, got " +
                          Truncate(literal, kMaxShownCharacters) + " (beyond the range of a double";
    const size_t at = text.find(literal);
    if (at != std::string::npos) message += "; " + LineColumnText(text, at + 1);
    message += ")";
    const std::string path = duplicates.PendingPath();
    if (error) *error = path.empty() ? message : path + ": " + message;
    return false;
  } catch (const std::exception& e) {
    if (error) *error = std::string("cannot parse: ") + e.what();
    return false;
  }
  if (!duplicates.duplicate().empty()) {
    if (error) *error = duplicates.duplicate() + ": duplicate field (each field may appear once)";
    return false;
  }
  return ParseScene(document, scene, error);
}

bool LoadScene(const std::string& path, Scene* scene, std::string* error) {
  std::string text;
  if (!ReadFile(path, &text, error)) return false;
  std::string why;
  if (!ParseSceneText(text, scene, &why)) {
    if (error) *error = path + ": " + why;
    return false;
  }
  return true;
}

}  // namespace ringlet
