// Shared by the hair exporters: locale-independent number text (the HairCurves check itself is
// CheckHairCurves in hair_curves.h). Private to src/io.
#pragma once

#include <charconv>
#include <string>
#include <string_view>

#include "ringlet/hair_curves.h"

namespace ringlet::io_internal {

/// Writes the shortest decimal text that reads back as exactly value at p (room for 16
/// characters needed: at most 15 for a float) and returns the end. std::to_chars: no locale.
inline char* WriteNumber(char* p, float value) { return std::to_chars(p, p + 16, value).ptr; }

/// Appends the shortest decimal text that reads back as exactly value (std::to_chars, so no
/// locale and the same text on every run); integral values print without a decimal point.
inline void AppendNumber(std::string* out, float value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out->append(buffer, result.ptr);
}
inline void AppendNumber(std::string* out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out->append(buffer, result.ptr);
}
inline void AppendNumber(std::string* out, long long value) {
  char buffer[24];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out->append(buffer, result.ptr);
}

}  // namespace ringlet::io_internal
