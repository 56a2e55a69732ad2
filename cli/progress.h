// A progress bar on stderr for long runs (only when stderr is a terminal).
#pragma once

#include <chrono>
#include <string>

namespace ringlet::cli {

/// Draws "label [#######.........]  512/1000  51%  0.4 s, about 0.4 s left" on one terminal line,
/// redrawn at most 10 times a second, and erases it when done. Does nothing when disabled or when
/// stderr is not a terminal (logs and pipes stay clean). Not thread-safe: feed it from one thread
/// at a time (SolveStrands serializes its progress calls).
class ProgressBar {
 public:
  ProgressBar(std::string label, bool enabled);
  ~ProgressBar() { Finish(); }
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  /// Reports that done of total items are finished.
  void Update(long done, long total);
  /// Erases the bar (idempotent).
  void Finish();

 private:
  std::string label_;
  bool active_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace ringlet::cli
