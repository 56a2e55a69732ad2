#include "outputs.h"

#include <filesystem>
#include <system_error>

#include "ringlet/atomic_file.h"

namespace ringlet::cli {

namespace fs = std::filesystem;

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

bool CheckOutputDirectory(const std::string& directory, const std::vector<std::string>& names,
                          bool force, std::string* error) {
  if (directory.empty()) {
    *error = "--output: expected a directory name, got an empty string";
    return false;
  }
  std::error_code ec;
  const fs::file_status status = fs::status(directory, ec);
  if (!fs::exists(status)) return true;
  if (!fs::is_directory(status)) {
    *error = directory + ": exists and is not a directory; give a directory to --output";
    return false;
  }
  for (const std::string& name : names) {
    const fs::path file = fs::path(directory) / name;
    // --force replaces regular files only (not a device, FIFO or symbolic link).
    if (force) {
      if (!CheckReplaceable(file.string(), true, error)) return false;
    } else if (fs::exists(fs::symlink_status(file, ec))) {
      *error = file.string() + ": already exists (use --force to overwrite it)";
      return false;
    }
  }
  return true;
}

bool WriteOutputFiles(const std::string& directory,
                      const std::vector<std::pair<std::string, std::string>>& files, bool force,
                      std::string* error) {
  return WriteFilesAtomically(directory, files, force, error);
}

}  // namespace ringlet::cli
