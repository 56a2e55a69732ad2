// Masters files: explicit master strands of a hairstyle, each with its root, segments and rest
// shape (docs/hairstyle-format.md, "Explicit masters"; written by `ringlet invert`).
#pragma once

#include <string>
#include <vector>

#include "ringlet/hairstyle.h"

namespace ringlet {

/// Parses the text of a masters file ({"masters": [{"root": {"position", "frame"},
/// "segment_lengths", ...}, ...]}): every field checked where it is read (unknown, missing, wrong
/// type, out of range; the triples of "rest_curvatures" and "curvatures" counted against
/// "segment_lengths"; at most kMaxMasters masters and kMaxSegments segments each, the counts
/// checked before anything is allocated for them). On failure returns false with one line
/// naming the master and the field ("masters[3].rest_curvatures: has 19 entries, expected 20
/// (one triple per segment)") and leaves *masters untouched. Never throws.
bool ParseMastersText(const std::string& text, std::vector<ExplicitMaster>* masters,
                      std::string* error);

/// Reads and parses the masters file at path (ReadFile's size cap); messages start with the path.
bool LoadMastersFile(const std::string& path, std::vector<ExplicitMaster>* masters,
                     std::string* error);

/// The masters file of `masters` (text, ending with a newline), every field written that is
/// given (optional fields only when set); numbers are the shortest decimals that read back
/// bit-identical, so ParseMastersText returns the same masters.
std::string MastersToString(const std::vector<ExplicitMaster>& masters);

/// The explicit master of one model: its root, frame, segments, section, material, natural
/// curvature, rest shape and support offsets (no start, layer, wisp radius or clearance).
ExplicitMaster ExplicitMasterOf(const StrandModel& model);

/// The explicit masters that rebuild `masters` bit for bit (BuildMasters with them gives the
/// same models, layers, wisp radii and clearances): each model's root, frame, segments,
/// section, material, natural curvature and rest shape, with its layer, wisp radius and
/// contact radius. `starts`, when not null, gives each master's start curvatures (one per
/// master, each empty or 3n).
std::vector<ExplicitMaster> ExplicitMastersOf(const HairstyleMasters& masters,
                                              const std::vector<VecX>* starts = nullptr);

}  // namespace ringlet
