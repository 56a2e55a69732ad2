// Wavefront OBJ lines: 'v' vertices and 'l' elements, one per segment (default) or one per
// strand (Wavefront's OBJ specification, "Line" element: l v1 v2 ... with 1-based vertex
// references).
#include "ringlet/obj_export.h"

#include <cmath>
#include <numbers>

#include "io/curves_check.h"
#include "ringlet/atomic_file.h"

namespace ringlet {

using io_internal::AppendNumber;

bool EncodeObj(const HairCurves& curves, std::string* text, std::string* error) {
  return EncodeObj(curves, ObjExportOptions{}, text, error);
}

bool EncodeObj(const HairCurves& curves, const ObjExportOptions& options, std::string* text,
               std::string* error) {
  std::string why;
  if (!CheckHairCurves(curves, "curves", &why)) {
    if (error) *error = why;
    return false;
  }
  const bool with_colors = !curves.colors.empty();
  // Everything is checked: from here on nothing fails, so write straight into *text (reusing
  // its capacity).
  std::string& out = *text;
  out.clear();
  const size_t per_point = (options.polylines ? 56 : 72) + (with_colors ? 24 : 0);
  out.reserve(per_point * curves.points.size() + 512);
  out += "# ringlet hair curves: ";
  AppendNumber(&out, static_cast<long long>(curves.NumStrands()));
  out += " strands, ";
  AppendNumber(&out, static_cast<long long>(curves.NumPoints()));
  out += " points\n# units: metres; axes: right-handed, z up (an importer that assumes y up needs "
         "Forward Y, Up Z)\n";
  out += options.polylines ? "# one 'l' polyline per strand, root to tip\n"
                           : "# one 2-vertex 'l' segment per edge, root to tip\n";
  out += "# fibre widths are not stored (OBJ has no per-vertex width)";
  out += with_colors ? "; 'v x y z r g b' carries the strand colour\n" : "\n";
  out += "o hair\n";
  size_t first = 0;
  std::string color;  // " r g b" of the strand, formatted once and repeated on its points
  for (size_t k = 0; k < curves.point_counts.size(); ++k) {
    if (with_colors) {
      color.clear();
      for (int c = 0; c < 3; ++c) {
        color += ' ';
        AppendNumber(&color, curves.colors[k][c]);
      }
    }
    for (size_t i = first; i < first + curves.point_counts[k]; ++i) {
      // "v x y z" formatted in a local buffer and appended once.
      const Vec3f& x = curves.points[i];
      char buffer[64];
      char* p = buffer;
      *p++ = 'v';
      for (int c = 0; c < 3; ++c) {
        *p++ = ' ';
        p = io_internal::WriteNumber(p, x[c]);
      }
      out.append(buffer, p);
      out += color;
      out += '\n';
    }
    first += curves.point_counts[k];
  }
  first = 0;
  for (uint32_t count : curves.point_counts) {
    if (options.polylines) {
      out += 'l';
      for (size_t i = first; i < first + count; ++i) {
        out += ' ';
        AppendNumber(&out, static_cast<long long>(i + 1));
      }
      out += '\n';
    } else {
      for (size_t i = first; i + 1 < first + count; ++i) {  // segment (i, i + 1), 1-based
        out += "l ";
        AppendNumber(&out, static_cast<long long>(i + 1));
        out += ' ';
        AppendNumber(&out, static_cast<long long>(i + 2));
        out += '\n';
      }
    }
    first += count;
  }
  return true;
}

bool WriteObj(const std::string& path, const HairCurves& curves, bool overwrite,
              std::string* error) {
  std::string text, why;
  if (!EncodeObj(curves, &text, &why)) {
    if (error) *error = DisplayPath(path) + ": " + why;
    return false;
  }
  return WriteFileAtomically(path, text, overwrite, error);
}

namespace {

// "v x y z" of a double point (shortest round-trip text of each coordinate).
void AppendVertex(std::string* out, const Vec3& x) {
  *out += 'v';
  for (int c = 0; c < 3; ++c) {
    *out += ' ';
    AppendNumber(out, x[c]);
  }
  *out += '\n';
}

void AppendFace(std::string* out, long long a, long long b, long long c) {
  *out += 'f';
  for (long long i : {a, b, c}) {
    *out += ' ';
    AppendNumber(out, i);
  }
  *out += '\n';
}

}  // namespace

void EncodeBodyObj(const Body& body, std::string* text) {
  std::string& out = *text;
  out.clear();
  out += "# ringlet body: ";
  AppendNumber(&out, static_cast<long long>(body.spheres().size()));
  out += " spheres (UV spheres of ";
  AppendNumber(&out, static_cast<long long>(kBodySphereSegments));
  out += " x ";
  AppendNumber(&out, static_cast<long long>(kBodySphereRings));
  out += "), ";
  AppendNumber(&out, static_cast<long long>(body.meshes().size()));
  out += " meshes\n# units: metres; axes: right-handed, z up (an importer that assumes y up needs "
         "Forward Y, Up Z)\n";
  long long base = 1;  // 1-based index of the component's first vertex
  for (size_t k = 0; k < body.spheres().size(); ++k) {
    const Sphere& sphere = body.spheres()[k];
    out += "o ";
    out += sphere.name.empty() ? "sphere_" + std::to_string(k) : sphere.name;
    out += '\n';
    // Vertices: north pole, rings j = 1..rings-1 of `segments` vertices each (polar angle
    // pi j / rings, azimuth 2 pi i / segments), south pole.
    const int segments = kBodySphereSegments, rings = kBodySphereRings;
    AppendVertex(&out, sphere.center + sphere.radius * Vec3::UnitZ());
    for (int j = 1; j < rings; ++j) {
      const double v = std::numbers::pi * j / rings;
      for (int i = 0; i < segments; ++i) {
        const double u = 2.0 * std::numbers::pi * i / segments;
        const Vec3 n(std::sin(v) * std::cos(u), std::sin(v) * std::sin(u), std::cos(v));
        AppendVertex(&out, sphere.center + sphere.radius * n);
      }
    }
    AppendVertex(&out, sphere.center - sphere.radius * Vec3::UnitZ());
    const long long north = base;
    const long long south = base + 1 + static_cast<long long>(rings - 1) * segments;
    // Vertex i (mod segments) of ring j in 1..rings-1.
    const auto ring = [&](int j, int i) {
      return base + 1 + static_cast<long long>(j - 1) * segments + i % segments;
    };
    // Counter-clockwise seen from outside: azimuth grows counter-clockwise about +z.
    for (int i = 0; i < segments; ++i) AppendFace(&out, north, ring(1, i), ring(1, i + 1));
    for (int j = 1; j < rings - 1; ++j) {
      for (int i = 0; i < segments; ++i) {
        AppendFace(&out, ring(j, i), ring(j + 1, i), ring(j + 1, i + 1));
        AppendFace(&out, ring(j, i), ring(j + 1, i + 1), ring(j, i + 1));
      }
    }
    for (int i = 0; i < segments; ++i) {
      AppendFace(&out, ring(rings - 1, i), south, ring(rings - 1, i + 1));
    }
    base = south + 1;
  }
  for (size_t k = 0; k < body.meshes().size(); ++k) {
    const TriangleMesh& mesh = body.meshes()[k];
    out += "o ";
    out += mesh.name().empty() ? "mesh_" + std::to_string(k) : mesh.name();
    out += '\n';
    for (const Vec3& x : mesh.vertices()) AppendVertex(&out, x);
    for (const auto& t : mesh.triangles()) AppendFace(&out, base + t[0], base + t[1], base + t[2]);
    base += static_cast<long long>(mesh.vertices().size());
  }
}

}  // namespace ringlet
