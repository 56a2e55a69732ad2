// A reader of the USD text format (.usda) restricted to what hair files need: linear BasisCurves
// prims with their points, counts, widths and colours, and the stage's metersPerUnit and upAxis.
// There is no USD library in Debian 12, so this follows the grammar of Pixar's text format
// (Sdf's textFileFormat lexer and parser: "#usda 1.0", layer metadata in parentheses, prims
// "def|over|class [Type] "name" (metadata) { ... }", properties "[custom] [uniform|varying]
// type[[]] name [= value] [(metadata)]", "name.timeSamples = { time: value, ... }", comments
// '#', '//' and '/* */') for the subset documented in docs/file-formats.md, and refuses what it
// cannot honour (composition arcs, transforms, other curve types) instead of reading it wrong.
// Memory is bounded by the text: every array grows one parsed element at a time, and nesting
// is limited to kMaxUsdaDepth.
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "io/strand_readers.h"

namespace ringlet::io_internal {
namespace {

// Nesting of brackets and prims (real files need < 10; Pixar's writer indents each level).
constexpr int kMaxUsdaDepth = 64;

enum class Kind { kEnd, kIdent, kNumber, kString, kPath, kAsset, kPunct };

struct Token {
  Kind kind = Kind::kEnd;
  std::string_view text;  // strings, paths and assets without their delimiters
  uint64_t line = 0;
};

// Text from the file as a message shows it: control characters (and DEL) as '?', cut to at most
// max characters followed by "...", so that a message stays one bounded line.
std::string Printable(std::string_view text, size_t max) {
  std::string shown;
  for (const char c : text.substr(0, max)) {
    const unsigned char u = static_cast<unsigned char>(c);
    shown += u < 0x20 || u == 0x7f ? '?' : c;
  }
  if (text.size() > max) shown += "...";
  return shown;
}

// A token shown in a message: printable characters only, cut to a few characters.
std::string Show(const Token& t) {
  if (t.kind == Kind::kEnd) return "the end of the file";
  return "\"" + Printable(t.text, 24) + "\"";
}

bool IsIdentStart(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_';
}
bool IsIdentChar(char c) { return IsIdentStart(c) || (c >= '0' && c <= '9') || c == ':' || c == '.'; }
bool IsNumberChar(char c) {
  return (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E';
}

class Lexer {
 public:
  explicit Lexer(std::string_view text) : text_(text) {}

  // The next token, without consuming it. On a lexical error returns kEnd and sets error().
  const Token& Peek() {
    if (!peeked_) {
      next_ = Lex();
      peeked_ = true;
    }
    return next_;
  }
  Token Next() {
    Peek();
    peeked_ = false;
    return next_;
  }
  uint64_t line() const { return line_; }
  const std::string& error() const { return error_; }
  // Skips the rest of the current line (the "#usda 1.0" header).
  void SkipLine() {
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
  }

 private:
  void SkipBlanksAndComments() {
    while (pos_ < text_.size()) {
      const char c = text_[pos_];
      if (c == '\n') {
        ++line_;
        ++pos_;
      } else if (c == ' ' || c == '\t' || c == '\r' || c == ';') {
        ++pos_;  // ';' separates metadata entries like a newline
      } else if (c == '#' || (c == '/' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '/')) {
        while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
      } else if (c == '/' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '*') {
        const size_t end = text_.find("*/", pos_ + 2);
        const size_t stop = end == std::string_view::npos ? text_.size() : end + 2;
        for (size_t i = pos_; i < stop; ++i) line_ += text_[i] == '\n';
        pos_ = stop;
      } else {
        return;
      }
    }
  }

  Token Fail(const std::string& what) {
    if (error_.empty()) error_ = "line " + std::to_string(line_) + ": " + what;
    pos_ = text_.size();
    return Token{Kind::kEnd, {}, line_};
  }

  Token Lex() {
    SkipBlanksAndComments();
    Token t;
    t.line = line_;
    if (pos_ >= text_.size()) {
      // The end of the file is on its last line, not on the empty one after a final newline.
      if (t.line > 1 && !text_.empty() && text_.back() == '\n') --t.line;
      return t;
    }
    const char c = text_[pos_];
    const size_t start = pos_;
    if (IsIdentStart(c)) {
      while (pos_ < text_.size() && IsIdentChar(text_[pos_])) ++pos_;
      t.kind = Kind::kIdent;
      t.text = text_.substr(start, pos_ - start);
      return t;
    }
    if ((c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.') {
      while (pos_ < text_.size() && (IsNumberChar(text_[pos_]) || IsIdentStart(text_[pos_]))) {
        ++pos_;  // letters too, so that "-inf" and "1.5x" are one (checked) token
      }
      t.kind = Kind::kNumber;
      t.text = text_.substr(start, pos_ - start);
      return t;
    }
    if (c == '"' || c == '\'') {
      const std::string_view quotes = c == '"' ? std::string_view("\"\"\"") : "'''";
      const bool triple = text_.substr(pos_, 3) == quotes;
      const size_t open = triple ? 3 : 1;
      size_t i = pos_ + open;
      uint64_t lines = 0;
      while (true) {
        if (i >= text_.size()) return Fail("unterminated string");
        const char d = text_[i];
        if (d == '\\') {
          i += 2;
          continue;
        }
        if (d == '\n') {
          if (!triple) return Fail("unterminated string (a newline inside a quoted string)");
          ++lines;
        }
        if (d == c && (!triple || text_.substr(i, 3) == quotes)) break;
        ++i;
      }
      t.kind = Kind::kString;
      t.text = text_.substr(pos_ + open, i - pos_ - open);
      pos_ = i + open;
      line_ += lines;
      return t;
    }
    if (c == '<' || c == '@') {
      // A path <...> or an asset path @...@ (or @@@...@@@).
      const std::string_view close = c == '<' ? ">" : (text_.substr(pos_, 3) == "@@@" ? "@@@" : "@");
      const size_t open = c == '<' ? 1 : close.size();
      const size_t end = text_.find(close, pos_ + open);
      if (end == std::string_view::npos) return Fail(c == '<' ? "unterminated path" : "unterminated asset path");
      t.kind = c == '<' ? Kind::kPath : Kind::kAsset;
      t.text = text_.substr(pos_ + open, end - pos_ - open);
      for (char d : t.text) line_ += d == '\n';
      pos_ = end + close.size();
      return t;
    }
    if (c == '(' || c == ')' || c == '[' || c == ']' || c == '{' || c == '}' || c == '=' ||
        c == ',' || c == ':') {
      ++pos_;
      t.kind = Kind::kPunct;
      t.text = text_.substr(start, 1);
      return t;
    }
    const unsigned char u = static_cast<unsigned char>(c);
    char hex[8];
    std::snprintf(hex, sizeof(hex), "0x%02x", u);
    return Fail(std::string("unexpected character ") +
                (u >= 0x20 && u < 0x7f ? "'" + std::string(1, c) + "'" : std::string(hex)));
  }

  std::string_view text_;
  size_t pos_ = 0;
  uint64_t line_ = 1;
  bool peeked_ = false;
  Token next_;
  std::string error_;
};

bool IsPunct(const Token& t, char c) { return t.kind == Kind::kPunct && t.text[0] == c; }

// Values of the attributes read: numbers, tuples and lists of them, strings.
struct Value {
  enum class Type { kNone, kNumber, kString, kList, kTuple, kOther } type = Type::kNone;
  double number = 0.0;
  std::string_view string;
  std::vector<double> numbers;  // a list of numbers, or the flattened tuples of a list
  int tuple_size = 0;           // > 0: a list of tuples of this size (or a tuple itself)
  bool empty_list = false;
};

// The attribute values of one BasisCurves prim that the reader uses.
struct Attribute {
  bool authored = false;
  Value value;
  std::string interpolation;  // from the metadata, when authored
  uint64_t line = 0;
  // Time samples: the earliest one, when there is no default value.
  bool has_sample = false;
  double sample_time = 0.0;
  Value sample;
};

struct CurvesPrim {
  std::string path;
  uint64_t line = 0;
  Attribute type, wrap, counts, points, widths, primvar_widths, colors, basis;
  bool widths_indexed = false;
};

class Parser {
 public:
  Parser(std::string_view text, TextStrands* out) : lexer_(text), out_(out) {}

  bool Parse(std::string* error) {
    if (!ParseLayer()) {
      *error = !lexer_.error().empty() ? lexer_.error() : error_;
      return false;
    }
    return Finish(error);
  }

 private:
  // (ParseUsdaCurves makes every message one bounded line.)
  bool Fail(const std::string& what) {
    if (error_.empty()) error_ = what;
    return false;
  }
  bool FailAt(const Token& t, const std::string& what) {
    return Fail("line " + std::to_string(t.line) + ": " + what);
  }
  bool Expect(char c, const char* where) {
    const Token t = lexer_.Next();
    if (IsPunct(t, c)) return true;
    return FailAt(t, std::string("expected '") + c + "' " + where + ", got " + Show(t));
  }
  // Lexical errors come back as kEnd tokens: report them rather than "unexpected end".
  bool LexOk() const { return lexer_.error().empty(); }

  // The header line "#usda 1.0" is a comment to the lexer (checked by ParseUsdaCurves).
  bool ParseLayer() { return ParseStatements(0, "") && LexOk(); }

  // Layer metadata, prims, until the end of the file (depth 0) or the closing '}' of a prim.
  bool ParseStatements(int depth, const std::string& parent) {
    if (depth == 0) {
      const Token& t = lexer_.Peek();
      if (IsPunct(t, '(')) {
        lexer_.Next();
        if (!ParseMetadata(depth + 1, "layer metadata", true)) return false;
      }
    }
    while (true) {
      const Token t = lexer_.Peek();
      if (t.kind == Kind::kEnd) {
        if (!LexOk()) return false;
        if (depth > 0) return FailAt(t, "expected '}' closing prim <" + parent + ">, got the end of the file");
        return true;
      }
      if (depth > 0 && IsPunct(t, '}')) return true;
      if (t.kind == Kind::kIdent && (t.text == "def" || t.text == "over" || t.text == "class")) {
        if (!ParsePrim(depth, parent)) return false;
        continue;
      }
      if (depth == 0) {
        return FailAt(t, "expected a prim (def, over or class), got " + Show(t));
      }
      if (!ParseProperty(depth, parent)) return false;
    }
  }

  // Metadata "( key = value ... )" after the opening parenthesis, through the closing one.
  bool ParseMetadata(int depth, const std::string& what, bool layer, CurvesPrim* prim = nullptr,
                     Attribute* attribute = nullptr) {
    if (depth > kMaxUsdaDepth) return FailAt(lexer_.Peek(), "nesting deeper than 64 levels");
    while (true) {
      Token t = lexer_.Next();
      if (IsPunct(t, ')')) return true;
      if (t.kind == Kind::kString) continue;  // a doc string
      if (t.kind != Kind::kIdent) {
        if (!LexOk()) return false;
        return FailAt(t, "expected a " + what + " entry or ')', got " + Show(t));
      }
      std::string_view key = t.text;
      if (key == "add" || key == "prepend" || key == "append" || key == "delete" ||
          key == "reorder") {
        t = lexer_.Next();
        if (t.kind != Kind::kIdent) return FailAt(t, "expected a " + what + " key after " + std::string(key) + ", got " + Show(t));
        key = t.text;
      }
      if (key == "subLayers" || key == "references" || key == "payload" || key == "inherits" ||
          key == "specializes" || key == "variants" || key == "variantSets") {
        return FailAt(t, std::string(key) +
                             ": composition (sublayers, references, payloads, inherits, "
                             "specializes, variants) is not supported; flatten the stage first "
                             "(e.g. usdcat --flatten)");
      }
      if (!Expect('=', ("after " + what + " key \"" + std::string(key) + "\"").c_str())) return false;
      Value value;
      const Token at = lexer_.Peek();
      if (!ParseValue(depth + 1, &value)) return false;
      if (layer && key == "upAxis") {
        if (value.type != Value::Type::kString || (value.string != "Y" && value.string != "Z")) {
          return FailAt(at, "upAxis: expected \"Y\" or \"Z\", got " + Show(at));
        }
        out_->has_up_axis = true;
        out_->up_axis = value.string == "Y" ? StrandTargetOptions::UpAxis::kY
                                            : StrandTargetOptions::UpAxis::kZ;
      } else if (layer && key == "metersPerUnit") {
        if (value.type != Value::Type::kNumber || !std::isfinite(value.number) ||
            !(value.number > 0.0)) {
          return FailAt(at, "metersPerUnit: expected a finite number > 0, got " + Show(at));
        }
        out_->has_meters_per_unit = true;
        out_->meters_per_unit = value.number;
      } else if (attribute != nullptr && key == "interpolation") {
        if (value.type != Value::Type::kString) {
          return FailAt(at, "interpolation: expected a token string, got " + Show(at));
        }
        attribute->interpolation = std::string(value.string);
      }
      (void)prim;
    }
  }

  // A value: number, string, identifier (None, inf...), path, asset, list [...], tuple (...),
  // dictionary {...}. Lists of numbers and of tuples of numbers are kept; the rest is checked
  // for balance and skipped.
  bool ParseValue(int depth, Value* value) {
    if (depth > kMaxUsdaDepth) return FailAt(lexer_.Peek(), "nesting deeper than 64 levels");
    const Token t = lexer_.Next();
    switch (t.kind) {
      case Kind::kNumber:
      case Kind::kIdent: {
        double x = 0.0;
        if (ToNumber(t, &x)) {
          value->type = Value::Type::kNumber;
          value->number = x;
          return true;
        }
        if (t.kind == Kind::kNumber) return FailAt(t, "malformed number " + Show(t));
        value->type = Value::Type::kOther;  // None, a token, a type name of a dictionary ...
        return true;
      }
      case Kind::kString:
        value->type = Value::Type::kString;
        value->string = t.text;
        return true;
      case Kind::kPath:
      case Kind::kAsset:
        value->type = Value::Type::kOther;
        return true;
      case Kind::kPunct:
        if (t.text[0] == '[') return ParseList(depth, value);
        if (t.text[0] == '(') return ParseTuple(depth, value);
        if (t.text[0] == '{') return SkipDictionary(depth);
        return FailAt(t, "expected a value, got " + Show(t));
      case Kind::kEnd:
        if (!LexOk()) return false;
        return FailAt(t, "expected a value, got the end of the file");
    }
    return false;
  }

  static bool ToNumber(const Token& t, double* x) {
    std::string_view s = t.text;
    if (s == "inf" || s == "+inf") {
      *x = std::numeric_limits<double>::infinity();
      return true;
    }
    if (s == "-inf") {
      *x = -std::numeric_limits<double>::infinity();
      return true;
    }
    if (s == "nan") {
      *x = std::numeric_limits<double>::quiet_NaN();
      return true;
    }
    if (t.kind != Kind::kNumber) return false;
    if (!s.empty() && s[0] == '+') s.remove_prefix(1);
    const auto result = std::from_chars(s.data(), s.data() + s.size(), *x);
    return result.ec == std::errc() && result.ptr == s.data() + s.size();
  }

  // After '(': numbers only (a tuple of numbers), or anything balanced.
  bool ParseTuple(int depth, Value* value) {
    value->type = Value::Type::kTuple;
    bool numeric = true;
    int n = 0;
    std::vector<double> numbers;
    while (true) {
      if (IsPunct(lexer_.Peek(), ')')) {
        lexer_.Next();
        break;
      }
      Value item;
      if (!ParseValue(depth + 1, &item)) return false;
      if (item.type == Value::Type::kNumber) {
        if (n < 4) numbers.push_back(item.number);
      } else {
        numeric = false;
      }
      ++n;
      const Token t = lexer_.Next();
      if (IsPunct(t, ')')) break;
      if (!IsPunct(t, ',')) return FailAt(t, "expected ',' or ')' in a tuple, got " + Show(t));
    }
    if (!numeric || n > 4) {
      value->type = Value::Type::kOther;
      return true;
    }
    value->tuple_size = n;
    value->numbers = std::move(numbers);
    return true;
  }

  // After '[': a list of numbers or of numeric tuples of one size is kept.
  bool ParseList(int depth, Value* value) {
    value->type = Value::Type::kList;
    value->empty_list = true;
    bool keep = true;
    while (true) {
      if (IsPunct(lexer_.Peek(), ']')) {
        lexer_.Next();
        break;
      }
      Value item;
      if (!ParseValue(depth + 1, &item)) return false;
      if (keep) {
        if (item.type == Value::Type::kNumber && value->tuple_size == 0) {
          value->numbers.push_back(item.number);
        } else if (item.type == Value::Type::kTuple &&
                   (value->empty_list || value->tuple_size == item.tuple_size)) {
          value->tuple_size = item.tuple_size;
          value->numbers.insert(value->numbers.end(), item.numbers.begin(), item.numbers.end());
        } else {
          keep = false;
          value->numbers = std::vector<double>();
        }
      }
      value->empty_list = false;
      const Token t = lexer_.Next();
      if (IsPunct(t, ']')) break;
      if (!IsPunct(t, ',')) return FailAt(t, "expected ',' or ']' in a list, got " + Show(t));
    }
    if (!keep) value->type = Value::Type::kOther;
    return true;
  }

  // After '{': anything balanced up to the matching '}'.
  bool SkipDictionary(int depth) {
    while (true) {
      const Token t = lexer_.Peek();
      if (t.kind == Kind::kEnd) {
        if (!LexOk()) return false;
        return FailAt(t, "expected '}' closing a dictionary, got the end of the file");
      }
      if (IsPunct(t, '}')) {
        lexer_.Next();
        return true;
      }
      if (IsPunct(t, '[') || IsPunct(t, '(') || IsPunct(t, '{')) {
        Value skipped;
        if (!ParseValue(depth + 1, &skipped)) return false;
        continue;
      }
      if (IsPunct(t, ']') || IsPunct(t, ')')) return FailAt(t, "unbalanced " + Show(t) + " in a dictionary");
      lexer_.Next();
    }
  }

  bool ParsePrim(int depth, const std::string& parent) {
    if (depth + 1 > kMaxUsdaDepth) return FailAt(lexer_.Peek(), "prims nested deeper than 64 levels");
    const Token specifier = lexer_.Next();
    Token t = lexer_.Next();
    std::string_view type_name;
    if (t.kind == Kind::kIdent) {
      type_name = t.text;
      t = lexer_.Next();
    }
    if (t.kind != Kind::kString) {
      if (!LexOk()) return false;
      return FailAt(t, "expected the prim's name in quotes after " + Show(specifier) + ", got " + Show(t));
    }
    const std::string path = parent + "/" + std::string(t.text);
    const bool defines = specifier.text == "def" && !in_class_;
    if (defines && (type_name == "NurbsCurves" || type_name == "HermiteCurves")) {
      return FailAt(t, "<" + path + "> is a " + std::string(type_name) +
                           " prim: only linear BasisCurves are read");
    }
    const bool curves = defines && type_name == "BasisCurves";
    CurvesPrim prim;
    prim.path = path;
    prim.line = t.line;
    if (IsPunct(lexer_.Peek(), '(')) {
      lexer_.Next();
      if (!ParseMetadata(depth + 1, "prim metadata", false)) return false;
    }
    if (!Expect('{', ("opening prim <" + path + ">").c_str())) return false;
    const bool was_in_class = in_class_;
    in_class_ = in_class_ || specifier.text == "class";  // abstract: not part of the scene
    CurvesPrim* saved = current_;
    current_ = curves ? &prim : nullptr;
    current_path_.push_back(path);
    if (!ParseStatements(depth + 1, path)) return false;
    current_path_.pop_back();
    current_ = saved;
    in_class_ = was_in_class;
    if (!Expect('}', ("closing prim <" + path + ">").c_str())) return false;
    if (curves) prims_.push_back(std::move(prim));
    return true;
  }

  // A property inside a prim: attribute (with value, time samples or connection), relationship,
  // variantSet (refused) or reorder statement.
  bool ParseProperty(int depth, const std::string& prim_path) {
    Token t = lexer_.Next();
    if (t.kind != Kind::kIdent) {
      if (!LexOk()) return false;
      return FailAt(t, "expected a property, a prim or '}' in <" + prim_path + ">, got " + Show(t));
    }
    if (t.text == "variantSet") {
      return FailAt(t, "variantSet: composition (variants) is not supported; flatten the stage "
                       "first (e.g. usdcat --flatten)");
    }
    if (t.text == "reorder") {
      // reorder nameChildren = [...] / reorder properties = [...]
      lexer_.Next();
      if (!Expect('=', "after reorder")) return false;
      Value skipped;
      return ParseValue(depth + 1, &skipped);
    }
    bool uniform = false;
    while (t.kind == Kind::kIdent && (t.text == "custom" || t.text == "uniform" ||
                                      t.text == "varying" || t.text == "config" ||
                                      t.text == "prepend" || t.text == "append" ||
                                      t.text == "add" || t.text == "delete")) {
      uniform = uniform || t.text == "uniform";
      t = lexer_.Next();
    }
    if (t.kind != Kind::kIdent) return FailAt(t, "expected a property type, got " + Show(t));
    const bool relationship = t.text == "rel";
    std::string_view type = t.text;
    bool array = false;
    if (!relationship && IsPunct(lexer_.Peek(), '[')) {
      lexer_.Next();
      if (!Expect(']', "after '[' in an array type")) return false;
      array = true;
    }
    const Token name_token = lexer_.Next();
    if (name_token.kind != Kind::kIdent) {
      return FailAt(name_token, "expected a property name after " + Show(t) + ", got " + Show(name_token));
    }
    std::string_view name = name_token.text;
    bool time_samples = false;
    if (name.size() > 12 && name.substr(name.size() - 12) == ".timeSamples") {
      time_samples = true;
      name.remove_suffix(12);
    } else if (name.find('.') != std::string_view::npos) {
      // name.connect, name.spline ...: skipped with their value
      if (IsPunct(lexer_.Peek(), '=')) {
        lexer_.Next();
        Value skipped;
        return ParseValue(depth + 1, &skipped);
      }
      return true;
    }
    Attribute scratch;
    Attribute* attribute = Target(name);
    if (attribute == nullptr) attribute = &scratch;
    attribute->line = name_token.line;
    (void)uniform;
    (void)array;
    (void)type;

    if (name == "xformOpOrder") transformed_.push_back(prim_path);
    if (IsPunct(lexer_.Peek(), '=')) {
      lexer_.Next();
      if (time_samples) {
        if (!Expect('{', ("opening " + std::string(name) + ".timeSamples").c_str())) return false;
        if (!ParseTimeSamples(depth + 1, attribute, name)) return false;
      } else {
        Value value;
        if (!ParseValue(depth + 1, &value)) return false;
        if (name == "xformOpOrder" && value.type == Value::Type::kList && value.empty_list) {
          transformed_.pop_back();  // an empty op order is the identity
        }
        attribute->authored = true;
        attribute->value = std::move(value);
      }
    }
    if (IsPunct(lexer_.Peek(), '(')) {
      lexer_.Next();
      if (!ParseMetadata(depth + 1, "attribute metadata", false, nullptr, attribute)) return false;
    }
    return true;
  }

  bool ParseTimeSamples(int depth, Attribute* attribute, std::string_view name) {
    while (true) {
      const Token t = lexer_.Next();
      if (IsPunct(t, '}')) return true;
      double time = 0.0;
      if (!ToNumber(t, &time) || !std::isfinite(time)) {
        if (!LexOk()) return false;
        return FailAt(t, std::string(name) + ".timeSamples: expected a time code, got " + Show(t));
      }
      if (!Expect(':', "after a time code")) return false;
      Value value;
      if (!ParseValue(depth + 1, &value)) return false;
      if (!attribute->has_sample || time < attribute->sample_time) {
        attribute->has_sample = true;
        attribute->sample_time = time;
        attribute->sample = std::move(value);
      }
      const Token next = lexer_.Next();
      if (IsPunct(next, '}')) return true;
      if (!IsPunct(next, ',')) return FailAt(next, "expected ',' or '}' in time samples, got " + Show(next));
    }
  }

  Attribute* Target(std::string_view name) {
    if (current_ == nullptr || current_path_.empty() || current_path_.back() != current_->path) {
      return nullptr;
    }
    if (name == "type") return &current_->type;
    if (name == "wrap") return &current_->wrap;
    if (name == "basis") return &current_->basis;
    if (name == "curveVertexCounts") return &current_->counts;
    if (name == "points") return &current_->points;
    if (name == "widths") return &current_->widths;
    if (name == "primvars:widths") return &current_->primvar_widths;
    if (name == "primvars:widths:indices") {
      current_->widths_indexed = true;
      return nullptr;
    }
    if (name == "primvars:displayColor") return &current_->colors;
    return nullptr;
  }

  // The value an attribute holds for the reader: its default, else its earliest time sample.
  static const Value* Resolved(const Attribute& a) {
    if (a.authored && a.value.type != Value::Type::kOther) return &a.value;
    if (a.has_sample) return &a.sample;
    if (a.authored) return &a.value;
    return nullptr;
  }

  bool Finish(std::string* error) {
    const auto fail = [&](const std::string& what) {
      *error = what;
      return false;
    };
    if (prims_.empty()) {
      return fail("no BasisCurves prim (def BasisCurves \"name\" { ... }) in the file");
    }
    for (const CurvesPrim& prim : prims_) {
      for (const std::string& t : transformed_) {
        if (prim.path == t || prim.path.compare(0, t.size() + 1, t + "/") == 0) {
          return fail("<" + prim.path + ">: transforms (xformOpOrder on <" + t +
                      ">) are not supported: bake them into the points first");
        }
      }
    }
    HairCurves& out = out_->curves;
    bool any_widths = false, all_widths = true;
    bool all_colors = true;
    for (const CurvesPrim& prim : prims_) {
      const std::string at = "<" + prim.path + ">.";
      // type: linear only (the schema's fallback is "cubic").
      const Value* type = Resolved(prim.type);
      if (type == nullptr) {
        return fail(at + "type: not authored, and the schema's fallback is \"cubic\": only "
                         "linear curves are read (uniform token type = \"linear\")");
      }
      if (type->type != Value::Type::kString || type->string != "linear") {
        return fail(at + "type: only \"linear\" curves are read, got " +
                    (type->type == Value::Type::kString ? "\"" + std::string(type->string).substr(0, 24) + "\"" : std::string("a non-token value")));
      }
      if (const Value* wrap = Resolved(prim.wrap)) {
        if (wrap->type != Value::Type::kString ||
            (wrap->string != "nonperiodic" && wrap->string != "pinned")) {
          return fail(at + "wrap: only open curves are read (\"nonperiodic\"), got " +
                      (wrap->type == Value::Type::kString ? "\"" + std::string(wrap->string).substr(0, 24) + "\"" : std::string("a non-token value")));
        }
      }
      const Value* counts = Resolved(prim.counts);
      if (counts == nullptr) return fail(at + "curveVertexCounts: not authored");
      if (counts->type != Value::Type::kList || counts->tuple_size != 0) {
        return fail(at + "curveVertexCounts: expected a list of integers");
      }
      const Value* points = Resolved(prim.points);
      if (points == nullptr) return fail(at + "points: not authored");
      if (points->type != Value::Type::kList ||
          (points->tuple_size != 3 && !points->empty_list)) {
        return fail(at + "points: expected a list of (x, y, z) tuples");
      }
      // Counts: integers >= 2 whose sum is the number of points.
      uint64_t total = 0;
      const size_t first_strand = out.point_counts.size();
      for (size_t j = 0; j < counts->numbers.size(); ++j) {
        const double c = counts->numbers[j];
        if (!(c >= 2.0) || c != std::floor(c) || c > 4294967295.0) {
          return fail(at + "curveVertexCounts[" + std::to_string(j) + "]: expected an integer >= 2 (a linear curve needs 2 points), got " + ShowNumber(c));
        }
        total += static_cast<uint64_t>(c);
      }
      const uint64_t n_points = points->numbers.size() / 3;
      if (total != n_points) {
        return fail(at + "points: " + std::to_string(n_points) + " points, but curveVertexCounts add up to " + std::to_string(total));
      }
      if (out.points.size() + n_points > std::numeric_limits<uint32_t>::max()) {
        return fail(at + "points: more than 2^32 - 1 points in the file");
      }
      const size_t first_point = out.points.size();
      for (size_t i = 0; i < n_points; ++i) {
        const Vec3f x(static_cast<float>(points->numbers[3 * i]),
                      static_cast<float>(points->numbers[3 * i + 1]),
                      static_cast<float>(points->numbers[3 * i + 2]));
        if (!std::isfinite(x.x()) || !std::isfinite(x.y()) || !std::isfinite(x.z())) {
          return fail(at + "points[" + std::to_string(i) + "]: expected finite coordinates (as float)");
        }
        out.points.push_back(x);
      }
      for (size_t j = 0; j < counts->numbers.size(); ++j) {
        out.point_counts.push_back(static_cast<uint32_t>(counts->numbers[j]));
        out_->labels.push_back({static_cast<uint32_t>(out_->label_prefixes.size()), j});
      }
      // The prim's path names its strands in later messages (ReadStrandTargets' checks), which
      // the sanitizing above does not reach: shown the same way here (found by the fuzzer).
      out_->label_prefixes.push_back("<" + Printable(prim.path, 200) + "> curve ");
      const size_t n_curves = counts->numbers.size();
      // Widths: primvars:widths wins over widths (UsdGeomPrimvar); interpolation constant,
      // uniform (per curve), vertex or varying (per point, the same for linear curves).
      const bool primvar = prim.primvar_widths.authored || prim.primvar_widths.has_sample;
      const Attribute& wa = primvar ? prim.primvar_widths : prim.widths;
      const std::string wname = primvar ? "primvars:widths" : "widths";
      const Value* widths = Resolved(wa);
      if (widths != nullptr && primvar && prim.widths_indexed) {
        return fail(at + "primvars:widths:indices: indexed widths are not supported");
      }
      if (widths != nullptr && !(widths->type == Value::Type::kList && widths->empty_list)) {
        if (widths->type != Value::Type::kList || widths->tuple_size != 0) {
          return fail(at + wname + ": expected a list of numbers");
        }
        const std::string interpolation = wa.interpolation.empty() ? "vertex" : wa.interpolation;
        const size_t m = widths->numbers.size();
        size_t expected = 0;
        if (interpolation == "constant") expected = 1;
        else if (interpolation == "uniform") expected = n_curves;
        else if (interpolation == "vertex" || interpolation == "varying" || interpolation == "faceVarying") expected = n_points;
        else return fail(at + wname + ": unknown interpolation \"" + interpolation.substr(0, 24) + "\"");
        if (m != expected) {
          return fail(at + wname + ": " + std::to_string(m) + " values, but " + interpolation + " interpolation needs " + std::to_string(expected));
        }
        out.widths.resize(first_point + n_points);
        size_t p = first_point;
        for (size_t j = 0; j < n_curves; ++j) {
          const uint32_t count = out.point_counts[first_strand + j];
          for (uint32_t i = 0; i < count; ++i, ++p) {
            const size_t v = interpolation == "constant" ? 0 : interpolation == "uniform" ? j : p - first_point;
            const double w = widths->numbers[v];
            if (!std::isfinite(w) || w < 0.0) {
              return fail(at + wname + "[" + std::to_string(v) + "]: expected a finite width >= 0");
            }
            out.widths[p] = static_cast<float>(w);
          }
        }
        any_widths = true;
      } else {
        all_widths = false;
        out.widths.resize(first_point + n_points, 0.0f);
      }
      // Colours (primvars:displayColor), one per strand: constant, uniform, or the root's.
      const Value* colors = Resolved(prim.colors);
      if (colors != nullptr && colors->type == Value::Type::kList && colors->tuple_size == 3) {
        const std::string interpolation = prim.colors.interpolation.empty() ? "constant" : prim.colors.interpolation;
        const size_t m = colors->numbers.size() / 3;
        size_t p = 0;
        for (size_t j = 0; j < n_curves; ++j) {
          size_t v = 0;
          if (interpolation == "uniform") v = j;
          else if (interpolation == "vertex" || interpolation == "varying" || interpolation == "faceVarying") v = p;
          if (v >= m) {
            return fail(at + "primvars:displayColor: " + std::to_string(m) + " colours, too few for " + interpolation + " interpolation");
          }
          out.colors.emplace_back(static_cast<float>(colors->numbers[3 * v]),
                                  static_cast<float>(colors->numbers[3 * v + 1]),
                                  static_cast<float>(colors->numbers[3 * v + 2]));
          p += out.point_counts[first_strand + j];
        }
      } else {
        all_colors = false;
      }
    }
    if (any_widths && !all_widths) {
      return fail("widths: authored on some BasisCurves prims and not on others");
    }
    out_->has_widths = any_widths;
    if (!any_widths) out.widths.clear();
    if (!all_colors) out.colors.clear();
    return true;
  }

  static std::string ShowNumber(double x) {
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof(buffer), x);
    return std::string(buffer, result.ptr);
  }

  Lexer lexer_;
  TextStrands* out_;
  std::string error_;
  bool in_class_ = false;
  CurvesPrim* current_ = nullptr;
  std::vector<std::string> current_path_;
  std::vector<CurvesPrim> prims_;
  std::vector<std::string> transformed_;
};

}  // namespace

bool ParseUsdaCurves(std::string_view text, TextStrands* out, std::string* error) {
  // The header: "#usda 1.0" (Sdf's cookie "#usda" followed by the version).
  const size_t eol = text.find('\n');
  std::string_view first = text.substr(0, eol);
  if (!first.empty() && first.back() == '\r') first.remove_suffix(1);
  if (first.substr(0, 6) != "#usda ") {
    *error = "line 1: expected the header \"#usda 1.0\" (a text USD layer)";
    return false;
  }
  TextStrands result;
  Parser parser(text, &result);
  if (!parser.Parse(error)) {
    // One line of bounded length whatever the file holds (prim names, paths and tokens come
    // from the file; found by the fuzzer, tests/fuzz/fuzz_usda_targets.cpp): control characters
    // become '?' and the message is cut at 400 characters.
    constexpr size_t kMaxMessage = 400;
    *error = Printable(*error, kMaxMessage);
    return false;
  }
  *out = std::move(result);
  return true;
}

}  // namespace ringlet::io_internal
