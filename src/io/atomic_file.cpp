// Atomic file writes (temporary file + fsync + rename) and whole-file reads, with POSIX calls so
// that every failure has an errno to report.
#include "ringlet/atomic_file.h"

#include <fcntl.h>
#include <pthread.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <chrono>
#include <ctime>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

namespace ringlet {
namespace {

// How many random temporary names to try before giving up (collisions are astronomically rare;
// a loop that keeps failing means something else is wrong).
constexpr int kTemporaryNameAttempts = 100;

std::string ErrnoText(int error_number) { return std::strerror(error_number); }

bool Fail(std::string* error, const std::string& path, const std::string& what, int error_number) {
  if (error) *error = DisplayPath(path) + ": " + what + ": " + ErrnoText(error_number);
  return false;
}

// The directory part of path, "." when it has none ("out.json" -> ".", "/x/out.json" -> "/x").
std::string DirectoryOf(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

// The file name part of path.
std::string BaseNameOf(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// Writes all of data to fd, retrying on short writes and EINTR.
bool WriteAll(int fd, std::string_view data, int* error_number) {
  const char* p = data.data();
  size_t left = data.size();
  while (left > 0) {
    const ssize_t written = ::write(fd, p, left);
    if (written < 0) {
      if (errno == EINTR) continue;
      *error_number = errno;
      return false;
    }
    p += written;
    left -= static_cast<size_t>(written);
  }
  return true;
}

// ---- Temporaries removed on SIGINT / SIGTERM (RemoveTemporariesOnSignals) ----
//
// A fixed table, so that the signal handler touches no heap and no lock: each slot holds a
// path and an atomic state. Registering writes the path while the slot is kBusy and publishes
// it with kFile / kDirectory; the handler only reads published slots. std::atomic<int> is
// lock-free on every platform ringlet builds on, hence async-signal-safe.
constexpr int kCleanupSlots = 256;
constexpr size_t kCleanupPathBytes = 4096;
enum SlotState : int { kFree = 0, kBusy = 1, kFile = 2, kDirectory = 3, kStaging = 4 };
struct CleanupSlot {
  std::atomic<int> state{kFree};
  char path[kCleanupPathBytes];
};
CleanupSlot g_cleanup[kCleanupSlots];
static_assert(std::atomic<int>::is_always_lock_free);

// Registers path for removal by the signal handler; returns the slot, or -1 when the table is
// full or the path too long (the file is then not removed on a signal: best effort).
int RegisterCleanup(const std::string& path, SlotState kind) {
  if (path.size() + 1 > kCleanupPathBytes) return -1;
  for (int i = 0; i < kCleanupSlots; ++i) {
    int expected = kFree;
    if (g_cleanup[i].state.compare_exchange_strong(expected, kBusy)) {
      std::memcpy(g_cleanup[i].path, path.c_str(), path.size() + 1);
      g_cleanup[i].state.store(kind);
      return i;
    }
  }
  return -1;
}

void UnregisterCleanup(int slot) {
  if (slot < 0) return;
  g_cleanup[slot].state.store(kBusy);
  g_cleanup[slot].state.store(kFree);
}

// The other threads go on running while one handles the signal: one of them could register and
// make a temporary after the handler has passed its slot, and leave it behind (seen under load:
// groom's files are written in parallel). So every "register, then create" runs inside a
// SignalGuard: SIGINT / SIGTERM are blocked on its thread meanwhile (the handler never runs
// inside one), it counts itself in g_creations, and it makes nothing once g_removing is set. The
// handler sets g_removing, waits for g_creations to reach zero, and only then looks at the table
// (both sequentially consistent: a guard either sees g_removing or is waited for).
// Putting files in place runs inside a SignalGuard too: the renames of a whole set
// (WriteFilesAtomically, StagedDirectory::Commit into an existing directory) in one guard, so
// that a signal part-way (on this thread or another) cannot remove the temporaries not yet
// renamed and leave the output half old, half new; a single file's Commit (WriteFileAtomically)
// in its own, so that the exchange with what was at the path and its check are one step. The
// set goes into place whole, then the signal ends the process (renaming writes no data: a few
// system calls per file). Guards are never nested: an inner one that met g_removing would wait
// forever while the outer one still counted, and the handler would give up waiting after 2 s.
std::atomic<int> g_creations{0};
std::atomic<bool> g_removing{false};
static_assert(std::atomic<bool>::is_always_lock_free);

class SignalGuard {
 public:
  SignalGuard() {
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    ::pthread_sigmask(SIG_BLOCK, &signals, &previous_);
    g_creations.fetch_add(1);
    if (g_removing.load()) {
      // Another thread is removing the temporaries and will end the process: make nothing.
      g_creations.fetch_sub(1);
      for (;;) ::pause();
    }
  }
  ~SignalGuard() {
    g_creations.fetch_sub(1);
    ::pthread_sigmask(SIG_SETMASK, &previous_, nullptr);
  }
  SignalGuard(const SignalGuard&) = delete;
  SignalGuard& operator=(const SignalGuard&) = delete;

 private:
  sigset_t previous_;
};

// A directory entry as getdents64 returns it (linux_dirent64).
struct DirectoryEntry64 {
  std::uint64_t inode;
  std::int64_t offset;
  unsigned short length;
  unsigned char type;
  char name[1];
};

// Removes the files of a staging directory (StagedDirectory: regular files only), then the
// directory. Async-signal-safe (open, getdents64, unlinkat, rmdir; no heap): the signal handler
// calls it. Entries are read again until a pass removes none (removing while reading may skip
// some), a few passes at most.
void EmptyAndRemoveDirectory(const char* path) {
  const int fd = ::open(path, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return;
  alignas(8) char buffer[4096];
  for (int pass = 0; pass < 8; ++pass) {
    bool removed = false;
    ::lseek(fd, 0, SEEK_SET);
    for (;;) {
      const long got = ::syscall(SYS_getdents64, fd, buffer, sizeof buffer);
      if (got <= 0) break;
      for (long at = 0; at < got;) {
        const auto* entry = reinterpret_cast<const DirectoryEntry64*>(buffer + at);
        at += entry->length;
        const char* name = entry->name;
        if (name[0] == '.' && (name[1] == 0 || (name[1] == '.' && name[2] == 0))) continue;
        if (::unlinkat(fd, name, 0) == 0) removed = true;
      }
    }
    if (!removed) break;
  }
  ::close(fd);
  ::rmdir(path);
}

extern "C" void RemoveTemporariesAndReraise(int signal_number) {
  // No new temporaries from here on; the creations in flight on other threads finish first
  // (SignalGuard: a few system calls each; 2 s at most, in case one is stuck on a slow disk).
  g_removing.store(true);
  for (int waited = 0; waited < 2000 && g_creations.load() > 0; ++waited) {
    struct timespec millisecond {0, 1000000};
    ::nanosleep(&millisecond, nullptr);
  }
  // Files first, then the directories created for them (deepest were registered last).
  // Only regular files: for the instant of a RENAME_EXCHANGE (Commit) a temporary name can
  // hold what was at the output path, which is swapped back when it is not a regular file.
  for (int i = 0; i < kCleanupSlots; ++i) {
    struct stat info;
    if (g_cleanup[i].state.load() == kFile && ::lstat(g_cleanup[i].path, &info) == 0 &&
        S_ISREG(info.st_mode)) {
      ::unlink(g_cleanup[i].path);
    }
  }
  for (int i = 0; i < kCleanupSlots; ++i) {
    if (g_cleanup[i].state.load() == kStaging) EmptyAndRemoveDirectory(g_cleanup[i].path);
  }
  for (int i = kCleanupSlots - 1; i >= 0; --i) {
    if (g_cleanup[i].state.load() == kDirectory) ::rmdir(g_cleanup[i].path);  // only if empty
  }
  // End the process as the signal would have (exit status 128 + signal in a shell).
  ::signal(signal_number, SIG_DFL);
  ::raise(signal_number);
}

// A temporary file written in full, not yet in place.
struct Staged {
  std::string path;       // where it goes
  std::string temporary;  // where it is
  int slot = -1;          // its cleanup registration
};

// Removes a staged temporary (after a failure) and its registration.
void Discard(Staged* staged) {
  if (!staged->temporary.empty()) ::unlink(staged->temporary.c_str());
  UnregisterCleanup(staged->slot);
  staged->slot = -1;
  staged->temporary.clear();
}

// Creates a new temporary file next to path: "<dir>/.<name>.tmp-<random>", opened for writing
// with O_EXCL (never an existing file) and mode 0666 minus the umask, like any new file. The
// name is registered for removal on SIGINT / SIGTERM before the file exists, so that no
// interrupt can leave it behind.
int CreateTemporary(const std::string& path, Staged* staged, int* error_number) {
  const std::string prefix = DirectoryOf(path) + "/." + BaseNameOf(path) + ".tmp-";
  // Seeded from the clock and the process id (std::random_device may throw): O_EXCL, not the
  // quality of the numbers, is what makes the name safe.
  std::mt19937_64 rng(
      static_cast<uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count()) ^
      (static_cast<uint64_t>(::getpid()) << 40));
  for (int attempt = 0; attempt < kTemporaryNameAttempts; ++attempt) {
    char suffix[17];
    std::snprintf(suffix, sizeof(suffix), "%016llx", static_cast<unsigned long long>(rng()));
    const std::string temporary = prefix + suffix;
    SignalGuard guard;
    const int slot = RegisterCleanup(temporary, kFile);
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      staged->temporary = temporary;
      staged->slot = slot;
      return fd;
    }
    const int open_errno = errno;
    UnregisterCleanup(slot);
    errno = open_errno;
    if (errno != EEXIST) break;
  }
  *error_number = errno;
  return -1;
}

// Flushes the directory holding path so that the rename itself survives a crash. Best effort:
// some file systems refuse fsync on directories, and the data is already safe in the file.
void SyncDirectory(const std::string& path) {
  const int fd = ::open(DirectoryOf(path).c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

// "a directory", "a FIFO", ...: what a non-regular file is, for messages.
std::string FileKind(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISLNK(mode)) return "a symbolic link";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISREG(mode)) return "a regular file";
  return "a special file";
}

// Writes what produce hands its sink to a new temporary next to path, flushed and closed. On
// failure nothing is left and *error names path.
bool Stage(const std::string& path, const std::function<void(const FileSink&)>& produce,
           Staged* staged, std::string* error) {
  staged->path = path;
  int error_number = 0;
  const int fd = CreateTemporary(path, staged, &error_number);
  if (fd < 0) {
    return Fail(error, path, "cannot create a temporary file in " + DirectoryOf(path),
                error_number);
  }
  auto abandon = [&](const std::string& what, int number) {
    Discard(staged);
    return Fail(error, path, what, number);
  };
  bool written = true;
  try {
    produce([&](std::string_view piece) {
      written = written && WriteAll(fd, piece, &error_number);
      return written;
    });
  } catch (...) {  // a producer that fails (out of memory): reported, never thrown on
    ::close(fd);
    return abandon("cannot write", ENOMEM);
  }
  if (!written) {
    ::close(fd);
    return abandon("cannot write", error_number);
  }
  if (::fsync(fd) != 0) {
    error_number = errno;
    ::close(fd);
    return abandon("cannot flush to disk", error_number);
  }
  if (::close(fd) != 0) return abandon("cannot close", errno);
  return true;
}

// Whether renameat2's flags are refused by this kernel or file system (then the plain calls
// are used).
bool FlagsUnsupported(int error_number) {
  return error_number == EINVAL || error_number == ENOSYS || error_number == ENOTSUP ||
         error_number == EOPNOTSUPP;
}

// Puts a staged file in place. With overwrite, only a regular file is replaced, and that test
// and the replacement are one step where the file system can exchange names (renameat2 with
// RENAME_EXCHANGE: the new file and whatever is at path swap names; if what came back is not a
// regular file it is swapped back, untouched). Without overwrite, RENAME_NOREPLACE (or link())
// refuses an existing path atomically. On failure the temporary is removed.
bool Commit(Staged* staged, bool overwrite, std::string* error) {
  const char* temporary = staged->temporary.c_str();
  const char* path = staged->path.c_str();
  auto abandon = [&](const std::string& what, int number) {
    Discard(staged);
    return Fail(error, staged->path, what, number);
  };
  auto exists = [&]() {
    Discard(staged);
    if (error) *error = DisplayPath(staged->path) + ": already exists";
    return false;
  };
  if (overwrite) {
    if (::renameat2(AT_FDCWD, temporary, AT_FDCWD, path, RENAME_EXCHANGE) == 0) {
      // The old file is now at the temporary name: check what it was.
      struct stat old;
      if (::lstat(temporary, &old) == 0 && !S_ISREG(old.st_mode)) {
        const int swapped_back = ::renameat2(AT_FDCWD, temporary, AT_FDCWD, path, RENAME_EXCHANGE);
        if (swapped_back == 0) Discard(staged);  // the temporary name holds our file again
        if (error) {
          *error = DisplayPath(staged->path) + ": exists and is " + FileKind(old.st_mode) +
                   "; only a regular file may be replaced";
        }
        return false;
      }
      ::unlink(temporary);  // the replaced regular file
      UnregisterCleanup(staged->slot);
      staged->slot = -1;
      return true;
    }
    const int exchange_errno = errno;
    if (exchange_errno != ENOENT && !FlagsUnsupported(exchange_errno)) {
      return abandon("cannot rename", exchange_errno);
    }
    if (FlagsUnsupported(exchange_errno)) {
      // No exchange here: check, then rename (a node appearing in between is replaced; see
      // docs/robustness.md).
      if (!CheckReplaceable(staged->path, true, error)) {
        Discard(staged);
        return false;
      }
      if (::rename(temporary, path) != 0) return abandon("cannot rename", errno);
      UnregisterCleanup(staged->slot);
      staged->slot = -1;
      return true;
    }
    // ENOENT: nothing at path (any more): fall through to the no-replace rename.
  }
  if (::renameat2(AT_FDCWD, temporary, AT_FDCWD, path, RENAME_NOREPLACE) == 0) {
    UnregisterCleanup(staged->slot);
    staged->slot = -1;
    return true;
  }
  if (errno == EEXIST) {
    // With overwrite this is a node that appeared after the exchange found none: not replaced.
    return exists();
  }
  if (!FlagsUnsupported(errno)) return abandon("cannot rename", errno);
  // link() fails with EEXIST if path appeared meanwhile: the check and the write are one step.
  if (::link(temporary, path) == 0) {
    Discard(staged);
    return true;
  }
  if (errno == EEXIST) return exists();
  if (errno == EPERM || errno == ENOTSUP || errno == EOPNOTSUPP || errno == ENOSYS ||
      errno == EMLINK) {
    // No hard links on this file system either: check, then rename.
    if (::access(path, F_OK) == 0) return exists();
    if (::rename(temporary, path) != 0) return abandon("cannot rename", errno);
    UnregisterCleanup(staged->slot);
    staged->slot = -1;
    return true;
  }
  return abandon("cannot create", errno);
}

}  // namespace

void RemoveTemporariesOnSignals() {
  static std::atomic<bool> installed{false};
  if (installed.exchange(true)) return;
  struct sigaction action {};
  action.sa_handler = RemoveTemporariesAndReraise;
  sigemptyset(&action.sa_mask);
  sigaddset(&action.sa_mask, SIGINT);
  sigaddset(&action.sa_mask, SIGTERM);
  action.sa_flags = SA_RESETHAND;
  for (int signal_number : {SIGINT, SIGTERM}) {
    // A signal the caller's parent set to be ignored (nohup, background jobs) stays ignored.
    struct sigaction previous {};
    if (::sigaction(signal_number, nullptr, &previous) == 0 && previous.sa_handler == SIG_IGN) {
      continue;
    }
    ::sigaction(signal_number, &action, nullptr);
  }
}

bool CheckReplaceable(const std::string& path, bool overwrite, std::string* error) {
  // lstat: a symbolic link is judged as itself (rename would replace the link, not its target).
  struct stat existing;
  if (::lstat(path.c_str(), &existing) == 0) {
    if (S_ISDIR(existing.st_mode)) {
      if (error) *error = DisplayPath(path) + ": is a directory";
      return false;
    }
    if (!overwrite) {
      if (error) *error = DisplayPath(path) + ": already exists";
      return false;
    }
    if (!S_ISREG(existing.st_mode)) {
      if (error) {
        *error = DisplayPath(path) + ": exists and is " + FileKind(existing.st_mode) +
                 "; only a regular file may be replaced";
      }
      return false;
    }
  }
  return true;
}

bool WriteFileAtomically(const std::string& path, const std::string& contents, bool overwrite,
                         std::string* error) {
  return WriteFileAtomically(
      path, [&contents](const FileSink& sink) { sink(contents); }, overwrite, error);
}

bool WriteFileAtomically(const std::string& path,
                         const std::function<void(const FileSink&)>& produce, bool overwrite,
                         std::string* error) {
  if (path.empty()) {
    if (error) *error = "(empty path): cannot write a file without a name";
    return false;
  }
  // Refuse early what the final step would refuse, with a clearer message.
  if (!CheckReplaceable(path, overwrite, error)) return false;
  Staged staged;
  if (!Stage(path, produce, &staged, error)) return false;
  {
    // The exchange with what was at path and its check are one step for a signal too: a
    // handler between them would leave a node that is not a regular file (swapped back by
    // Commit) under the temporary's name.
    SignalGuard guard;
    if (!Commit(&staged, overwrite, error)) return false;
  }
  SyncDirectory(path);
  return true;
}

namespace {

// The directories from `path` up that do not exist, innermost first.
std::vector<std::string> MissingDirectories(std::string path) {
  std::vector<std::string> missing;
  while (!path.empty() && path != "/" && path != ".") {
    struct stat info;
    if (::stat(path.c_str(), &info) == 0) break;
    missing.push_back(path);
    const size_t slash = path.find_last_of('/');
    if (slash == std::string::npos) break;
    path = path.substr(0, slash);
  }
  return missing;
}

// Creates `missing` (MissingDirectories' order) outermost first, each registered for removal on
// a signal (its slot appended to *slots) and appended to *created; one made by someone else
// meanwhile is left alone. False with the directory and errno of a failure; what was created
// stays in *created and *slots for the caller's roll-back.
bool CreateDirectories(const std::vector<std::string>& missing, std::vector<int>* slots,
                       std::vector<std::string>* created, std::string* failed,
                       int* error_number) {
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    SignalGuard guard;
    slots->push_back(RegisterCleanup(*it, kDirectory));
    if (::mkdir(it->c_str(), 0777) != 0) {
      const int e = errno;
      UnregisterCleanup(slots->back());  // not ours to remove
      slots->pop_back();
      if (e == EEXIST) continue;  // made by someone else meanwhile
      *failed = *it;
      *error_number = e;
      return false;
    }
    created->push_back(*it);
  }
  return true;
}

}  // namespace

bool WriteFilesAtomically(const std::string& directory,
                          const std::vector<std::pair<std::string, std::string>>& files,
                          bool overwrite, std::string* error) {
  if (directory.empty()) {
    if (error) *error = "(empty path): cannot write into a directory without a name";
    return false;
  }
  // The directories to create, outermost first; each is registered for removal on a signal
  // and removed again on failure (if still empty).
  const std::vector<std::string> missing = MissingDirectories(directory);
  std::vector<int> directory_slots;
  std::vector<std::string> created;
  std::vector<Staged> staged;
  auto roll_back = [&]() {
    for (Staged& s : staged) Discard(&s);
    for (auto it = created.rbegin(); it != created.rend(); ++it) ::rmdir(it->c_str());
    for (int slot : directory_slots) UnregisterCleanup(slot);
  };
  std::string failed;
  int error_number = 0;
  if (!CreateDirectories(missing, &directory_slots, &created, &failed, &error_number)) {
    roll_back();
    return Fail(error, failed, "cannot create the directory", error_number);
  }
  // 1. Every file in full to its temporary: a failure (disk full, a bad path) rolls everything
  // back, and nothing the user had is touched. The paths are checked first, in order; then the
  // files are written and flushed each by its own thread (copying and flushing hundreds of MB,
  // `ringlet invert` of a full head, is then bounded by the largest file, not by their sum),
  // and a failure reports the first failing file in order, as one writer after the other would.
  for (const auto& [name, contents] : files) {
    if (!CheckReplaceable(directory + "/" + name, overwrite, error)) {
      roll_back();
      if (error) *error += " (nothing was written)";
      return false;
    }
  }
  std::vector<Staged> writing(files.size());
  std::vector<std::string> reasons(files.size());
  std::vector<char> written(files.size(), 0);
  {
    const auto stage = [&](size_t k) {
      const std::string& contents = files[k].second;
      written[k] = Stage(directory + "/" + files[k].first,
                         [&contents](const FileSink& sink) { sink(contents); }, &writing[k],
                         &reasons[k])
                       ? 1
                       : 0;
    };
    std::vector<std::thread> threads;
    for (size_t k = 1; k < files.size(); ++k) {
      try {
        threads.emplace_back(stage, k);
      } catch (const std::system_error&) {  // no thread to be had: this one writes it
        stage(k);
      }
    }
    if (!files.empty()) stage(0);
    for (std::thread& t : threads) t.join();
  }
  for (size_t k = 0; k < files.size(); ++k) {
    if (written[k]) staged.push_back(std::move(writing[k]));
  }
  for (size_t k = 0; k < files.size(); ++k) {
    if (!written[k]) {
      roll_back();
      if (error) *error = reasons[k] + " (nothing was written)";
      return false;
    }
  }
  // 2. Into place, one rename each (no data is written any more: only a race with another
  // process or an I/O error can stop this half-way, and then the message says which files are
  // new and which are missing). SIGINT / SIGTERM wait until the whole set is in place.
  {
    SignalGuard guard;
    for (size_t k = 0; k < staged.size(); ++k) {
      std::string why;
      if (!Commit(&staged[k], overwrite, &why)) {
        std::string done, missing_names;
        for (size_t j = 0; j < staged.size(); ++j) {
          std::string& list = j < k ? done : missing_names;
          list += (list.empty() ? "" : ", ") + BaseNameOf(staged[j].path);
        }
        for (size_t j = k + 1; j < staged.size(); ++j) Discard(&staged[j]);
        for (int slot : directory_slots) UnregisterCleanup(slot);
        if (error) {
          *error = why + "; written: " + (done.empty() ? "none" : done) + "; not written: " +
                   missing_names;
        }
        return false;
      }
    }
  }
  for (int slot : directory_slots) UnregisterCleanup(slot);
  SyncDirectory(directory + "/.");
  return true;
}

// ---- StagedDirectory ----

StagedDirectory::File::~File() {
  if (fd_ >= 0) ::close(fd_);
}

bool StagedDirectory::File::Write(std::string_view data) {
  if (fd_ < 0 || errno_ != 0) return false;
  return WriteAll(fd_, data, &errno_);
}

bool StagedDirectory::File::Close(std::string* error) {
  if (fd_ < 0) {
    return errno_ != 0 ? Fail(error, path_, "cannot write", errno_) : true;
  }
  const int result = ::close(fd_);
  const int close_errno = errno;
  fd_ = -1;
  if (errno_ != 0) return Fail(error, path_, "cannot write", errno_);
  if (result != 0) {
    errno_ = close_errno;
    return Fail(error, path_, "cannot close", close_errno);
  }
  return true;
}

StagedDirectory::~StagedDirectory() { Discard(); }

void StagedDirectory::Discard() {
  if (!staging_.empty()) EmptyAndRemoveDirectory(staging_.c_str());
  UnregisterCleanup(slot_);
  slot_ = -1;
  for (auto it = created_.rbegin(); it != created_.rend(); ++it) ::rmdir(it->c_str());
  for (int slot : parent_slots_) UnregisterCleanup(slot);
  parent_slots_.clear();
  created_.clear();
  names_.clear();
  staging_.clear();
}

bool StagedDirectory::Open(const std::string& directory, bool overwrite, std::string* error) {
  Discard();
  if (directory.empty()) {
    if (error) *error = "(empty path): cannot write into a directory without a name";
    return false;
  }
  directory_ = directory;
  while (directory_.size() > 1 && directory_.back() == '/') directory_.pop_back();
  overwrite_ = overwrite;
  std::string prefix;
  struct stat info;
  if (::stat(directory.c_str(), &info) == 0) {
    if (!S_ISDIR(info.st_mode)) {
      if (error) *error = DisplayPath(directory) + ": exists and is not a directory";
      return false;
    }
    existed_ = true;
    prefix = directory + "/.staging.tmp-";
  } else {
    existed_ = false;
    const std::string& d = directory_;
    const std::string name = BaseNameOf(d);
    if (name.empty() || name == "." || name == "..") {
      if (error) *error = DisplayPath(directory) + ": cannot create the directory";
      return false;
    }
    // The missing parents, outermost first, each registered for removal on a signal.
    std::string failed;
    int error_number = 0;
    if (!CreateDirectories(MissingDirectories(DirectoryOf(d)), &parent_slots_, &created_, &failed,
                           &error_number)) {
      Discard();
      return Fail(error, failed, "cannot create the directory", error_number);
    }
    prefix = DirectoryOf(d) + "/." + name + ".tmp-";
  }
  std::mt19937_64 rng(
      static_cast<uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count()) ^
      (static_cast<uint64_t>(::getpid()) << 40));
  int error_number = 0;
  for (int attempt = 0; attempt < kTemporaryNameAttempts; ++attempt) {
    char suffix[17];
    std::snprintf(suffix, sizeof(suffix), "%016llx", static_cast<unsigned long long>(rng()));
    const std::string staging = prefix + suffix;
    SignalGuard guard;
    const int slot = RegisterCleanup(staging, kStaging);
    if (::mkdir(staging.c_str(), 0777) == 0) {
      staging_ = staging;
      slot_ = slot;
      return true;
    }
    error_number = errno;
    UnregisterCleanup(slot);
    if (error_number != EEXIST) break;
  }
  Discard();
  return Fail(error, directory, "cannot create a staging directory for it", error_number);
}

bool StagedDirectory::Create(const std::string& name, File* file, std::string* error) {
  if (file->fd_ >= 0) ::close(file->fd_);
  file->fd_ = -1;
  file->errno_ = 0;
  file->path_ = directory_ + "/" + name;
  if (staging_.empty()) {
    if (error) *error = DisplayPath(file->path_) + ": the output directory is not open";
    return false;
  }
  const std::string path = staging_ + "/" + name;
  int fd = -1;
  int open_errno = 0;
  {
    // A file made in the staging directory after the handler emptied it would keep it (rmdir).
    SignalGuard guard;
    fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    open_errno = errno;
  }
  if (fd < 0) return Fail(error, file->path_, "cannot create", open_errno);
  file->fd_ = fd;
  names_.push_back(name);
  return true;
}

bool StagedDirectory::WriteFile(const std::string& name, std::string_view contents,
                                std::string* error) {
  File file;
  if (!Create(name, &file, error)) return false;
  file.Write(contents);
  if (file.Close(error)) return true;
  // Not part of the output: a caller may go on without it (a video that did not fit).
  ::unlink((staging_ + "/" + name).c_str());
  names_.pop_back();
  return false;
}

bool StagedDirectory::Commit(std::string* error) {
  if (staging_.empty()) {
    if (error) *error = DisplayPath(directory_) + ": the output directory is not open";
    return false;
  }
  // 1. Every file to disk (the data is mostly written back already): a failure leaves nothing.
  for (const std::string& name : names_) {
    const std::string path = staging_ + "/" + name;
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0 || ::fsync(fd) != 0) {
      const int error_number = errno;
      if (fd >= 0) ::close(fd);
      Discard();
      Fail(error, directory_ + "/" + name, "cannot flush to disk", error_number);
      if (error) *error += " (nothing was written)";
      return false;
    }
    ::close(fd);
  }
  // 2a. A new output directory: the staging directory renamed to it, complete at once.
  if (!existed_) {
    int rename_errno = 0;
    if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, directory_.c_str(),
                    RENAME_NOREPLACE) == 0) {
      rename_errno = 0;
    } else {
      rename_errno = errno;
      if (FlagsUnsupported(rename_errno)) {
        struct stat info;
        if (::lstat(directory_.c_str(), &info) != 0) {
          rename_errno = ::rename(staging_.c_str(), directory_.c_str()) == 0 ? 0 : errno;
        } else {
          rename_errno = EEXIST;
        }
      }
    }
    if (rename_errno == 0) {
      staging_.clear();  // it is the output directory now
      UnregisterCleanup(slot_);
      slot_ = -1;
      for (int slot : parent_slots_) UnregisterCleanup(slot);
      parent_slots_.clear();
      created_.clear();
      names_.clear();
      SyncDirectory(directory_);
      return true;
    }
    struct stat info;
    const bool appeared = (rename_errno == EEXIST || rename_errno == ENOTEMPTY) &&
                          ::stat(directory_.c_str(), &info) == 0 && S_ISDIR(info.st_mode);
    if (!appeared) {
      Discard();
      Fail(error, directory_, "cannot rename the staging directory into place", rename_errno);
      if (error) *error += " (nothing was written)";
      return false;
    }
    // The directory was made meanwhile by someone else: file by file into it, as below.
  }
  // 2b. An existing output directory: one rename per file (Commit: overwrite only regular
  // files); a failure here names the files written and not written. SIGINT / SIGTERM wait until
  // the whole set is in place (SignalGuard).
  SignalGuard guard;
  for (size_t k = 0; k < names_.size(); ++k) {
    Staged staged;
    staged.path = directory_ + "/" + names_[k];
    staged.temporary = staging_ + "/" + names_[k];
    std::string why;
    if (!ringlet::Commit(&staged, overwrite_, &why)) {
      std::string done, missing_names;
      for (size_t j = 0; j < names_.size(); ++j) {
        if (j == k) continue;
        std::string& list = j < k ? done : missing_names;
        list += (list.empty() ? "" : ", ") + names_[j];
      }
      missing_names = names_[k] + (missing_names.empty() ? "" : ", " + missing_names);
      Discard();
      if (error) {
        *error = why + "; written: " + (done.empty() ? "none" : done) + "; not written: " +
                 missing_names;
      }
      return false;
    }
  }
  names_.clear();
  Discard();  // the staging directory, empty now
  SyncDirectory(directory_ + "/.");
  return true;
}

std::string DisplayPath(const std::string& path) {
  constexpr size_t kMaxShown = 300, kHead = 100;
  std::string out;
  for (const char c : path) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u != 0x7f) {
      out += c;
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\t') {
      out += "\\t";
    } else {
      static const char kHex[] = "0123456789abcdef";
      out += "\\x";
      out += kHex[u >> 4];
      out += kHex[u & 15];
    }
  }
  if (out.size() <= kMaxShown) return out;
  // Escapes and UTF-8 may be cut in the middle; the "..." marks the cut either way.
  return out.substr(0, kHead) + "..." + out.substr(out.size() - (kMaxShown - kHead - 3));
}

std::string FormatBytes(std::uint64_t bytes) {
  constexpr std::uint64_t kMiB = std::uint64_t{1} << 20, kGiB = std::uint64_t{1} << 30;
  if (bytes >= kGiB && bytes % kGiB == 0) return std::to_string(bytes / kGiB) + " GiB";
  if (bytes >= kMiB && bytes % kMiB == 0) return std::to_string(bytes / kMiB) + " MiB";
  return std::to_string(bytes) + " bytes";
}

bool ReadFile(const std::string& path, std::string* contents, std::string* error,
              std::uint64_t max_bytes) {
  // O_NONBLOCK: opening a FIFO must not wait for a writer; it is refused just below. (On a
  // regular file the flag changes nothing.)
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) return Fail(error, path, "cannot open", errno);
  struct stat info;
  if (::fstat(fd, &info) != 0) {
    const int error_number = errno;
    ::close(fd);
    return Fail(error, path, "cannot read", error_number);
  }
  if (!S_ISREG(info.st_mode)) {
    ::close(fd);
    if (error) {
      *error = DisplayPath(path) + ": is " + FileKind(info.st_mode) +
               ", not a regular file (inputs must be " +
               "regular files)";
    }
    return false;
  }
  const auto too_large = [&](const std::string& size) {
    ::close(fd);
    if (error) {
      *error = DisplayPath(path) + ": is " + size + ", more than the limit of " +
               FormatBytes(max_bytes) +
               " for this kind of file";
    }
    return false;
  };
  if (static_cast<std::uint64_t>(info.st_size) > max_bytes) {
    return too_large(std::to_string(static_cast<std::uint64_t>(info.st_size)) + " bytes");
  }
  std::string text;
  text.reserve(static_cast<size_t>(info.st_size));
  char buffer[1 << 16];
  for (;;) {
    const ssize_t got = ::read(fd, buffer, sizeof(buffer));
    if (got == 0) break;
    if (got < 0) {
      if (errno == EINTR) continue;
      const int error_number = errno;
      ::close(fd);
      return Fail(error, path, "cannot read", error_number);
    }
    // The file may grow while it is read: the limit holds for what is read.
    if (text.size() + static_cast<size_t>(got) > max_bytes) return too_large("larger");
    text.append(buffer, static_cast<size_t>(got));
  }
  ::close(fd);
  *contents = std::move(text);
  return true;
}

}  // namespace ringlet
