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

/// Options of SolveStrands.
struct BatchOptions {
  /// Worker threads; 0 = all hardware threads. The results do not depend on it: every strand is
  /// solved by the same deterministic sequence of operations whichever thread runs it.
  int threads = 0;
  /// Progress reports (may be empty).
  ProgressCallback progress;
  /// Cooperative cancellation of the styling operations (styling.h; the studio's stale
  /// re-solves), may be null: when set, they solve their masters in blocks and, once *cancel is
  /// true, stop between blocks and return false with why = "cancelled". SolveStrands itself does
  /// not read it (one call runs to the end). Blocks do not change the results.
  const std::atomic<bool>* cancel = nullptr;
};

/// Solves every model with SolveStrand (TBB parallel loop, one task per strand). warm_starts,
/// when not null, holds one initial curvature vector per model (an empty vector = natural shape).
/// Returns the solutions in the order of the models.
std::vector<StrandSolution> SolveStrands(const std::vector<StrandModel>& models,
                                         const SolveOptions& options,
                                         const BatchOptions& batch = {},
                                         const std::vector<VecX>* warm_starts = nullptr);

}  // namespace ringlet
