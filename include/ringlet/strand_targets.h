// Hair strands read from files as targets (issue 13, item 2): the polylines an inverse-statics
// fit starts from, in ringlet's convention (metres, z up), validated strand by strand.
//
// Formats, chosen by the file's extension (case-insensitive):
//   .hair  Cem Yuksel's binary format (hair_file.h)
//   .data  USC-HairSalon's binary format (usc_data.h)
//   .usda  USD text: linear BasisCurves prims (a hand-written reader of the subset that USD
//          writers emit; docs/file-formats.md lists what is accepted)
//   .obj   Wavefront polylines: 'v' and 'l' elements
// The accepted subsets, the rules (joining OBJ segments, skipping HairSalon's 1-vertex strands,
// the y-up rotation) and the limits are in docs/file-formats.md and docs/robustness.md.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ringlet/hair_curves.h"

namespace ringlet {

/// The largest target file read, whatever its format: 1 GiB (as kMaxHairFileBytes). Reading
/// holds the bytes and the curves: about 2x the file for the binary formats, about 3x for the
/// text formats (measured: docs/robustness.md).
inline constexpr std::uint64_t kMaxStrandTargetFileBytes = std::uint64_t{1} << 30;
/// The largest coordinate accepted, after conversion to metres: |x| <= 10^4 m (the renderer's
/// kMaxSceneCoordinate; a target farther away is a unit mistake, and squares of such lengths
/// stay far from float overflow in the fit).
inline constexpr double kMaxTargetCoordinate = 1e4;

/// How the files' numbers become metres, z up.
struct StrandTargetOptions {
  /// File length units per metre: file values are divided by this (1 = metres, 100 =
  /// centimetres, 1000 = millimetres). Finite and > 0. For .usda the stage's metersPerUnit is
  /// used instead (see ignore_file_metadata).
  double units_per_metre = 1.0;
  /// The file's up axis. kZ: taken as is (ringlet's own files). kY: a right-handed y-up file is
  /// turned z up by the rotation of +90 degrees about x, (x, y, z) -> (x, -z, y), the conversion
  /// Blender and USD apply to y-up assets (so a y-up head that faces +z faces -y afterwards).
  /// For .usda the stage's upAxis is used instead (see ignore_file_metadata).
  enum class UpAxis { kZ, kY } up_axis = UpAxis::kZ;
  /// Fibre diameter (m) given to every point of a file without widths (.data, .obj, and .usda
  /// without widths): 70 um, about the diameter of European hair (Franbourg et al. 2003, the
  /// source of hair_type.cpp's sections). Finite and >= 0.
  double default_width = 70e-6;
  /// .usda only: when false (default) the stage's authored metersPerUnit and upAxis decide, and
  /// USD's fallbacks where they are not authored (metersPerUnit 0.01, upAxis "Y", as
  /// UsdGeomGetStageMetersPerUnit / UsdGeomGetStageUpAxis); units_per_metre and up_axis are not
  /// used. When true, units_per_metre and up_axis replace the stage's metadata.
  bool ignore_file_metadata = false;

  /// True if the options can be used; otherwise *why (if given) names the field and the problem.
  bool IsValid(std::string* why) const;
};

/// What reading left out or decided, for a summary line.
struct StrandTargetSummary {
  /// Strands of the file that hold no hair and were skipped: HairSalon's strands of 0 or 1
  /// vertex ("1 vertex strand means no hair grown from this root", USC-HairSalon's README).
  /// Only .data files have them; any other format with such a strand is an error.
  std::uint64_t skipped_empty_strands = 0;
  /// For each strand read, its index in the file (the n-th strand, 'l' chain or curve, from 0):
  /// differs from the position in HairCurves only when strands were skipped.
  std::vector<std::uint64_t> file_strand_index;
  /// The length unit and up axis that were applied (from the options or, for .usda, the stage).
  double metres_per_unit = 1.0;
  StrandTargetOptions::UpAxis up_axis = StrandTargetOptions::UpAxis::kZ;
};

/// Reads polylines (converted to metres, z up) by extension: .hair .data .usda .obj; fills
/// HairCurves (points, point_counts, widths; colors where the file has per-strand colours;
/// major_axes when the file has frames). Every strand is validated: at least 2 points, finite
/// coordinates within kMaxTargetCoordinate, no repeated consecutive points (a zero-length
/// segment has no tangent), finite widths >= 0. Nothing is allocated from a count before the
/// count is checked against the file's size. On failure *curves is unchanged and *why gets one
/// line naming the file, strand and point ("a.obj: strand 3 (line 12), point 4: ...").
bool ReadStrandTargets(const std::string& path, const StrandTargetOptions& options,
                       HairCurves* curves, std::string* why);

/// ReadStrandTargets, also filling *summary (if given) with what was skipped and applied.
bool ReadStrandTargets(const std::string& path, const StrandTargetOptions& options,
                       HairCurves* curves, StrandTargetSummary* summary, std::string* why);

/// The checks ReadStrandTargets makes on the converted curves (also used by the writers'
/// tests): consistent sizes, >= 2 points per strand, finite coordinates within
/// kMaxTargetCoordinate, no repeated consecutive points, finite widths >= 0. Messages start
/// with "strand K, point I: " (K from file_strand_index when it is not empty).
bool CheckStrandTargets(const HairCurves& curves,
                        const std::vector<std::uint64_t>& file_strand_index, std::string* why);

}  // namespace ringlet
