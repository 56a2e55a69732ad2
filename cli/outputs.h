// The output directory of `ringlet groom` and `ringlet style`: checked before any work, written
// only after every file has been encoded, each file atomically.
#pragma once

#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace ringlet::cli {

/// Wall time since start (s).
double SecondsSince(std::chrono::steady_clock::time_point start);

/// The directory may exist (it is created otherwise) but none of the named files may, unless
/// force: nothing the user had is overwritten silently. A path that is not a directory is an
/// error even with force. On failure *error gets one line.
bool CheckOutputDirectory(const std::string& directory, const std::vector<std::string>& names,
                          bool force, std::string* error);

/// Creates the directory if needed and writes the (name, contents) into it as one output
/// (WriteFilesAtomically): all files or, after a failure while writing, none; a failure while
/// renaming names the files written and missing. On failure *error gets one line.
bool WriteOutputFiles(const std::string& directory,
                      const std::vector<std::pair<std::string, std::string>>& files, bool force,
                      std::string* error);

}  // namespace ringlet::cli
