// Wavefront OBJ polylines: 'v' vertices and one 'l' element per strand (Wavefront's OBJ
// specification, "Line" element: l v1 v2 ... with 1-based vertex references).
#include "ringlet/obj_export.h"

#include "io/curves_check.h"
#include "ringlet/atomic_file.h"

namespace ringlet {

using io_internal::AppendNumber;

bool EncodeObj(const HairCurves& curves, std::string* text, std::string* error) {
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
  out.reserve(56 * curves.points.size() + (with_colors ? 24 * curves.points.size() : 0) + 512);
  out += "# ringlet hair curves: ";
  AppendNumber(&out, static_cast<long long>(curves.NumStrands()));
  out += " strands, ";
  AppendNumber(&out, static_cast<long long>(curves.NumPoints()));
  out += " points\n# units: metres; axes: z up; one 'l' polyline per strand, root to tip\n";
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
    out += 'l';
    for (size_t i = first; i < first + count; ++i) {
      out += ' ';
      AppendNumber(&out, static_cast<long long>(i + 1));
    }
    out += '\n';
    first += count;
  }
  return true;
}

bool WriteObj(const std::string& path, const HairCurves& curves, bool overwrite,
              std::string* error) {
  std::string text, why;
  if (!EncodeObj(curves, &text, &why)) {
    if (error) *error = path + ": " + why;
    return false;
  }
  return WriteFileAtomically(path, text, overwrite, error);
}

}  // namespace ringlet
