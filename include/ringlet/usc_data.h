// USC-HairSalon's binary hair format (.data), reading and writing HairCurves.
//
// The format of the USC-HairSalon database (Hu, Ma, Luo and Li, "Single-view hair modeling
// using a hairstyle database", SIGGRAPH 2015), as its public readers and writers use it (the
// database has no written specification; docs/file-formats.md cites the sources):
//   int32 number of strands
//   per strand: int32 number of vertices n, then n float32 (x, y, z) triples
// little-endian, nothing else (no header, no widths). The database's models are in metres with
// y up, each with 10,000 strands of 1 or 100 vertices, "1 vertex strand means no hair grown from
// this root"; Hair20k (the data set of Perm, He et al. 2024) uses the same format and leaves
// such strands out.
#pragma once

#include <string>
#include <string_view>

#include "ringlet/hair_curves.h"
#include "ringlet/strand_targets.h"

namespace ringlet {

/// Encodes curves (metres, z up) as the bytes of a .data file: coordinates in file units
/// (multiplied by options.units_per_metre) and axes (options.up_axis = kY writes the database's
/// y-up convention: the inverse of the reading rotation, (x, y, z) -> (x, z, -y)). Widths and
/// colours are not stored (the format has none). The curves must pass CheckHairCurves, have at
/// most 2^31 - 1 strands and points per strand, and stay finite in file units; otherwise false
/// with one line in *error naming the field ("curves.points[7]: ...").
bool EncodeUscData(const HairCurves& curves, const StrandTargetOptions& options,
                   std::string* bytes, std::string* error);

/// EncodeUscData, then WriteFileAtomically (the file appears only complete). When overwrite is
/// false an existing file is an error. Errors start with path.
bool WriteUscData(const std::string& path, const HairCurves& curves,
                  const StrandTargetOptions& options, bool overwrite, std::string* error);

/// Decodes the bytes of a .data file into *curves (metres, z up per options; every width
/// options.default_width). Strands of 0 or 1 vertex (no hair at this root) are skipped and
/// counted in summary->skipped_empty_strands. Every count is checked against the bytes left
/// before anything is allocated for it: the strand count against the 4 bytes each strand needs
/// at least, each vertex count against the bytes left; negative counts, truncated data and
/// trailing bytes are errors. Strands are then validated as by CheckStrandTargets. On failure
/// *curves is unchanged and *error gets one line ("strand 3, point 7: ...", "header: ...").
bool DecodeUscData(std::string_view bytes, const StrandTargetOptions& options, HairCurves* curves,
                   StrandTargetSummary* summary, std::string* error);

}  // namespace ringlet
