// The "operations" list of hairstyle files (src/io/hairstyle_json.cpp, docs/hairstyle-format.md):
// every operation and field reaches its StyleOperation, defaults are the library's, the example
// with operations loads, and every bad list gives one line naming the field, for
// ParseStyleOperations and for ParseHairstyle alike (a file with bad operations is a bad file).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "ringlet/hairstyle_json.h"
#include "ringlet/styling.h"

namespace ringlet {
namespace {

using nlohmann::json;
using Kind = StyleOperation::Kind;

std::string HairstyleDir() { return std::string(RINGLET_EXAMPLES_DIR) + "/hairstyles"; }

// A minimal hairstyle with the given operations list (JSON text).
std::string WithOperations(const std::string& operations) {
  return R"({"body": "../bodies/mannequin.json", "operations": )" + operations + "}";
}

std::vector<StyleOperation> MustParse(const std::string& operations) {
  std::vector<StyleOperation> out;
  std::string error;
  const json document = json::parse(WithOperations(operations));
  EXPECT_TRUE(ParseStyleOperations(document, &out, &error)) << operations << "\n" << error;
  // The same file is a valid hairstyle too.
  Hairstyle style;
  EXPECT_TRUE(ParseHairstyle(document, HairstyleDir(), &style, &error)) << error;
  return out;
}

TEST(StyleOperationsJson, AbsentListIsEmpty) {
  std::vector<StyleOperation> out(3);
  std::string error;
  ASSERT_TRUE(ParseStyleOperations(json::parse(R"({"body": "x.json"})"), &out, &error)) << error;
  EXPECT_TRUE(out.empty());
  EXPECT_TRUE(MustParse("[]").empty());
}

TEST(StyleOperationsJson, EveryOperationAndFieldArrives) {
  const std::vector<StyleOperation> ops = MustParse(R"([
    {"curl": {"radius": 0.008, "pitch": -0.02}},
    {"curl": {"radius": "inf", "pitch": 0, "select": {"indices": [0, 4, 7]}}},
    {"curl": {"radius": 0.01, "pitch": 0.03,
              "select": {"polar_angle": [0.1, 0.8], "height": [-0.02, 0.09]}}},
    {"wet": {}},
    {"dry": {}},
    {"wet": {"stiffness_factor": 0.2, "swelling": 1.1, "water_density": 1000,
             "layer_factor": 0.25}},
    {"cut": {"z": -0.12, "settle": true, "tolerance": 0.001, "max_rounds": 7,
             "samples_per_segment": 3}},
    {"cut": {"plane": {"normal": [0, -2, 0], "offset": -0.05}}},
    {"cut": {"sphere": {"centre": [0, 0.01, 0.02], "radius": 0.18}}},
    {"cut": {"length": 0.2}},
    {"grow": {"step": 0.01, "steps": 5}},
    {"grow": {"step": 0.02}}
  ])");
  ASSERT_EQ(ops.size(), 12u);
  EXPECT_EQ(ops[0].kind, Kind::kCurl);
  EXPECT_EQ(ops[0].curl_radius, 0.008);
  EXPECT_EQ(ops[0].curl_pitch, -0.02);
  EXPECT_TRUE(ops[0].selection.indices.empty());
  EXPECT_EQ(ops[0].selection.min_polar_angle, 0.0);  // the default selects every master
  EXPECT_EQ(ops[0].selection.max_height, std::numeric_limits<double>::infinity());
  EXPECT_EQ(ops[1].curl_radius, std::numeric_limits<double>::infinity());
  EXPECT_EQ(ops[1].selection.indices, (std::vector<int>{0, 4, 7}));
  EXPECT_EQ(ops[2].selection.min_polar_angle, 0.1);
  EXPECT_EQ(ops[2].selection.max_polar_angle, 0.8);
  EXPECT_EQ(ops[2].selection.min_height, -0.02);
  EXPECT_EQ(ops[2].selection.max_height, 0.09);
  EXPECT_EQ(ops[3].kind, Kind::kWet);
  EXPECT_EQ(ops[3].wet.stiffness_factor, kWetStiffnessFactor);  // Robbins' defaults
  EXPECT_EQ(ops[3].wet.swelling, kWetSwelling);
  EXPECT_EQ(ops[4].kind, Kind::kDry);
  EXPECT_EQ(ops[5].wet.stiffness_factor, 0.2);
  EXPECT_EQ(ops[5].wet.swelling, 1.1);
  EXPECT_EQ(ops[5].wet.water_density, 1000.0);
  EXPECT_EQ(ops[5].wet.layer_factor, 0.25);
  EXPECT_EQ(ops[6].kind, Kind::kCut);
  EXPECT_EQ(ops[6].cut_region.kind, CutRegion::Kind::kAbovePlane);
  EXPECT_EQ(ops[6].cut_region.normal, Vec3::UnitZ());
  EXPECT_EQ(ops[6].cut_region.offset, -0.12);
  EXPECT_TRUE(ops[6].cut.settle);
  EXPECT_EQ(ops[6].cut.tolerance, 0.001);
  EXPECT_EQ(ops[6].cut.max_rounds, 7);
  EXPECT_EQ(ops[6].cut.samples_per_segment, 3);
  EXPECT_EQ(ops[7].cut_region.kind, CutRegion::Kind::kAbovePlane);
  EXPECT_EQ(ops[7].cut_region.normal, Vec3(0, -2, 0));
  EXPECT_EQ(ops[7].cut_region.offset, -0.05);
  EXPECT_FALSE(ops[7].cut.settle);
  EXPECT_EQ(ops[8].cut_region.kind, CutRegion::Kind::kInsideSphere);
  EXPECT_EQ(ops[8].cut_region.centre, Vec3(0, 0.01, 0.02));
  EXPECT_EQ(ops[8].cut_region.radius, 0.18);
  EXPECT_EQ(ops[9].cut_region.kind, CutRegion::Kind::kMaxLength);
  EXPECT_EQ(ops[9].cut_region.length, 0.2);
  EXPECT_EQ(ops[10].kind, Kind::kGrow);
  EXPECT_EQ(ops[10].grow_step, 0.01);
  EXPECT_EQ(ops[10].grow_steps, 5);
  EXPECT_EQ(ops[11].grow_steps, 10);  // the default, as `ringlet style --steps`
  for (const StyleOperation& op : ops) {
    std::string why;
    EXPECT_TRUE(op.IsValid(&why)) << why;
  }
}

TEST(StyleOperationsJson, ExampleWithOperationsLoads) {
  Hairstyle style;
  std::vector<StyleOperation> ops;
  std::string error;
  ASSERT_TRUE(LoadHairstyle(HairstyleDir() + "/wavy_styled.json", &style, &ops, &error)) << error;
  ASSERT_GE(ops.size(), 3u);
  EXPECT_EQ(style.roots.count, 1000);  // the hairstyle itself is wavy_mannequin.json's
  // The three-argument LoadHairstyle accepts the same file (what `ringlet groom` reads).
  Hairstyle plain;
  EXPECT_TRUE(LoadHairstyle(HairstyleDir() + "/wavy_styled.json", &plain, &error)) << error;
}

TEST(StyleOperationsJson, BadListsNameTheField) {
  struct Case {
    const char* operations;
    const char* message;  // expected substring of the one-line error
  };
  const Case cases[] = {
      {R"({"wet": {}})", "operations: expected an array of operations"},
      {R"([{"wet": {}, "dry": {}}])", "operations[0]: expected an object with one key"},
      {R"([{}])", "operations[0]: expected an object with one key"},
      {R"(["wet"])", "operations[0]: expected an object with one key"},
      {R"([{"wet": {}}, {"perm": {}}])", "operations[1].perm: unknown operation"},
      {R"([{"wet": true}])", "operations[0].wet: expected an object, got true"},
      {R"([{"dry": {"fast": 1}}])", "operations[0].dry.fast: unknown field"},
      {R"([{"wet": {"select": {"indices": [-2]}}}])",
       "operations[0].wet.select.indices[0]: expected a master index"},
      {R"([{"cut": {"z": 0, "select": {"height": [1, 0]}}}])",
       "operations[0].cut.select.height: expected [min, max] with min <= max"},
      {R"([{"grow": {"step": 0.01, "select": {"indices": []}}}])",
       "operations[0].grow.select.indices: expected a non-empty array"},
      {R"([{"dry": {"select": [1]}}])", "operations[0].dry.select: expected an object"},
      // curl
      {R"([{"curl": {"pitch": 0.02}}])", "operations[0].curl.radius: missing required field"},
      {R"([{"curl": {"radius": 0.01}}])", "operations[0].curl.pitch: missing required field"},
      {R"([{"curl": {"radius": -0.01, "pitch": 0.02}}])",
       "operations[0].curl.radius: expected a finite number >= 0 (m) or \"inf\""},
      {R"([{"curl": {"radius": "big", "pitch": 0.02}}])", "operations[0].curl.radius: expected"},
      {R"([{"curl": {"radius": 0.01, "pitch": "low"}}])",
       "operations[0].curl.pitch: expected a finite number (m; < 0 = left-handed), got \"low\""},
      {R"([{"curl": {"radius": 0, "pitch": 0}}])", "operations[0].curl: radius = pitch = 0"},
      {R"([{"curl": {"radius": 0.01, "pitch": 0.02, "colour": 1}}])",
       "operations[0].curl.colour: unknown field"},
      {R"([{"curl": {"radius": 0.01, "pitch": 0.02, "select": {"indices": [0, -1]}}}])",
       "operations[0].curl.select.indices[1]: expected a master index"},
      {R"([{"curl": {"radius": 0.01, "pitch": 0.02, "select": {"indices": [1.5]}}}])",
       "operations[0].curl.select.indices[0]: expected a master index"},
      {R"([{"curl": {"radius": 0.01, "pitch": 0.02, "select": {"indices": []}}}])",
       "operations[0].curl.select.indices: expected a non-empty array"},
      {R"([{"curl": {"radius": 0.01, "pitch": 0.02,
                     "select": {"indices": [1], "height": [0, 1]}}}])",
       "operations[0].curl.select: give either indices or polar_angle/height"},
      {R"([{"curl": {"radius": 0.01, "pitch": 0.02, "select": {"polar_angle": [1, 0.5]}}}])",
       "operations[0].curl.select.polar_angle: expected [min, max] with 0 <= min <= max <= pi"},
      {R"([{"curl": {"radius": 0.01, "pitch": 0.02, "select": {"polar_angle": [0, 4]}}}])",
       "operations[0].curl.select.polar_angle: expected [min, max]"},
      {R"([{"curl": {"radius": 0.01, "pitch": 0.02, "select": {"height": [0.1, 0]}}}])",
       "operations[0].curl.select.height: expected [min, max] with min <= max"},
      {R"([{"curl": {"radius": 0.01, "pitch": 0.02, "select": {"height": 0.1}}}])",
       "operations[0].curl.select.height: expected an array of 2 finite numbers"},
      {R"([{"curl": {"radius": 0.01, "pitch": 0.02, "select": [0]}}])",
       "operations[0].curl.select: expected an object"},
      // wet
      {R"([{"wet": {"stiffness_factor": 0}}])", "operations[0].wet.stiffness_factor: expected"},
      {R"([{"wet": {"swelling": 0.9}}])", "operations[0].wet.swelling: expected"},
      {R"([{"wet": {"water_density": -1}}])", "operations[0].wet.water_density: expected"},
      {R"([{"wet": {"layer_factor": 2}}])", "operations[0].wet.layer_factor: expected"},
      {R"([{"wet": {"swelling": 1.1, "stiffnes_factor": 0.2}}])",
       "operations[0].wet.stiffnes_factor: unknown field (did you mean \"stiffness_factor\"?)"},
      // cut
      {R"([{"wet": {}}, {"cut": {}}])", "operations[1].cut: missing the region"},
      {R"([{"cut": {"z": -0.1, "length": 0.2}}])", "operations[0].cut: expected exactly one of"},
      {R"([{"cut": {"z": "low"}}])",
       "operations[0].cut.z: expected a finite number (m), got \"low\""},
      {R"([{"cut": {"z": null}}])", "operations[0].cut.z: expected a finite number (m), got null"},
      {R"([{"cut": {"length": 0}}])", "operations[0].cut.length: expected a finite number > 0"},
      {R"([{"cut": {"length": 0.2, "settle": true}}])", "operations[0].cut.settle: only for"},
      {R"([{"cut": {"z": -0.1, "settle": "yes"}}])",
       "operations[0].cut.settle: expected true or false"},
      {R"([{"cut": {"z": -0.1, "tolerance": 0}}])", "operations[0].cut.tolerance: expected"},
      {R"([{"cut": {"z": -0.1, "max_rounds": 0}}])",
       "operations[0].cut.max_rounds: expected an integer"},
      {R"([{"cut": {"z": -0.1, "samples_per_segment": 2000}}])",
       "operations[0].cut.samples_per_segment: expected an integer between 1 and 1024"},
      {R"([{"cut": {"sphere": {"centre": [0, 0], "radius": 0.2}}}])",
       "operations[0].cut.sphere.centre: expected an array of 3 finite numbers"},
      {R"([{"cut": {"sphere": {"centre": [0, 0, 0]}}}])",
       "operations[0].cut.sphere.radius: missing required field"},
      {R"([{"cut": {"sphere": {"centre": [0, 0, 0], "radius": -1}}}])",
       "operations[0].cut.sphere.radius: expected a finite number > 0 (m)"},
      {R"([{"cut": {"sphere": 0.2}}])", "operations[0].cut.sphere: expected an object"},
      {R"([{"cut": {"plane": {"normal": [0, 0, 0], "offset": 0}}}])",
       "operations[0].cut.plane.normal: expected a non-zero direction"},
      {R"([{"cut": {"plane": {"normal": [0, 0, 1]}}}])",
       "operations[0].cut.plane.offset: missing required field"},
      // grow
      {R"([{"grow": {}}])", "operations[0].grow.step: missing required field"},
      {R"([{"grow": {"step": -0.01}}])",
       "operations[0].grow.step: expected a finite number in (0, 1] (m)"},
      {R"([{"grow": {"step": 0.01, "steps": 0}}])",
       "operations[0].grow.steps: expected an integer between 1 and 1000"},
      {R"([{"grow": {"step": 1e300}}])",
       "operations[0].grow.step: expected a finite number in (0, 1] (m), got 1e+300"},
      {R"([{"grow": {"step": 0.01, "steps": 1001}}])",
       "operations[0].grow.steps: expected an integer between 1 and 1000"},
      {R"([{"curl": {"radius": 1e-300, "pitch": 0}}])",
       "operations[0].curl.radius: expected a helix with curvature and torsion at most 100000 "
       "1/m"},
      {R"([{"curl": {"radius": 0, "pitch": 1e-9}}])", "operations[0].curl.pitch: expected a helix"},
      {R"([{"cut": {"plane": {"normal": [1e300, 1e300, 1e300], "offset": 0}}}])",
       "operations[0].cut.plane.normal: expected a non-zero direction of finite length"},
      {R"([{"grow": {"step": 0.01, "steps": 2.5}}])",
       "operations[0].grow.steps: expected an integer"},
  };
  for (const Case& c : cases) {
    const json document = json::parse(WithOperations(c.operations));
    std::vector<StyleOperation> ops(2);  // untouched on failure
    std::string error;
    EXPECT_FALSE(ParseStyleOperations(document, &ops, &error)) << c.operations;
    EXPECT_NE(error.find(c.message), std::string::npos)
        << c.operations << "\n  got: " << error << "\n  expected: " << c.message;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    EXPECT_EQ(ops.size(), 2u);
    // The hairstyle reader rejects the file with the same message.
    Hairstyle style;
    std::string hairstyle_error;
    EXPECT_FALSE(ParseHairstyle(document, HairstyleDir(), &style, &hairstyle_error));
    EXPECT_EQ(hairstyle_error, error);
  }
}

}  // namespace
}  // namespace ringlet
