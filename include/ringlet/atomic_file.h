// Writing files so that readers see either the old contents or the new, never a half-written file.
#pragma once

#include <cstdint>
#include <string>

namespace ringlet {

/// The largest JSON file ringlet reads (scenes, hairstyles, bodies, render settings): 64 MiB,
/// about 200,000 strands of a scene. Parsed, such a document takes up to about ten times its
/// size in memory (docs/robustness.md).
inline constexpr std::uint64_t kMaxJsonFileBytes = std::uint64_t{64} << 20;
/// The largest OBJ body mesh ringlet reads: 256 MiB (about 5 million triangles).
inline constexpr std::uint64_t kMaxObjFileBytes = std::uint64_t{256} << 20;
/// The largest .hair file ringlet reads: 1 GiB (about 40 million points with thickness and
/// colour); decoding holds the bytes and the curves, about twice the size.
inline constexpr std::uint64_t kMaxHairFileBytes = std::uint64_t{1} << 30;

/// Writes contents to path through a temporary file in the same directory (created with the
/// usual permissions, 0666 minus the umask), flushed to disk and then renamed over path, so
/// that path never holds partial contents. When overwrite is false an existing path is an error
/// and is left untouched (the check and the final link are one atomic step where the file system
/// supports hard links). When overwrite is true only a regular file is replaced: a directory, a
/// symbolic link (even to a regular file), a device, a FIFO or a socket at path is an error and
/// is left untouched. Every write, flush and close error is an error. On failure the temporary file
/// is removed, *error receives one line starting with the path and the function returns false.
/// Never throws.
bool WriteFileAtomically(const std::string& path, const std::string& contents, bool overwrite,
                         std::string* error);

/// The checks WriteFileAtomically makes before writing to path, for front ends that check their
/// outputs before any work: false with one line in *error when path is a directory, exists and
/// overwrite is false, or exists (as itself: a symbolic link is not followed) and is not a
/// regular file. A path that does not exist passes.
bool CheckReplaceable(const std::string& path, bool overwrite, std::string* error);

/// Reads the whole file at path into *contents. Only regular files are read (a directory,
/// device, FIFO or socket is refused without blocking on it; a symbolic link to a regular file
/// is followed), and only up to max_bytes: a larger file is refused before anything is
/// allocated for it. On failure *error receives one line starting with the path
/// ("scene.json: cannot read: No such file or directory") and the function returns false.
/// Never throws.
bool ReadFile(const std::string& path, std::string* contents, std::string* error,
              std::uint64_t max_bytes = kMaxJsonFileBytes);

/// "64 MiB", "1 GiB", "1234 bytes": a byte count as the limits are documented.
std::string FormatBytes(std::uint64_t bytes);

}  // namespace ringlet
