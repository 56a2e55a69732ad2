// The result writer (src/io/result_json.cpp, src/io/json_writer.cpp): numbers read back bit for
// bit through the repository's JSON reader, strings are escaped, and the directly written text
// is the same JSON value, member order included, as a document built independently with
// nlohmann from the same results (what the dump-based writer produced before issue 11).
#include "ringlet/result_json.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "io/json_reader.h"
#include "io/json_writer.h"
#include "ringlet/atomic_file.h"
#include "ringlet/scene_json.h"
#include "ringlet/statics.h"

namespace ringlet {
namespace {

using ordered_json = nlohmann::ordered_json;

// Parses text with the repository's reader (duplicate members refused), expecting success.
nlohmann::json ReadBack(const std::string& text) {
  nlohmann::json document;
  std::string error;
  EXPECT_TRUE(internal::ParseJsonText(text, &document, &error)) << error;
  return document;
}

// The doubles that formatting gets wrong most easily, then random ones from four families
// (random bit patterns over the whole range, subnormals, magnitudes near 1, huge magnitudes),
// seeded: every finite double class is there, both signs.
std::vector<double> TestDoubles() {
  using limits = std::numeric_limits<double>;
  std::vector<double> values = {0.0,
                                -0.0,
                                1.0,
                                -1.0,
                                0.1,
                                1.0 / 3.0,
                                2.0,
                                100.0,
                                1e15,
                                1e16,
                                1e20,
                                1e21,
                                1e22,
                                1.2345678901234568e20,
                                9007199254740992.0,  // 2^53
                                9007199254740994.0,
                                1e-5,
                                1e-4,
                                5e-324,
                                limits::denorm_min(),
                                -limits::denorm_min(),
                                std::nextafter(limits::min(), 0.0),  // largest subnormal
                                limits::min(),
                                -limits::min(),
                                limits::max(),
                                limits::lowest(),
                                std::nextafter(limits::max(), 0.0),
                                limits::epsilon(),
                                1.0 + limits::epsilon(),
                                3.141592653589793,
                                0.013333333333333334};
  std::mt19937_64 rng(20261201);
  std::uniform_int_distribution<uint64_t> bits;
  std::uniform_real_distribution<double> near_one(-1.0, 1.0);
  for (int i = 0; i < 20000; ++i) {
    // Any bit pattern that is a finite number.
    const double any = std::bit_cast<double>(bits(rng));
    if (std::isfinite(any)) values.push_back(any);
    // A subnormal: exponent field zero, random non-zero mantissa and sign.
    const uint64_t mantissa = bits(rng) & ((uint64_t{1} << 52) - 1);
    const uint64_t sign = bits(rng) & (uint64_t{1} << 63);
    if (mantissa != 0) values.push_back(std::bit_cast<double>(sign | mantissa));
    values.push_back(near_one(rng));
    // Huge: exponent field within 16 of the largest finite one.
    const uint64_t exponent = 2046 - (bits(rng) % 16);
    values.push_back(std::bit_cast<double>(sign | (exponent << 52) | mantissa));
  }
  return values;
}

TEST(JsonWriter, NumbersRoundTripBitExactly) {
  const std::vector<double> values = TestDoubles();
  std::string text = "[";
  for (size_t i = 0; i < values.size(); ++i) {
    if (i > 0) text += ", ";
    internal::AppendJsonNumber(values[i], &text);
  }
  text += "]";
  const nlohmann::json parsed = ReadBack(text);
  ASSERT_EQ(parsed.size(), values.size());
  int subnormals = 0, huge = 0, negative_zeros = 0;
  for (size_t i = 0; i < values.size(); ++i) {
    // Every double stays a floating-point number (1.0 is "1.0", not the integer 1) ...
    ASSERT_TRUE(parsed[i].is_number_float()) << i << ": " << parsed[i].dump();
    // ... and reads back with the same bits (the sign of zero included).
    ASSERT_EQ(std::bit_cast<uint64_t>(parsed[i].get<double>()), std::bit_cast<uint64_t>(values[i]))
        << i << ": " << values[i] << " written as " << parsed[i].dump();
    subnormals += std::fpclassify(values[i]) == FP_SUBNORMAL;
    huge += std::abs(values[i]) > 1e300;
    negative_zeros += values[i] == 0.0 && std::signbit(values[i]);
  }
  // Anti-vacuity: the hard classes were really there.
  EXPECT_GT(subnormals, 10000);
  EXPECT_GT(huge, 10000);
  EXPECT_EQ(negative_zeros, 1);
}

TEST(JsonWriter, ShortestFormsAndFloatMarkers) {
  const auto write = [](double x) {
    std::string s;
    internal::AppendJsonNumber(x, &s);
    return s;
  };
  EXPECT_EQ(write(0.0), "0.0");
  EXPECT_EQ(write(-0.0), "-0.0");
  EXPECT_EQ(write(2.0), "2.0");
  EXPECT_EQ(write(0.1), "0.1");
  EXPECT_EQ(write(0.013333333333333334), "0.013333333333333334");
  EXPECT_EQ(write(1e-7), "1e-07");
  EXPECT_EQ(write(5e-324), "5e-324");
  EXPECT_EQ(write(std::numeric_limits<double>::max()), "1.7976931348623157e+308");
  // Non-finite numbers have no JSON literal: null, as nlohmann writes them.
  EXPECT_EQ(write(std::numeric_limits<double>::quiet_NaN()), "null");
  EXPECT_EQ(write(std::numeric_limits<double>::infinity()), "null");
  EXPECT_EQ(write(-std::numeric_limits<double>::infinity()), "null");
  std::string integers;
  internal::AppendJsonInteger(0, &integers);
  integers += " ";
  internal::AppendJsonInteger(-42, &integers);
  integers += " ";
  internal::AppendJsonInteger(std::numeric_limits<long long>::min(), &integers);
  EXPECT_EQ(integers, "0 -42 -9223372036854775808");
}

TEST(JsonWriter, StringsAreEscapedLikeNlohmann) {
  const std::vector<std::string> texts = {
      "",
      "plain ascii: converged",
      "quote \" backslash \\ slash /",
      "controls \b \f \n \r \t \x01 \x1f and DEL \x7f",
      "\"", "\\\\\"\n", "\x01first and last\x02",  // escapes at the ends and in a row
      "UTF-8: caf\xc3\xa9, \xe2\x80\x94 dash",
  };
  for (const std::string& text : texts) {
    std::string written;
    internal::AppendJsonString(text, &written);
    EXPECT_EQ(written, nlohmann::json(text).dump()) << text;
    EXPECT_EQ(ReadBack(written).get<std::string>(), text);
    EXPECT_EQ(written.find('\n'), std::string::npos) << "a string stays on one line";
  }
  // Invalid UTF-8 is replaced (U+FFFD), not thrown on or copied into the file.
  std::string written;
  internal::AppendJsonString("bad \xff byte", &written);
  EXPECT_EQ(ReadBack(written).get<std::string>(), "bad \xef\xbf\xbd byte");
}

// ---------------------------------------------------------------------------------------------
// Whole result documents.

// The result document of a list of results, built value by value with nlohmann, independently of
// src/io/result_json.cpp, with the members and units of docs/scene-format.md in their order.
ordered_json ReferenceDocument(const std::vector<StrandResult>& results, double seconds) {
  const auto number = [](double x) { return std::isfinite(x) ? ordered_json(x) : ordered_json(); };
  const auto triple = [&](double a, double b, double c) {
    return ordered_json::array({number(a), number(b), number(c)});
  };
  ordered_json strands = ordered_json::array();
  int converged = 0, stable = 0;
  double max_penetration = 0.0;
  for (const StrandResult& r : results) {
    const SolveSummary& s = r.summary;
    converged += s.Converged();
    stable += s.stable;
    max_penetration = std::max(max_penetration, s.contact.max_penetration);
    ordered_json points = ordered_json::array();
    for (const Vec3& p : r.points) points.push_back(triple(p.x(), p.y(), p.z()));
    ordered_json curvatures = ordered_json::array();
    for (Eigen::Index i = 0; i + 2 < r.curvatures.size(); i += 3) {
      curvatures.push_back(triple(r.curvatures(i), r.curvatures(i + 1), r.curvatures(i + 2)));
    }
    ordered_json lengths = ordered_json::array();
    for (double l : r.segment_lengths) lengths.push_back(number(l));
    ordered_json strand;
    strand["points"] = points;
    strand["curvatures"] = curvatures;
    strand["segment_lengths"] = lengths;
    if (r.rest_curvatures.size() >= 3) {  // only strands with a per-segment rest shape
      ordered_json rest = ordered_json::array();
      for (Eigen::Index i = 0; i + 2 < r.rest_curvatures.size(); i += 3) {
        rest.push_back(
            triple(r.rest_curvatures(i), r.rest_curvatures(i + 1), r.rest_curvatures(i + 2)));
      }
      strand["rest_curvatures"] = rest;
    }
    strand["energy"]["elastic"] = number(s.energy.elastic);
    strand["energy"]["gravity"] = number(s.energy.gravity);
    strand["energy"]["contact"] = number(s.energy.contact);
    strand["energy"]["total"] = number(s.energy.total);
    strand["gradient_norm"] = number(s.gradient_norm);
    strand["residual"] = number(s.residual);
    strand["kirchhoff_residual"] = number(r.kirchhoff_residual);
    strand["iterations"] = s.iterations;
    strand["evaluations"] = s.evaluations;
    strand["hessian_evaluations"] = s.hessian_evaluations;
    strand["termination"] = TerminationName(s.termination);
    strand["stable"] = s.stable;
    strand["stability_checked"] = s.stability_checked;
    strand["min_hessian_eigenvalue"] = s.stability_checked ? number(s.min_eigenvalue) : nullptr;
    strand["stability_restarts"] = s.stability_restarts;
    strand["max_penetration"] = number(s.contact.max_penetration);
    strand["contact_samples"] = s.contact.samples_in_contact;
    strand["message"] = s.message;
    strands.push_back(strand);
  }
  ordered_json document;
  document["strands"] = strands;
  document["summary"]["strands"] = results.size();
  document["summary"]["converged"] = converged;
  document["summary"]["stable"] = stable;
  document["summary"]["max_penetration"] = number(max_penetration);
  document["summary"]["seconds"] = number(seconds);
  ordered_json& units = document["units"];
  units["points"] = "m, world coordinates, root to tip";
  units["curvatures"] = "1/m: [kappa1, kappa2, tau] per segment in the material frame (n1, n2, t)";
  units["segment_lengths"] = "m";
  units["rest_curvatures"] =
      "1/m: [kappa1^0, kappa2^0, tau^0] per segment, the rest shape (only for strands that have "
      "one, e.g. from ringlet invert)";
  units["energy"] = "J: elastic, gravity (measured from the root), contact penalty and their total";
  units["gradient_norm"] = "J m: norm of the energy gradient with respect to the curvatures";
  units["residual"] = "dimensionless: internal-moment mismatch relative to the largest moment";
  units["kirchhoff_residual"] =
      "dimensionless: the same balance by quadrature of the hanging weight's moment, "
      "independent of the solver (ringlet solve --check)";
  units["min_hessian_eigenvalue"] =
      "dimensionless: stiffness-scaled Hessian, 1 for an unloaded rod, < 0 unstable; "
      "null when the stability check did not run";
  units["max_penetration"] =
      "m: largest depth of the strand below the body surface (0 without a body)";
  units["contact_samples"] = "count: contact samples inside the clearance layer (carrying a force)";
  units["seconds"] = "s: wall time of the whole solve";
  units["null"] = "a number that was NaN or infinite (termination is then non_finite)";
  // Through text, as the old writer's dump() and a reader of the file see it.
  return ordered_json::parse(document.dump());
}

// The solved results of an example scene.
std::vector<StrandResult> SolveExample(const char* name, bool check_stability,
                                       int points_per_segment) {
  Scene scene;
  std::string error;
  EXPECT_TRUE(LoadScene(std::string(RINGLET_EXAMPLES_DIR) + "/" + name, &scene, &error)) << error;
  scene.solver.check_stability = check_stability;
  std::vector<StrandResult> results;
  for (const StrandModel& model : scene.strands) {
    results.push_back(
        MakeStrandResult(model, SolveStrand(model, scene.solver), points_per_segment));
  }
  return results;
}

// The written text against the independent reference and against ResultToJson (the tree that
// groom and style extend): the same values, members in the same order.
void ExpectSameDocument(const std::vector<StrandResult>& results, double seconds,
                        const std::string& label) {
  const std::string text = ResultToString(results, seconds);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n') << label;
  const ordered_json written = ordered_json::parse(text);
  const ordered_json reference = ReferenceDocument(results, seconds);
  EXPECT_EQ(written, reference) << label << "\nwritten:\n"
                                << written.dump(1).substr(0, 2000) << "\nreference:\n"
                                << reference.dump(1).substr(0, 2000);
  EXPECT_EQ(written, ordered_json::parse(ResultToJson(results, seconds).dump())) << label;
  // The reader the repository uses accepts it too (no duplicate members).
  ReadBack(text);
}

TEST(ResultWriter, SameDocumentAsTheReferenceForExampleScenes) {
  for (bool check : {false, true}) {
    ExpectSameDocument(SolveExample("vertical_curly.json", check, 1), 0.25,
                       std::string("vertical_curly check=") + (check ? "on" : "off"));
    ExpectSameDocument(SolveExample("strands.json", check, 1), 1.5e-3,
                       std::string("strands check=") + (check ? "on" : "off"));
  }
  ExpectSameDocument(SolveExample("horizontal_10cm.json", true, 4), 0.0, "points_per_segment 4");
  ExpectSameDocument({}, 0.0, "no strands");
}

TEST(ResultWriter, NonFiniteStrandMatchesTheReference) {
  std::vector<StrandResult> results = SolveExample("horizontal_10cm.json", true, 1);
  StrandSolution broken;
  Scene scene;
  std::string error;
  ASSERT_TRUE(
      LoadScene(std::string(RINGLET_EXAMPLES_DIR) + "/horizontal_10cm.json", &scene, &error));
  broken = SolveStrand(scene.strands[0]);
  broken.curvatures(1) = std::numeric_limits<double>::quiet_NaN();
  broken.summary.gradient_norm = -std::numeric_limits<double>::infinity();
  results.push_back(MakeStrandResult(scene.strands[0], broken, 1));
  ASSERT_EQ(results.back().summary.termination, Termination::kNonFinite);
  ExpectSameDocument(results, std::numeric_limits<double>::quiet_NaN(), "non-finite");
  const ordered_json written = ordered_json::parse(ResultToString(results, 0.0));
  EXPECT_TRUE(written["strands"][1]["curvatures"][0][1].is_null());
  EXPECT_TRUE(written["strands"][1]["gradient_norm"].is_null());
  EXPECT_TRUE(written["strands"][1]["kirchhoff_residual"].is_null());
  EXPECT_EQ(written["strands"][1]["termination"], "non_finite");
}

// Every number field of a result, filled with the hard doubles, reads back bit for bit through
// the whole writer; contact fields and messages with escapes are written too.
TEST(ResultWriter, EveryNumberFieldRoundTripsBitExactly) {
  const std::vector<double> values = TestDoubles();
  size_t next = 0;
  const auto take = [&] { return values[next++ % values.size()]; };
  std::vector<StrandResult> results(40);
  for (size_t k = 0; k < results.size(); ++k) {
    StrandResult& r = results[k];
    const int n = 25;
    for (int i = 0; i <= n; ++i) r.points.push_back(Vec3(take(), take(), take()));
    r.curvatures.resize(3 * n);
    for (int i = 0; i < 3 * n; ++i) r.curvatures(i) = take();
    // Every other strand has uniform segments (the writer copies a repeated length's text).
    const double uniform = take();
    for (int i = 0; i < n; ++i) r.segment_lengths.push_back(k % 2 ? uniform : take());
    SolveSummary& s = r.summary;
    s.energy.elastic = take();
    s.energy.gravity = take();
    s.energy.contact = take();
    s.energy.total = take();
    s.gradient_norm = take();
    s.residual = take();
    s.stability_checked = true;
    s.min_eigenvalue = take();
    s.contact.max_penetration = std::abs(take());
    s.contact.samples_in_contact = static_cast<int>(next % 7);
    s.iterations = static_cast<int>(next);
    s.message = "quote \" and\nnewline " + std::to_string(next);
    r.kirchhoff_residual = take();
  }
  ASSERT_GT(next, 4000u);
  const double seconds = take();
  const std::string text = ResultToString(results, seconds);
  const nlohmann::json doc = ReadBack(text);
  const auto bits = [](double x) { return std::bit_cast<uint64_t>(x); };
  const auto same = [&](const nlohmann::json& v, double x) {
    return v.is_number_float() && bits(v.get<double>()) == bits(x);
  };
  ASSERT_EQ(doc["strands"].size(), results.size());
  for (size_t k = 0; k < results.size(); ++k) {
    const StrandResult& r = results[k];
    const nlohmann::json& s = doc["strands"][k];
    for (size_t i = 0; i < r.points.size(); ++i) {
      for (int j = 0; j < 3; ++j) ASSERT_TRUE(same(s["points"][i][j], r.points[i](j))) << k;
    }
    for (size_t i = 0; i < r.segment_lengths.size(); ++i) {
      for (int j = 0; j < 3; ++j) {
        ASSERT_TRUE(same(s["curvatures"][i][j], r.curvatures(3 * static_cast<int>(i) + j)));
      }
      ASSERT_TRUE(same(s["segment_lengths"][i], r.segment_lengths[i]));
    }
    EXPECT_TRUE(same(s["energy"]["elastic"], r.summary.energy.elastic));
    EXPECT_TRUE(same(s["energy"]["gravity"], r.summary.energy.gravity));
    EXPECT_TRUE(same(s["energy"]["contact"], r.summary.energy.contact));
    EXPECT_TRUE(same(s["energy"]["total"], r.summary.energy.total));
    EXPECT_TRUE(same(s["gradient_norm"], r.summary.gradient_norm));
    EXPECT_TRUE(same(s["residual"], r.summary.residual));
    EXPECT_TRUE(same(s["kirchhoff_residual"], r.kirchhoff_residual));
    EXPECT_TRUE(same(s["min_hessian_eigenvalue"], r.summary.min_eigenvalue));
    EXPECT_TRUE(same(s["max_penetration"], r.summary.contact.max_penetration));
    EXPECT_EQ(s["contact_samples"], r.summary.contact.samples_in_contact);
    EXPECT_EQ(s["iterations"], r.summary.iterations);
    EXPECT_EQ(s["message"], r.summary.message);
  }
  EXPECT_TRUE(same(doc["summary"]["seconds"], seconds));
  ExpectSameDocument(results, seconds, "hard doubles");
}

// MakeStrandResults: the results of MakeStrandResult strand by strand, bit for bit, on any number
// of threads.
TEST(ResultWriter, MakeStrandResultsIsIndependentOfThreads) {
  Scene scene;
  std::string error;
  ASSERT_TRUE(LoadScene(std::string(RINGLET_EXAMPLES_DIR) + "/strands.json", &scene, &error));
  std::vector<StrandModel> models;
  for (int copy = 0; copy < 8; ++copy) {
    models.insert(models.end(), scene.strands.begin(), scene.strands.end());
  }
  std::vector<StrandSolution> solutions;
  for (const StrandModel& model : models) solutions.push_back(SolveStrand(model, scene.solver));
  std::vector<StrandResult> sequential;
  for (size_t i = 0; i < models.size(); ++i) {
    sequential.push_back(MakeStrandResult(models[i], solutions[i], 2));
  }
  const std::string expected = ResultToString(sequential, 1.0);
  for (int threads : {1, 2, 4, 0}) {
    const std::vector<StrandResult> parallel = MakeStrandResults(models, solutions, 2, threads);
    ASSERT_EQ(parallel.size(), models.size());
    EXPECT_EQ(ResultToString(parallel, 1.0), expected) << threads << " threads";
  }
  // Anti-vacuity: the strands differ, so a mix-up of their order would show.
  EXPECT_NE(sequential[0].points.back(), sequential[1].points.back());
}

// The layout of docs/scene-format.md: two-space indentation, a point or a curvature triple per
// line, the segment lengths on one line.
TEST(ResultWriter, LayoutKeepsNumberArraysOnOneLine) {
  const std::vector<StrandResult> results = SolveExample("horizontal_10cm.json", true, 1);
  const std::string text = ResultToString(results, 0.5);
  std::istringstream lines(text);
  std::vector<std::string> all;
  for (std::string line; std::getline(lines, line);) all.push_back(line);
  ASSERT_GE(all.size(), 6u);
  EXPECT_EQ(all[0], "{");
  EXPECT_EQ(all[1], "  \"strands\": [");
  EXPECT_EQ(all[2], "    {");
  EXPECT_EQ(all[3], "      \"points\": [");
  EXPECT_EQ(all[4], "        [0.0, 0.0, 0.0],");
  const size_t n = results[0].segment_lengths.size();
  // n + 1 point lines, then the closing bracket and the curvatures.
  EXPECT_EQ(all[4 + n + 1], "      ],");
  EXPECT_EQ(all[4 + n + 2], "      \"curvatures\": [");
  EXPECT_EQ(all[4 + n + 3 + n], "      ],");
  EXPECT_EQ(all[4 + n + 4 + n].rfind("      \"segment_lengths\": [", 0), 0u);
  EXPECT_EQ(all[4 + n + 4 + n].back(), ',');
  EXPECT_EQ(all.back(), "}");
}

// The streaming form (ringlet solve's file) hands out exactly ResultToString's bytes, in pieces
// of about 1 MiB: 400 copies of the curly strand make ~1.3 MB, so at least two pieces. A sink
// that fails stops the formatting after its first piece.
TEST(ResultWriter, StreamedTextIsTheSameBytesInPieces) {
  const std::vector<StrandResult> one = SolveExample("vertical_curly.json", true, 1);
  ASSERT_EQ(one.size(), 1u);
  const std::vector<StrandResult> results(400, one[0]);
  const std::string expected = ResultToString(results, 0.75);
  ASSERT_GT(expected.size(), size_t{1} << 20);
  std::string streamed;
  int pieces = 0;
  WriteResultText(results, 0.75, [&](std::string_view piece) {
    streamed.append(piece);
    ++pieces;
    EXPECT_LE(piece.size(), (size_t{1} << 20) + 65536);
    return true;
  });
  EXPECT_EQ(streamed, expected);
  EXPECT_GE(pieces, 2);
  int calls = 0;
  WriteResultText(results, 0.75, [&](std::string_view) {
    ++calls;
    return false;
  });
  EXPECT_EQ(calls, 1);
}

}  // namespace
}  // namespace ringlet
