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

#include <cstddef>
#include <string>
#include <vector>

#include "ringlet/atomic_file.h"
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

/// EncodeUsdaSequence's text written frame by frame, so that a long sequence is never held in
/// memory (`ringlet simulate`): Begin writes the layer metadata, the prim and its curve counts
/// and opens the points' time samples; Append writes one frame's sample (its extent is kept:
/// two points a frame); Finish closes the samples and writes the widths, the colours and the
/// extent's samples. The bytes are those of EncodeUsdaSequence for the same frames; it takes
/// only sequences whose curve counts, widths and colours are the first frame's in every frame
/// (written once, before the points' samples, as EncodeUsdaSequence writes them then). The
/// points of a frame are formatted in parallel (TBB, in the caller's arena) in fixed blocks
/// handed to the sink in order: the bytes do not depend on the thread count. Memory: the
/// first frame's counts, widths and colours, a few MB of text, 24 bytes a frame.
class UsdaSequenceWriter {
 public:
  /// Checks options and the first frame (CheckHairCurves) and writes everything before the
  /// first sample through sink. frames (>= 1) is how many frames Append will receive (the
  /// header says it). False with one line in *error naming the field; "cannot write" when the
  /// sink refused (its owner knows why).
  bool Begin(const HairCurves& first, int frames, const UsdExportOptions& options,
             FileSink sink, std::string* error);
  /// One frame: checked (CheckHairCurves, "frames[k]...") and compared with the first
  /// (counts, widths, colours: "frames[k].widths: differ from frame 0's ..."), then written.
  bool Append(const HairCurves& frame, std::string* error);
  /// After the last frame: the rest of the text. False if not every announced frame came.
  bool Finish(std::string* error);

 private:
  bool Flush(std::string* error);

  UsdExportOptions options_;
  FileSink sink_;
  int frames_ = 0;
  int appended_ = 0;
  bool begun_ = false;
  bool failed_ = false;
  std::vector<std::uint32_t> counts_;
  std::vector<float> widths_;
  std::vector<Vec3f> colors_;
  std::vector<Vec3f> extents_;  // two per frame: lower and upper corner
  std::string buffer_;
  std::vector<std::string> blocks_;
};

/// EncodeUsda, then WriteFileAtomically (the file appears only complete). Errors start with path.
bool WriteUsda(const std::string& path, const HairCurves& curves, const UsdExportOptions& options,
               bool overwrite, std::string* error);

/// EncodeUsdaSequence, then WriteFileAtomically. Errors start with path.
bool WriteUsdaSequence(const std::string& path, const std::vector<HairCurves>& frames,
                       const UsdExportOptions& options, bool overwrite, std::string* error);

}  // namespace ringlet
