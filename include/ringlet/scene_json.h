// Scene files: the JSON description of the strands to solve (docs/scene-format.md).
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "ringlet/statics.h"
#include "ringlet/strand_model.h"

namespace ringlet {

/// Default number of segments of a strand: the paper samples each strand into 15 helices.
inline constexpr int kDefaultSegments = 15;
/// Default mean radius of a strand (m): 50 um, the paper's value for human hair.
inline constexpr double kDefaultRadius = 50e-6;
/// Two segment-length lists agree with the strand length when their sum is within this relative
/// tolerance of it (dimensionless).
inline constexpr double kSegmentLengthSumTolerance = 1e-9;

/// Everything a scene file describes: the strands, each with its own gravity, and the options of
/// the solver shared by all of them.
struct Scene {
  /// The strands in file order; each one is valid (IsValid(const StrandModel&)).
  std::vector<StrandModel> strands;
  /// Options of SolveStrand, from the optional "solver" object (SolveOptions defaults otherwise).
  SolveOptions solver;
};

/// Builds a scene from a parsed JSON document, checking every field: unknown or missing fields,
/// wrong types, values out of range and inconsistent combinations are all errors. On success
/// fills *scene and returns true; on failure leaves *scene untouched, writes one line naming the
/// field into *error (e.g. "strands[2].radius: expected a finite number > 0 (m), got -1") and
/// returns false. Never throws.
bool ParseScene(const nlohmann::json& document, Scene* scene, std::string* error);

/// Parses scene text: JSON syntax errors are reported with their line and column ("line 3,
/// column 14: invalid JSON: ..."), duplicate fields are errors, then ParseScene checks the rest.
/// Never throws.
bool ParseSceneText(const std::string& text, Scene* scene, std::string* error);

/// Reads and parses the scene file at path. Every error message starts with the path
/// ("scene.json: strands[0].length: missing required field ..."). Never throws.
bool LoadScene(const std::string& path, Scene* scene, std::string* error);

/// The scene document of models (docs/scene-format.md) that ParseScene reads back to the same
/// models up to rounding: per strand length, segment_lengths, radius, eccentricity, material,
/// natural_curvature / natural_twist, rest_curvatures (when the model has one) and root
/// (position, tangent t, normal n1); gravity from the first model (all must share it). Contact
/// is not part of the scene format and is left out. Text, indented, ending with a newline.
std::string SceneToString(const std::vector<StrandModel>& models);

/// The name of a minimization method in scene files: "bfgs", "lbfgs", "newton" or "auto".
const char* MethodName(Method method);

}  // namespace ringlet
