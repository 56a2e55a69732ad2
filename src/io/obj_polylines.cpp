// Wavefront OBJ polylines as strands: 'v' vertices and 'l' line elements (Wavefront's OBJ
// specification, "Line" element: l v1/vt1 v2/vt2 ..., 1-based references, negative ones
// counting back from the last vertex defined). Hand-written rather than tinyobjloader, which
// reads a bad number as 0 and an index "8x" as 8 (issue 16). The rules (joining 2-vertex
// segments into strands, what is ignored) are in docs/file-formats.md.
#include <charconv>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "io/strand_readers.h"

namespace ringlet::io_internal {
namespace {

std::vector<std::string_view> Tokens(std::string_view line) {
  std::vector<std::string_view> tokens;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
  return tokens;
}

std::string ShowToken(std::string_view token) {
  std::string shown;
  for (char c : token.substr(0, 24)) {
    const unsigned char u = static_cast<unsigned char>(c);
    shown += u >= 0x20 && u < 0x7f ? c : '?';
  }
  return "\"" + shown + (token.size() > 24 ? "...\"" : "\"");
}

// A whole finite number ("1.5x", "nan", "" are not); from_chars: no locale.
bool ParseNumber(std::string_view token, double* x) {
  if (!token.empty() && token[0] == '+') token.remove_prefix(1);
  const auto result = std::from_chars(token.data(), token.data() + token.size(), *x);
  return !token.empty() && result.ec == std::errc() &&
         result.ptr == token.data() + token.size() && std::isfinite(*x);
}

// A whole non-zero integer ("8x" is not).
bool ParseIndex(std::string_view token, int64_t* i) {
  const auto result = std::from_chars(token.data(), token.data() + token.size(), *i);
  return !token.empty() && result.ec == std::errc() &&
         result.ptr == token.data() + token.size() && *i != 0;
}

}  // namespace

bool ParseObjPolylines(std::string_view text, TextStrands* out, std::string* error) {
  std::vector<Vec3f> vertices;
  std::vector<Vec3f> colors;  // per vertex, while every vertex has one
  bool all_colored = true;
  // The 'l' elements: 0-based vertex references, flat, with each element's start and line.
  std::vector<uint32_t> refs;
  std::vector<uint64_t> element_start;
  std::vector<uint64_t> element_line;
  uint64_t line_number = 0;
  size_t start = 0;
  const auto fail = [&](const std::string& what) {
    *error = "line " + std::to_string(line_number) + ": " + what;
    return false;
  };
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    start = end + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const size_t comment = line.find('#');
    if (comment != std::string_view::npos) line = line.substr(0, comment);
    const std::vector<std::string_view> tokens = Tokens(line);
    if (tokens.empty()) continue;
    if (tokens.back() == "\\" || tokens.back().back() == '\\') {
      return fail("line continuations ('\\' at the end of a line) are not supported");
    }
    const std::string_view key = tokens[0];
    if (key == "v") {
      const size_t n = tokens.size() - 1;
      if (n != 3 && n != 4 && n != 6) {
        return fail("expected 'v x y z' (optionally a weight, or r g b), got " +
                    std::to_string(n) + " values");
      }
      double value[6];
      for (size_t c = 0; c < n; ++c) {
        if (!ParseNumber(tokens[1 + c], &value[c])) {
          return fail("expected a finite number for the vertex's value " + std::to_string(c + 1) +
                      ", got " + ShowToken(tokens[1 + c]));
        }
      }
      if (vertices.size() >= std::numeric_limits<uint32_t>::max()) {
        return fail("more than 2^32 - 1 vertices");
      }
      const Vec3f x(static_cast<float>(value[0]), static_cast<float>(value[1]),
                    static_cast<float>(value[2]));
      if (!std::isfinite(x.x()) || !std::isfinite(x.y()) || !std::isfinite(x.z())) {
        return fail("vertex coordinates overflow a float");
      }
      vertices.push_back(x);
      if (n == 6 && all_colored) {
        colors.emplace_back(static_cast<float>(value[3]), static_cast<float>(value[4]),
                            static_cast<float>(value[5]));
      } else if (all_colored) {
        all_colored = false;
        colors = std::vector<Vec3f>();
      }
    } else if (key == "l") {
      if (tokens.size() < 3) {
        return fail("an 'l' element needs at least 2 vertices, got " +
                    std::to_string(tokens.size() - 1));
      }
      element_start.push_back(refs.size());
      element_line.push_back(line_number);
      for (size_t t = 1; t < tokens.size(); ++t) {
        // "v" or "v/vt": the vertex reference before the first slash.
        const std::string_view ref = tokens[t].substr(0, tokens[t].find('/'));
        int64_t i = 0;
        if (!ParseIndex(ref, &i)) {
          return fail("expected a non-zero vertex index, got " + ShowToken(tokens[t]));
        }
        // Negative: relative to the vertices defined so far (-1 is the last one). Positive:
        // 1-based, checked against all vertices at the end (a reference may come first).
        const int64_t defined = static_cast<int64_t>(vertices.size());
        const int64_t index = i < 0 ? defined + i : i - 1;
        if (index < 0 || index > static_cast<int64_t>(std::numeric_limits<uint32_t>::max()) - 1) {
          return fail("vertex index " + ShowToken(ref) + " refers to no vertex (" +
                      std::to_string(defined) + " defined so far)");
        }
        refs.push_back(static_cast<uint32_t>(index));
      }
    } else if (key == "curv" || key == "curv2" || key == "cstype" || key == "surf") {
      return fail("free-form curves and surfaces ('" + std::string(key) +
                  "') are not supported: only 'l' polylines are read");
    }
    // Anything else (faces, points, normals, texture coordinates, groups, materials) is not a
    // strand and is skipped.
  }
  if (element_start.empty()) {
    *error = "no 'l' elements (polylines) in the file";
    return false;
  }
  element_start.push_back(refs.size());
  for (size_t e = 0; e + 1 < element_start.size(); ++e) {
    for (uint64_t r = element_start[e]; r < element_start[e + 1]; ++r) {
      if (refs[r] >= vertices.size()) {
        *error = "line " + std::to_string(element_line[e]) + ": vertex index " +
                 std::to_string(uint64_t{refs[r]} + 1) + " refers to no vertex (the file has " +
                 std::to_string(vertices.size()) + ")";
        return false;
      }
    }
  }

  // Strands: each element, continued by the elements that follow it and start where it ends.
  TextStrands result;
  HairCurves& curves = result.curves;
  result.label_prefixes.push_back("line ");
  const bool with_colors = all_colored && !vertices.empty();
  uint64_t count = 0;
  uint32_t last = 0;
  for (size_t e = 0; e + 1 < element_start.size(); ++e) {
    const uint64_t first = element_start[e], stop = element_start[e + 1];
    const bool continues = e > 0 && count > 0 && refs[first] == last;
    if (!continues) {
      if (count > 0) curves.point_counts.push_back(static_cast<uint32_t>(count));
      count = 0;
      result.labels.push_back({0, element_line[e]});
      if (with_colors) curves.colors.push_back(colors[refs[first]]);
    }
    for (uint64_t r = continues ? first + 1 : first; r < stop; ++r) {
      curves.points.push_back(vertices[refs[r]]);
      ++count;
    }
    if (count > std::numeric_limits<uint32_t>::max()) {
      *error = "line " + std::to_string(element_line[e]) + ": a strand of more than 2^32 - 1 points";
      return false;
    }
    last = refs[stop - 1];
  }
  if (count > 0) curves.point_counts.push_back(static_cast<uint32_t>(count));
  *out = std::move(result);
  return true;
}

}  // namespace ringlet::io_internal
