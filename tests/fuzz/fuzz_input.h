// Shared by the libFuzzer harnesses of tests/fuzz (docs/robustness.md, "Fuzzing").
//
// A harness is one file fuzz_<reader>.cpp that defines LLVMFuzzerTestOneInput: it hands the
// input to one reader and passes the reader's answer to CheckAnswer. Readers taking text use
// Text(); readers taking only a path use InputFile(), which writes the input to a file of a
// per-process directory on tmpfs (/dev/shm when present) with the suffix the reader expects.
// The harness is then registered with one ringlet_add_fuzzer(...) line in tests/fuzz/CMakeLists.txt.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>

namespace ringlet::fuzz {

// Longest error message a reader may give: messages quote values cut to 60 characters and
// paths with keys cut the same way, so real messages stay far below this.
inline constexpr size_t kMaxErrorLength = 2000;

// The input as text (the readers take std::string).
inline std::string Text(const std::uint8_t* data, size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// The contract every reader keeps (docs/robustness.md): success, or failure with one non-empty
// line of bounded length naming what is wrong. Anything else aborts, which libFuzzer reports
// as a crash with the input that caused it.
inline void CheckAnswer(bool ok, const std::string& error) {
  if (ok) return;
  if (error.empty() || error.size() > kMaxErrorLength ||
      error.find_first_of("\n\r") != std::string::npos) {
    std::fprintf(stderr, "reader failed without one bounded error line (%zu bytes): %.*s\n",
                 error.size(), static_cast<int>(std::min<size_t>(error.size(), 4000)),
                 error.data());
    std::abort();
  }
}

// A check of a successful result (the reader's own invariants): aborts with the reason.
inline void Require(bool condition, const std::string& why) {
  if (condition) return;
  std::fprintf(stderr, "reader accepted an invalid result: %s\n", why.c_str());
  std::abort();
}

// A directory that names no file, used as the base of relative paths in documents: every
// referenced file (bodies, OBJ meshes) is then missing, so the harness never reads the disk
// and each run depends on its input alone.
inline constexpr const char* kNoDirectory = "/nonexistent-ringlet-fuzz-directory";

// Writes the input to <tmpfs>/ringlet-fuzz-<pid>/input<suffix> (overwritten by each run,
// removed when the process exits) and returns the path, for readers that take only a path.
inline std::string InputFile(const std::uint8_t* data, size_t size, std::string_view suffix) {
  static const std::filesystem::path directory = [] {
    std::error_code ec;
    std::filesystem::path root = std::filesystem::exists("/dev/shm", ec)
                                     ? std::filesystem::path("/dev/shm")
                                     : std::filesystem::temp_directory_path();
    std::filesystem::path dir = root / ("ringlet-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    static const std::string to_remove = dir.string();
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(to_remove, ignored);
    });
    return dir;
  }();
  const std::filesystem::path path = directory / ("input" + std::string(suffix));
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.close();
  if (!out) {
    std::fprintf(stderr, "cannot write the fuzz input to %s\n", path.c_str());
    std::abort();
  }
  return path.string();
}

}  // namespace ringlet::fuzz
