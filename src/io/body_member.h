// The "body" member of a document (hairstyles, scenes): a body file name or the body object.
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "io/json_reader.h"
#include "ringlet/body.h"

namespace ringlet::internal {

/// Reads document["body"]: a string is a body file (docs/body.md) relative to base_directory
/// (LoadBody), an object is the body itself (ParseBody, messages prefixed "body."). A missing
/// member is an error when required, else leaves *out untouched and returns true.
bool ParseBodyMember(Reader& reader, const nlohmann::json& document,
                     const std::string& base_directory, bool required,
                     std::shared_ptr<const Body>* out);

}  // namespace ringlet::internal
