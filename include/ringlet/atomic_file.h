// Writing files so that readers see either the old contents or the new, never a half-written file.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

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
/// and is left untouched (the check and the final rename are one atomic step: renameat2 with
/// RENAME_NOREPLACE, or link() where that flag is not supported). When overwrite is true only a
/// regular file is replaced: a directory, a symbolic link (even to a regular file), a device, a
/// FIFO or a socket at path is an error and is left untouched (also when it appears between the
/// check and the rename: the names are exchanged with RENAME_EXCHANGE and swapped back if what
/// was at path is not a regular file; file systems without the flag fall back to check, then
/// rename). The temporary is removed on SIGINT / SIGTERM (RemoveTemporariesOnSignals). Every write, flush and close error is an error. On failure the temporary file
/// is removed, *error receives one line starting with the path and the function returns false.
/// Never throws.
bool WriteFileAtomically(const std::string& path, const std::string& contents, bool overwrite,
                         std::string* error);

/// Where a producer writes a file's contents, piece by piece, in order. Returns false once a
/// write has failed (the producer may stop; the error is reported by the call that wrote).
using FileSink = std::function<bool(std::string_view)>;

/// WriteFileAtomically with contents produced in pieces: produce(sink) hands every piece to
/// sink, which appends it to the temporary file; the same checks, flush, rename, clean-up and
/// messages, without holding the whole contents in memory (ringlet solve's result text).
bool WriteFileAtomically(const std::string& path,
                         const std::function<void(const FileSink&)>& produce, bool overwrite,
                         std::string* error);

/// Writes several files into directory as one output (a groom's strands.hair, strands.usda,
/// ...): the missing directories are created, then every file is written in full to a
/// temporary next to its final name (flushed), and only when all are written are they renamed
/// into place, one after another. A failure while writing (a disk full, a bad path) removes
/// every temporary and the directories it created, leaves every file the user had untouched,
/// and *error says "... (nothing was written)". A failure while renaming (a race with another
/// process, an I/O error: no data is written any more then) removes the remaining temporaries
/// and *error names the files written and the ones not written. Names are plain file names.
/// overwrite as for WriteFileAtomically. Never throws.
bool WriteFilesAtomically(const std::string& directory,
                          const std::vector<std::pair<std::string, std::string>>& files,
                          bool overwrite, std::string* error);

/// Installs SIGINT and SIGTERM handlers that remove the temporary files WriteFileAtomically and
/// WriteFilesAtomically are writing at that moment (and the directories WriteFilesAtomically
/// created, when still empty), then end the process by the same signal (exit status 128 +
/// signal in a shell). The handler is async-signal-safe (a fixed table of paths, unlink, rmdir,
/// raise). For front ends: call once at start (the `ringlet` command does); signals that were
/// ignored when it is called (nohup) stay ignored. Calling it again does nothing.
void RemoveTemporariesOnSignals();

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

/// A file name as shown in a one-line message: control characters (a newline inside a name read
/// from a JSON string, say) escaped as \n, \r, \t or \xHH, and a name longer than 300 bytes cut
/// in its middle ("..."), so that a message stays one bounded line whatever the name. Ordinary
/// names are returned unchanged.
std::string DisplayPath(const std::string& path);

}  // namespace ringlet
