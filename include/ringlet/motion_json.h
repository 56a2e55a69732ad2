// Motion files of `ringlet simulate --motion FILE.json` (docs/dynamics.md, "Motion files"):
// keyframes of a rigid head motion, checked field by field.
#pragma once

#include <string>

#include "ringlet/math.h"
#include "ringlet/motion.h"

namespace ringlet {

/// Parses a motion document:
///   {"description": "...", "pivot": [x, y, z],
///    "keyframes": [{"time": s, "translation": [x, y, z], "axis": [x, y, z], "angle": deg}, ...]}
/// "pivot" (m) is optional (default_pivot when absent); in each keyframe only "time" is required
/// (translation [0, 0, 0], axis [0, 0, 1], angle 0 degrees by default). On failure *error gets one
/// line naming the field ("keyframes[2].time: expected a finite number >= 0 (s), got -1") and
/// *motion is untouched. Never throws.
bool ParseMotionText(const std::string& text, const Vec3& default_pivot, HeadMotion* motion,
                     std::string* error);

/// Reads and parses a motion file; errors start with the path.
bool LoadMotion(const std::string& path, const Vec3& default_pivot, HeadMotion* motion,
                std::string* error);

}  // namespace ringlet
