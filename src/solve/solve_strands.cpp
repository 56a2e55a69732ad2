// Parallel statics of independent strands with TBB; deterministic whatever the thread count.
#include "ringlet/solve_strands.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <cassert>
#include <mutex>

namespace ringlet {

std::vector<StrandSolution> SolveStrands(const std::vector<StrandModel>& models,
                                         const SolveOptions& options, const BatchOptions& batch,
                                         const std::vector<VecX>* warm_starts) {
  const int total = static_cast<int>(models.size());
  assert(!warm_starts || static_cast<int>(warm_starts->size()) == total);
  std::vector<StrandSolution> solutions(models.size());
  std::mutex progress_mutex;
  int finished = 0;
  auto solve_one = [&](int i) {
    // Cancelled: skip the strands not yet started (the caller checks the flag after the call).
    if (batch.cancel && batch.cancel->load(std::memory_order_relaxed)) {
      solutions[i].summary.message = kCancelledMessage;
      return;
    }
    const VecX* start = nullptr;
    if (warm_starts && (*warm_starts)[i].size() > 0) start = &(*warm_starts)[i];
    solutions[i] = SolveStrand(models[i], options, start);
    if (batch.progress) {
      std::lock_guard<std::mutex> lock(progress_mutex);
      batch.progress(++finished, total);
    }
  };
  // One strand per task (grain 1): solve times vary 100x between straight and curly strands.
  tbb::task_arena arena(batch.threads > 0 ? batch.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, total, 1), [&](const tbb::blocked_range<int>& r) {
      for (int i = r.begin(); i != r.end(); ++i) solve_one(i);
    });
  });
  return solutions;
}

}  // namespace ringlet
