// Wavefront OBJ export of hair curves: one 'v' line per point and, by default, one 2-vertex 'l'
// element per segment (1-based vertex indices), root to tip. Two-vertex lines are what every OBJ
// importer keeps: Blender 3.4's built-in importer keeps only the first edge of a longer 'l'
// polyline (checked with Blender 3.4.1), other readers drop or split polylines. The polyline form
// (one 'l' per strand) stays available for readers that keep it (ObjExportOptions::polylines):
// it is 5-15% smaller. Units metres, z up (the header comment says so: importers that
// assume y up need Forward Y, Up Z); widths are not stored (OBJ has no per-vertex width).
// Strand colours, when present, are written with the common "v x y z r g b" vertex-colour
// extension (read by Blender and tinyobjloader; other readers may ignore or reject it).
#pragma once

#include <string>

#include "ringlet/body.h"
#include "ringlet/hair_curves.h"

namespace ringlet {

/// How hair curves are written as OBJ.
struct ObjExportOptions {
  /// false (default): one 2-vertex 'l' element per segment, kept by every OBJ importer.
  /// true: one 'l' element per strand listing all its points (smaller; some importers keep only
  /// its first edge).
  bool polylines = false;
};

/// Writes curves as OBJ text into *text, with a comment header (strand and point counts, units,
/// axes). Returns false with one line in *error naming the field if the curves are inconsistent
/// (sizes, counts < 2, non-finite values, negative widths).
bool EncodeObj(const HairCurves& curves, const ObjExportOptions& options, std::string* text,
               std::string* error);
/// EncodeObj with the default options (2-vertex segments).
bool EncodeObj(const HairCurves& curves, std::string* text, std::string* error);

/// EncodeObj, then WriteFileAtomically (the file appears only complete). Errors start with path.
bool WriteObj(const std::string& path, const HairCurves& curves, bool overwrite,
              std::string* error);

/// Tessellation of a body sphere in the body OBJ: kBodySphereSegments meridians and
/// kBodySphereRings parallels (a UV sphere with a single vertex at each pole).
constexpr int kBodySphereSegments = 48;
constexpr int kBodySphereRings = 24;

/// Writes the body as OBJ text (metres, z up, like the hair): one 'o' object per component,
/// named after it ("head"; "sphere_3" / "mesh_1" when unnamed), spheres first then meshes, in
/// the body's order. A sphere becomes a closed UV sphere whose vertices lie on it (centre +
/// radius x unit direction; poles on the z axis through the centre): (rings - 1) x segments + 2
/// vertices and 2 x segments x (rings - 1) triangles, counter-clockwise seen from outside. A mesh
/// is written as it is (vertices and triangles, same orientation). 'v' and 'f' only (1-based
/// indices), no normals or texture coordinates. An empty body gives a header only.
void EncodeBodyObj(const Body& body, std::string* text);

}  // namespace ringlet
