// Result files: solved strands -> JSON (docs/scene-format.md, "Result format").
#include "ringlet/result_json.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <string_view>
#include <utility>
#include <vector>

#include "io/json_writer.h"
#include "ringlet/kirchhoff.h"
#include "ringlet/strand_geometry.h"

namespace ringlet {
namespace {

using json = nlohmann::ordered_json;

// A number, or null when it is NaN or infinite (JSON has no such numbers; nlohmann would write
// null too, but silently).
json Number(double x) { return std::isfinite(x) ? json(x) : json(nullptr); }

json Vector(const Vec3& v) { return json::array({Number(v.x()), Number(v.y()), Number(v.z())}); }

// The "units" member: the unit and meaning of each number, for readers of the file. Shared by
// ResultToJson and ResultToString so that the two cannot drift apart.
struct UnitEntry {
  const char* key;
  const char* text;
};
constexpr UnitEntry kUnits[] = {
    {"points", "m, world coordinates, root to tip"},
    {"curvatures", "1/m: [kappa1, kappa2, tau] per segment in the material frame (n1, n2, t)"},
    {"segment_lengths", "m"},
    {"rest_curvatures",
     "1/m: [kappa1^0, kappa2^0, tau^0] per segment, the rest shape (only for strands that have "
     "one, e.g. from ringlet invert)"},
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

// The largest max_penetration over the strands (m), 0 for none.
double MaxPenetration(const std::vector<StrandResult>& strands) {
  double max_penetration = 0.0;
  for (const StrandResult& r : strands) {
    max_penetration = std::max(max_penetration, r.summary.contact.max_penetration);
  }
  return max_penetration;
}

// ResultToString's text, written member by member in the layout of docs/scene-format.md:
// indented by two spaces, arrays of numbers (a point, a curvature triple, the segment lengths)
// on one line. Keys are literals; numbers and strings go through io/json_writer.h.
// With a sink, the text is handed to it in pieces of about kPieceBytes (then *out is a buffer
// that never grows much beyond that); without one, all of it stays in *out.
class ResultWriter {
 public:
  static constexpr size_t kPieceBytes = size_t{1} << 20;
  // The text goes at the end of *out, which Document leaves holding exactly the text (without a
  // sink) or empty (with one).
  explicit ResultWriter(std::string* out, const FileSink* sink = nullptr)
      : out_(out), sink_(sink), used_(out->size()) {
    out_->resize(std::max(out_->capacity(), used_ + kMinRoom));
  }

  void Document(const std::vector<StrandResult>& strands, double seconds) {
    Raw("{\n  \"strands\": [");
    for (size_t i = 0; i < strands.size(); ++i) {
      if (i > 0) Raw(",");
      Raw("\n    {\n");
      Strand(strands[i]);
      Raw("\n    }");
      if (sink_ && used_ >= kPieceBytes) Flush();
      if (!ok_) {  // a write failed: WriteFileAtomically reports it
        out_->clear();
        return;
      }
    }
    if (!strands.empty()) Raw("\n  ");
    Raw("]");

    const ResultCounts counts = CountResults(strands);
    Raw(",\n  \"summary\": {\n    \"strands\": ");
    Integer(counts.strands);
    Raw(",\n    \"converged\": ");
    Integer(counts.converged);
    Raw(",\n    \"stable\": ");
    Integer(counts.stable);
    Raw(",\n    \"max_penetration\": ");
    Number(MaxPenetration(strands));
    Raw(",\n    \"seconds\": ");
    Number(seconds);
    Raw("\n  },\n  \"units\": {");
    bool first = true;
    for (const UnitEntry& unit : kUnits) {
      if (!first) Raw(",");
      Raw("\n    ");
      first = false;
      String(unit.key);
      Raw(": ");
      String(unit.text);
    }
    Raw("\n  }\n}\n");
    if (sink_) Flush();
    out_->resize(used_);
  }

 private:
  // The members of one strand, at indentation 6, without the braces.
  void Strand(const StrandResult& r) {
    const SolveSummary& s = r.summary;
    Raw("      \"points\": ");
    if (r.points.empty()) {
      Raw("[]");
    } else {
      Raw("[");
      for (size_t i = 0; i < r.points.size(); ++i) {
        if (i > 0) Raw(",");
        Raw("\n        ");
        Triple(r.points[i].x(), r.points[i].y(), r.points[i].z());
      }
      Raw("\n      ]");
    }
    Raw(",\n      \"curvatures\": ");
    if (r.curvatures.size() < 3) {
      Raw("[]");
    } else {
      Raw("[");
      for (Eigen::Index i = 0; i + 2 < r.curvatures.size(); i += 3) {
        if (i > 0) Raw(",");
        Raw("\n        ");
        Triple(r.curvatures(i), r.curvatures(i + 1), r.curvatures(i + 2));
      }
      Raw("\n      ]");
    }
    Raw(",\n      \"segment_lengths\": [");
    // Uniform segments repeat one length: its text is copied, not formatted again.
    size_t previous_begin = 0, previous_size = 0;
    for (size_t i = 0; i < r.segment_lengths.size(); ++i) {
      if (i > 0) Raw(", ");
      const size_t begin = used_;
      if (i > 0 && std::bit_cast<uint64_t>(r.segment_lengths[i]) ==
                       std::bit_cast<uint64_t>(r.segment_lengths[i - 1])) {
        char* to = Room(previous_size);  // may move the text: the source is taken after
        std::memcpy(to, out_->data() + previous_begin, previous_size);
        used_ += previous_size;
      } else {
        Number(r.segment_lengths[i]);
      }
      previous_begin = begin;
      previous_size = used_ - begin;
    }
    Raw("]");
    if (r.rest_curvatures.size() >= 3) {
      Raw(",\n      \"rest_curvatures\": [");
      for (Eigen::Index i = 0; i + 2 < r.rest_curvatures.size(); i += 3) {
        if (i > 0) Raw(",");
        Raw("\n        ");
        Triple(r.rest_curvatures(i), r.rest_curvatures(i + 1), r.rest_curvatures(i + 2));
      }
      Raw("\n      ]");
    }
    Raw(",\n      \"energy\": {\n        \"elastic\": ");
    Number(s.energy.elastic);
    Raw(",\n        \"gravity\": ");
    Number(s.energy.gravity);
    Raw(",\n        \"contact\": ");
    Number(s.energy.contact);
    Raw(",\n        \"total\": ");
    Number(s.energy.total);
    Raw("\n      },\n      \"gradient_norm\": ");
    Number(s.gradient_norm);
    Raw(",\n      \"residual\": ");
    Number(s.residual);
    Raw(",\n      \"kirchhoff_residual\": ");
    Number(r.kirchhoff_residual);
    Raw(",\n      \"iterations\": ");
    Integer(s.iterations);
    Raw(",\n      \"evaluations\": ");
    Integer(s.evaluations);
    Raw(",\n      \"hessian_evaluations\": ");
    Integer(s.hessian_evaluations);
    Raw(",\n      \"termination\": ");
    String(TerminationName(s.termination));
    Raw(",\n      \"stable\": ");
    Raw(std::string_view(s.stable ? "true" : "false"));
    Raw(",\n      \"stability_checked\": ");
    Raw(std::string_view(s.stability_checked ? "true" : "false"));
    Raw(",\n      \"min_hessian_eigenvalue\": ");
    if (s.stability_checked) {
      Number(s.min_eigenvalue);
    } else {
      Raw("null");
    }
    Raw(",\n      \"stability_restarts\": ");
    Integer(s.stability_restarts);
    Raw(",\n      \"max_penetration\": ");
    Number(s.contact.max_penetration);
    Raw(",\n      \"contact_samples\": ");
    Integer(s.contact.samples_in_contact);
    Raw(",\n      \"message\": ");
    String(s.message);
  }

  void Triple(double a, double b, double c) {
    Raw("[");
    Number(a);
    Raw(", ");
    Number(b);
    Raw(", ");
    Number(c);
    Raw("]");
  }

  // The text is written through a cursor: *out_'s size is the writable area, used_ the text in
  // it (one call per number or literal instead of a std::string append each: the appends were
  // a tenth of the command's formatting, docs/benchmarks.md, "CLI overhead").
  static constexpr size_t kMinRoom = 4096;
  char* Room(size_t n) {
    if (out_->size() - used_ < n) [[unlikely]] Grow(n);
    return out_->data() + used_;
  }
  [[gnu::noinline]] void Grow(size_t n) {
    out_->resize(std::max(2 * out_->size(), used_ + n + kMinRoom));
  }
  template <size_t N>
  void Raw(const char (&text)[N]) {  // a literal: a copy of known size
    std::memcpy(Room(N - 1), text, N - 1);
    used_ += N - 1;
  }
  void Raw(std::string_view text) {
    std::memcpy(Room(text.size()), text.data(), text.size());
    used_ += text.size();
  }
  void Number(double x) {
    char* begin = Room(internal::kMaxJsonNumberChars);
    used_ += static_cast<size_t>(internal::WriteJsonNumber(x, begin) - begin);
  }
  void Integer(long long x) {
    scratch_.clear();
    internal::AppendJsonInteger(x, &scratch_);
    Raw(scratch_);
  }
  void String(std::string_view text) {
    scratch_.clear();
    internal::AppendJsonString(text, &scratch_);
    Raw(scratch_);
  }

  // Hands the text to the sink; after a failed write the rest is not formatted in vain.
  void Flush() {
    if (ok_) ok_ = (*sink_)(std::string_view(out_->data(), used_));
    used_ = 0;
  }

  std::string* out_;
  const FileSink* sink_;
  size_t used_;           // bytes of text at the start of *out_
  std::string scratch_;   // strings and integers before they are copied in
  bool ok_ = true;
};

}  // namespace

bool StrandResult::Succeeded() const {
  return summary.Converged() && (summary.stable || !summary.stability_checked);
}

StrandResult MakeStrandResult(const StrandModel& model, const StrandSolution& solution,
                              int points_per_segment) {
  assert(points_per_segment >= 1);
  assert(solution.curvatures.size() == 3 * model.NumSegments());
  StrandResult result;
  // One reconstruction serves the points (at one point per segment they are its segment ends)
  // and the certificate.
  std::vector<Vec3> segment_moments;
  StrandGeometry geometry = ComputeGeometry(model, solution.curvatures, &segment_moments);
  result.curvatures = solution.curvatures;
  result.segment_lengths = model.segment_lengths;
  result.rest_curvatures = model.rest_curvatures;
  result.summary = solution.summary;
  result.kirchhoff_residual =
      result.curvatures.allFinite()
          ? KirchhoffResidual(model, result.curvatures, geometry, segment_moments)
          : std::numeric_limits<double>::quiet_NaN();
  result.points = points_per_segment == 1
                      ? std::move(geometry.points)
                      : SampleCentreline(model, solution.curvatures, points_per_segment);

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

std::vector<StrandResult> MakeStrandResults(const std::vector<StrandModel>& models,
                                            const std::vector<StrandSolution>& solutions,
                                            int points_per_segment, int threads) {
  assert(models.size() == solutions.size());
  std::vector<StrandResult> results(models.size());
  const int total = static_cast<int>(models.size());
  // Each result depends on its strand alone, so any split gives the same results.
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, total), [&](const tbb::blocked_range<int>& r) {
      for (int i = r.begin(); i < r.end(); ++i) {
        results[i] = MakeStrandResult(models[i], solutions[i], points_per_segment);
      }
    });
  });
  return results;
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
    if (r.rest_curvatures.size() >= 3) {
      json rest = json::array();
      for (Eigen::Index i = 0; i + 2 < r.rest_curvatures.size(); i += 3) {
        rest.push_back(Vector(r.rest_curvatures.segment<3>(i)));
      }
      strand["rest_curvatures"] = std::move(rest);
    }
    strand["energy"] = {{"elastic", Number(s.energy.elastic)},
                        {"gravity", Number(s.energy.gravity)},
                        {"contact", Number(s.energy.contact)},
                        {"total", Number(s.energy.total)}};
    strand["gradient_norm"] = Number(s.gradient_norm);
    strand["residual"] = Number(s.residual);
    strand["kirchhoff_residual"] = Number(r.kirchhoff_residual);
    strand["iterations"] = s.iterations;
    strand["evaluations"] = s.evaluations;
    strand["hessian_evaluations"] = s.hessian_evaluations;
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
  json document = json::object();
  document["strands"] = std::move(strand_array);
  document["summary"] = {{"strands", counts.strands},
                         {"converged", counts.converged},
                         {"stable", counts.stable},
                         {"max_penetration", Number(MaxPenetration(strands))},
                         {"seconds", Number(seconds)}};
  json units = json::object();
  for (const UnitEntry& unit : kUnits) units[unit.key] = unit.text;
  document["units"] = std::move(units);
  return document;
}

std::string ResultToString(const std::vector<StrandResult>& strands, double seconds) {
  // Reserve about what a strand takes (3 numbers of ~20 characters per point and per segment,
  // plus ~900 characters of scalars and keys) so that the text is not copied as it grows.
  size_t estimate = 2048;
  for (const StrandResult& r : strands) {
    estimate += 900 + 70 * (r.points.size() + static_cast<size_t>(r.curvatures.size() / 3)) +
                24 * r.segment_lengths.size();
  }
  std::string text;
  text.reserve(estimate);
  ResultWriter(&text).Document(strands, seconds);
  return text;
}

void WriteResultText(const std::vector<StrandResult>& strands, double seconds,
                     const FileSink& sink) {
  std::string buffer;
  buffer.reserve(ResultWriter::kPieceBytes + 65536);
  ResultWriter(&buffer, &sink).Document(strands, seconds);
}

}  // namespace ringlet
