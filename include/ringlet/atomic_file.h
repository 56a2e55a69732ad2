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

/// An output directory written file by file during a long run (`ringlet simulate`: a frame's
/// files as it is made, hair.usda piece by piece) and put in place only at the end, all or
/// none, like WriteFilesAtomically. Open makes a staging directory: beside the output directory
/// when that does not exist yet ("<parent>/.<name>.tmp-<random>", the missing parents created),
/// inside it when it does (".staging.tmp-<random>", hidden; the same file system either way).
/// Files are written into it; Commit flushes them to disk and puts them in place: a new
/// output directory by one rename of the staging directory (it appears complete), an existing
/// one by one rename per file (overwrite as for WriteFileAtomically: only regular files are
/// replaced, and only now). Any failure before Commit, Discard, the destructor, and SIGINT /
/// SIGTERM (RemoveTemporariesOnSignals: the handler empties and removes the staging directory
/// and the parents Open created) leave nothing: no staging directory, no output directory that
/// was not there, every file the user had untouched. Names are plain file names. Messages name
/// the final path (directory/name), never the staging one. Not thread-safe; never throws.
class StagedDirectory {
 public:
  /// A file being written into the staging directory.
  class File {
   public:
    File() = default;
    File(const File&) = delete;
    File& operator=(const File&) = delete;
    ~File();
    /// Appends data; false once a write has failed (Close says why).
    bool Write(std::string_view data);
    /// Closes the file; false with one line ("out/hair.usda: cannot write: No space left on
    /// device") if a write or the close failed.
    bool Close(std::string* error);

   private:
    friend class StagedDirectory;
    int fd_ = -1;
    int errno_ = 0;
    std::string path_;  // the final path, for messages
  };

  StagedDirectory() = default;
  StagedDirectory(const StagedDirectory&) = delete;
  StagedDirectory& operator=(const StagedDirectory&) = delete;
  ~StagedDirectory();  // Discard unless committed

  /// Creates the staging directory for directory (and its missing parents). False with one
  /// line when directory is not a directory or cannot be created.
  bool Open(const std::string& directory, bool overwrite, std::string* error);
  /// Creates the file name in the staging directory (an existing one is an error).
  bool Create(const std::string& name, File* file, std::string* error);
  /// Create, Write and Close in one; on failure the file is removed again (not part of the
  /// output).
  bool WriteFile(const std::string& name, std::string_view contents, std::string* error);
  /// The staging directory (its files can be read there, e.g. by ffmpeg).
  const std::string& staging() const { return staging_; }
  /// Flushes every file and puts them in place (see above). A failure while flushing leaves
  /// nothing ("... (nothing was written)"); a failure while renaming into an existing
  /// directory names the files written and not written, as WriteFilesAtomically.
  bool Commit(std::string* error);
  /// Removes the staging directory, its files and the parents Open created.
  void Discard();

 private:
  std::string directory_;             // the output directory
  std::string staging_;               // the staging directory
  bool existed_ = false;              // the output directory was there at Open
  bool overwrite_ = false;
  int slot_ = -1;                     // the staging directory's cleanup registration
  std::vector<int> parent_slots_;     // the created parents' registrations
  std::vector<std::string> created_;  // the parents Open created, outermost first
  std::vector<std::string> names_;    // the files, in order of creation
};

/// Installs SIGINT and SIGTERM handlers that remove the temporary files WriteFileAtomically and
/// WriteFilesAtomically are writing at that moment (and the directories WriteFilesAtomically
/// created, when still empty) and the staging directories of StagedDirectory with their files, then end the process by the same signal (exit status 128 +
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
