// Cem Yuksel's binary HAIR file format (.hair): writing and reading HairCurves.
//
// Specification: http://www.cemyuksel.com/research/hairmodels/ ("HAIR File Format Specification")
// and the reference reader/writer cyHairFile.h in cyCodeBase. A 128-byte little-endian header
//   bytes  0-3   "HAIR"
//   bytes  4-7   uint32 number of strands
//   bytes  8-11  uint32 total number of points
//   bytes 12-15  uint32 bit array of the arrays present: 1 segments, 2 points, 4 thickness,
//                8 transparency, 16 colour; bits 5-31 reserved (must be 0)
//   bytes 16-19  uint32 default segment count (used when there is no segments array)
//   bytes 20-23  float default thickness     bytes 24-27  float default transparency
//   bytes 28-39  float[3] default colour     bytes 40-127 char[88] information (ASCII)
// followed by the arrays present, in this order: segments (uint16 per strand = points - 1),
// points (3 floats per point), thickness (float per point), transparency (float per point),
// colour (3 floats per point).
//
// The format has no unit. ringlet writes metres by default (see HairFileOptions::units_per_metre)
// and states the unit it used in the info text (DefaultHairInfo).
#pragma once

#include <string>
#include <string_view>

#include "ringlet/hair_curves.h"

namespace ringlet {

/// How HairCurves are written to a .hair file.
struct HairFileOptions {
  /// File length units per metre: points and thicknesses are multiplied by this when writing
  /// (1 = metres, 100 = centimetres, 1000 = millimetres). The format itself has no unit and the
  /// importers we found disagree (Epic's legacy loader multiplies file values by 10 to get cm,
  /// other viewers rescale to fit), so ringlet keeps the project's SI convention by default and
  /// says so in the info field. Must be finite and > 0. Reading needs the same value back.
  double units_per_metre = 1.0;
  /// Free text stored in the header's 88-byte info field: printable ASCII, at most 87
  /// characters (the 88th byte is the terminating zero). Empty (the default) writes
  /// DefaultHairInfo(units_per_metre), which states the unit actually used.
  std::string info;
  /// Store the per-point thickness array (fibre diameter, in file units). When false only the
  /// header's default thickness (the mean width) is stored and a reader gets that everywhere.
  bool store_thickness = true;
  /// Store the per-point colour array (each strand's colour repeated on its points) when the
  /// curves have colours. When false, or without colours, no colour array is written.
  bool store_colors = true;

  /// True if the options can be used; otherwise *why (if given) names the field and the problem.
  bool IsValid(std::string* why) const;
};

/// The info text ringlet writes by default: "ringlet hair curves; U units per metre (NAME); z up;
/// thickness: diameter", U the shortest decimal of units_per_metre ("1 unit per metre" for 1)
/// and NAME metres, centimetres or millimetres for 1, 100 and 1000 (left out otherwise). At most
/// 87 characters for any finite units_per_metre > 0. Readers (the Blender add-on) parse U back.
std::string DefaultHairInfo(double units_per_metre);

/// Encodes curves as the bytes of a .hair file into *bytes. The segments array is left out when
/// every strand has the same number of points (the header's default segment count says it).
/// Strands must have 2..65536 points (the segment count is a uint16), coordinates, widths and
/// colours must be finite, widths >= 0 and the array sizes consistent; otherwise returns false
/// with one line in *error naming the field ("curves.point_counts[3]: 70000 points ...").
bool EncodeHairFile(const HairCurves& curves, const HairFileOptions& options, std::string* bytes,
                    std::string* error);

/// Encodes curves and writes them to path atomically (WriteFileAtomically): the file appears
/// only complete. When overwrite is false an existing file is an error. Errors start with path.
bool WriteHairFile(const std::string& path, const HairCurves& curves,
                   const HairFileOptions& options, bool overwrite, std::string* error);

/// Decodes the bytes of a .hair file into *curves (metres: file values divided by
/// units_per_metre). Validates the signature, the reserved bits, the presence of the points
/// array, strand and point counts against the segments array or default, the exact size of the
/// arrays present (truncated or trailing bytes are errors), finite coordinates, and finite
/// non-negative thicknesses. Without a thickness array every width is the default thickness;
/// without a colour array curves->colors is empty; with one, each strand takes the colour of its
/// root point (HairCurves has one colour per strand). A transparency array is checked for size
/// and skipped. On failure *curves is left unchanged and *error gets one line naming the field
/// ("header.point_count: ...").
bool DecodeHairFile(std::string_view bytes, HairCurves* curves, std::string* error,
                    double units_per_metre = 1.0);

/// Reads and decodes the .hair file at path; errors start with the path.
bool ReadHairFile(const std::string& path, HairCurves* curves, std::string* error,
                  double units_per_metre = 1.0);

}  // namespace ringlet
