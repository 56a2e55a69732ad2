// Small text helpers shared by the subcommands.
#pragma once

#include <cstdio>
#include <string>

namespace ringlet::cli {

/// printf into a std::string.
template <typename... Args>
std::string Format(const char* format, Args... args) {
  const int size = std::snprintf(nullptr, 0, format, args...);
  if (size <= 0) return {};
  std::string text(static_cast<size_t>(size) + 1, '\0');
  std::snprintf(text.data(), text.size(), format, args...);
  text.pop_back();
  return text;
}

/// "0.4 ms" below a second, "1.23 s" above.
inline std::string FormatSeconds(double seconds) {
  return seconds < 1.0 ? Format("%.1f ms", seconds * 1e3) : Format("%.2f s", seconds);
}

}  // namespace ringlet::cli
