// An empirical grading rule for heavy strands, measured against the heavy-elastica reference
// (docs/validation.md, "Heavy elastica"): a proposal for the core, shared by the elastica test and
// tools/convergence_study.cpp so that both use the same rule.
#pragma once

#include <cmath>

#include "ringlet/strand_model.h"

namespace ringlet::reference {

/// Last/first segment length ratio for GradedSegments(L, n, ratio) given the load
/// lambda = w L^3 / EI (dimensionless):
///   ratio = 1 + lambda / (2 sqrt(1 + lambda / 64)),
/// i.e. ~1 + lambda/2 for light strands (where grading gains little, at most ~15%) and
/// ~4 sqrt(lambda) for heavy ones, where the bending layer at the root has width ~L / sqrt(lambda).
/// It was fitted to the ratio minimizing the tip error of a horizontally clamped straight strand
/// (a broad minimum, flat to ~10% over a factor 2 in ratio) for lambda in [0.5, 3000] and n in
/// [10, 50]: the tip error with this rule is within 6.4% of the optimum's (10% at lambda = 10,
/// n = 10). The optimum grows only slowly with n (x1.5 from n = 10 to 50), so the rule ignores n.
/// Curled strands prefer 3-8 times smaller ratios (their tip needs short segments too).
/// The rule now lives in the library as RecommendedGradingRatio (the scene's "grading": "auto").
inline double SuggestedGradingRatio(double load) { return RecommendedGradingRatio(load); }

}  // namespace ringlet::reference
