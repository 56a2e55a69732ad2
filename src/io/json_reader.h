// Reading JSON documents with one-line errors that name the field (private to io/).
//
// Every field is checked where it is read, so that an error names the field, what was expected
// and what was found, in one line: "strands[2].radius: expected a finite number > 0 (metres),
// got -1". Shared by the scene, body and hairstyle readers.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "ringlet/statics.h"

namespace ringlet::internal {

using nlohmann::json;

// Values quoted in error messages are cut to this many characters.
constexpr size_t kMaxShownCharacters = 60;
// A path in a message is at most this long: a longer one (64 levels of 60-character keys reach
// ~4 KB) keeps its start and its end, the part nearest the value, around "...".
constexpr size_t kMaxShownPath = 400;
// nlohmann's own messages (which quote the text read) are cut to this many characters.
constexpr size_t kMaxMessage = 200;
// Unknown fields this close (edit distance) to a known one get a "did you mean" hint.
constexpr size_t kSuggestionDistance = 2;
// Deepest nesting of arrays and objects in any JSON file ringlet reads (the top-level object is
// depth 1; the deepest real file, a hairstyle with a cut plane, has depth 6). Checked while
// parsing, so no deeper document is ever built (docs/robustness.md).
constexpr int kMaxJsonDepth = 64;
// Largest integer a JSON integer field may hold exactly (seeds): 2^53.
constexpr std::uint64_t kMaxExactInteger = std::uint64_t{1} << 53;
// Integral numbers written with a fraction or an exponent ("15.0", "1e3") are accepted as
// integers only below this bound, where no float literal of a few digits rounds onto an integer
// it does not denote; larger integers must be written as digits.
constexpr double kMaxFloatInteger = 2147483648.0;  // 2^31

// Keys made of letters, digits and underscores are shown bare; others are quoted.
bool IsPlainKey(const std::string& key);
// The path of a member: "strands[0]" + "radius" -> "strands[0].radius"; odd keys are quoted
// (escaped, ASCII only) so that a message always stays on one line: strands[0]["a\nb"].
// Paths stay within kMaxShownPath bytes (both functions).
std::string Member(const std::string& path, const std::string& key);
// The path of an array element: "strands" + 2 -> "strands[2]".
std::string Element(const std::string& path, size_t index);
// text cut to at most max_bytes, at a UTF-8 character boundary, marked with "...".
std::string Truncate(std::string text, size_t max_bytes);
// A value as quoted in a message: compact JSON, ASCII only, cut to kMaxShownCharacters. Walks
// the value iteratively and stops once enough is written, so that any value (deep, long or
// large) costs O(kMaxShownCharacters) time and no recursion.
std::string Show(const json& value);
// Levenshtein distance, for "did you mean" hints on misspelt fields.
size_t EditDistance(const std::string& a, const std::string& b);
// "line L, column C" of the 1-based byte position in text.
std::string LineColumnText(const std::string& text, size_t byte);

// Parses text into *document, refusing duplicate members and nesting deeper than kMaxJsonDepth;
// on failure *error gets one line with the position ("line 3, column 14: invalid JSON: ...") or
// the path of the duplicate or of the too deep value. Never throws.
bool ParseJsonText(const std::string& text, json* document, std::string* error);

// What a number field accepts: always finite, and in range by accepts(); expected describes
// both, with the unit, for messages ("a finite number > 0 (metres)").
struct NumberRule {
  const char* expected;
  bool (*accepts)(double);
};

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
        // The distance is at least the difference of the lengths: skip what cannot be close
        // (and a huge key's quadratic cost).
        const size_t length = std::char_traits<char>::length(k);
        if ((key.size() > length ? key.size() - length : length - key.size()) >
            kSuggestionDistance) {
          continue;
        }
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
    // The field's path is built only for a message: the valid case allocates nothing.
    if (it == object.end()) {
      if (required) return Missing(Member(path, key), rule.expected);
      return true;
    }
    if (!it->is_number()) return Expected(Member(path, key), rule.expected, *it);
    const double x = it->get<double>();
    if (!std::isfinite(x) || !rule.accepts(x)) {
      return Expected(Member(path, key), rule.expected, *it);
    }
    *out = x;
    if (present) *present = true;
    return true;
  }

  // An integer field in [min, max]; 15 and 15.0 are both accepted, 15.5 is not.
  bool ReadInteger(const json& object, const std::string& path, const char* key, int min, int max,
                   int* out, bool* present = nullptr) {
    if (present) *present = false;
    const auto it = object.find(key);
    if (it == object.end()) return true;
    std::int64_t value = 0;
    if (!ExactInteger(*it, &value) || value < min || value > max) {
      return Expected(Member(path, key),
                      "an integer between " + std::to_string(min) + " and " + std::to_string(max),
                      *it);
    }
    *out = static_cast<int>(value);
    if (present) *present = true;
    return true;
  }

  // An unsigned integer field in [0, max] (max <= kMaxExactInteger), read as an integer: a
  // value the file states but a double cannot hold (2^53 + 1) is refused, never rounded.
  bool ReadUnsigned(const json& object, const std::string& path, const char* key, std::uint64_t max,
                    const char* max_text, std::uint64_t* out) {
    const auto it = object.find(key);
    if (it == object.end()) return true;
    const std::string expected = std::string("an integer between 0 and ") + max_text;
    std::int64_t value = 0;
    if (!ExactInteger(*it, &value) || value < 0 || static_cast<std::uint64_t>(value) > max) {
      return Expected(Member(path, key), expected, *it);
    }
    *out = static_cast<std::uint64_t>(value);
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
    const auto fail = [&] {
      const std::string expected =
          "an array of " + std::to_string(N) + " finite numbers (" + unit + ")";
      return it == object.end() ? Missing(Member(path, key), expected)
                                : Expected(Member(path, key), expected, *it);
    };
    if (it == object.end()) return required ? fail() : true;
    if (!it->is_array() || it->size() != static_cast<size_t>(N)) return fail();
    Eigen::Matrix<double, N, 1> v;
    for (int i = 0; i < N; ++i) {
      const json& element = (*it)[static_cast<size_t>(i)];
      if (!element.is_number() || !std::isfinite(element.get<double>())) return fail();
      v(i) = element.get<double>();
    }
    *out = v;
    return true;
  }

  // An optional array field: absent gives nullptr, a non-array is an error.
  bool ReadArray(const json& object, const std::string& path, const char* key, const char* expected,
                 const json** out) {
    *out = nullptr;
    const auto it = object.find(key);
    if (it == object.end()) return true;
    if (!it->is_array()) return Expected(Member(path, key), expected, *it);
    *out = &*it;
    return true;
  }

  bool Missing(const std::string& field, const std::string& expected) {
    return Fail(field, "missing required field (expected " + expected + ")");
  }

  bool Expected(const std::string& field, const std::string& expected, const json& got) {
    return Fail(field, "expected " + expected + ", got " + Show(got));
  }

  // The exact integer value of a JSON number: integer literals as they are (within int64),
  // integral float literals ("15.0", "1e3") below kMaxFloatInteger. False otherwise.
  static bool ExactInteger(const json& value, std::int64_t* out) {
    if (value.is_number_unsigned()) {
      const std::uint64_t u = value.get<std::uint64_t>();
      if (u > static_cast<std::uint64_t>(INT64_MAX)) return false;
      *out = static_cast<std::int64_t>(u);
      return true;
    }
    if (value.is_number_integer()) {
      *out = value.get<std::int64_t>();
      return true;
    }
    if (!value.is_number_float()) return false;
    const double x = value.get<double>();
    if (!(std::abs(x) < kMaxFloatInteger) || x != std::floor(x)) return false;
    *out = static_cast<std::int64_t>(x);
    return true;
  }

 private:
  std::string error_;
};

// The optional "solver" member of parent ({"method", "tolerance", "max_iterations",
// "check_stability"}) into *options (defined with the scene reader, docs/scene-format.md).
bool ParseSolverObject(Reader& reader, const json& parent, const std::string& parent_path,
                       SolveOptions* options);

/// An optional object member parent[key]: *out is null when absent; an error naming
/// parent_path.key when present but not an object.
bool OptionalObject(Reader& reader, const json& parent, const std::string& parent_path,
                    const char* key, const json** out);

}  // namespace ringlet::internal
