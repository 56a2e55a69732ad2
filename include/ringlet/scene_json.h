// Scene files: the JSON description of the strands to solve (docs/scene-format.md).
#pragma once

#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "ringlet/body.h"
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
  /// The body of the optional "body" member (a body file name or object, docs/body.md), null
  /// without one. Every strand's contact.obstacle is this body (penalty contact, contact.h) and
  /// contact.clearance the optional "contact": {"clearance": m} (default 0).
  std::shared_ptr<const Body> body;
};

/// Builds a scene from a parsed JSON document, checking every field: unknown or missing fields,
/// wrong types, values out of range and inconsistent combinations are all errors. On success
/// fills *scene and returns true; on failure leaves *scene untouched, writes one line naming the
/// field into *error (e.g. "strands[2].radius: expected a finite number > 0 (m), got -1") and
/// returns false. Never throws.
bool ParseScene(const nlohmann::json& document, Scene* scene, std::string* error);

/// The same, with a body file name in "body" (and OBJ paths in an inline body) relative to
/// base_directory; the overload above takes them relative to the current directory.
bool ParseScene(const nlohmann::json& document, const std::string& base_directory, Scene* scene,
                std::string* error);

/// Parses scene text: JSON syntax errors are reported with their line and column ("line 3,
/// column 14: invalid JSON: ..."), duplicate fields are errors, then ParseScene checks the rest.
/// Never throws.
bool ParseSceneText(const std::string& text, Scene* scene, std::string* error);

/// Reads and parses the scene file at path; a "body" file name is relative to the scene file's
/// directory. Every error message starts with the path
/// ("scene.json: strands[0].length: missing required field ..."). Never throws.
bool LoadScene(const std::string& path, Scene* scene, std::string* error);

/// The scene document of models (docs/scene-format.md) that ParseScene reads back to the same
/// models up to rounding: per strand length, segment_lengths, radius, eccentricity, material,
/// natural_curvature / natural_twist, rest_curvatures (when the model has one) and root
/// (position, tangent t, normal n1); gravity from the first model (all must share it). Contact
/// (a body) is not written: add "body" to the document to solve against one. Text, indented, ending with a newline.
std::string SceneToString(const std::vector<StrandModel>& models);

/// The name of a minimization method in scene files: "bfgs", "lbfgs", "newton" or "auto".
const char* MethodName(Method method);

}  // namespace ringlet
