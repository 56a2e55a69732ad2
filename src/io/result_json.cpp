// Result files: solved strands -> JSON (docs/scene-format.md, "Result format").
#include "ringlet/result_json.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "ringlet/kirchhoff.h"
#include "ringlet/strand_geometry.h"

namespace ringlet {
namespace {

using json = nlohmann::ordered_json;

// A number, or null when it is NaN or infinite (JSON has no such numbers; nlohmann would write
// null too, but silently).
json Number(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

json Vector(const Vec3& v) { return json::array({Number(v.x()), Number(v.y()), Number(v.z())}); }

// Whether value is an array of numbers and nulls only (a point, a curvature triple, the list of
// segment lengths): those are written on one line.
bool IsFlatArray(const json& value) {
  if (!value.is_array()) return false;
  for (const json& element : value) {
    if (!element.is_number() && !element.is_null()) return false;
  }
  return true;
}

// Indented JSON like dump(2), except that flat arrays stay on one line: a point reads
// [0.1, 0.0, -0.02] instead of five lines. Scalars are nlohmann's own (full precision).
void WriteIndented(const json& value, int indent, std::string* out) {
  const std::string inner(static_cast<size_t>(indent + 2), ' ');
  if (value.is_object() && !value.empty()) {
    *out += "{\n";
    size_t i = 0;
    for (const auto& item : value.items()) {
      *out += inner + json(item.key()).dump() + ": ";
      WriteIndented(item.value(), indent + 2, out);
      *out += ++i < value.size() ? ",\n" : "\n";
    }
    *out += std::string(static_cast<size_t>(indent), ' ') + "}";
  } else if (value.is_array() && !value.empty() && !IsFlatArray(value)) {
    *out += "[\n";
    size_t i = 0;
    for (const json& element : value) {
      *out += inner;
      WriteIndented(element, indent + 2, out);
      *out += ++i < value.size() ? ",\n" : "\n";
    }
    *out += std::string(static_cast<size_t>(indent), ' ') + "]";
  } else if (IsFlatArray(value)) {
    *out += "[";
    size_t i = 0;
    for (const json& element : value) *out += element.dump() + (++i < value.size() ? ", " : "");
    *out += "]";
  } else {
    // Messages are ASCII, but replace invalid UTF-8 rather than throw if one ever is not.
    *out += value.dump(-1, ' ', false, json::error_handler_t::replace);
  }
}

}  // namespace

bool StrandResult::Succeeded() const {
  return summary.Converged() && (summary.stable || !summary.stability_checked);
}

StrandResult MakeStrandResult(const StrandModel& model, const StrandSolution& solution,
                              int points_per_segment) {
  assert(points_per_segment >= 1);
  assert(solution.curvatures.size() == 3 * model.NumSegments());
  StrandResult result;
  result.points = SampleCentreline(model, solution.curvatures, points_per_segment);
  result.curvatures = solution.curvatures;
  result.segment_lengths = model.segment_lengths;
  result.summary = solution.summary;
  result.kirchhoff_residual = result.curvatures.allFinite()
                                  ? KirchhoffResidual(model, result.curvatures)
                                  : std::numeric_limits<double>::quiet_NaN();

  // The non-finite rule: a result with NaN or infinity anywhere is not an equilibrium, whatever
  // the minimizer said, and its file must say so (those numbers are written as null).
  SolveSummary& s = result.summary;
  bool finite = result.curvatures.allFinite() && std::isfinite(s.energy.elastic) &&
                std::isfinite(s.energy.gravity) && std::isfinite(s.energy.total) &&
                std::isfinite(s.gradient_norm) && std::isfinite(s.residual) &&
                (!s.stability_checked || std::isfinite(s.min_eigenvalue));
  for (const Vec3& p : result.points) finite = finite && p.allFinite();
  if (!finite && s.termination != Termination::kNonFinite) {
    s.termination = Termination::kNonFinite;
    s.message = "non-finite values in the result (written as null); the solver said: " + s.message;
  }
  if (s.termination == Termination::kNonFinite) s.stable = false;
  return result;
}

ResultCounts CountResults(const std::vector<StrandResult>& strands) {
  ResultCounts counts;
  for (const StrandResult& r : strands) {
    ++counts.strands;
    if (r.summary.Converged()) ++counts.converged;
    if (r.summary.stable) ++counts.stable;
    if (r.Succeeded()) ++counts.succeeded;
  }
  return counts;
}

nlohmann::ordered_json ResultToJson(const std::vector<StrandResult>& strands, double seconds) {
  json strand_array = json::array();
  for (const StrandResult& r : strands) {
    const SolveSummary& s = r.summary;
    json points = json::array();
    for (const Vec3& p : r.points) points.push_back(Vector(p));
    json curvatures = json::array();
    for (Eigen::Index i = 0; i + 2 < r.curvatures.size(); i += 3) {
      curvatures.push_back(Vector(r.curvatures.segment<3>(i)));
    }
    json lengths = json::array();
    for (double l : r.segment_lengths) lengths.push_back(Number(l));

    json strand = json::object();
    strand["points"] = std::move(points);
    strand["curvatures"] = std::move(curvatures);
    strand["segment_lengths"] = std::move(lengths);
    strand["energy"] = {{"elastic", Number(s.energy.elastic)},
                        {"gravity", Number(s.energy.gravity)},
                        {"contact", Number(s.energy.contact)},
                        {"total", Number(s.energy.total)}};
    strand["gradient_norm"] = Number(s.gradient_norm);
    strand["residual"] = Number(s.residual);
    strand["kirchhoff_residual"] = Number(r.kirchhoff_residual);
    strand["iterations"] = s.iterations;
    strand["evaluations"] = s.evaluations;
    strand["termination"] = TerminationName(s.termination);
    strand["stable"] = s.stable;
    strand["stability_checked"] = s.stability_checked;
    strand["min_hessian_eigenvalue"] =
        s.stability_checked ? Number(s.min_eigenvalue) : json(nullptr);
    strand["stability_restarts"] = s.stability_restarts;
    strand["max_penetration"] = Number(s.contact.max_penetration);
    strand["contact_samples"] = s.contact.samples_in_contact;
    strand["message"] = s.message;
    strand_array.push_back(std::move(strand));
  }

  const ResultCounts counts = CountResults(strands);
  double max_penetration = 0.0;
  for (const StrandResult& r : strands) {
    max_penetration = std::max(max_penetration, r.summary.contact.max_penetration);
  }
  json document = json::object();
  document["strands"] = std::move(strand_array);
  document["summary"] = {{"strands", counts.strands},
                         {"converged", counts.converged},
                         {"stable", counts.stable},
                         {"max_penetration", Number(max_penetration)},
                         {"seconds", Number(seconds)}};
  document["units"] = {
      {"points", "m, world coordinates, root to tip"},
      {"curvatures", "1/m: [kappa1, kappa2, tau] per segment in the material frame (n1, n2, t)"},
      {"segment_lengths", "m"},
      {"energy", "J: elastic, gravity (measured from the root), contact penalty and their total"},
      {"gradient_norm", "J m: norm of the energy gradient with respect to the curvatures"},
      {"residual", "dimensionless: internal-moment mismatch relative to the largest moment"},
      {"kirchhoff_residual",
       "dimensionless: the same balance by quadrature of the hanging weight's moment, "
       "independent of the solver (ringlet solve --check)"},
      {"min_hessian_eigenvalue",
       "dimensionless: stiffness-scaled Hessian, 1 for an unloaded rod, < 0 unstable; "
       "null when the stability check did not run"},
      {"max_penetration", "m: largest depth of the strand below the body surface (0 without a body)"},
      {"contact_samples", "count: contact samples inside the clearance layer (carrying a force)"},
      {"seconds", "s: wall time of the whole solve"},
      {"null", "a number that was NaN or infinite (termination is then non_finite)"}};
  return document;
}

std::string ResultToString(const std::vector<StrandResult>& strands, double seconds) {
  std::string text;
  WriteIndented(ResultToJson(strands, seconds), 0, &text);
  return text + "\n";
}

}  // namespace ringlet
