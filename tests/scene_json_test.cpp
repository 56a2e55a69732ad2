// Scene files (defaults, sections, root frames, every bad input), result files (keys, precision,
// non-finite values) and atomic writes: src/io/.
#include "ringlet/scene_json.h"

#include <dlfcn.h>
#include <gtest/gtest.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <new>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "io/json_reader.h"
#include "ringlet/atomic_file.h"
#include "ringlet/result_json.h"
#include "ringlet/statics.h"
#include "ringlet/strand_geometry.h"
#include "ringlet/strand_model.h"

namespace ringlet {
namespace {

using nlohmann::json;

// A valid scene with one horizontal 10-cm strand and nothing but the required fields.
json MinimalScene() {
  return json::parse(R"({
    "strands": [{
      "length": 0.1,
      "root": {"position": [0, 0, 0], "tangent": [1, 0, 0], "normal": [0, 0, 1]}
    }]
  })");
}

// Parses document, expecting success.
Scene MustParse(const json& document) {
  Scene scene;
  std::string error;
  EXPECT_TRUE(ParseScene(document, &scene, &error)) << error;
  return scene;
}

// A fresh empty directory for file tests, removed by the destructor.
class TempDirectory {
 public:
  TempDirectory() {
    std::string pattern = ::testing::TempDir() + "ringlet_io_XXXXXX";
    path_ = ::mkdtemp(pattern.data()) ? pattern : std::string();
  }
  ~TempDirectory() {
    std::error_code ec;
    if (!path_.empty()) std::filesystem::remove_all(path_, ec);
  }
  const std::string& path() const { return path_; }
  // Names of the entries in the directory, hidden ones included.
  std::vector<std::string> Entries() const {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(path_)) {
      names.push_back(entry.path().filename().string());
    }
    return names;
  }

 private:
  std::string path_;
};

std::string ReadAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

// ---------------------------------------------------------------------------------------------
// Scene parsing: defaults and fields.

TEST(SceneJson, DefaultsAreThePapers) {
  const Scene scene = MustParse(MinimalScene());
  ASSERT_EQ(scene.strands.size(), 1u);
  const StrandModel& m = scene.strands[0];
  // 15 equal segments summing to the length.
  EXPECT_EQ(kDefaultSegments, 15);
  ASSERT_EQ(m.NumSegments(), 15);
  for (double l : m.segment_lengths) EXPECT_DOUBLE_EQ(l, 0.1 / 15);
  EXPECT_NEAR(m.Length(), 0.1, 1e-15);
  // Circular section of radius 50 um.
  EXPECT_DOUBLE_EQ(m.section.a, 50e-6);
  EXPECT_DOUBLE_EQ(m.section.b, 50e-6);
  // Material: E = 10 GPa, sigma = 0.3, rho = 1300 kg/m^3.
  EXPECT_DOUBLE_EQ(m.material.young_modulus, 10e9);
  EXPECT_DOUBLE_EQ(m.material.poisson_ratio, 0.3);
  EXPECT_DOUBLE_EQ(m.material.density, 1300.0);
  // Straight at rest, no twist; gravity 9.81 m/s^2 down.
  EXPECT_EQ(m.natural_curvature, Vec3::Zero());
  EXPECT_EQ(m.gravity, Vec3(0.0, 0.0, -9.81));
  // Root as given.
  EXPECT_EQ(m.root_position, Vec3::Zero());
  EXPECT_TRUE(m.root_frame.col(2).isApprox(Vec3(1, 0, 0)));
  EXPECT_TRUE(m.root_frame.col(0).isApprox(Vec3(0, 0, 1)));
  // Solver: SolveOptions' own defaults.
  const SolveOptions defaults;
  EXPECT_EQ(scene.solver.method, defaults.method);
  EXPECT_EQ(scene.solver.tolerance, defaults.tolerance);
  EXPECT_EQ(scene.solver.max_iterations, defaults.max_iterations);
  EXPECT_EQ(scene.solver.check_stability, defaults.check_stability);
  EXPECT_EQ(scene.solver.max_stability_restarts, defaults.max_stability_restarts);
}

TEST(SceneJson, EveryFieldIsRead) {
  json d = MinimalScene();
  d["gravity"] = {1.0, 2.0, -3.0};
  json& s = d["strands"][0];
  s["segments"] = 7;
  s["radius"] = 40e-6;
  s["young_modulus"] = 3e9;
  s["poisson_ratio"] = 0.25;
  s["density"] = 1100;
  s["natural_curvature"] = {50.0, -2.0};
  s["natural_twist"] = 10.0;
  s["root"]["position"] = {0.1, 0.2, 0.3};
  d["solver"] = {{"method", "newton"},
                 {"tolerance", 1e-7},
                 {"max_iterations", 33},
                 {"check_stability", false}};
  const Scene scene = MustParse(d);
  const StrandModel& m = scene.strands[0];
  EXPECT_EQ(m.NumSegments(), 7);
  EXPECT_DOUBLE_EQ(m.section.MeanRadius(), 40e-6);
  EXPECT_EQ(m.material.young_modulus, 3e9);
  EXPECT_EQ(m.material.poisson_ratio, 0.25);
  EXPECT_EQ(m.material.density, 1100.0);
  EXPECT_EQ(m.natural_curvature, Vec3(50.0, -2.0, 10.0));
  EXPECT_EQ(m.gravity, Vec3(1.0, 2.0, -3.0));
  EXPECT_EQ(m.root_position, Vec3(0.1, 0.2, 0.3));
  EXPECT_EQ(scene.solver.method, Method::kNewton);
  EXPECT_EQ(scene.solver.tolerance, 1e-7);
  EXPECT_EQ(scene.solver.max_iterations, 33);
  EXPECT_FALSE(scene.solver.check_stability);
}

TEST(SceneJson, IntegralFloatSegmentsAreIntegers) {
  json d = MinimalScene();
  d["strands"][0]["segments"] = 12.0;
  EXPECT_EQ(MustParse(d).strands[0].NumSegments(), 12);
}

TEST(SceneJson, EveryMethodNameRoundTrips) {
  for (const Method method : {Method::kBfgs, Method::kLbfgs, Method::kNewton}) {
    json d = MinimalScene();
    d["solver"]["method"] = MethodName(method);
    EXPECT_EQ(MustParse(d).solver.method, method) << MethodName(method);
  }
}

TEST(SceneJson, EccentricityKeepsTheMeanRadius) {
  json d = MinimalScene();
  d["strands"][0]["eccentricity"] = 0.6;
  const CrossSection c = MustParse(d).strands[0].section;
  EXPECT_NEAR(c.Eccentricity(), 0.6, 1e-12);
  EXPECT_NEAR(c.a * c.b, 50e-6 * 50e-6, 1e-22);
  EXPECT_GT(c.a, c.b);
}

TEST(SceneJson, EllipticityIsTheRatioOfSemiAxes) {
  json d = MinimalScene();
  d["strands"][0]["ellipticity"] = 1.5;
  d["strands"][0]["radius"] = 30e-6;
  const CrossSection c = MustParse(d).strands[0].section;
  EXPECT_NEAR(c.a / c.b, 1.5, 1e-12);
  EXPECT_NEAR(c.a * c.b, 30e-6 * 30e-6, 1e-22);
}

TEST(SceneJson, NormalIsOrthogonalizedAgainstTheTangent) {
  json d = MinimalScene();
  d["strands"][0]["root"]["tangent"] = {2.0, 0.0, 0.0};  // any length
  d["strands"][0]["root"]["normal"] = {1.0, 0.0, 3.0};   // not orthogonal, not unit
  const Mat3 q = MustParse(d).strands[0].root_frame;
  EXPECT_TRUE(q.col(2).isApprox(Vec3(1, 0, 0), 1e-15));   // t
  EXPECT_TRUE(q.col(0).isApprox(Vec3(0, 0, 1), 1e-15));   // n1: the normal minus its t part
  EXPECT_TRUE(q.col(1).isApprox(Vec3(0, -1, 0), 1e-15));  // n2 = t x n1
  EXPECT_TRUE((q.transpose() * q).isApprox(Mat3::Identity(), 1e-15));
  EXPECT_NEAR(q.determinant(), 1.0, 1e-15);
}

TEST(SceneJson, GradingGrowsSegmentsTowardsTheTip) {
  json d = MinimalScene();
  d["strands"][0]["length"] = 0.4;
  d["strands"][0]["segments"] = 40;
  d["strands"][0]["grading"] = 8.0;
  const StrandModel m = MustParse(d).strands[0];
  ASSERT_EQ(m.NumSegments(), 40);
  EXPECT_NEAR(m.segment_lengths.back() / m.segment_lengths.front(), 8.0, 1e-9);
  EXPECT_NEAR(m.Length(), 0.4, 1e-15);
  for (int i = 1; i < 40; ++i) EXPECT_GT(m.segment_lengths[i], m.segment_lengths[i - 1]);
}

// "grading": "auto" applies RecommendedGradingRatio to the strand's own load w L^3 / (E I1),
// computed here by hand for a circular 50-um hair: w = rho pi r^2 g, E I1 = E pi r^4 / 4.
TEST(SceneJson, AutoGradingUsesTheLoad) {
  json d = MinimalScene();
  d["strands"][0]["length"] = 0.5;
  d["strands"][0]["segments"] = 30;
  d["strands"][0]["grading"] = "auto";
  const StrandModel m = MustParse(d).strands[0];
  const double r = 50e-6, pi = std::acos(-1.0);
  const double load = 1300 * pi * r * r * 9.81 * 0.125 / (10e9 * pi * r * r * r * r / 4);
  EXPECT_NEAR(load, 255.06, 0.01);  // 4 rho g L^3 / (E r^2): a heavy hair, grading matters
  EXPECT_NEAR(m.segment_lengths.back() / m.segment_lengths.front(), RecommendedGradingRatio(load),
              1e-9 * RecommendedGradingRatio(load));
  EXPECT_GT(m.segment_lengths.back() / m.segment_lengths.front(), 30.0);
  EXPECT_NEAR(m.Length(), 0.5, 1e-15);
}

TEST(SceneJson, ExplicitSegmentLengthsAreKept) {
  json d = MinimalScene();
  d["strands"][0]["segment_lengths"] = {0.01, 0.02, 0.03, 0.04};
  d["strands"][0]["segments"] = 4;  // allowed when it matches
  const StrandModel m = MustParse(d).strands[0];
  EXPECT_EQ(m.segment_lengths, (std::vector<double>{0.01, 0.02, 0.03, 0.04}));
  // Without "segments" the count comes from the list.
  d["strands"][0].erase("segments");
  EXPECT_EQ(MustParse(d).strands[0].NumSegments(), 4);
}

TEST(SceneJson, GravityAppliesToEveryStrand) {
  json d = MinimalScene();
  const json copy = d["strands"][0];
  d["strands"].push_back(copy);
  d["gravity"] = {0.0, -9.81, 0.0};
  const Scene scene = MustParse(d);
  ASSERT_EQ(scene.strands.size(), 2u);
  for (const StrandModel& m : scene.strands) EXPECT_EQ(m.gravity, Vec3(0.0, -9.81, 0.0));
}

// ---------------------------------------------------------------------------------------------
// Scene parsing: every bad input is one line naming the field.

struct BadScene {
  const char* name;
  std::function<void(json&)> change;
  const char* field;  // the error must contain this
};

std::vector<BadScene> BadScenes() {
  auto strand = [](json& d) -> json& { return d["strands"][0]; };
  auto root = [](json& d) -> json& { return d["strands"][0]["root"]; };
  return {
      // Structure.
      {"TopLevelArray", [](json& d) { d = json::array({d}); }, "top level"},
      {"MissingStrands", [](json& d) { d.erase("strands"); }, "strands"},
      {"EmptyStrands", [](json& d) { d["strands"] = json::array(); }, "strands"},
      {"StrandsNotArray", [](json& d) { d["strands"] = json::object(); }, "strands"},
      {"StrandNotObject", [](json& d) { d["strands"][0] = 3; }, "strands[0]"},
      {"UnknownTopLevel",
       [](json& d) {
         d["gravty"] = {0, 0, -9.81};
       },
       "gravty"},
      {"UnknownStrandField", [=](json& d) { strand(d)["lenght"] = 0.1; }, "strands[0].lenght"},
      {"UnknownRootField",
       [=](json& d) {
         root(d)["up"] = {0, 0, 1};
       },
       "strands[0].root.up"},
      {"UnknownSolverField",
       [](json& d) {
         d["solver"] = {{"tol", 1e-6}};
       },
       "solver.tol"},
      {"SecondStrandBad",
       [](json& d) {
         const json copy = d["strands"][0];
         d["strands"].push_back(copy);
         d["strands"][1]["radius"] = -1;
       },
       "strands[1].radius"},
      // Length.
      {"MissingLength", [=](json& d) { strand(d).erase("length"); }, "strands[0].length"},
      {"ZeroLength", [=](json& d) { strand(d)["length"] = 0; }, "strands[0].length"},
      {"NegativeLength", [=](json& d) { strand(d)["length"] = -0.1; }, "strands[0].length"},
      {"StringLength", [=](json& d) { strand(d)["length"] = "10cm"; }, "strands[0].length"},
      {"NullLength", [=](json& d) { strand(d)["length"] = nullptr; }, "strands[0].length"},
      // Segments.
      {"ZeroSegments", [=](json& d) { strand(d)["segments"] = 0; }, "strands[0].segments"},
      {"NegativeSegments", [=](json& d) { strand(d)["segments"] = -3; }, "strands[0].segments"},
      {"TooManySegments", [=](json& d) { strand(d)["segments"] = kMaxSegments + 1; },
       "strands[0].segments"},
      {"HugeSegments", [=](json& d) { strand(d)["segments"] = 1e300; }, "strands[0].segments"},
      {"FractionalSegments", [=](json& d) { strand(d)["segments"] = 2.5; }, "strands[0].segments"},
      {"StringSegments", [=](json& d) { strand(d)["segments"] = "15"; }, "strands[0].segments"},
      {"BoolSegments", [=](json& d) { strand(d)["segments"] = true; }, "strands[0].segments"},
      {"GradingBelowOne", [=](json& d) { strand(d)["grading"] = 0.5; }, "strands[0].grading"},
      {"SegmentLengthsWithGrading",
       [=](json& d) {
         strand(d)["segment_lengths"] = {0.05, 0.05};
         strand(d)["grading"] = 2;
       },
       "strands[0].grading"},
      {"SegmentLengthsCountMismatch",
       [=](json& d) {
         strand(d)["segment_lengths"] = {0.05, 0.05};
         strand(d)["segments"] = 3;
       },
       "strands[0].segment_lengths"},
      {"SegmentLengthsSumMismatch",
       [=](json& d) {
         strand(d)["segment_lengths"] = {0.05, 0.04};
       },
       "strands[0].segment_lengths"},
      {"SegmentLengthsNegative",
       [=](json& d) {
         strand(d)["segment_lengths"] = {0.15, -0.05};
       },
       "strands[0].segment_lengths[1]"},
      {"SegmentLengthsEmpty", [=](json& d) { strand(d)["segment_lengths"] = json::array(); },
       "strands[0].segment_lengths"},
      {"SegmentLengthsNotArray", [=](json& d) { strand(d)["segment_lengths"] = 0.1; },
       "strands[0].segment_lengths"},
      // Section.
      {"ZeroRadius", [=](json& d) { strand(d)["radius"] = 0; }, "strands[0].radius"},
      {"NegativeRadius", [=](json& d) { strand(d)["radius"] = -1; }, "strands[0].radius"},
      {"EccentricityOne", [=](json& d) { strand(d)["eccentricity"] = 1.0; },
       "strands[0].eccentricity"},
      {"EccentricityNegative", [=](json& d) { strand(d)["eccentricity"] = -0.1; },
       "strands[0].eccentricity"},
      {"EllipticityBelowOne", [=](json& d) { strand(d)["ellipticity"] = 0.9; },
       "strands[0].ellipticity"},
      {"EccentricityAndEllipticity",
       [=](json& d) {
         strand(d)["eccentricity"] = 0.3;
         strand(d)["ellipticity"] = 1.2;
       },
       "strands[0].ellipticity"},
      // Material.
      {"ZeroModulus", [=](json& d) { strand(d)["young_modulus"] = 0; }, "strands[0].young_modulus"},
      {"NegativeModulus", [=](json& d) { strand(d)["young_modulus"] = -1e9; },
       "strands[0].young_modulus"},
      {"PoissonTooLarge", [=](json& d) { strand(d)["poisson_ratio"] = 0.6; },
       "strands[0].poisson_ratio"},
      {"PoissonMinusOne", [=](json& d) { strand(d)["poisson_ratio"] = -1; },
       "strands[0].poisson_ratio"},
      {"NegativeDensity", [=](json& d) { strand(d)["density"] = -1; }, "strands[0].density"},
      // Natural shape and gravity.
      {"CurvatureThreeEntries",
       [=](json& d) {
         strand(d)["natural_curvature"] = {1, 2, 3};
       },
       "strands[0].natural_curvature"},
      {"CurvatureString",
       [=](json& d) {
         strand(d)["natural_curvature"] = {1, "2"};
       },
       "strands[0].natural_curvature"},
      {"TwistString", [=](json& d) { strand(d)["natural_twist"] = "ten"; },
       "strands[0].natural_twist"},
      {"GravityTwoEntries",
       [](json& d) {
         d["gravity"] = {0, -9.81};
       },
       "gravity"},
      // Root.
      {"MissingRoot", [=](json& d) { strand(d).erase("root"); }, "strands[0].root"},
      {"RootNotObject",
       [=](json& d) {
         strand(d)["root"] = {0, 0, 0};
       },
       "strands[0].root"},
      {"MissingPosition", [=](json& d) { root(d).erase("position"); }, "strands[0].root.position"},
      {"MissingTangent", [=](json& d) { root(d).erase("tangent"); }, "strands[0].root.tangent"},
      {"MissingNormal", [=](json& d) { root(d).erase("normal"); }, "strands[0].root.normal"},
      {"ZeroTangent",
       [=](json& d) {
         root(d)["tangent"] = {0, 0, 0};
       },
       "strands[0].root.tangent"},
      {"OverflowingTangent",
       [=](json& d) {
         root(d)["tangent"] = {1e300, 1e300, 0};
       },
       "strands[0].root.tangent"},
      {"ShortTangent",
       [=](json& d) {
         root(d)["tangent"] = {1, 0};
       },
       "strands[0].root.tangent"},
      {"ZeroNormal",
       [=](json& d) {
         root(d)["normal"] = {0, 0, 0};
       },
       "strands[0].root.normal"},
      {"ParallelNormal",
       [=](json& d) {
         root(d)["normal"] = {-3, 0, 0};
       },
       "strands[0].root.normal"},
      {"PositionString", [=](json& d) { root(d)["position"] = "origin"; },
       "strands[0].root.position"},
      // Solver.
      {"SolverNotObject", [](json& d) { d["solver"] = "bfgs"; }, "solver"},
      {"UnknownMethod",
       [](json& d) {
         d["solver"] = {{"method", "cg"}};
       },
       "solver.method"},
      {"MethodNotString",
       [](json& d) {
         d["solver"] = {{"method", 1}};
       },
       "solver.method"},
      {"ZeroTolerance",
       [](json& d) {
         d["solver"] = {{"tolerance", 0}};
       },
       "solver.tolerance"},
      {"ToleranceAboveOne",
       [](json& d) {
         d["solver"] = {{"tolerance", 2}};
       },
       "solver.tolerance"},
      {"ZeroIterations",
       [](json& d) {
         d["solver"] = {{"max_iterations", 0}};
       },
       "solver.max_iterations"},
      {"FractionalIterations",
       [](json& d) {
         d["solver"] = {{"max_iterations", 1.5}};
       },
       "solver.max_iterations"},
      {"GradingUnknownWord", [](json& d) { d["strands"][0]["grading"] = "automatic"; },
       "strands[0].grading"},
      {"StabilityString",
       [](json& d) {
         d["solver"] = {{"check_stability", "yes"}};
       },
       "solver.check_stability"},
  };
}

TEST(SceneJson, EveryBadInputNamesItsField) {
  for (const BadScene& bad : BadScenes()) {
    SCOPED_TRACE(bad.name);
    json d = MinimalScene();
    bad.change(d);
    // A sentinel scene: a failed parse must leave it untouched.
    Scene scene;
    scene.solver.max_iterations = 7;
    std::string error;
    EXPECT_FALSE(ParseScene(d, &scene, &error));
    EXPECT_NE(error.find(bad.field), std::string::npos) << "error: " << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << "error: " << error;
    EXPECT_TRUE(scene.strands.empty());
    EXPECT_EQ(scene.solver.max_iterations, 7);
  }
}

TEST(SceneJson, ErrorQuotesWhatWasFound) {
  json d = MinimalScene();
  d["strands"][0]["radius"] = -1;
  Scene scene;
  std::string error;
  ASSERT_FALSE(ParseScene(d, &scene, &error));
  EXPECT_EQ(error, "strands[0].radius: expected a finite number > 0 (metres), got -1");
}

TEST(SceneJson, MisspeltFieldGetsAHint) {
  json d = MinimalScene();
  d["strands"][0]["raduis"] = 1e-4;
  Scene scene;
  std::string error;
  ASSERT_FALSE(ParseScene(d, &scene, &error));
  EXPECT_NE(error.find("did you mean \"radius\""), std::string::npos) << error;
}

TEST(SceneJson, OddKeysStayOnOneLine) {
  json d = MinimalScene();
  d["strands"][0]["a\nb"] = 1;
  Scene scene;
  std::string error;
  ASSERT_FALSE(ParseScene(d, &scene, &error));
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  EXPECT_NE(error.find(R"(strands[0]["a\nb"])"), std::string::npos) << error;
}

// ---------------------------------------------------------------------------------------------
// Scene text: JSON syntax, positions, duplicates, files.

TEST(SceneJsonText, SyntaxErrorSaysLineAndColumn) {
  const std::string text = "{\n  \"strands\": [\n    {\"length\": 0.1,,}\n  ]\n}\n";
  Scene scene;
  std::string error;
  ASSERT_FALSE(ParseSceneText(text, &scene, &error));
  EXPECT_NE(error.find("line 3, column 20"), std::string::npos) << error;
  EXPECT_NE(error.find("invalid JSON"), std::string::npos) << error;
  EXPECT_EQ(error.find("json.exception"), std::string::npos) << error;
}

TEST(SceneJsonText, ColumnsCountCharactersNotBytes) {
  // "é" is two bytes in UTF-8 but one column: the second comma is character 9, byte 10.
  const std::string text = "{\"\xc3\xa9\": 1,,}";
  Scene scene;
  std::string error;
  ASSERT_FALSE(ParseSceneText(text, &scene, &error));
  EXPECT_NE(error.find("line 1, column 9"), std::string::npos) << error;
}

TEST(SceneJsonText, EmptyTextIsAnError) {
  Scene scene;
  std::string error;
  ASSERT_FALSE(ParseSceneText("", &scene, &error));
  EXPECT_NE(error.find("line 1, column 1"), std::string::npos) << error;
}

TEST(SceneJsonText, NumberOverflowIsNotInfinity) {
  const std::string text = "{\n \"strands\": [\n  {\"length\": 1e999}]}";
  Scene scene;
  std::string error;
  ASSERT_FALSE(ParseSceneText(text, &scene, &error));
  EXPECT_EQ(error,
            "strands[0].length: expected a finite number, got 1e999 (beyond the range of a "
            "double; line 3, column 14)");
  // Inside an array, the element is named.
  ASSERT_FALSE(ParseSceneText(R"({"gravity": [0, -1e400, 0]})", &scene, &error));
  EXPECT_NE(error.find("gravity[1]: expected a finite number, got -1e400"), std::string::npos)
      << error;
}

TEST(SceneJsonText, DuplicateFieldIsAnError) {
  const std::string text = R"({"strands": [{"length": 0.1, "radius": 1e-4, "radius": 2e-4,
      "root": {"position": [0, 0, 0], "tangent": [1, 0, 0], "normal": [0, 0, 1]}}]})";
  Scene scene;
  std::string error;
  ASSERT_FALSE(ParseSceneText(text, &scene, &error));
  EXPECT_NE(error.find("strands[0].radius: duplicate field"), std::string::npos) << error;
}

TEST(SceneJsonText, DuplicateInLaterArrayElementIsLocated) {
  const std::string text =
      R"({"gravity": [0, 0, -9.81], "strands": [{"length": 0.1}, {"root": {"tangent": 1, )"
      R"("tangent": 2}}]})";
  Scene scene;
  std::string error;
  ASSERT_FALSE(ParseSceneText(text, &scene, &error));
  EXPECT_NE(error.find("strands[1].root.tangent: duplicate field"), std::string::npos) << error;
}

// The duplicate finder reuses its per-depth frames from one object to the next and switches from
// a linear search to a set beyond a few dozen keys: neither may leak keys between sibling objects
// nor miss a duplicate among many keys.
TEST(SceneJsonText, DuplicatesAmongManyKeysAndSiblingObjects) {
  json document;
  std::string error;
  // Sibling objects (same depth) with the same keys are fine, also after an unrelated object.
  EXPECT_TRUE(internal::ParseJsonText(
      R"([{"a": 1, "b": {"x": 1}}, {"a": 2, "b": {"x": 2, "y": 3}}, {"b": 0, "a": 1}])", &document,
      &error))
      << error;
  // Many keys: every one distinct is fine, a repeat of an early one after the 40th is found.
  std::string many = "{";
  for (int i = 0; i < 50; ++i) many += (i ? ", \"k" : "\"k") + std::to_string(i) + "\": 0";
  EXPECT_TRUE(internal::ParseJsonText(many + "}", &document, &error)) << error;
  EXPECT_FALSE(internal::ParseJsonText(many + ", \"k3\": 1}", &document, &error));
  EXPECT_NE(error.find("k3: duplicate field"), std::string::npos) << error;
  // And again in a later sibling, after a frame was reused with many keys.
  EXPECT_FALSE(internal::ParseJsonText("[" + many + "}, {\"a\": 1, \"a\": 2}]", &document, &error));
  EXPECT_NE(error.find("[1].a: duplicate field"), std::string::npos) << error;
}

TEST(SceneJsonText, ValidTextParses) {
  Scene scene;
  std::string error;
  EXPECT_TRUE(ParseSceneText(MinimalScene().dump(2), &scene, &error)) << error;
  EXPECT_EQ(scene.strands.size(), 1u);
}

TEST(SceneJsonFile, MissingFileNamesThePath) {
  Scene scene;
  std::string error;
  ASSERT_FALSE(LoadScene("/nonexistent/scene.json", &scene, &error));
  EXPECT_EQ(error.rfind("/nonexistent/scene.json: ", 0), 0u) << error;
}

TEST(SceneJsonFile, DirectoryIsNotAScene) {
  TempDirectory dir;
  Scene scene;
  std::string error;
  ASSERT_FALSE(LoadScene(dir.path(), &scene, &error));
  EXPECT_NE(error.find("is a directory"), std::string::npos) << error;
}

TEST(SceneJsonFile, ErrorsStartWithThePath) {
  TempDirectory dir;
  const std::string path = dir.path() + "/scene.json";
  json d = MinimalScene();
  d["strands"][0]["radius"] = -1;
  std::ofstream(path) << d.dump();
  Scene scene;
  std::string error;
  ASSERT_FALSE(LoadScene(path, &scene, &error));
  EXPECT_EQ(error, path + ": strands[0].radius: expected a finite number > 0 (metres), got -1");
  // And a good file loads.
  std::ofstream(path) << MinimalScene().dump();
  EXPECT_TRUE(LoadScene(path, &scene, &error)) << error;
}

// A scene's optional body (issue 25, item 5): a file relative to the scene or an inline object;
// every strand then touches it through the statics penalty (contact.h).
TEST(SceneJsonFile, BodyFileIsRelativeToTheScene) {
  TempDirectory dir;
  std::filesystem::create_directory(dir.path() + "/bodies");
  std::ofstream(dir.path() + "/bodies/ball.json")
      << R"({"spheres": [{"name": "head", "center": [0, 0, 0], "radius": 0.05}]})";
  json d = MinimalScene();
  d["body"] = "bodies/ball.json";
  d["contact"] = {{"clearance", 0.001}};
  std::ofstream(dir.path() + "/scene.json") << d.dump();
  Scene scene;
  std::string error;
  ASSERT_TRUE(LoadScene(dir.path() + "/scene.json", &scene, &error)) << error;
  ASSERT_NE(scene.body, nullptr);
  const Sphere* head = scene.body->FindSphere("head");
  ASSERT_NE(head, nullptr);
  EXPECT_EQ(head->radius, 0.05);
  EXPECT_EQ(scene.strands[0].contact.obstacle, scene.body);
  EXPECT_EQ(scene.strands[0].contact.clearance, 0.001);
  // Without a body, no contact (the default of every strand).
  const Scene bare = MustParse(MinimalScene());
  EXPECT_EQ(bare.body, nullptr);
  EXPECT_EQ(bare.strands[0].contact.obstacle, nullptr);
}

TEST(SceneJson, BadBodiesNameTheField) {
  const json sphere = json::parse(R"({"spheres": [{"center": [0, 0, 0], "radius": 0.05}]})");
  struct Case {
    std::function<void(json&)> edit;
    std::string error;
  };
  const std::vector<Case> cases = {
      {[](json& d) { d["contact"] = {{"clearance", 0.001}}; },
       "contact: needs a \"body\" to touch (docs/scene-format.md)"},
      {[](json& d) { d["body"] = 3; },
       "body: expected a body file name or a body object {\"spheres\": [...], \"meshes\": "
       "[...]}, got 3"},
      {[&](json& d) {
         d["body"] = sphere;
         d["body"]["spheres"][0]["radius"] = -1;
       },
       "body.spheres[0].radius: expected a positive number (m), got -1"},
      {[&](json& d) {
         d["body"] = sphere;
         d["contact"] = {{"clearance", 0.2}};
       },
       "contact.clearance: expected a finite number in [0, 0.1) (m), got 0.2"},
      {[&](json& d) {
         d["body"] = sphere;
         d["contact"] = {{"clearence", 0.01}};
       },
       "contact.clearence: unknown field (did you mean \"clearance\"?)"},
  };
  for (const Case& c : cases) {
    json d = MinimalScene();
    c.edit(d);
    Scene scene;
    std::string error;
    EXPECT_FALSE(ParseScene(d, &scene, &error)) << d.dump();
    EXPECT_EQ(error, c.error) << d.dump();
  }
  // A body file that does not exist: the body field and the path.
  json d = MinimalScene();
  d["body"] = "/nonexistent/body.json";
  Scene scene;
  std::string error;
  EXPECT_FALSE(ParseScene(d, &scene, &error));
  EXPECT_EQ(error.rfind("body: /nonexistent/body.json: ", 0), 0u) << error;
}

// A horizontal 10-cm strand (root at z = 3 cm) above a 5-cm ball placed where its free end
// sags to (the bare tip is at (0.0966, 0, 0.0057)): without the body the equilibrium passes
// 3 cm deep into the ball (the vacuity check; measured 0.0208 m from the centre); with it, every
// sampled point stays outside up to the penalty's small penetration (the distance from the
// ball's centre checks it, not the solver's contact measure; measured 0.12 mm inside).
TEST(SceneJson, InlineBodyHoldsTheStrand) {
  json d = MinimalScene();
  d["strands"][0]["root"]["position"] = {0.0, 0.0, 0.03};
  const Scene bare = MustParse(d);
  const Vec3 centre(0.095, 0.0, -0.015);
  d["body"] = {{"spheres", {{{"center", {0.095, 0.0, -0.015}}, {"radius", 0.05}}}}};
  const Scene touching = MustParse(d);
  auto min_radius = [&centre](const StrandModel& model) {
    const StrandSolution solution = SolveStrand(model);
    EXPECT_TRUE(solution.summary.Converged()) << solution.summary.message;
    double r = 1.0;
    for (const Vec3& p : SampleCentreline(model, solution.curvatures, 8)) {
      r = std::min(r, (p - centre).norm());
    }
    return r;
  };
  EXPECT_LT(min_radius(bare.strands[0]), 0.045);
  EXPECT_GT(min_radius(touching.strands[0]), 0.05 - 0.5e-3);
}

// ---------------------------------------------------------------------------------------------
// Result files.

StrandModel HorizontalStrand() { return MustParse(MinimalScene()).strands[0]; }

TEST(ResultJson, HasEveryKeyAndRoundTripsNumbers) {
  const StrandModel model = HorizontalStrand();
  const StrandSolution solution = SolveStrand(model);
  ASSERT_TRUE(solution.summary.Converged()) << solution.summary.message;
  const std::vector<StrandResult> results = {MakeStrandResult(model, solution, 1)};
  const json doc = json::parse(ResultToString(results, 0.25));

  for (const char* key : {"strands", "summary", "units"}) EXPECT_TRUE(doc.contains(key)) << key;
  ASSERT_EQ(doc["strands"].size(), 1u);
  const json& s = doc["strands"][0];
  for (const char* key : {"points", "curvatures", "segment_lengths", "energy", "gradient_norm",
                          "residual", "iterations", "evaluations", "termination", "stable",
                          "min_hessian_eigenvalue", "stability_restarts", "message"}) {
    EXPECT_TRUE(s.contains(key)) << key;
  }
  for (const char* key : {"elastic", "gravity", "total"}) EXPECT_TRUE(s["energy"].contains(key));
  for (const char* key : {"strands", "converged", "stable", "seconds"}) {
    EXPECT_TRUE(doc["summary"].contains(key)) << key;
  }

  // Shapes: n + 1 points, n curvature triples, n lengths.
  const int n = model.NumSegments();
  ASSERT_EQ(s["points"].size(), static_cast<size_t>(n + 1));
  ASSERT_EQ(s["curvatures"].size(), static_cast<size_t>(n));
  ASSERT_EQ(s["segment_lengths"].size(), static_cast<size_t>(n));
  for (const json& p : s["points"]) EXPECT_EQ(p.size(), 3u);
  for (const json& c : s["curvatures"]) EXPECT_EQ(c.size(), 3u);

  // Values, bit for bit (full precision).
  const StrandResult& r = results[0];
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j < 3; ++j) EXPECT_EQ(s["points"][i][j].get<double>(), r.points[i](j));
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < 3; ++j) {
      EXPECT_EQ(s["curvatures"][i][j].get<double>(), solution.curvatures(3 * i + j));
    }
    EXPECT_EQ(s["segment_lengths"][i].get<double>(), model.segment_lengths[i]);
  }
  EXPECT_EQ(s["energy"]["total"].get<double>(), solution.summary.energy.total);
  EXPECT_EQ(s["residual"].get<double>(), solution.summary.residual);
  EXPECT_EQ(s["termination"], "converged");
  EXPECT_EQ(s["stable"], true);
  EXPECT_EQ(s["iterations"], solution.summary.iterations);
  EXPECT_EQ(doc["summary"]["strands"], 1);
  EXPECT_EQ(doc["summary"]["converged"], 1);
  EXPECT_EQ(doc["summary"]["stable"], 1);
  EXPECT_EQ(doc["summary"]["seconds"], 0.25);
  // The first point is the root; the strand sags under gravity.
  EXPECT_EQ(r.points.front(), model.root_position);
  EXPECT_LT(r.points.back().z(), 0.0);
}

TEST(ResultJson, PointsPerSegmentSamplesTheCentreline) {
  const StrandModel model = HorizontalStrand();
  const StrandSolution solution = SolveStrand(model);
  const int n = model.NumSegments();
  for (int k : {1, 2, 5}) {
    const StrandResult r = MakeStrandResult(model, solution, k);
    ASSERT_EQ(r.points.size(), static_cast<size_t>(n * k + 1)) << k;
    // Every k-th sample is a segment end, whatever k.
    const StrandResult ends = MakeStrandResult(model, solution, 1);
    for (int i = 0; i <= n; ++i) {
      EXPECT_TRUE(r.points[static_cast<size_t>(i * k)].isApprox(ends.points[i], 1e-12))
          << k << " " << i;
    }
  }
}

TEST(ResultJson, NonFiniteValuesAreNullAndSaySo) {
  const StrandModel model = HorizontalStrand();
  StrandSolution solution = SolveStrand(model);
  ASSERT_TRUE(solution.summary.stable);
  solution.curvatures(4) = std::numeric_limits<double>::quiet_NaN();
  solution.summary.energy.total = std::numeric_limits<double>::infinity();
  const StrandResult r = MakeStrandResult(model, solution, 1);
  EXPECT_EQ(r.summary.termination, Termination::kNonFinite);
  EXPECT_FALSE(r.summary.stable);
  EXPECT_FALSE(r.Succeeded());

  const std::string text = ResultToString({r}, 0.0);
  json doc;
  ASSERT_NO_THROW(doc = json::parse(text));  // valid JSON, no NaN or Infinity literals
  const json& s = doc["strands"][0];
  EXPECT_EQ(s["termination"], "non_finite");
  EXPECT_EQ(s["stable"], false);
  EXPECT_TRUE(s["curvatures"][1][1].is_null());
  EXPECT_TRUE(s["energy"]["total"].is_null());
  EXPECT_NE(s["message"].get<std::string>().find("non-finite"), std::string::npos);
  EXPECT_EQ(doc["summary"]["converged"], 0);
  EXPECT_EQ(doc["summary"]["stable"], 0);
}

TEST(ResultJson, UncheckedStabilityStillSucceedsWhenConverged) {
  const StrandModel model = HorizontalStrand();
  SolveOptions options;
  options.check_stability = false;
  const StrandResult r = MakeStrandResult(model, SolveStrand(model, options), 1);
  EXPECT_TRUE(r.summary.Converged());
  EXPECT_FALSE(r.summary.stability_checked);
  EXPECT_TRUE(r.Succeeded());
  const json s = json::parse(ResultToString({r}, 0.0))["strands"][0];
  EXPECT_TRUE(s["min_hessian_eigenvalue"].is_null());
  EXPECT_EQ(s["stability_checked"], false);
}

TEST(ResultJson, CountsOverStrands) {
  const StrandModel model = HorizontalStrand();
  SolveOptions short_budget;
  short_budget.max_iterations = 1;
  const std::vector<StrandResult> results = {
      MakeStrandResult(model, SolveStrand(model), 1),
      MakeStrandResult(model, SolveStrand(model, short_budget), 1)};
  ASSERT_FALSE(results[1].summary.Converged());  // anti-vacuity: one strand really failed
  const ResultCounts counts = CountResults(results);
  EXPECT_EQ(counts.strands, 2);
  EXPECT_EQ(counts.converged, 1);
  EXPECT_EQ(counts.stable, 1);
  EXPECT_EQ(counts.succeeded, 1);
  EXPECT_EQ(json::parse(ResultToString(results, 0.0))["strands"][1]["termination"],
            "max_iterations");
}

// ---------------------------------------------------------------------------------------------
// Atomic writes.

TEST(AtomicFile, WritesNewFileAndLeavesNoTemporary) {
  TempDirectory dir;
  const std::string path = dir.path() + "/out.json";
  std::string error;
  ASSERT_TRUE(WriteFileAtomically(path, "hello\n", false, &error)) << error;
  EXPECT_EQ(ReadAll(path), "hello\n");
  EXPECT_EQ(dir.Entries(), std::vector<std::string>{"out.json"});
}

// The producer form (ringlet solve's streamed result): the pieces in order, and a producer that
// throws (out of memory while formatting) gives one line and leaves nothing behind, the user's
// file untouched.
TEST(AtomicFile, ProducerWritesPiecesAndAFailingOneLeavesNothing) {
  TempDirectory dir;
  const std::string path = dir.path() + "/out.json";
  std::string error;
  ASSERT_TRUE(WriteFileAtomically(
      path, [](const FileSink& sink) { EXPECT_TRUE(sink("one, ") && sink("two\n")); }, false,
      &error))
      << error;
  EXPECT_EQ(ReadAll(path), "one, two\n");
  EXPECT_FALSE(WriteFileAtomically(
      path,
      [](const FileSink& sink) {
        sink("partial");
        throw std::bad_alloc();
      },
      true, &error));
  EXPECT_EQ(error.rfind(path + ": cannot write: ", 0), 0u) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  EXPECT_EQ(ReadAll(path), "one, two\n");
  EXPECT_EQ(dir.Entries(), std::vector<std::string>{"out.json"});
}

TEST(AtomicFile, RefusesToOverwriteWithoutPermission) {
  TempDirectory dir;
  const std::string path = dir.path() + "/out.json";
  std::ofstream(path) << "precious";
  std::string error;
  EXPECT_FALSE(WriteFileAtomically(path, "new", false, &error));
  EXPECT_NE(error.find("already exists"), std::string::npos) << error;
  EXPECT_EQ(error.rfind(path, 0), 0u) << error;
  EXPECT_EQ(ReadAll(path), "precious");
  EXPECT_EQ(dir.Entries(), std::vector<std::string>{"out.json"});
}

TEST(AtomicFile, OverwritesWhenAllowed) {
  TempDirectory dir;
  const std::string path = dir.path() + "/out.json";
  std::ofstream(path) << "old";
  std::string error;
  ASSERT_TRUE(WriteFileAtomically(path, "new", true, &error)) << error;
  EXPECT_EQ(ReadAll(path), "new");
  EXPECT_EQ(dir.Entries(), std::vector<std::string>{"out.json"});
}

TEST(AtomicFile, FailsCleanlyInAMissingDirectory) {
  TempDirectory dir;
  const std::string path = dir.path() + "/missing/out.json";
  std::string error;
  EXPECT_FALSE(WriteFileAtomically(path, "x", false, &error));
  EXPECT_EQ(error.rfind(path, 0), 0u) << error;
  EXPECT_TRUE(dir.Entries().empty());
}

TEST(AtomicFile, RefusesADirectory) {
  TempDirectory dir;
  std::string error;
  EXPECT_FALSE(WriteFileAtomically(dir.path(), "x", true, &error));
  EXPECT_NE(error.find("is a directory"), std::string::npos) << error;
  EXPECT_TRUE(dir.Entries().empty());
}

// The directory of a death test in the threadsafe style (the child runs the test again from the
// start): the parent makes it and passes it to the child through the environment variable; the
// style and the variable are restored when the test ends (also on an ASSERT's early return).
class DeathTestDirectory {
 public:
  explicit DeathTestDirectory(const char* variable)
      : variable_(variable), previous_style_(GTEST_FLAG_GET(death_test_style)) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    if (const char* inherited = std::getenv(variable)) {
      path_ = inherited;  // the child: the parent's directory
      return;
    }
    own_ = std::make_unique<TempDirectory>();
    path_ = own_->path();
    if (!path_.empty()) ::setenv(variable, path_.c_str(), 1);
  }
  ~DeathTestDirectory() {
    if (own_) ::unsetenv(variable_);
    GTEST_FLAG_SET(death_test_style, previous_style_);  // the rest of the binary's tests as they were
  }
  DeathTestDirectory(const DeathTestDirectory&) = delete;
  DeathTestDirectory& operator=(const DeathTestDirectory&) = delete;
  bool parent() const { return own_ != nullptr; }
  const std::string& path() const { return path_; }

 private:
  const char* variable_;
  std::string previous_style_;
  std::unique_ptr<TempDirectory> own_;
  std::string path_;
};

// A signal while other threads keep writing: the handler runs on one thread and the others go on,
// so one of them could make a temporary after the handler had passed its slot and leave it
// behind (cli_limits' groom SIGTERM case saw one under load; SignalGuard in atomic_file.cpp).
// Each trial is a death test in the threadsafe style (the child runs this test again from the
// start, so the directory comes through the environment): 3 threads write small files without
// pause while the main thread raises SIGTERM after a few milliseconds; the child must die by
// the signal and leave only whole files. Before the fix, 6 of the 20 trials left one (idle).
TEST(AtomicFileDeathTest, SignalWhileOtherThreadsWriteLeavesNoTemporary) {
  const DeathTestDirectory death_directory("RINGLET_TEST_SIGNAL_DIRECTORY");
  const std::string& directory = death_directory.path();
  ASSERT_FALSE(directory.empty());
  for (int trial = 0; trial < 20; ++trial) {
    const std::string trial_directory = directory + "/" + std::to_string(trial);
    ::mkdir(trial_directory.c_str(), 0777);
    EXPECT_EXIT(
        {
          RemoveTemporariesOnSignals();
          std::atomic<int> written{0};
          std::vector<std::thread> writers;
          for (int t = 0; t < 3; ++t) {
            writers.emplace_back([&, t] {
              for (int k = 0;; ++k) {
                std::string error;
                const std::string name = trial_directory + "/f" + std::to_string(t) + "_" +
                                         std::to_string(k % 4);
                if (WriteFileAtomically(name, std::string(512, 'x'), true, &error)) ++written;
              }
            });
          }
          while (written.load() < 6) std::this_thread::yield();
          std::this_thread::sleep_for(std::chrono::microseconds(200 * (trial % 5)));
          std::raise(SIGTERM);
          for (std::thread& w : writers) w.join();  // not reached
        },
        ::testing::KilledBySignal(SIGTERM), "");
    for (const auto& entry : std::filesystem::directory_iterator(trial_directory)) {
      const std::string name = entry.path().filename().string();
      EXPECT_EQ(name.find(".tmp-"), std::string::npos) << "trial " << trial << " left " << name;
    }
  }
}

// A set of files put in place one rename at a time (WriteFilesAtomically; StagedDirectory::
// Commit into an existing directory, as `ringlet simulate -o` an existing folder does) must not
// be cut in two by a signal: before SignalGuard covered the renames, SIGTERM after the first
// rename removed the temporaries not yet renamed, and the output was one new file among old
// ones. The signal is raised from inside the first successful renameat2 of the set: this test
// binary defines renameat2 (below, after the tests' namespace), which the library's calls
// resolve to; it calls the C library's and raises SIGTERM on the thread once
// g_raise_after_renames renames have succeeded (0, the default: it only passes through).
std::atomic<int> g_raise_after_renames{0};

// Runs `commit` (which writes "new" over the files of `names` in directory/<way>) in a
// death-test child that SIGTERM ends right after the first rename; the set must be all new and
// no temporary or staging directory left (DeathTestDirectory; the child skips the set-up).
void ExpectSignalLeavesWholeSet(
    const std::string& way, const std::vector<std::string>& names,
    const std::function<void(const std::string&, const std::vector<std::string>&)>& commit) {
  const DeathTestDirectory death_directory("RINGLET_TEST_COMMIT_DIRECTORY");
  ASSERT_FALSE(death_directory.path().empty());
  const std::string directory = death_directory.path() + "/" + way;
  if (death_directory.parent()) {  // the child finds it set up
    ASSERT_EQ(::mkdir(directory.c_str(), 0777), 0);
    for (const std::string& name : names) {
      std::string error;
      ASSERT_TRUE(WriteFileAtomically(directory + "/" + name, "old", false, &error)) << error;
    }
  }
  EXPECT_EXIT(
      {
        RemoveTemporariesOnSignals();
        g_raise_after_renames.store(1);
        commit(directory, names);
        std::exit(0);  // not reached: the signal ends the process once the set is in place
      },
      ::testing::KilledBySignal(SIGTERM), "");
  if (death_directory.parent()) {
    for (const std::string& name : names) {
      std::string contents, error;
      ASSERT_TRUE(ReadFile(directory + "/" + name, &contents, &error)) << error;
      EXPECT_EQ(contents, "new") << way << ": " << name << " was left as it was";
    }
    size_t entries = 0;
    for (const auto& entry : std::filesystem::directory_iterator(directory)) {
      const std::string name = entry.path().filename().string();
      EXPECT_EQ(name.find(".tmp-"), std::string::npos) << way << " left " << name;
      ++entries;
    }
    EXPECT_EQ(entries, names.size()) << way;
  }
}

const std::vector<std::string> kOutputSet = {"hair.usda", "strands.hair", "strands.obj",
                                             "summary.json"};

TEST(AtomicFileDeathTest, SignalDuringWriteFilesPutsTheWholeSetInPlace) {
  ExpectSignalLeavesWholeSet(
      "files", kOutputSet, [](const std::string& directory, const std::vector<std::string>& names) {
        std::vector<std::pair<std::string, std::string>> files;
        for (const std::string& name : names) files.emplace_back(name, "new");
        std::string error;
        WriteFilesAtomically(directory, files, true, &error);
      });
}

TEST(AtomicFileDeathTest, SignalDuringStagedCommitPutsTheWholeSetInPlace) {
  ExpectSignalLeavesWholeSet(
      "staged", kOutputSet, [](const std::string& directory, const std::vector<std::string>& names) {
        StagedDirectory staged;
        std::string error;
        if (!staged.Open(directory, true, &error)) return;
        for (const std::string& name : names) {
          if (!staged.WriteFile(name, "new", &error)) return;
        }
        staged.Commit(&error);
      });
}

TEST(AtomicFile, ReadFileReadsWhatWasWritten) {
  TempDirectory dir;
  const std::string path = dir.path() + "/data";
  std::string big(200000, 'x');  // more than one read() buffer
  big[123456] = 'y';
  std::string error;
  ASSERT_TRUE(WriteFileAtomically(path, big, false, &error)) << error;
  std::string back;
  ASSERT_TRUE(ReadFile(path, &back, &error)) << error;
  EXPECT_EQ(back, big);
}

// ---------------------------------------------------------------------------------------------
// Hostile input (issue 16, docs/robustness.md).

// "[[...]]" nested depth levels deep inside {"strands": ...}.
std::string Nested(int depth) {
  return "{\"strands\": " + std::string(depth, '[') + std::string(depth, ']') + "}";
}

TEST(JsonReader, NestingIsLimitedWhileParsing) {
  json document;
  std::string error;
  // The top-level object is level 1: 63 arrays inside it make 64 levels, the limit.
  EXPECT_TRUE(internal::ParseJsonText(Nested(internal::kMaxJsonDepth - 1), &document, &error))
      << error;
  EXPECT_FALSE(internal::ParseJsonText(Nested(internal::kMaxJsonDepth), &document, &error));
  EXPECT_NE(error.find("nested deeper than 64 levels"), std::string::npos) << error;
  EXPECT_EQ(error.rfind("strands[0][0]", 0), 0u) << error;
  // 70,000 levels (the tester's 140 KB file) stop at the same point, without recursion.
  EXPECT_FALSE(internal::ParseJsonText(Nested(70000), &document, &error));
  EXPECT_NE(error.find("nested deeper than 64 levels"), std::string::npos) << error;
  EXPECT_LT(error.size(), 300u) << error;
}

// ParseJsonText parses with simdjson and falls back to nlohmann's parser when simdjson refuses
// (json_reader.cpp, FastParse). The reference is nlohmann's own parser on the same text: the two
// must accept the same documents (apart from ringlet's own refusals: duplicate members and
// nesting beyond kMaxJsonDepth) and give the same values, integers and floats told apart (dump()
// writes 1 and 1.0 differently). Corpus: every JSON file of the examples and the test data,
// edge cases where simdjson and nlohmann differ (byte-order mark, integers beyond 64 bits, -0,
// out-of-range numbers, surrogates, invalid UTF-8), and 3,000 byte-level mutants of them.
TEST(JsonReader, SimdjsonAndNlohmannAgree) {
  std::vector<std::string> corpus = {
      "\xef\xbb\xbf{\"a\": [1, 2.5]}",  // byte-order mark: simdjson refuses, nlohmann skips it
      "18446744073709551616", "-9223372036854775809", "[123456789012345678901234567890]",
      "18446744073709551615", "9223372036854775808", "-9223372036854775808", "[-0, 0, -0.0]",
      "[1E+2, 1e5, 0.1, -1.5e-5, 1e-400, 4.9e-324, 2.2250738585072011e-308]",
      "[1.7976931348623157e308]", "[1e309]", "{\"a\": -1e999}", "[01]", "[1.]", "[.5]",
      "\"\\ud800\"", "\"\\ud83d\\ude00 \\u00e9 \\u0000\"", "\"\xc3\xa9\"", "\"\xff\"",
      "\"\xed\xa0\x80\"", "\"\xc0\xaf\"", "\"\x01\"", "\"\x7f\"", "", " ", "{} x", "[1,]",
      "nul", "true ", "\t\n\r {}", "\f{}", std::string("[1]\0", 4), "{\"a\": 1, \"a\": 2}",
      "[{\"b\": {\"c\": null, \"d\": false}}, [], {}, \"\"]",
      Nested(internal::kMaxJsonDepth - 1), Nested(internal::kMaxJsonDepth), Nested(1100)};
  const size_t handmade = corpus.size();
  for (const char* dir : {RINGLET_EXAMPLES_DIR, RINGLET_TEST_DATA_DIR}) {
    for (const auto& entry : std::filesystem::recursive_directory_iterator(dir)) {
      if (entry.path().extension() != ".json") continue;
      std::ifstream in(entry.path(), std::ios::binary);
      std::stringstream text;
      text << in.rdbuf();
      corpus.push_back(text.str());
    }
  }
  ASSERT_GT(corpus.size(), handmade + 20);  // the files were found
  std::mt19937 rng(20261202);
  const size_t files = corpus.size();
  for (int i = 0; i < 3000; ++i) {
    std::string text = corpus[rng() % files];
    if (text.empty()) continue;
    const int edits = 1 + static_cast<int>(rng() % 3);
    for (int e = 0; e < edits; ++e) {
      const size_t at = rng() % text.size();
      static constexpr char kBytes[] = "{}[],:\"\\-+.eE0123456789 \ntrufalsn\x80\xff";
      text[at] = kBytes[rng() % (sizeof(kBytes) - 1)];
    }
    corpus.push_back(text);
  }

  int both_accept = 0, both_refuse = 0, ringlet_refuses = 0;
  for (size_t i = 0; i < corpus.size(); ++i) {
    const std::string& text = corpus[i];
    json reference;
    bool reference_ok = true;
    try {
      reference = json::parse(text);
    } catch (const json::exception&) {
      reference_ok = false;
    }
    json document;
    std::string error;
    const bool ok = internal::ParseJsonText(text, &document, &error);
    if (!reference_ok) {
      EXPECT_FALSE(ok) << "case " << i << " accepted, nlohmann refuses: " << text.substr(0, 80);
      ++both_refuse;
    } else if (!ok) {
      // Only ringlet's own two rules may refuse what nlohmann accepts.
      EXPECT_TRUE(error.find("duplicate field") != std::string::npos ||
                  error.find("nested deeper than") != std::string::npos)
          << "case " << i << ": " << error;
      ++ringlet_refuses;
    } else {
      EXPECT_EQ(document.dump(), reference.dump()) << "case " << i;
      ++both_accept;
    }
  }
  // Anti-vacuity: every class was exercised.
  EXPECT_GT(both_accept, 40);
  EXPECT_GT(both_refuse, 500);
  EXPECT_GT(ringlet_refuses, 1);
}

// A bad value deep under long keys: the path in the message keeps its start and its end (the
// part that names the value) and stays within kMaxShownPath, however deep and long the keys.
TEST(JsonReader, PathsInMessagesAreBounded) {
  const std::string key(58, 'k');  // quoted keys are cut to kMaxShownCharacters anyway
  std::string text = "{\"strands\": [";
  const int levels = internal::kMaxJsonDepth - 4;
  for (int i = 0; i < levels; ++i) text += "{\"" + key + std::to_string(i) + "\": ";
  text += "[1e999]";
  for (int i = 0; i < levels; ++i) text += "}";
  text += "]}";
  json document;
  std::string error;
  ASSERT_FALSE(internal::ParseJsonText(text, &document, &error));
  // Unbounded, the path alone would be ~60 levels x 60 bytes = 3.6 KB.
  EXPECT_LT(error.size(), internal::kMaxShownPath + internal::kMaxMessage) << error;
  EXPECT_EQ(error.rfind("strands[0]." + key.substr(0, 20), 0), 0u) << error;
  EXPECT_NE(error.find("..."), std::string::npos) << error;
  EXPECT_NE(error.find(key + std::to_string(levels - 1) + "[0]: "), std::string::npos) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos);
  // Member and Element themselves never return more than kMaxShownPath bytes.
  std::string path;
  for (int i = 0; i < 1000; ++i) {
    path = i % 2 ? internal::Element(path, 123456789) : internal::Member(path, key);
    ASSERT_LE(path.size(), internal::kMaxShownPath);
  }
  EXPECT_EQ(path.substr(path.size() - 11), "[123456789]");
}

TEST(JsonReader, ShowIsBoundedForDeepLongAndLargeValues) {
  // Deep: built by hand (the parser would refuse it), walked without recursion.
  json deep = json::array();
  json* innermost = &deep;
  for (int i = 0; i < 100000; ++i) {
    innermost->push_back(json::array());
    innermost = &innermost->back();
  }
  const std::string shown = internal::Show(deep);
  EXPECT_LE(shown.size(), internal::kMaxShownCharacters);
  EXPECT_EQ(shown.rfind("[[[[", 0), 0u) << shown;
  EXPECT_EQ(shown.substr(shown.size() - 3), "...") << shown;
  // The destructor of nlohmann's json is iterative (3.10 and later); release level by level
  // anyway so that the test does not depend on it.
  while (deep.is_array() && !deep.empty()) {
    json inner = std::move(deep[0]);
    deep = std::move(inner);
  }
  // Long string, big object: cut, and the cut is marked.
  EXPECT_LE(internal::Show(json(std::string(10000000, 'a'))).size(), internal::kMaxShownCharacters);
  json big = json::object();
  for (int i = 0; i < 1000; ++i) big["key" + std::to_string(i)] = i;
  const std::string big_shown = internal::Show(big);
  EXPECT_LE(big_shown.size(), internal::kMaxShownCharacters);
  EXPECT_EQ(big_shown.substr(big_shown.size() - 3), "...") << big_shown;
  // Small values are shown whole, as compact ASCII JSON.
  EXPECT_EQ(internal::Show(json::parse(R"({"a": [1, 2.5, "x\u00e9"], "b": {}, "c": []})")),
            R"({"a":[1,2.5,"x\u00e9"],"b":{},"c":[]})");
  EXPECT_EQ(internal::Show(json(-64)), "-64");
}

TEST(JsonReader, HugeKeysAreCutInPathsAndNotCompared) {
  json d = MinimalScene();
  d["strands"][0][std::string(10000000, 'k')] = 1;  // an unknown field with a 10 MB name
  Scene scene;
  std::string error;
  EXPECT_FALSE(ParseScene(d, &scene, &error));
  EXPECT_EQ(error.rfind("strands[0][\"kkkk", 0), 0u) << error.substr(0, 200);
  EXPECT_NE(error.find("unknown field (known fields: length"), std::string::npos)
      << error.substr(0, 200);
  EXPECT_LT(error.size(), 400u);
}

TEST(JsonReader, IntegersAreReadExactly) {
  internal::Reader reader;
  const json object = json::parse(
      R"({"exact": 9007199254740992, "beyond": 9007199254740993, "negative": -1,
          "float": 15.0, "fraction": 15.5, "big_float": 4e9, "huge": 18446744073709551615})");
  std::uint64_t value = 0;
  ASSERT_TRUE(reader.ReadUnsigned(object, "", "exact", internal::kMaxExactInteger, "2^53", &value));
  EXPECT_EQ(value, internal::kMaxExactInteger);
  for (const char* key : {"beyond", "negative", "fraction", "big_float", "huge"}) {
    EXPECT_FALSE(reader.ReadUnsigned(object, "", key, internal::kMaxExactInteger, "2^53", &value))
        << key;
    EXPECT_NE(reader.error().find(std::string(key) + ": expected an integer between 0 and 2^53"),
              std::string::npos)
        << reader.error();
  }
  EXPECT_EQ(value, internal::kMaxExactInteger);  // untouched on failure
  ASSERT_TRUE(reader.ReadUnsigned(object, "", "float", internal::kMaxExactInteger, "2^53", &value));
  EXPECT_EQ(value, 15u);
  int small = 0;
  EXPECT_TRUE(reader.ReadInteger(object, "", "float", 0, 100, &small));
  EXPECT_EQ(small, 15);
  EXPECT_FALSE(reader.ReadInteger(object, "", "huge", 0, 100, &small));
  EXPECT_FALSE(reader.ReadInteger(object, "", "beyond", 0, 2147483647, &small));
}

TEST(SceneJson, TinyLengthNamesTheLengthNotTheAbsentGrading) {
  json d = MinimalScene();
  d["strands"][0]["length"] = 5e-324;  // the segment lengths underflow to 0
  Scene scene;
  std::string error;
  EXPECT_FALSE(ParseScene(d, &scene, &error));
  EXPECT_EQ(error.rfind("strands[0].length: is too small for 15 segments", 0), 0u) << error;
  // With a grading, the grading is blamed (and shown).
  d["strands"][0]["length"] = 1e-20;
  d["strands"][0]["grading"] = 1e308;
  d["strands"][0]["segments"] = 2;
  EXPECT_FALSE(ParseScene(d, &scene, &error));
  EXPECT_EQ(error.rfind("strands[0].grading: is too large for 2 segments", 0), 0u) << error;
}

TEST(AtomicFile, ReadFileRefusesWhatIsNotARegularFile) {
  TempDirectory dir;
  const std::string fifo = dir.path() + "/fifo.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string text, error;
  // Returns at once (the FIFO has no writer: a blocking open would wait forever).
  EXPECT_FALSE(ReadFile(fifo, &text, &error));
  EXPECT_EQ(error, fifo + ": is a FIFO, not a regular file (inputs must be regular files)");
  EXPECT_FALSE(ReadFile("/dev/zero", &text, &error));
  EXPECT_EQ(error.rfind("/dev/zero: is a character device, not a regular file", 0), 0u) << error;
  Scene scene;
  EXPECT_FALSE(LoadScene(fifo, &scene, &error));
  EXPECT_NE(error.find("is a FIFO"), std::string::npos) << error;
}

TEST(AtomicFile, ReadFileRefusesFilesAboveTheCap) {
  TempDirectory dir;
  const std::string path = dir.path() + "/data";
  std::string error;
  ASSERT_TRUE(WriteFileAtomically(path, std::string(1001, 'x'), false, &error)) << error;
  std::string text = "untouched";
  EXPECT_FALSE(ReadFile(path, &text, &error, 1000));
  EXPECT_EQ(error, path +
                       ": is 1001 bytes, more than the limit of 1000 bytes for this kind of "
                       "file");
  EXPECT_EQ(text, "untouched");
  EXPECT_TRUE(ReadFile(path, &text, &error, 1001)) << error;
  EXPECT_EQ(text.size(), 1001u);
  EXPECT_EQ(FormatBytes(kMaxJsonFileBytes), "64 MiB");
  EXPECT_EQ(FormatBytes(kMaxHairFileBytes), "1 GiB");
}

TEST(AtomicFile, OverwriteReplacesOnlyRegularFiles) {
  TempDirectory dir;
  const std::string fifo = dir.path() + "/fifo";
  const std::string target = dir.path() + "/target";
  const std::string link = dir.path() + "/link";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::ofstream(target) << "keep";
  ASSERT_EQ(::symlink("target", link.c_str()), 0);
  std::string error;
  EXPECT_FALSE(WriteFileAtomically(fifo, "x", true, &error));
  EXPECT_EQ(error, fifo + ": exists and is a FIFO; only a regular file may be replaced");
  EXPECT_FALSE(WriteFileAtomically(link, "x", true, &error));
  EXPECT_EQ(error, link + ": exists and is a symbolic link; only a regular file may be replaced");
  EXPECT_FALSE(CheckReplaceable(link, true, &error));
  struct stat info;
  ASSERT_EQ(::lstat(fifo.c_str(), &info), 0);
  EXPECT_TRUE(S_ISFIFO(info.st_mode));
  ASSERT_EQ(::lstat(link.c_str(), &info), 0);
  EXPECT_TRUE(S_ISLNK(info.st_mode));
  EXPECT_EQ(ReadAll(target), "keep");
  // The regular file is still replaced, and nothing else is left behind.
  EXPECT_TRUE(WriteFileAtomically(target, "new", true, &error)) << error;
  EXPECT_EQ(ReadAll(target), "new");
  EXPECT_EQ(dir.Entries().size(), 3u);
}

// Several files as one output (issue 16): all of them, or none and nothing left behind.
TEST(AtomicFile, WriteFilesWritesAllInNewDirectories) {
  TempDirectory dir;
  const std::string out = dir.path() + "/a/b";
  std::string error;
  ASSERT_TRUE(WriteFilesAtomically(out, {{"one", "1"}, {"two", "22"}, {"three", ""}}, false,
                                   &error))
      << error;
  EXPECT_EQ(ReadAll(out + "/one"), "1");
  EXPECT_EQ(ReadAll(out + "/two"), "22");
  EXPECT_EQ(ReadAll(out + "/three"), "");
  size_t entries = 0;
  for (const auto& e : std::filesystem::directory_iterator(out)) {
    ++entries;
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos);
  }
  EXPECT_EQ(entries, 3u);
}

TEST(AtomicFile, WriteFilesWritesNoneWhenOneCannotBeWritten) {
  TempDirectory dir;
  // An existing output: "one" holds old contents, "three" is a FIFO (never replaced).
  std::ofstream(dir.path() + "/one") << "old";
  ASSERT_EQ(::mkfifo((dir.path() + "/three").c_str(), 0600), 0);
  std::string error;
  EXPECT_FALSE(WriteFilesAtomically(dir.path(), {{"one", "new"}, {"two", "2"}, {"three", "3"}},
                                    true, &error));
  EXPECT_EQ(error, dir.path() + "/three: exists and is a FIFO; only a regular file may be "
                                "replaced (nothing was written)");
  EXPECT_EQ(ReadAll(dir.path() + "/one"), "old");
  std::vector<std::string> entries = dir.Entries();
  std::sort(entries.begin(), entries.end());
  EXPECT_EQ(entries, (std::vector<std::string>{"one", "three"}));  // no "two", no temporary
}

TEST(AtomicFile, WriteFilesRemovesTheDirectoriesItCreatedOnFailure) {
  TempDirectory dir;
  std::string error;
  // The second name points into a directory that does not exist: its temporary cannot be
  // created, after the first file was staged and two directories were made.
  EXPECT_FALSE(WriteFilesAtomically(dir.path() + "/x/y", {{"one", "1"}, {"missing/two", "2"}},
                                    false, &error));
  EXPECT_NE(error.find("missing/two: cannot create a temporary file"), std::string::npos)
      << error;
  EXPECT_NE(error.find("(nothing was written)"), std::string::npos) << error;
  EXPECT_TRUE(dir.Entries().empty());
}

// The files are written side by side (a thread each): every one in full, and of several that
// fail the first in order is reported, as one writer after the other would.
TEST(AtomicFile, WriteFilesWritesManyFilesSideBySide) {
  TempDirectory dir;
  std::vector<std::pair<std::string, std::string>> files;
  for (int k = 0; k < 20; ++k) {
    const char fill = static_cast<char>('a' + k % 26);
    files.emplace_back("f" + std::to_string(k), std::string(static_cast<size_t>(1000 * k), fill));
  }
  std::string error;
  ASSERT_TRUE(WriteFilesAtomically(dir.path(), files, false, &error)) << error;
  for (const auto& [name, contents] : files) EXPECT_EQ(ReadAll(dir.path() + "/" + name), contents);
  EXPECT_EQ(dir.Entries().size(), files.size());
}

TEST(AtomicFile, WriteFilesReportsTheFirstFailingFileInOrder) {
  TempDirectory dir;
  std::string error;
  EXPECT_FALSE(WriteFilesAtomically(
      dir.path(), {{"one", "1"}, {"a/two", "2"}, {"three", "3"}, {"b/four", "4"}}, false, &error));
  EXPECT_EQ(error.find(dir.path() + "/a/two: cannot create a temporary file"), 0u) << error;
  EXPECT_NE(error.find("(nothing was written)"), std::string::npos) << error;
  EXPECT_TRUE(dir.Entries().empty());
}

TEST(AtomicFile, WriteFilesRefusesExistingFilesWithoutOverwrite) {
  TempDirectory dir;
  std::ofstream(dir.path() + "/two") << "keep";
  std::string error;
  EXPECT_FALSE(WriteFilesAtomically(dir.path(), {{"one", "1"}, {"two", "2"}}, false, &error));
  EXPECT_EQ(error, dir.path() + "/two: already exists (nothing was written)");
  EXPECT_EQ(dir.Entries(), std::vector<std::string>{"two"});
  EXPECT_EQ(ReadAll(dir.path() + "/two"), "keep");
}

}  // namespace
}  // namespace ringlet

// The test binary's renameat2 (AtomicFileDeathTest.SignalDuring*): the C library's, then SIGTERM
// on this thread when g_raise_after_renames counts down to zero (only in those tests' children).
extern "C" int renameat2(int old_directory, const char* old_path, int new_directory,
                         const char* new_path, unsigned int flags) noexcept {
  using Function = int (*)(int, const char*, int, const char*, unsigned int);
  static const Function real = reinterpret_cast<Function>(::dlsym(RTLD_NEXT, "renameat2"));
  const int result = real(old_directory, old_path, new_directory, new_path, flags);
  if (result == 0 && ringlet::g_raise_after_renames.load() > 0 &&
      ringlet::g_raise_after_renames.fetch_sub(1) == 1) {
    std::raise(SIGTERM);
  }
  return result;
}
