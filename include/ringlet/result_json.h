// Result files: the solved strands as JSON (docs/scene-format.md, "Result format").
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "ringlet/atomic_file.h"
#include "ringlet/math.h"
#include "ringlet/statics.h"
#include "ringlet/strand_model.h"

namespace ringlet {

/// One solved strand, as written to a result file.
struct StrandResult {
  /// Centreline samples, root to tip (m): the n + 1 segment ends, or n k + 1 points with k
  /// points per segment.
  std::vector<Vec3> points;
  /// Equilibrium curvatures (kappa1, kappa2, tau) per segment, size 3n (1/m).
  VecX curvatures;
  /// Length of each segment, root to tip (m).
  std::vector<double> segment_lengths;
  /// The model's per-segment rest shape (StrandModel::rest_curvatures, size 3n, 1/m), or empty
  /// when the model has none (natural_curvature on every segment). Written as "rest_curvatures"
  /// only when not empty.
  VecX rest_curvatures;
  /// The solver's summary. termination is kNonFinite (and stable false) whenever any number
  /// above or in the summary is NaN or infinite.
  SolveSummary summary;
  /// The equilibrium certificate KirchhoffResidual (dimensionless): Kirchhoff's moment balance
  /// by quadrature, independent of the solver's gradient (include/ringlet/kirchhoff.h).
  double kirchhoff_residual = 0.0;

  /// True when the strand reached a usable equilibrium: converged and, when the stability check
  /// ran, stable.
  bool Succeeded() const;
};

/// Builds the result of one solved strand, sampling the centreline with points_per_segment >= 1
/// points per segment (SampleCentreline). Applies the non-finite rule: if any position,
/// curvature, energy, gradient norm, residual or checked eigenvalue is NaN or infinite, the
/// termination becomes kNonFinite, stable false, and the message says so.
StrandResult MakeStrandResult(const StrandModel& model, const StrandSolution& solution,
                              int points_per_segment);

/// MakeStrandResult of every strand: results[i] that of models[i] and solutions[i] (same sizes),
/// computed in parallel across strands on `threads` worker threads (0: all hardware threads).
/// The results do not depend on the thread count. The Kirchhoff certificate in each result costs
/// about half a solve without the stability check (docs/benchmarks.md, "CLI overhead"), hence
/// the threads.
std::vector<StrandResult> MakeStrandResults(const std::vector<StrandModel>& models,
                                            const std::vector<StrandSolution>& solutions,
                                            int points_per_segment, int threads = 0);

/// Counts over all strands of a scene.
struct ResultCounts {
  int strands = 0;    ///< number of strands
  int converged = 0;  ///< strands whose termination is kConverged
  int stable = 0;     ///< strands found stable by the Hessian test
  int succeeded = 0;  ///< strands for which StrandResult::Succeeded() holds
};

/// Counts converged, stable and succeeded strands.
ResultCounts CountResults(const std::vector<StrandResult>& strands);

/// The result document {"strands": [...], "summary": {...}, "units": {...}}, members in that
/// (insertion) order; seconds is the wall time of the solve (s). Non-finite numbers are null, so
/// the document is valid JSON.
nlohmann::ordered_json ResultToJson(const std::vector<StrandResult>& strands, double seconds);

/// ResultToJson as text, indented by two spaces with arrays of numbers (points, curvature
/// triples, segment lengths) on one line, ending with a newline. Written directly, without
/// building the json tree: the same JSON value as ResultToJson(strands, seconds), at a tenth of
/// the cost. Numbers are the shortest decimals that read back bit-identical (std::to_chars),
/// always with a fraction or an exponent ("0.0", "1e-07"); NaN and infinities are null.
std::string ResultToString(const std::vector<StrandResult>& strands, double seconds);

/// ResultToString's text handed to sink in pieces of about 1 MiB (for WriteFileAtomically's
/// streaming form): the same bytes, without the whole text in memory (32 MB for 10,000
/// 15-segment strands). Stops formatting once the sink reports a failed write.
void WriteResultText(const std::vector<StrandResult>& strands, double seconds,
                     const FileSink& sink);

}  // namespace ringlet
