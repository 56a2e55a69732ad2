// Body meshes from Wavefront OBJ files, read with tinyobjloader: one closed component per OBJ
// object or group, polygons triangulated here (docs/body.md).
#include <tiny_obj_loader.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "ringlet/atomic_file.h"
#include "ringlet/body.h"

namespace ringlet {
namespace {

// The first line of a tinyobjloader message, without its trailing punctuation noise.
std::string FirstLine(const std::string& text) {
  std::string line = text.substr(0, text.find('\n'));
  while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
  return line;
}

// Splits the simple polygon `polygon` (vertex indices, counter-clockwise about its Newell
// normal) into triangles of the same orientation by ear clipping (Meisters, "Polygons have
// ears", 1975): repeatedly cut off a convex corner whose triangle holds no other vertex.
// Convex polygons give a fan. Returns false if the polygon is not simple and planar enough.
bool Triangulate(const std::vector<int>& polygon, const std::vector<Vec3>& vertices,
                 std::vector<TriangleMesh::Triangle>* triangles) {
  if (polygon.size() == 3) {
    triangles->push_back({polygon[0], polygon[1], polygon[2]});
    return true;
  }
  auto position = [&](int index) -> const Vec3& { return vertices[static_cast<size_t>(index)]; };
  // Newell's normal: the area vector of the polygon, robust for non-convex polygons.
  Vec3 normal = Vec3::Zero();
  for (size_t i = 0; i < polygon.size(); ++i) {
    normal += position(polygon[i]).cross(position(polygon[(i + 1) % polygon.size()]));
  }
  if (!(normal.norm() > 0.0)) return false;
  std::vector<int> remaining = polygon;
  while (remaining.size() > 3) {
    const size_t n = remaining.size();
    bool clipped = false;
    for (size_t i = 0; i < n && !clipped; ++i) {
      const int ia = remaining[(i + n - 1) % n], ib = remaining[i], ic = remaining[(i + 1) % n];
      const Vec3 &a = position(ia), &b = position(ib), &c = position(ic);
      // A convex corner turns counter-clockwise about the normal.
      if (!((b - a).cross(c - b).dot(normal) > 0.0)) continue;
      // No other remaining vertex inside (or on) the triangle (a, b, c).
      bool empty = true;
      for (size_t j = 0; j < n && empty; ++j) {
        const int ip = remaining[j];
        if (ip == ia || ip == ib || ip == ic) continue;
        const Vec3& p = position(ip);
        if ((b - a).cross(p - a).dot(normal) >= 0.0 && (c - b).cross(p - b).dot(normal) >= 0.0 &&
            (a - c).cross(p - c).dot(normal) >= 0.0) {
          empty = false;
        }
      }
      if (!empty) continue;
      triangles->push_back({ia, ib, ic});
      remaining.erase(remaining.begin() + static_cast<std::ptrdiff_t>(i));
      clipped = true;
    }
    if (!clipped) return false;
  }
  triangles->push_back({remaining[0], remaining[1], remaining[2]});
  return true;
}

// The tokens of one OBJ line, separated by blanks.
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

// A token shown in a message: printable ASCII only, cut to a few characters.
std::string ShowToken(std::string_view token) {
  std::string shown;
  for (char c : token.substr(0, 24)) {
    const unsigned char u = static_cast<unsigned char>(c);
    shown += u >= 0x20 && u < 0x7f ? c : '?';
  }
  return "\"" + shown + (token.size() > 24 ? "...\"" : "\"");
}

// Whether token is a whole finite number (strtod must use every character: "1.5x" is not).
bool IsFiniteNumber(std::string_view token) {
  const std::string text(token);
  char* end = nullptr;
  errno = 0;
  const double x = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && !text.empty() && std::isfinite(x) && errno == 0;
}

// Whether token is a whole non-zero integer that fits an int ("8x" is not).
bool IsIndex(std::string_view token) {
  const std::string text(token);
  char* end = nullptr;
  errno = 0;
  const long long i = std::strtoll(text.c_str(), &end, 10);
  return !text.empty() && end == text.c_str() + text.size() && errno == 0 && i != 0 &&
         i >= -2147483647LL && i <= 2147483647LL;
}

// tinyobjloader reads what it cannot parse as 0 ("nan", "abc", a missing coordinate) and stops
// at the first non-digit of an index ("8x" -> 8), so the vertex and face lines are checked here
// first: v lines hold 3 finite coordinates (optionally a weight, or an RGB colour), f lines
// vertex references v, v/vt, v//vn or v/vt/vn made of non-zero integers. Other lines are left to
// tinyobjloader. On failure *error gets "line N: ...".
bool CheckObjText(const std::string& text, std::string* error) {
  size_t line_number = 0;
  size_t start = 0;
  while (start < text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string_view line(text.data() + start, end - start);
    start = end + 1;
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    const size_t comment = line.find('#');
    if (comment != std::string_view::npos) line = line.substr(0, comment);
    const std::vector<std::string_view> tokens = Tokens(line);
    if (tokens.empty()) continue;
    const std::string at = "line " + std::to_string(line_number) + ": ";
    if (tokens[0] == "v") {
      const size_t n = tokens.size() - 1;
      if (n != 3 && n != 4 && n != 6) {
        *error =
            at + "vertex: expected 3 coordinates x y z (m), got " + std::to_string(n) + " values";
        return false;
      }
      for (size_t k = 1; k < tokens.size(); ++k) {
        if (!IsFiniteNumber(tokens[k])) {
          *error = at + "vertex: expected finite numbers, got " + ShowToken(tokens[k]);
          return false;
        }
      }
    } else if (tokens[0] == "f") {
      if (tokens.size() < 4) {
        *error =
            at + "face: expected at least 3 vertices, got " + std::to_string(tokens.size() - 1);
        return false;
      }
      for (size_t k = 1; k < tokens.size(); ++k) {
        // v, v/vt, v//vn or v/vt/vn: the vertex index is required, the others optional.
        const std::string_view ref = tokens[k];
        const size_t first = ref.find('/');
        const std::string_view v = ref.substr(0, first);
        bool good = IsIndex(v);
        if (good && first != std::string_view::npos) {
          const std::string_view rest = ref.substr(first + 1);
          const size_t second = rest.find('/');
          const std::string_view vt = rest.substr(0, second);
          good = vt.empty() ? second != std::string_view::npos : IsIndex(vt);
          if (good && second != std::string_view::npos) {
            const std::string_view vn = rest.substr(second + 1);
            good = IsIndex(vn);
          }
        }
        if (!good) {
          *error = at +
                   "face: expected vertex references v, v/vt, v//vn or v/vt/vn (non-zero "
                   "integers), got " +
                   ShowToken(ref);
          return false;
        }
      }
    }
  }
  return true;
}

}  // namespace

bool LoadObjMeshes(const std::string& path, std::vector<TriangleMesh>* meshes, std::string* error) {
  std::string text;
  if (!ReadFile(path, &text, error, kMaxObjFileBytes)) return false;
  std::string why;
  if (!ParseObjMeshes(text, meshes, &why)) {
    if (error) *error = DisplayPath(path) + ": " + why;
    return false;
  }
  return true;
}

bool ParseObjMeshes(std::string_view text_view, std::vector<TriangleMesh>* meshes,
                    std::string* error) {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (text_view.size() > kMaxObjFileBytes) {
    return fail("is " + std::to_string(text_view.size()) + " bytes, more than the limit of " +
                FormatBytes(kMaxObjFileBytes) + " for this kind of file");
  }
  const std::string text(text_view);
  std::string text_error;
  if (!CheckObjText(text, &text_error)) return fail(text_error);

  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warnings, errors;
  std::istringstream stream(text);
  bool parsed = false;
  try {
    // No material reader (materials do not matter for collisions); polygons are kept whole
    // (triangulate = false) and triangulated below, preserving their orientation.
    parsed = tinyobj::LoadObj(&attrib, &shapes, &materials, &warnings, &errors, &stream,
                              /*readMatFn=*/nullptr, /*triangulate=*/false);
  } catch (const std::exception& e) {
    return fail(std::string("cannot parse: ") + e.what());
  }
  if (!parsed || !errors.empty()) {
    return fail("invalid OBJ: " +
                (errors.empty() ? std::string("parse failure") : FirstLine(errors)));
  }

  std::vector<Vec3> vertices(attrib.vertices.size() / 3);
  for (size_t i = 0; i < vertices.size(); ++i) {
    vertices[i] =
        Vec3(attrib.vertices[3 * i], attrib.vertices[3 * i + 1], attrib.vertices[3 * i + 2]);
    if (!vertices[i].allFinite()) {
      return fail("vertex " + std::to_string(i + 1) + " has a non-finite coordinate");
    }
  }

  std::vector<TriangleMesh> result;
  size_t face_number = 0;  // 1-based, counted over the whole file
  for (size_t s = 0; s < shapes.size(); ++s) {
    const tinyobj::mesh_t& mesh = shapes[s].mesh;
    if (mesh.num_face_vertices.empty()) continue;  // lines or points only
    const std::string name =
        shapes[s].name.empty() ? "object " + std::to_string(s + 1) : shapes[s].name;
    std::vector<TriangleMesh::Triangle> triangles;
    triangles.reserve(mesh.num_face_vertices.size());
    size_t offset = 0;
    for (size_t f = 0; f < mesh.num_face_vertices.size(); ++f) {
      ++face_number;
      const size_t count = mesh.num_face_vertices[f];
      std::vector<int> polygon(count);
      for (size_t k = 0; k < count; ++k) {
        const int index = mesh.indices[offset + k].vertex_index;
        if (index < 0 || static_cast<size_t>(index) >= vertices.size()) {
          return fail(name + ": face " + std::to_string(face_number) + " uses vertex " +
                      std::to_string(static_cast<long>(index) + 1) + ", out of range (" +
                      std::to_string(vertices.size()) + " vertices)");
        }
        polygon[k] = index;
      }
      offset += count;
      if (count < 3) {
        return fail(name + ": face " + std::to_string(face_number) + " has " +
                    std::to_string(count) + " vertices (at least 3 expected)");
      }
      if (!Triangulate(polygon, vertices, &triangles)) {
        return fail(name + ": face " + std::to_string(face_number) + " (" + std::to_string(count) +
                    " vertices) cannot be triangulated: not a simple planar polygon");
      }
    }
    TriangleMesh component;
    std::string why;
    // All the file's vertices go in (unused ones are dropped), so messages quote the file's
    // 1-based vertex numbers.
    if (!TriangleMesh::Create(vertices, std::move(triangles), name, &component, &why,
                              /*message_index_base=*/1)) {
      return fail(why);
    }
    result.push_back(std::move(component));
  }
  if (result.empty()) return fail("no faces (a body mesh needs closed triangle surfaces)");
  *meshes = std::move(result);
  return true;
}

}  // namespace ringlet
