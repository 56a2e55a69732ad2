// The consistency check of HairCurves (hair_curves.h), relied on by the exporters and the
// renderer.
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>

#include "ringlet/hair_curves.h"

namespace ringlet {
namespace {

// The shortest text that reads back as exactly value (std::to_chars: no locale).
void AppendNumber(std::string* out, float value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out->append(buffer, result.ptr);
}

bool Fail(std::string* why, std::string_view name, const std::string& what) {
  if (why) *why = std::string(name) + what;
  return false;
}

std::string Index(const char* field, size_t i) {
  return std::string(".") + field + "[" + std::to_string(i) + "]";
}

bool Finite(const Vec3f& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}

std::string Text(const Vec3f& v) {
  std::string s = "(";
  AppendNumber(&s, v.x());
  s += ", ";
  AppendNumber(&s, v.y());
  s += ", ";
  AppendNumber(&s, v.z());
  return s + ")";
}

}  // namespace

bool CheckHairCurves(const HairCurves& curves, std::string_view name, std::string* why) {
  uint64_t total = 0;
  for (size_t k = 0; k < curves.point_counts.size(); ++k) {
    const uint32_t count = curves.point_counts[k];
    if (count < 2) {
      return Fail(why, name,
                  Index("point_counts", k) + ": expected at least 2 points per strand, got " +
                      std::to_string(count));
    }
    total += count;
  }
  if (total != curves.points.size()) {
    return Fail(why, name,
                ".points: expected " + std::to_string(total) +
                    " points (the sum of point_counts), got " +
                    std::to_string(curves.points.size()));
  }
  if (curves.widths.size() != curves.points.size()) {
    return Fail(why, name,
                ".widths: expected one width per point (" + std::to_string(curves.points.size()) +
                    "), got " + std::to_string(curves.widths.size()));
  }
  if (!curves.colors.empty() && curves.colors.size() != curves.point_counts.size()) {
    return Fail(why, name,
                ".colors: expected none or one per strand (" +
                    std::to_string(curves.point_counts.size()) + "), got " +
                    std::to_string(curves.colors.size()));
  }
  if (!curves.major_axes.empty() && curves.major_axes.size() != curves.points.size()) {
    return Fail(why, name,
                ".major_axes: expected none or one per point (" +
                    std::to_string(curves.points.size()) + "), got " +
                    std::to_string(curves.major_axes.size()));
  }
  for (size_t i = 0; i < curves.major_axes.size(); ++i) {
    if (!Finite(curves.major_axes[i])) {
      return Fail(why, name,
                  Index("major_axes", i) + ": expected a finite direction, got " +
                      Text(curves.major_axes[i]));
    }
  }
  for (size_t i = 0; i < curves.points.size(); ++i) {
    if (!Finite(curves.points[i])) {
      return Fail(why, name,
                  Index("points", i) + ": expected finite coordinates (m), got " +
                      Text(curves.points[i]));
    }
    const float w = curves.widths[i];
    if (!std::isfinite(w) || w < 0.0f) {
      std::string text;
      AppendNumber(&text, w);
      return Fail(why, name,
                  Index("widths", i) + ": expected a finite diameter >= 0 (m), got " + text);
    }
  }
  for (size_t k = 0; k < curves.colors.size(); ++k) {
    if (!Finite(curves.colors[k])) {
      return Fail(why, name,
                  Index("colors", k) + ": expected a finite RGB colour, got " +
                      Text(curves.colors[k]));
    }
  }
  if (!curves.wetness.empty() && curves.wetness.size() != curves.point_counts.size()) {
    return Fail(why, name,
                ".wetness: expected none or one per strand (" +
                    std::to_string(curves.point_counts.size()) + "), got " +
                    std::to_string(curves.wetness.size()));
  }
  for (size_t k = 0; k < curves.wetness.size(); ++k) {
    const float wet = curves.wetness[k];
    if (!(wet >= 0.0f && wet <= 1.0f)) {
      std::string text;
      AppendNumber(&text, wet);
      return Fail(why, name, Index("wetness", k) + ": expected a value in [0, 1], got " + text);
    }
  }
  return true;
}

}  // namespace ringlet
