// USD text (.usda) export of hair curves as one UsdGeom BasisCurves prim, for one shape or a
// time-sampled sequence (e.g. a grow animation).
//
// Schema: UsdGeomBasisCurves / UsdGeomCurves (openusd.org API docs): type = "linear",
// curveVertexCounts, points, widths (vertex interpolation: one diameter per point), extent
// (bounding box of the points padded by half the largest width, as UsdGeomCurves::ComputeExtent),
// primvars:displayColor with uniform interpolation (one colour per curve) when colours exist.
// Stage metadata: metersPerUnit = 1, upAxis = "Z", defaultPrim = the curves prim.
// Numbers are written with std::to_chars (shortest text that reads back to the same float,
// independent of the locale), so the output is deterministic and floats round-trip exactly.
#pragma once

#include <string>
#include <vector>

#include "ringlet/hair_curves.h"

namespace ringlet {

/// Options of the USD text export.
struct UsdExportOptions {
  /// Name of the BasisCurves prim, which is also the stage's default prim: a USD identifier
  /// ([A-Za-z_][A-Za-z0-9_]*).
  std::string prim_name = "hair";
  /// Time code of the first frame of a sequence; frame i is at start_time_code + i. The default
  /// 1 matches Blender's default first frame. Ignored for a single shape (no time samples).
  int start_time_code = 1;
  /// Time codes (frames) per second of a sequence: timeCodesPerSecond and framesPerSecond
  /// (1/s, finite and > 0).
  double time_codes_per_second = 24.0;

  /// True if the options can be used; otherwise *why (if given) names the field and the problem.
  bool IsValid(std::string* why) const;
};

/// Writes curves (metres, z up) as .usda text into *text. Returns false with one line in *error
/// naming the field if the curves are inconsistent (sizes, counts < 2, non-finite values,
/// negative widths) or the options invalid.
bool EncodeUsda(const HairCurves& curves, const UsdExportOptions& options, std::string* text,
                std::string* error);

/// Writes a sequence of shapes as one time-sampled BasisCurves prim: points and extent are
/// time-sampled; curveVertexCounts, widths and displayColor are written once when identical in
/// every frame and time-sampled otherwise (so the number of curves may change). Stage metadata
/// adds startTimeCode, endTimeCode, timeCodesPerSecond and framesPerSecond. Either every frame
/// has colours or none. An empty sequence is an error.
bool EncodeUsdaSequence(const std::vector<HairCurves>& frames, const UsdExportOptions& options,
                        std::string* text, std::string* error);

/// EncodeUsda, then WriteFileAtomically (the file appears only complete). Errors start with path.
bool WriteUsda(const std::string& path, const HairCurves& curves, const UsdExportOptions& options,
               bool overwrite, std::string* error);

/// EncodeUsdaSequence, then WriteFileAtomically. Errors start with path.
bool WriteUsdaSequence(const std::string& path, const std::vector<HairCurves>& frames,
                       const UsdExportOptions& options, bool overwrite, std::string* error);

}  // namespace ringlet
