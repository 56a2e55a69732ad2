// Hairstyle files: the JSON description of a full head of hair (docs/hairstyle-format.md).
#pragma once

#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "ringlet/hairstyle.h"
#include "ringlet/styling.h"

namespace ringlet {

/// Builds a hairstyle from a parsed JSON document, checking every field (unknown, missing,
/// wrong type, out of range). Relative paths (the body file, OBJ meshes) are taken relative to
/// base_directory. On failure leaves *style untouched, writes one line naming the field into
/// *error ("hair.origin: expected one of \"asian\", \"caucasian\", \"african\", got \"martian\"")
/// and returns false. Never throws.
bool ParseHairstyle(const nlohmann::json& document, const std::string& base_directory,
                    Hairstyle* style, std::string* error);

/// ParseHairstyle with the body already read (shared, not copied): the document's "body" member
/// must be present but is not read again, and body stands for it (body null: read it as
/// ParseHairstyle does). For many documents over one base that differ in other fields (`ringlet
/// batch`'s items: a head mesh takes seconds to read). The caller guarantees that body is what
/// the member describes. Never throws.
bool ParseHairstyle(const nlohmann::json& document, const std::string& base_directory,
                    std::shared_ptr<const Body> body, Hairstyle* style, std::string* error);

/// The optional "operations" list of a hairstyle document (docs/hairstyle-format.md,
/// "operations"): the styling operations that `ringlet style` applies, in order, after grooming.
/// They are not part of the Hairstyle: ParseHairstyle checks them (a file with bad operations
/// is rejected by every command) but keeps only the unstyled hair. Absent = no operations. On
/// failure leaves *operations untouched and writes one line naming the field
/// ("operations[2].cut.z: expected a finite number (m), got \"low\"") into *error. Never throws.
bool ParseStyleOperations(const nlohmann::json& document, std::vector<StyleOperation>* operations,
                          std::string* error);

/// Reads and parses the hairstyle file at path (relative paths are relative to its directory).
/// Syntax errors give line and column; every message starts with the path. Never throws.
bool LoadHairstyle(const std::string& path, Hairstyle* style, std::string* error);

/// Parses hairstyle text (a whole file's contents, e.g. a studio session saved by Save): JSON
/// syntax errors with line and column, then ParseHairstyle and ParseStyleOperations (operations
/// may be null). Relative paths are relative to base_directory. Messages carry no file name.
/// Nothing is written on failure. Never throws. (LoadHairstyle reads the file and calls this;
/// the fuzz harness calls it directly.)
bool ParseHairstyleText(const std::string& text, const std::string& base_directory,
                        Hairstyle* style, std::vector<StyleOperation>* operations,
                        std::string* error);

/// LoadHairstyle that also returns the file's operations (ParseStyleOperations); operations may
/// be null. Nothing is written on failure.
bool LoadHairstyle(const std::string& path, Hairstyle* style,
                   std::vector<StyleOperation>* operations, std::string* error);

}  // namespace ringlet
