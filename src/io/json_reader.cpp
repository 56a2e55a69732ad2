// Reading JSON documents with one-line errors that name the field.
#include "io/json_reader.h"

#include <simdjson.h>

#include <algorithm>
#include <cstdint>
#include <set>
#include <string_view>
#include <utility>
#include <vector>

namespace ringlet::internal {
namespace {

// The path of the first duplicate member in a document, found while parsing (nlohmann keeps the
// last of duplicate members silently; a scene must not). Called for every token of a scene, so
// it allocates little: frames are reused from one object to the next, and an object's keys are
// searched linearly while they are few (a strand has at most 15) and in a set beyond that.
class DuplicateFinder {
 public:
  bool OnEvent(json::parse_event_t event, const json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
        BeginElement();
        Push(false);
        break;
      case json::parse_event_t::array_start:
        BeginElement();
        Push(true);
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        if (depth_ > 0) --depth_;
        break;
      case json::parse_event_t::key:
        if (parsed.is_string()) Key(parsed.get_ref<const std::string&>());
        break;
      case json::parse_event_t::value:
        BeginElement();
        break;
    }
    return true;  // keep every value
  }

  // A member's key (the key event, without wrapping the name in a json value: that would cost
  // a heap string per key, a tenth of the parse of a scene).
  void Key(const std::string& name) {
    if (depth_ == 0) return;
    Frame& top = stack_[depth_ - 1];
    top.key = name;
    if (!top.Insert(top.key) && duplicate_.empty()) duplicate_ = Path();
  }

  // Empty when there is no duplicate.
  const std::string& duplicate() const { return duplicate_; }

  // The path of the value being parsed when the parse stopped: the member after the last key,
  // or the next element of an array.
  std::string PendingPath() const {
    std::string path;
    for (size_t i = 0; i < depth_; ++i) {
      const Frame& frame = stack_[i];
      const bool last = i + 1 == depth_;
      path = frame.is_array ? Element(path, frame.next_index - (last ? 0 : 1))
                            : Member(path, frame.key);
    }
    return path;
  }

 private:
  // Keys of an object searched one by one up to this many, then in a set.
  static constexpr size_t kLinearKeys = 32;

  struct Frame {
    bool is_array = false;
    size_t next_index = 0;          // arrays: index of the next element
    std::string key;                // objects: the current member
    std::vector<std::string> keys;  // objects: the members so far, while few
    std::set<std::string> many;     // objects: all members, once there are many

    // Records key; false when the object already has it.
    bool Insert(const std::string& k) {
      if (many.empty()) {
        if (std::find(keys.begin(), keys.end(), k) != keys.end()) return false;
        if (keys.size() < kLinearKeys) {
          keys.push_back(k);
          return true;
        }
        many.insert(keys.begin(), keys.end());
        keys.clear();
      }
      return many.insert(k).second;
    }
  };

  void Push(bool is_array) {
    if (depth_ == stack_.size()) stack_.emplace_back();
    Frame& frame = stack_[depth_++];
    frame.is_array = is_array;
    frame.next_index = 0;
    frame.key.clear();
    frame.keys.clear();  // keeps the capacity for the next object at this depth
    frame.many.clear();
  }

  void BeginElement() {
    if (depth_ > 0 && stack_[depth_ - 1].is_array) ++stack_[depth_ - 1].next_index;
  }

  std::string Path() const {
    std::string path;
    for (size_t i = 0; i < depth_; ++i) {
      const Frame& frame = stack_[i];
      path = frame.is_array ? Element(path, frame.next_index - 1) : Member(path, frame.key);
    }
    return path;
  }

  std::vector<Frame> stack_;  // frames [0, depth_) are open; later ones are kept for reuse
  size_t depth_ = 0;
  std::string duplicate_;
};

// Thrown by the parser callback to stop at a container nested deeper than kMaxJsonDepth, with
// the path of the container.
struct TooDeep {
  std::string path;
};

}  // namespace

// ---------------------------------------------------------------------------------------------
// Paths and values in messages.

// Keys made of letters, digits and underscores are shown bare; others are quoted.
bool IsPlainKey(const std::string& key) {
  if (key.empty()) return false;
  return std::all_of(key.begin(), key.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  });
}

namespace {

// Paths are ASCII (keys are escaped), so any byte is a character boundary. The first third of
// the budget keeps the path's start, the rest its end; cutting again an already cut path keeps
// its start, so deep paths stay bounded level after level.
constexpr size_t kPathHead = kMaxShownPath / 3;
constexpr const char* kPathCut = "...";

std::string BoundPath(std::string path) {
  if (path.size() <= kMaxShownPath) return path;
  const size_t tail = kMaxShownPath - kPathHead - 3;
  return path.substr(0, kPathHead) + kPathCut + path.substr(path.size() - tail);
}

}  // namespace

// The path of a member: "strands[0]" + "radius" -> "strands[0].radius"; odd keys are quoted
// (escaped, ASCII only) so that a message always stays on one line: strands[0]["a\nb"].
std::string Member(const std::string& path, const std::string& key) {
  // A key of any length is shown cut to kMaxShownCharacters (marked with "...", and then always
  // quoted), and the whole path to kMaxShownPath, so that a path, too, stays short whatever the
  // file holds.
  if (key.size() > kMaxShownCharacters) {
    return BoundPath(path + "[" +
                     Truncate(json(Truncate(key, kMaxShownCharacters))
                                  .dump(-1, ' ', true, json::error_handler_t::replace),
                              kMaxShownCharacters + 8) +
                     "]");
  }
  if (IsPlainKey(key)) return BoundPath(path.empty() ? key : path + "." + key);
  return BoundPath(path + "[" + json(key).dump(-1, ' ', true, json::error_handler_t::replace) +
                   "]");
}

// The path of an array element: "strands" + 2 -> "strands[2]".
std::string Element(const std::string& path, size_t index) {
  return BoundPath(path + "[" + std::to_string(index) + "]");
}

// text cut to at most max_bytes, at a UTF-8 character boundary, marked with "...".
std::string Truncate(std::string text, size_t max_bytes) {
  if (text.size() <= max_bytes) return text;
  size_t cut = max_bytes - 3;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;
  return text.substr(0, cut) + "...";
}

namespace {

// A scalar (or an empty container) as compact ASCII JSON; a string is cut to max_bytes first, so
// that a huge string costs no more than a short one.
std::string ScalarText(const json& value, size_t max_bytes) {
  if (value.is_string()) {
    const std::string& text = value.get_ref<const std::string&>();
    const std::string cut =
        Truncate(text.substr(0, std::min(text.size(), max_bytes + 4)), max_bytes);
    return json(cut).dump(-1, ' ', true, json::error_handler_t::replace);
  }
  if (value.is_object()) return "{}";
  if (value.is_array()) return "[]";
  return value.dump(-1, ' ', true, json::error_handler_t::replace);
}

}  // namespace

// A value as quoted in a message: compact JSON, ASCII only (control characters escaped), cut to
// kMaxShownCharacters. Containers are walked with an explicit stack (never recursively: a
// document may be deeply nested) and the walk stops as soon as the text is long enough.
std::string Show(const json& value) {
  const size_t budget = kMaxShownCharacters + 1;  // one more: Truncate then marks the cut
  struct Frame {
    const json* container;
    json::const_iterator next;
    bool first;
  };
  std::vector<Frame> stack;
  std::string out;
  auto open = [&](const json& v) {
    if ((v.is_object() || v.is_array()) && !v.empty()) {
      out += v.is_object() ? '{' : '[';
      stack.push_back(Frame{&v, v.cbegin(), true});
    } else {
      out += ScalarText(v, budget);
    }
  };
  open(value);
  while (!stack.empty() && out.size() < budget) {
    Frame& top = stack.back();
    if (top.next == top.container->cend()) {
      out += top.container->is_object() ? '}' : ']';
      stack.pop_back();
      continue;
    }
    if (!top.first) out += ',';
    top.first = false;
    if (top.container->is_object()) out += ScalarText(json(top.next.key()), budget) + ':';
    const json& child = *top.next;
    ++top.next;
    open(child);  // may push: top is not used after this
  }
  if (!stack.empty()) out += "...";  // cut inside a container: Truncate below marks it
  return Truncate(out, kMaxShownCharacters);
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

namespace {

// A SAX handler that builds the document with nlohmann's own DOM builder and, on the way, finds
// duplicate members (DuplicateFinder) and stops at containers nested deeper than kMaxJsonDepth.
// nlohmann's callback parser (json::parse with a callback) would give the depth too, but after
// every object it scans the enclosing array for discarded values: quadratic in the length of an
// array of objects (a 64-MiB "[{},{},...]" took hours).
class CheckedDomBuilder {
 public:
  explicit CheckedDomBuilder(json* document) : dom_(*document, /*allow_exceptions=*/true) {}

  const DuplicateFinder& duplicates() const { return finder_; }

  bool null() { return Value() && dom_.null(); }
  bool boolean(bool value) { return Value() && dom_.boolean(value); }
  bool number_integer(json::number_integer_t value) {
    return Value() && dom_.number_integer(value);
  }
  bool number_unsigned(json::number_unsigned_t value) {
    return Value() && dom_.number_unsigned(value);
  }
  bool number_float(json::number_float_t value, const json::string_t& text) {
    return Value() && dom_.number_float(value, text);
  }
  bool string(json::string_t& value) { return Value() && dom_.string(value); }
  bool binary(json::binary_t& value) { return Value() && dom_.binary(value); }
  bool start_object(std::size_t size) {
    Open(json::parse_event_t::object_start);
    return dom_.start_object(size);
  }
  bool key(json::string_t& name) {
    finder_.Key(name);
    return dom_.key(name);
  }
  bool end_object() {
    Close(json::parse_event_t::object_end);
    return dom_.end_object();
  }
  bool start_array(std::size_t size) {
    Open(json::parse_event_t::array_start);
    return dom_.start_array(size);
  }
  bool end_array() {
    Close(json::parse_event_t::array_end);
    return dom_.end_array();
  }
  template <class Exception>
  bool parse_error(std::size_t position, const std::string& token, const Exception& e) {
    return dom_.parse_error(position, token, e);  // throws e
  }

 private:
  bool Value() { return finder_.OnEvent(json::parse_event_t::value, kNull); }
  void Open(json::parse_event_t event) {
    // The top-level container is level 1.
    if (depth_ >= kMaxJsonDepth) throw TooDeep{finder_.PendingPath()};
    ++depth_;
    finder_.OnEvent(event, kNull);
  }
  void Close(json::parse_event_t event) {
    --depth_;
    finder_.OnEvent(event, kNull);
  }

  inline static const json kNull;
  nlohmann::detail::json_sax_dom_parser<json> dom_;
  DuplicateFinder finder_;
  int depth_ = 0;
};

// Hands a document that simdjson has parsed and validated to a SAX handler as nlohmann's own
// parser would: the same events in the same order (members in file order, duplicates included;
// an integer literal >= 0 as unsigned, < 0 as signed, anything with a fraction or an exponent as
// a double). Recursion is bounded: the handler stops at kMaxJsonDepth.
template <class Handler>
void Replay(simdjson::dom::element element, Handler* handler) {
  using simdjson::dom::element_type;
  constexpr std::size_t kUnknownSize = static_cast<std::size_t>(-1);  // as from JSON text
  // The type is known, so each get_*() below succeeds (value_unsafe skips the error check);
  // containers are copied out of the temporary result before they are iterated.
  switch (element.type()) {
    case element_type::ARRAY: {
      const simdjson::dom::array array = element.get_array().value_unsafe();
      handler->start_array(kUnknownSize);
      for (const simdjson::dom::element child : array) Replay(child, handler);
      handler->end_array();
      return;
    }
    case element_type::OBJECT: {
      const simdjson::dom::object object = element.get_object().value_unsafe();
      handler->start_object(kUnknownSize);
      for (const simdjson::dom::key_value_pair member : object) {
        json::string_t key(member.key);
        handler->key(key);
        Replay(member.value, handler);
      }
      handler->end_object();
      return;
    }
    case element_type::INT64: {
      const std::int64_t value = element.get_int64().value_unsafe();
      if (value >= 0) {
        handler->number_unsigned(static_cast<json::number_unsigned_t>(value));
      } else {
        handler->number_integer(value);
      }
      return;
    }
    case element_type::UINT64: {
      handler->number_unsigned(element.get_uint64().value_unsafe());
      return;
    }
    case element_type::DOUBLE: {
      static const json::string_t kNoText;  // nlohmann's DOM builder ignores the literal
      handler->number_float(element.get_double().value_unsafe(), kNoText);
      return;
    }
    case element_type::STRING: {
      json::string_t value(element.get_string().value_unsafe());
      handler->string(value);
      return;
    }
    case element_type::BOOL: {
      handler->boolean(element.get_bool().value_unsafe());
      return;
    }
    case element_type::NULL_VALUE:
      handler->null();
      return;
  }
}

// simdjson's parse and the replay take 1.3 µs per strand of a scene where nlohmann's own parse
// takes 2.1 (BM_ParseJsonText, BM_ParseJsonOnly; docs/benchmarks.md, "CLI overhead"; the nlohmann
// document built by the replay is most of what is left). It is never more lenient:
// everything it accepts nlohmann accepts with the same values, and it refuses some documents
// nlohmann takes (a byte-order mark, integers beyond 64 bits, nesting beyond 1024), so any
// refusal goes back to nlohmann's parser, whose messages (position, cause) are the ones users
// see. Tested in tests/scene_json_test.cpp, JsonReader.SimdjsonAndNlohmannAgree.
bool FastParse(const std::string& text, CheckedDomBuilder* builder) {
  simdjson::dom::parser parser;
  simdjson::dom::element root;
  if (parser.parse(text.data(), text.size()).get(root) != simdjson::SUCCESS) return false;
  Replay(root, builder);
  return true;
}

}  // namespace

bool ParseJsonText(const std::string& text, nlohmann::json* out, std::string* error) {
  json document;
  CheckedDomBuilder builder(&document);
  const DuplicateFinder& duplicates = builder.duplicates();
  try {
    // simdjson refuses before any event, so a refusal leaves the builder untouched.
    if (!FastParse(text, &builder)) {
      json::sax_parse(text, &builder, json::input_format_t::json, /*strict=*/true,
                      /*ignore_comments=*/false);
    }
  } catch (const TooDeep& e) {
    if (error) {
      const std::string message = "invalid JSON: arrays and objects nested deeper than " +
                                  std::to_string(kMaxJsonDepth) + " levels (the limit)";
      *error = e.path.empty() ? message : Truncate(e.path, kMaxMessage) + ": " + message;
    }
    return false;
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
  *out = std::move(document);
  return true;
}

// An optional object member: null when absent, an error when not an object.
bool OptionalObject(Reader& reader, const json& parent, const std::string& parent_path,
                    const char* key, const json** out) {
  *out = nullptr;
  const auto it = parent.find(key);
  if (it == parent.end()) return true;
  if (!it->is_object()) return reader.Expected(Member(parent_path, key), "an object", *it);
  *out = &*it;
  return true;
}

}  // namespace ringlet::internal
