// Writing JSON values directly into a string.
#include "io/json_writer.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <system_error>

namespace ringlet::internal {

char* WriteJsonNumber(double x, char* out) {
  if (!std::isfinite(x)) {
    std::memcpy(out, "null", 4);
    return out + 4;
  }
  if (x == 0.0) {  // the commonest value of all (roots at the origin, no contact)
    const char* zero = std::signbit(x) ? "-0.0" : "0.0";
    const size_t size = std::signbit(x) ? 4 : 3;
    std::memcpy(out, zero, size);
    return out + size;
  }
  // 24 characters hold the longest shortest form ("-2.2250738585072014e-308"); the last two of
  // kMaxJsonNumberChars are kept for ".0".
  char* end = std::to_chars(out, out + kMaxJsonNumberChars - 2, x).ptr;
  // Only an integral value can come out with neither '.' nor 'e' (a fraction needs one or the
  // other), so the text is searched only then: one rounding instead of two library calls per
  // number (memchr was 2 % of `ringlet solve`'s samples in perf, docs/benchmarks.md).
  if (x == std::trunc(x) && std::memchr(out, '.', static_cast<size_t>(end - out)) == nullptr &&
      std::memchr(out, 'e', static_cast<size_t>(end - out)) == nullptr) {
    *end++ = '.';
    *end++ = '0';
  }
  return end;
}

void AppendJsonNumber(double x, std::string* out) {
  char buffer[kMaxJsonNumberChars];
  out->append(buffer, WriteJsonNumber(x, buffer));
}

void AppendJsonInteger(long long x, std::string* out) {
  char buffer[24];
  const std::to_chars_result r = std::to_chars(buffer, buffer + sizeof(buffer), x);
  out->append(buffer, r.ptr);
}

void AppendJsonString(std::string_view text, std::string* out) {
  // Non-ASCII text (never in ringlet's own messages) goes through nlohmann, which validates the
  // UTF-8; the common ASCII case is escaped here.
  for (const char c : text) {
    if (static_cast<unsigned char>(c) >= 0x80) {
      out->append(nlohmann::json(std::string(text))
                      .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
      return;
    }
  }
  static constexpr char kHex[] = "0123456789abcdef";
  out->push_back('"');
  size_t run = 0;  // start of the characters not yet appended, which need no escape
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c != '"' && c != '\\' && static_cast<unsigned char>(c) >= 0x20) continue;
    out->append(text.data() + run, i - run);
    run = i + 1;
    switch (c) {
      case '"':
        out->append("\\\"");
        break;
      case '\\':
        out->append("\\\\");
        break;
      case '\b':
        out->append("\\b");
        break;
      case '\f':
        out->append("\\f");
        break;
      case '\n':
        out->append("\\n");
        break;
      case '\r':
        out->append("\\r");
        break;
      case '\t':
        out->append("\\t");
        break;
      default:
        out->append("\\u00");  // the other control characters
        out->push_back(kHex[(c >> 4) & 0xf]);
        out->push_back(kHex[c & 0xf]);
    }
  }
  out->append(text.data() + run, text.size() - run);
  out->push_back('"');
}

}  // namespace ringlet::internal
