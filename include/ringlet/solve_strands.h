// Many strands at once: the statics solve of independent strands in parallel (paper, section 3).
#pragma once

#include <atomic>
#include <functional>
#include <vector>

#include "ringlet/math.h"
#include "ringlet/statics.h"
#include "ringlet/strand_model.h"

namespace ringlet {

/// Called as strands finish with (finished, total). Calls are serialized (never concurrent) and
/// finished increases strictly; they may come from any worker thread.
using ProgressCallback = std::function<void(int finished, int total)>;

/// The summary message of a strand that SolveStrands skipped because BatchOptions::cancel was
/// set (its curvatures are empty and its termination kMaxIterations with 0 iterations).
inline constexpr const char* kCancelledMessage = "cancelled before the solve started";

/// Options of SolveStrands.
struct BatchOptions {
  /// Worker threads; 0 = all hardware threads. The results do not depend on it: every strand is
  /// solved by the same deterministic sequence of operations whichever thread runs it.
  int threads = 0;
  /// Progress reports (may be empty).
  ProgressCallback progress;
  /// Cooperative cancellation, may be null. SolveStrands reads it before each strand: once
  /// *cancel is true, the strands not yet started are skipped (a strand already being solved
  /// runs to its end) and their solution has empty curvatures and the summary message
  /// kCancelledMessage; the caller must check *cancel after the call. The styling operations
  /// (styling.h; the studio's stale re-solves) also solve in blocks and return false with why =
  /// "cancelled"; GroomHairstyle returns false with why = "cancelled" (the Python module's
  /// Ctrl-C). Neither the flag nor the blocks change the results of the strands that are solved.
  const std::atomic<bool>* cancel = nullptr;
};

/// Solves every model with SolveStrand (TBB parallel loop, one task per strand). warm_starts,
/// when not null, holds one initial curvature vector per model (an empty vector = natural shape).
/// Returns the solutions in the order of the models. Strands skipped after batch.cancel was set
/// get an empty curvature vector and a summary whose message is kCancelledMessage.
std::vector<StrandSolution> SolveStrands(const std::vector<StrandModel>& models,
                                         const SolveOptions& options,
                                         const BatchOptions& batch = {},
                                         const std::vector<VecX>* warm_starts = nullptr);

}  // namespace ringlet
