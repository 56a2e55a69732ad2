// Atomic file writes (temporary file + fsync + rename) and whole-file reads, with POSIX calls so
// that every failure has an errno to report.
#include "ringlet/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>

namespace ringlet {
namespace {

// How many random temporary names to try before giving up (collisions are astronomically rare;
// a loop that keeps failing means something else is wrong).
constexpr int kTemporaryNameAttempts = 100;

std::string ErrnoText(int error_number) { return std::strerror(error_number); }

bool Fail(std::string* error, const std::string& path, const std::string& what, int error_number) {
  if (error) *error = path + ": " + what + ": " + ErrnoText(error_number);
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
bool WriteAll(int fd, const std::string& data, int* error_number) {
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

// Creates a new temporary file next to path: "<dir>/.<name>.tmp-<random>", opened for writing
// with O_EXCL (never an existing file) and mode 0666 minus the umask, like any new file.
int CreateTemporary(const std::string& path, std::string* temporary, int* error_number) {
  const std::string prefix = DirectoryOf(path) + "/." + BaseNameOf(path) + ".tmp-";
  // Seeded from the clock and the process id (std::random_device may throw): O_EXCL, not the
  // quality of the numbers, is what makes the name safe.
  std::mt19937_64 rng(
      static_cast<uint64_t>(std::chrono::steady_clock::now().time_since_epoch().count()) ^
      (static_cast<uint64_t>(::getpid()) << 40));
  for (int attempt = 0; attempt < kTemporaryNameAttempts; ++attempt) {
    char suffix[17];
    std::snprintf(suffix, sizeof(suffix), "%016llx", static_cast<unsigned long long>(rng()));
    *temporary = prefix + suffix;
    const int fd = ::open(temporary->c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) return fd;
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

}  // namespace

bool CheckReplaceable(const std::string& path, bool overwrite, std::string* error) {
  // lstat: a symbolic link is judged as itself (rename would replace the link, not its target).
  struct stat existing;
  if (::lstat(path.c_str(), &existing) == 0) {
    if (S_ISDIR(existing.st_mode)) {
      if (error) *error = path + ": is a directory";
      return false;
    }
    if (!overwrite) {
      if (error) *error = path + ": already exists";
      return false;
    }
    if (!S_ISREG(existing.st_mode)) {
      if (error) {
        *error = path + ": exists and is " + FileKind(existing.st_mode) +
                 "; only a regular file may be replaced";
      }
      return false;
    }
  }
  return true;
}

bool WriteFileAtomically(const std::string& path, const std::string& contents, bool overwrite,
                         std::string* error) {
  if (path.empty()) {
    if (error) *error = "(empty path): cannot write a file without a name";
    return false;
  }
  // Refuse early what the final step would refuse, with a clearer message.
  if (!CheckReplaceable(path, overwrite, error)) return false;

  std::string temporary;
  int error_number = 0;
  const int fd = CreateTemporary(path, &temporary, &error_number);
  if (fd < 0) {
    return Fail(error, path, "cannot create a temporary file in " + DirectoryOf(path),
                error_number);
  }
  // From here on, every failure removes the temporary file.
  auto abandon = [&](const std::string& what, int number) {
    ::unlink(temporary.c_str());
    return Fail(error, path, what, number);
  };
  if (!WriteAll(fd, contents, &error_number)) {
    ::close(fd);
    return abandon("cannot write", error_number);
  }
  if (::fsync(fd) != 0) {
    error_number = errno;
    ::close(fd);
    return abandon("cannot flush to disk", error_number);
  }
  if (::close(fd) != 0) return abandon("cannot close", errno);

  if (overwrite) {
    if (::rename(temporary.c_str(), path.c_str()) != 0) return abandon("cannot rename", errno);
  } else {
    // link() fails with EEXIST if path appeared meanwhile: the check and the write are one step.
    if (::link(temporary.c_str(), path.c_str()) == 0) {
      ::unlink(temporary.c_str());
    } else if (errno == EEXIST) {
      ::unlink(temporary.c_str());
      if (error) *error = path + ": already exists";
      return false;
    } else if (errno == EPERM || errno == ENOTSUP || errno == EOPNOTSUPP || errno == ENOSYS ||
               errno == EMLINK) {
      // No hard links on this file system: fall back to check-then-rename.
      if (::access(path.c_str(), F_OK) == 0) {
        ::unlink(temporary.c_str());
        if (error) *error = path + ": already exists";
        return false;
      }
      if (::rename(temporary.c_str(), path.c_str()) != 0) return abandon("cannot rename", errno);
    } else {
      return abandon("cannot create", errno);
    }
  }
  SyncDirectory(path);
  return true;
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
      *error = path + ": is " + FileKind(info.st_mode) + ", not a regular file (inputs must be " +
               "regular files)";
    }
    return false;
  }
  const auto too_large = [&](const std::string& size) {
    ::close(fd);
    if (error) {
      *error = path + ": is " + size + ", more than the limit of " + FormatBytes(max_bytes) +
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
