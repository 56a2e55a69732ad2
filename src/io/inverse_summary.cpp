// The summary of an inversion: inverse_summary.h.
#include "ringlet/inverse_summary.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace ringlet {

nlohmann::ordered_json InversionSummary(const std::vector<StrandModel>& models,
                                        const std::vector<InverseResult>& results,
                                        const std::vector<double>& fit_max_distance,
                                        const std::vector<double>& fit_rms_distance,
                                        double fit_seconds, double invert_seconds) {
  assert(results.size() == models.size() && fit_max_distance.size() == models.size() &&
         fit_rms_distance.size() == models.size());
  int unstable = 0, unconverged = 0, supported = 0, fallbacks = 0;
  double support_force = 0.0;
  double max_fit = 0.0, max_fit_l = 0.0, sum_fit2 = 0.0, max_dev = 0.0, max_dev_l = 0.0,
         max_naive = 0.0, max_naive_l = 0.0;
  nlohmann::ordered_json per_strand = nlohmann::ordered_json::array();
  for (size_t i = 0; i < models.size(); ++i) {
    const InverseResult& r = results[i];
    const double length = models[i].Length();
    unstable += r.stable ? 0 : 1;
    unconverged += r.forward.Converged() ? 0 : 1;
    max_fit = std::max(max_fit, fit_max_distance[i]);
    max_fit_l = std::max(max_fit_l, fit_max_distance[i] / length);
    sum_fit2 += fit_rms_distance[i] * fit_rms_distance[i];
    max_dev = std::max(max_dev, r.deviation);
    max_dev_l = std::max(max_dev_l, r.deviation / length);
    max_naive = std::max(max_naive, r.naive_deviation);
    max_naive_l = std::max(max_naive_l, r.naive_deviation / length);
    supported += r.supported_samples;  // contact forces as unknowns (docs/inverse.md)
    fallbacks += r.support_fallback ? 1 : 0;
    support_force += r.support_force;
    per_strand.push_back({{"length", length},
                          {"segments", models[i].NumSegments()},
                          {"fit_max_distance", fit_max_distance[i]},
                          {"fit_rms_distance", fit_rms_distance[i]},
                          {"stable", r.stable},
                          {"min_hessian_eigenvalue", r.min_eigenvalue},
                          {"kirchhoff_residual", r.kirchhoff_residual},
                          {"supported_samples", r.supported_samples},
                          {"support_force", r.support_force},
                          {"support_fallback", r.support_fallback},
                          {"rest_energy", r.rest_energy},
                          {"rest_energy_unsupported", r.rest_energy_unsupported},
                          {"deviation", r.deviation},
                          {"naive_deviation", r.naive_deviation},
                          {"forward_termination", TerminationName(r.forward.termination)},
                          {"message", r.message}});
  }
  const int n = static_cast<int>(models.size());
  return {
      {"strands", n},
      {"unstable", unstable},
      {"unconverged", unconverged},
      {"fit_max_distance", max_fit},
      {"fit_max_distance_per_length", max_fit_l},
      {"fit_rms_distance", std::sqrt(sum_fit2 / std::max(1, n))},
      {"max_deviation", max_dev},
      {"max_deviation_per_length", max_dev_l},
      {"naive_max_deviation", max_naive},
      {"naive_max_deviation_per_length", max_naive_l},
      {"supported_samples", supported},
      {"support_force", support_force},
      {"support_fallbacks", fallbacks},
      {"fit_seconds", fit_seconds},
      {"invert_seconds", invert_seconds},
      {"strand_results", std::move(per_strand)},
      {"units",
       {{"distances", "m (and per_length: units of each strand's length L)"},
        {"rest_energy", "J: elastic energy bending the hair type's natural shape into the "
                        "rest shape, what the support forces minimize (_unsupported: without them)"},
        {"support_force", "N: total normal force of the body on the contact samples that carry one "
                          "(supported_samples), chosen by the inversion"},
        {"deviation",
         "largest distance from the target of the forward equilibrium from the inverted rest "
         "shape (naive_: from the rest shape = target)"}}}};
}

}  // namespace ringlet
