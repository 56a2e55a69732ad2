// The bookkeeping of a batch output directory (batch.h, docs/batch.md): item folders written all
// or nothing, the `done` marker, manifest lines appended under a lock, and the share of items a
// run takes (--items A:B, --shard K/N).
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <system_error>

#include "ringlet/atomic_file.h"
#include "ringlet/batch.h"

namespace ringlet {
namespace {

namespace fs = std::filesystem;

// A whole decimal integer (no sign, no spaces).
bool ParseCount(const std::string& text, std::int64_t* out) {
  if (text.empty() || text.size() > 18) return false;
  for (const char c : text) {
    if (c < '0' || c > '9') return false;
  }
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), *out);
  return ec == std::errc() && end == text.data() + text.size();
}

std::string HostName() {
  char host[256] = {};
  if (gethostname(host, sizeof(host) - 1) != 0 || host[0] == '\0') return "host";
  std::string name(host);
  for (char& c : name) {
    if (c == '/' || c == '.' || static_cast<unsigned char>(c) < 0x20) c = '_';
  }
  return name;
}

}  // namespace

bool BatchItemDone(const std::string& outdir, const std::string& name) {
  std::error_code ec;
  return fs::is_regular_file(fs::path(outdir) / name / "done", ec);
}

int WriteBatchItem(const std::string& outdir, const BatchItem& item, const BatchItemResult& result,
                   std::string* error) {
  std::error_code ec;
  const fs::path final_path = fs::path(outdir) / item.name;
  const fs::path temporary = fs::path(outdir) / ("." + item.name + ".tmp." + HostName() + "." +
                                                 std::to_string(static_cast<long>(getpid())));
  fs::remove_all(temporary, ec);  // a leftover of this very host and process id
  std::vector<std::pair<std::string, std::string>> files = result.files;
  files.emplace_back("timing.json", result.timing.dump(1) + "\n");
  files.emplace_back("done", "");  // last: the folder is complete
  std::string why;
  if (!WriteFilesAtomically(temporary.string(), files, false, &why)) {
    fs::remove_all(temporary, ec);
    *error = why;
    return -1;
  }
  if (std::rename(temporary.c_str(), final_path.c_str()) != 0) {
    const int e = errno;
    fs::remove_all(temporary, ec);
    // Another process finished the same item: the same bytes are there.
    if ((e == ENOTEMPTY || e == EEXIST) && BatchItemDone(outdir, item.name)) return 0;
    if (e == ENOTEMPTY || e == EEXIST) {
      *error = DisplayPath(final_path.string()) +
               ": exists without a done marker (not written by ringlet batch); remove it to make "
               "the item";
      return -1;
    }
    *error = DisplayPath(final_path.string()) +
             ": cannot rename the item folder into place: " + std::strerror(e);
    return -1;
  }
  return 1;
}

std::string BatchManifestLine(const BatchItem& item, const BatchItemResult& result) {
  nlohmann::json line = {{"item", item.index},
                         {"name", item.name},
                         {"base", item.base},
                         {"status", BatchStatusName(result.status)}};
  if (result.status == BatchItemResult::Status::kFailed) line["error"] = result.error;
  return line.dump();
}

bool AppendManifestLine(const std::string& path, const std::string& line, std::string* error) {
  const std::string text = line + "\n";
  const int fd = open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0666);
  if (fd < 0) {
    *error = DisplayPath(path) + ": cannot open: " + std::strerror(errno);
    return false;
  }
  bool ok = flock(fd, LOCK_EX) == 0;
  int e = ok ? 0 : errno;
  size_t written = 0;
  while (ok && written < text.size()) {
    const ssize_t n = write(fd, text.data() + written, text.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      ok = false;
      e = errno;
      break;
    }
    written += static_cast<size_t>(n);
  }
  if (ok && fdatasync(fd) != 0) {
    ok = false;
    e = errno;
  }
  flock(fd, LOCK_UN);
  if (close(fd) != 0 && ok) {
    ok = false;
    e = errno;
  }
  if (!ok) *error = DisplayPath(path) + ": cannot append: " + std::strerror(e);
  return ok;
}

bool ParseItemRange(const std::string& text, std::int64_t count, BatchRange* range,
                    std::string* error) {
  const size_t colon = text.find(':');
  std::int64_t a = 0, b = 0;
  if (colon == std::string::npos || !ParseCount(text.substr(0, colon), &a) ||
      !ParseCount(text.substr(colon + 1), &b) || a >= b) {
    *error =
        "--items: expected A:B with integers 0 <= A < B (items A to B - 1), got \"" + text + "\"";
    return false;
  }
  if (b > count) {
    *error = "--items: " + text + " goes beyond the spec's " + std::to_string(count) +
             " items (the last is " + std::to_string(count - 1) + ")";
    return false;
  }
  range->begin = a;
  range->end = b;
  return true;
}

bool ParseShard(const std::string& text, int* k, int* n, std::string* error) {
  const size_t slash = text.find('/');
  std::int64_t a = 0, b = 0;
  if (slash == std::string::npos || !ParseCount(text.substr(0, slash), &a) ||
      !ParseCount(text.substr(slash + 1), &b) || b < 1 || b > 1000000 || a >= b) {
    *error = "--shard: expected K/N with integers 0 <= K < N <= 1000000 (shard K of N), got \"" +
             text + "\"";
    return false;
  }
  *k = static_cast<int>(a);
  *n = static_cast<int>(b);
  return true;
}

BatchRange ShardRange(const BatchRange& range, int k, int n) {
  const std::int64_t length = range.end - range.begin;
  // length * k fits: length <= 10^9, k < 10^6.
  return BatchRange{range.begin + length * k / n, range.begin + length * (k + 1) / n};
}

}  // namespace ringlet
