// The summary of an inversion (docs/inverse.md): what `ringlet invert` writes as summary.json and
// ringlet.invert returns as its "summary".
#pragma once

#include <nlohmann/json.hpp>
#include <vector>

#include "ringlet/inverse.h"
#include "ringlet/strand_model.h"

namespace ringlet {

/// The summary of InvertStrands' results for models (their lengths and segment counts) with the
/// fit errors of their targets (m, 0 for exact targets) and the fit and inversion times (s):
/// counts (strands, unstable, unconverged), the largest fit distances and deviations in m and
/// per strand length L, the support forces, the times, one object per strand
/// ("strand_results") and the units. All sizes must match.
nlohmann::ordered_json InversionSummary(const std::vector<StrandModel>& models,
                                        const std::vector<InverseResult>& results,
                                        const std::vector<double>& fit_max_distance,
                                        const std::vector<double>& fit_rms_distance,
                                        double fit_seconds, double invert_seconds);

}  // namespace ringlet
