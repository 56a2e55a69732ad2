// Writing files so that readers see either the old contents or the new, never a half-written file.
#pragma once

#include <string>

namespace ringlet {

/// Writes contents to path through a temporary file in the same directory (created with the
/// usual permissions, 0666 minus the umask), flushed to disk and then renamed over path, so
/// that path never holds partial contents. When overwrite is false an existing path is an error
/// and is left untouched (the check and the final link are one atomic step where the file system
/// supports hard links). On failure the temporary file is removed, *error receives one line
/// starting with the path and the function returns false. Never throws.
bool WriteFileAtomically(const std::string& path, const std::string& contents, bool overwrite,
                         std::string* error);

/// Reads the whole file at path into *contents. On failure *error receives one line starting
/// with the path ("scene.json: cannot read: No such file or directory") and the function
/// returns false. Never throws.
bool ReadFile(const std::string& path, std::string* contents, std::string* error);

}  // namespace ringlet
