// Body descriptions in JSON: spheres and OBJ meshes (docs/body.md).
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <string_view>

#include "ringlet/body.h"

namespace ringlet {

/// Crease-rounding radius of bodies read from JSON when "blend" is not given (m): the smooth
/// union of Body::Create, which keeps the contact penalty's gradient continuous where spheres
/// meet; strands float at most blend/4 = 1.25 mm above those seams.
inline constexpr double kDefaultBodyBlend = 0.005;

/// Mesh distance of bodies read from JSON: a distance grid ("mesh_distance": "grid", the
/// default; "exact" for tree queries) of spacing "grid_spacing" (m) clamped at "grid_band" (m),
/// MeshDistanceOptions. The spacing was chosen by measurement (docs/benchmarks.md, "Mesh bodies").
inline constexpr double kDefaultGridSpacing = 0.005;
inline constexpr double kDefaultGridBand = 0.03;

/// Builds a body from a JSON object
///   {"spheres": [{"name": "head", "center": [0, 0, 0], "radius": 0.1}, ...],
///    "meshes": [{"obj": "mannequin.obj"}, ...], "blend": 0.005, "description": "...",
///    "mesh_distance": "grid", "grid_spacing": 0.005, "grid_band": 0.03}
/// with an optional "moves_with": "head" | "torso" per sphere, and per mesh entry either one part
/// for every object of its OBJ file or {"object or group name": "head" | "torso", ...}
/// (BodyPart; unset: DefaultBodyPart of the name).
/// where every field is optional but the body needs at least one sphere or mesh: centres in m
/// (3 finite numbers), radii in m (finite, > 0), names unique among the spheres, OBJ paths
/// relative to base_directory (absolute paths are kept; LoadObjMeshes reads them, one closed
/// component per OBJ object or group). Unknown fields are errors. path is the location of the
/// object in the caller's document and prefixes every message ("body" gives
/// "body.spheres[2].radius: expected a positive number (m), got -0.1"; empty for a document of
/// its own). On success fills *body and returns true; on failure leaves *body untouched,
/// writes one line into *error and returns false. Never throws.
bool ParseBody(const nlohmann::json& document, std::string_view path,
               const std::string& base_directory, Body* body, std::string* error);

/// Parses the text of a standalone body file (JSON syntax errors with line and column, then
/// ParseBody at the top level); OBJ paths are relative to base_directory. Messages carry no
/// file name. Never throws.
bool ParseBodyText(const std::string& text, const std::string& base_directory, Body* body,
                   std::string* error);

/// Reads a standalone body file (the object above at the top level); OBJ paths are relative
/// to the file's directory. Every message starts with the file's path ("bodies/m.json: line 3,
/// column 14: invalid JSON: ...", "bodies/m.json: spheres[0].radius: ..."). Never throws.
bool LoadBody(const std::string& path, Body* body, std::string* error);

}  // namespace ringlet
