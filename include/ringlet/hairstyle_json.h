// Hairstyle files: the JSON description of a full head of hair (docs/hairstyle-format.md).
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>

#include "ringlet/hairstyle.h"

namespace ringlet {

/// Builds a hairstyle from a parsed JSON document, checking every field (unknown, missing,
/// wrong type, out of range). Relative paths (the body file, OBJ meshes) are taken relative to
/// base_directory. On failure leaves *style untouched, writes one line naming the field into
/// *error ("hair.origin: expected one of \"asian\", \"caucasian\", \"african\", got \"martian\"")
/// and returns false. Never throws.
bool ParseHairstyle(const nlohmann::json& document, const std::string& base_directory,
                    Hairstyle* style, std::string* error);

/// Reads and parses the hairstyle file at path (relative paths are relative to its directory).
/// Syntax errors give line and column; every message starts with the path. Never throws.
bool LoadHairstyle(const std::string& path, Hairstyle* style, std::string* error);

}  // namespace ringlet
