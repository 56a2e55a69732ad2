// Shared by the hair exporters: consistency checks of HairCurves and locale-independent number
// text. Private to src/io.
#pragma once

#include <charconv>
#include <string>
#include <string_view>

#include "ringlet/hair_curves.h"

namespace ringlet::io_internal {

/// Checks what every exporter relies on: each strand has >= 2 points, the counts add up to
/// points.size() (no overflow), widths.size() == points.size(), colors is empty or has one entry
/// per strand, coordinates and colours are finite, widths finite and >= 0. On failure *why gets
/// one line that starts with name and the field ("frames[2].widths[7]: ...").
bool CheckHairCurves(const HairCurves& curves, std::string_view name, std::string* why);

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
