// Wavefront OBJ export of hair curves as polylines: one 'v' line per point and one 'l' element
// per strand (1-based vertex indices), so any OBJ reader that keeps line elements shows the
// centrelines. Units metres, z up; widths are not stored (OBJ has no per-vertex width).
// Strand colours, when present, are written with the common "v x y z r g b" vertex-colour
// extension (read by Blender and tinyobjloader; other readers may ignore or reject it).
#pragma once

#include <string>

#include "ringlet/hair_curves.h"

namespace ringlet {

/// Writes curves as OBJ text into *text, with a comment header (strand and point counts, units,
/// axes). Returns false with one line in *error naming the field if the curves are inconsistent
/// (sizes, counts < 2, non-finite values, negative widths).
bool EncodeObj(const HairCurves& curves, std::string* text, std::string* error);

/// EncodeObj, then WriteFileAtomically (the file appears only complete). Errors start with path.
bool WriteObj(const std::string& path, const HairCurves& curves, bool overwrite,
              std::string* error);

}  // namespace ringlet
