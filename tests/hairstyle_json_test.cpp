// Hairstyle files (src/io/hairstyle_json.cpp, docs/hairstyle-format.md): the examples parse,
// every field reaches the Hairstyle, defaults are the documented ones, relative paths follow the
// file, and every bad input gives one line naming the field without touching the output.
#include "ringlet/hairstyle_json.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <numbers>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <variant>
#include <vector>

#include "ringlet/body_json.h"

namespace ringlet {
namespace {

using nlohmann::json;

std::string Examples() { return RINGLET_EXAMPLES_DIR; }
// Base directory of the documents below: examples/hairstyles, so that "../bodies/..." resolves.
std::string HairstyleDir() { return Examples() + "/hairstyles"; }

// The smallest valid hairstyle: a body and nothing else.
const char* kMinimal = R"({"body": "../bodies/mannequin.json"})";

Hairstyle MustParse(const std::string& text, const std::string& base = HairstyleDir()) {
  Hairstyle style;
  std::string error;
  EXPECT_TRUE(ParseHairstyle(json::parse(text), base, &style, &error)) << text << "\n" << error;
  return style;
}

// A fresh empty directory for file tests, removed by the destructor.
class TempDirectory {
 public:
  TempDirectory() {
    std::string pattern = ::testing::TempDir() + "ringlet_hairstyle_XXXXXX";
    path_ = ::mkdtemp(pattern.data()) ? pattern : std::string();
  }
  ~TempDirectory() {
    std::error_code ec;
    if (!path_.empty()) std::filesystem::remove_all(path_, ec);
  }
  const std::string& path() const { return path_; }
  std::string Write(const std::string& name, const std::string& text) const {
    const std::string file = path_ + "/" + name;
    std::filesystem::create_directories(std::filesystem::path(file).parent_path());
    std::ofstream(file) << text;
    return file;
  }

 private:
  std::string path_;
};

// ---------------------------------------------------------------------------------------------
// Good files.

// Every example loads and is valid; the examples on the head mesh (each load builds the head's
// distance grid, so they are checked here rather than loaded again) carry what each file sets.
TEST(HairstyleJson, ExamplesParse) {
  std::map<std::string, Hairstyle> loaded;
  for (const auto& entry : std::filesystem::directory_iterator(HairstyleDir())) {
    if (entry.path().extension() != ".json") continue;
    Hairstyle style;
    std::string error;
    EXPECT_TRUE(LoadHairstyle(entry.path().string(), &style, &error)) << error;
    std::string why;
    EXPECT_TRUE(style.IsValid(&why)) << entry.path() << ": " << why;
    loaded[entry.path().stem().string()] = style;
  }
  EXPECT_GE(loaded.size(), 1u);
  struct Row {
    const char* name;
    const char* origin;
    const char* curl;
    double length_back;  // m: hair.length (uniform) or its "back"
    int points_per_strand;
  };
  for (const Row& row : {Row{"straight", "asian", "straight", 0.38, 32},
                         Row{"curly", "caucasian", "curly", 0.28, 48},
                         Row{"african", "african", "kinky", 0.12, 64},
                         Row{"ringlets", "caucasian", "curly", 0.45, 64},
                         Row{"bob", "caucasian", "straight", 0.25, 32}}) {
    SCOPED_TRACE(row.name);
    ASSERT_EQ(loaded.count(row.name), 1u);
    const Hairstyle& s = loaded[row.name];
    ASSERT_NE(s.body, nullptr);
    EXPECT_EQ(s.body->meshes().size(), 2u);  // head.obj: "head" and "torso"
    EXPECT_TRUE(std::holds_alternative<MeshScalp>(s.scalp));
    EXPECT_GT(s.comb.face_sweep, 0.0);
    EXPECT_EQ(s.hair_type.origin, row.origin);
    EXPECT_EQ(s.hair_type.curl, row.curl);
    EXPECT_EQ(s.regional_length ? s.length_back : s.length, row.length_back);
    EXPECT_EQ(s.wisps.points_per_strand, row.points_per_strand);
    EXPECT_EQ(s.roots.count, 1000);
  }
  // The ringlets' narrow wisps: a fixed 3-mm radius, no jitter (defined spirals).
  EXPECT_EQ(loaded["ringlets"].wisps.wisp_radius, 0.003);
  EXPECT_EQ(loaded["ringlets"].wisps.jitter, 0.0);
  // The paper's body keeps the four hair types.
  for (const char* name :
       {"straight_mannequin", "wavy_mannequin", "curly_mannequin", "african_mannequin"}) {
    ASSERT_EQ(loaded.count(name), 1u) << name;
    EXPECT_TRUE(std::holds_alternative<SphereScalp>(loaded[name].scalp)) << name;
  }
}

TEST(HairstyleJson, WavyExampleFieldsArriveInTheHairstyle) {
  Hairstyle s;
  std::string error;
  // The wavy hair on the sphere mannequin (the paper's body; the main job's wavy.json before it
  // moved to the head mesh).
  ASSERT_TRUE(LoadHairstyle(HairstyleDir() + "/wavy_mannequin.json", &s, &error)) << error;
  ASSERT_NE(s.body, nullptr);
  EXPECT_NE(s.body->FindSphere("head"), nullptr);  // ../bodies/mannequin.json, relative to file
  ASSERT_TRUE(std::holds_alternative<SphereScalp>(s.scalp));
  const SphereScalp& scalp = std::get<SphereScalp>(s.scalp);
  EXPECT_EQ(scalp.radius, 0.1);
  EXPECT_EQ(scalp.hairline_front, 1.05);
  EXPECT_EQ(scalp.hairline_side, 1.45);
  EXPECT_EQ(scalp.hairline_back, 1.9);
  EXPECT_EQ(scalp.head.front, Vec3(0, 1, 0));
  EXPECT_EQ(s.roots.count, 1000);
  EXPECT_EQ(s.roots.seed, 1u);
  EXPECT_EQ(s.segments, 20);
  EXPECT_EQ(s.grading, 0.0);  // "auto"
  EXPECT_EQ(s.master_points_per_segment, 4);
  EXPECT_EQ(s.comb.tilt, 1.2);
  EXPECT_EQ(s.comb.direction, Vec3(0, 0, -1));
  EXPECT_TRUE(s.comb.parting);
  EXPECT_EQ(s.comb.parting_normal, Vec3(1, 0, 0));
  EXPECT_EQ(s.comb.parting_offset, 0.03);
  EXPECT_EQ(s.hair_type.origin, "caucasian");
  EXPECT_EQ(s.hair_type.curl, "wavy");
  EXPECT_EQ(s.length, 0.3);
  EXPECT_EQ(s.seed, 1u);
  EXPECT_EQ(s.wisps.strands_per_wisp, 50);
  EXPECT_EQ(s.wisps.tip_scale, 0.5);
  EXPECT_EQ(s.wisps.jitter, 0.001);
  EXPECT_EQ(s.wisps.length_variation, 0.1);
  EXPECT_EQ(s.wisps.points_per_strand, 32);
  EXPECT_EQ(s.layers.count, 4);
  EXPECT_EQ(s.layers.thickness, 0.003);
}

// wavy.json, the main job: the head mesh, its scalp triangles, the face sweep and the regional
// length (the values written in the file).
TEST(HairstyleJson, WavyExampleOnTheHeadMesh) {
  Hairstyle s;
  std::string error;
  ASSERT_TRUE(LoadHairstyle(HairstyleDir() + "/wavy.json", &s, &error)) << error;
  ASSERT_NE(s.body, nullptr);
  ASSERT_EQ(s.body->meshes().size(), 2u);  // head.obj: "head" and "torso"
  EXPECT_EQ(s.body->meshes()[0].name(), "head");
  ASSERT_TRUE(std::holds_alternative<MeshScalp>(s.scalp));
  EXPECT_GT(std::get<MeshScalp>(s.scalp).triangles.size(), 1000u);
  EXPECT_EQ(s.comb.face_sweep, 1.5);
  EXPECT_TRUE(s.comb.curl_inward);
  EXPECT_EQ(s.comb.direction, Vec3(0, -1, -0.3));
  EXPECT_TRUE(s.comb.parting);
  EXPECT_TRUE(s.regional_length);
  EXPECT_EQ(s.length_front, 0.13);
  EXPECT_EQ(s.length_side, 0.25);
  EXPECT_EQ(s.length_back, 0.32);
  EXPECT_EQ(s.length_crown, 0.32);
  EXPECT_EQ(s.crown_polar_angle, 0.85);  // the scalp's hairline_front
  // Below the front hairline's polar angle (pi here) L(phi) passes through the three values
  // (RegionalLength's cosine curve) ...
  const double below = std::numbers::pi;
  EXPECT_NEAR(RegionalLength(s, 0.0, below), 0.13, 1e-15);
  EXPECT_NEAR(RegionalLength(s, std::numbers::pi / 2, below), 0.25, 1e-15);
  EXPECT_NEAR(RegionalLength(s, -std::numbers::pi / 2, below), 0.25, 1e-15);
  EXPECT_NEAR(RegionalLength(s, std::numbers::pi, below), 0.32, 1e-15);
  // ... and between them, at 60 degrees: a1 = (F - B) / 2 = -0.095, a0 = ((F + B) / 2 + S) / 2 =
  // 0.2375, a2 = ((F + B) / 2 - S) / 2 = -0.0125 (by hand), so
  // L = a0 + a1 cos 60 + a2 cos 120 = 0.2375 - 0.0475 + 0.00625 = 0.19625 m.
  EXPECT_NEAR(RegionalLength(s, std::numbers::pi / 3, below), 0.19625, 1e-15);
  // Toward the crown the length blends linearly in the polar angle to length.crown: at the
  // crown itself 0.32 m whatever the azimuth, halfway to the front hairline (0.425 rad) the
  // fringe's 0.13 m is halfway to it, (0.13 + 0.32) / 2 = 0.225 m.
  EXPECT_NEAR(RegionalLength(s, 0.0, 0.0), 0.32, 1e-15);
  EXPECT_NEAR(RegionalLength(s, std::numbers::pi / 2, 0.0), 0.32, 1e-15);
  EXPECT_NEAR(RegionalLength(s, 0.0, 0.425), 0.225, 1e-15);
  EXPECT_NEAR(RegionalLength(s, 0.0, 0.85), 0.13, 1e-15);
}

// hair.curl_spread sets the relative spread of the curl radius between strands (one person's
// hair rather than the curl type's population), after curl_radius has set the mean; the
// masters' sampled radii follow it.
TEST(HairstyleJson, CurlSpreadSetsTheRadiusSpread) {
  const Hairstyle wavy = MustParse(R"({"body": "../bodies/mannequin.json",
      "hair": {"curl": "wavy"}})");
  const Hairstyle s = MustParse(R"({"body": "../bodies/mannequin.json",
      "hair": {"curl": "wavy", "curl_spread": 0.1, "curl_radius": 0.03}})");
  EXPECT_EQ(s.hair_type.curl_radius, 0.03);
  EXPECT_NEAR(s.hair_type.curl_radius_std, 0.003, 1e-17);
  const Hairstyle none = MustParse(R"({"body": "../bodies/mannequin.json",
      "hair": {"curl": "wavy", "curl_spread": 0}})");
  EXPECT_EQ(none.hair_type.curl_radius_std, 0.0);
  // Sampled: the relative SD of the masters' helix radii, the type's (0.52: 0.023 / 0.044 m,
  // hair-types.md) against 0.1 and 0.
  auto relative_sd = [](const Hairstyle& style) {
    Hairstyle small = style;
    small.roots.count = 400;
    HairstyleMasters m;
    std::string error;
    EXPECT_TRUE(BuildMasters(small, &m, &error)) << error;
    double sum = 0.0, sum2 = 0.0;
    for (const StrandModel& model : m.models) {
      const Vec3 k = model.natural_curvature;  // R = kappa / (kappa^2 + tau^2)
      const double r = std::abs(k.x()) / (k.x() * k.x() + k.z() * k.z());
      sum += r;
      sum2 += r * r;
    }
    const double n = static_cast<double>(m.models.size()), mean = sum / n;
    return std::sqrt(std::max(0.0, sum2 / n - mean * mean)) / mean;
  };
  EXPECT_NEAR(relative_sd(wavy), 0.023 / 0.044, 0.1);
  EXPECT_NEAR(relative_sd(s), 0.1, 0.02);
  EXPECT_LT(relative_sd(none), 1e-12);
}

// hair.length.crown: the crown takes its own length, blending into L(phi) at the front
// hairline's polar angle (RegionalLength's values are checked in WavyExampleOnTheHeadMesh);
// it needs the regional object and a length in (0, 10] m.
TEST(HairstyleJson, CrownLengthIsReadAndChecked) {
  const Hairstyle s = MustParse(R"({"body": "../bodies/mannequin.json",
      "scalp": {"hairline_front": 0.9},
      "hair": {"length": {"front": 0.1, "side": 0.2, "back": 0.3, "crown": 0.4}}})");
  EXPECT_EQ(s.length_crown, 0.4);
  EXPECT_EQ(s.crown_polar_angle, 0.9);
  EXPECT_NEAR(RegionalLength(s, 1.0, 0.0), 0.4, 1e-15);
  EXPECT_NEAR(RegionalLength(s, 0.0, 0.3), 0.4 + (0.1 - 0.4) / 3.0, 1e-15);
  EXPECT_EQ(MustParse(kMinimal).length_crown, 0.0);  // none by default
  Hairstyle out;
  std::string error;
  const std::string base = R"({"body": "../bodies/mannequin.json", "hair": {"length": )";
  for (const char* length : {R"({"front": 0.1, "side": 0.2, "back": 0.3, "crown": -0.1})",
                             R"({"front": 0.1, "side": 0.2, "back": 0.3, "crown": 11})"}) {
    error.clear();
    EXPECT_FALSE(ParseHairstyle(nlohmann::json::parse(base + length + "}}"), HairstyleDir(),
                                &out, &error));
    EXPECT_NE(error.find("hair.length.crown: expected a finite number"), std::string::npos)
        << error;
  }
}

// A regional length whose cosine curve dips to 0 between its values is refused, naming the field.
TEST(HairstyleJson, RegionalLengthBadValues) {
  Hairstyle s;
  std::string error;
  const std::string base = R"({"body": "../bodies/mannequin.json", "hair": {"length": )";
  EXPECT_FALSE(ParseHairstyle(nlohmann::json::parse(base + R"({"front": 0.1, "side": 0.3}}})"),
                              HairstyleDir(), &s, &error));
  EXPECT_NE(error.find("hair.length.back"), std::string::npos) << error;
  // front = back = 1 m, side 0.05 m: a0 = 0.525, a2 = 0.475, a1 = 0; L(phi) > 0 everywhere, so
  // this one is accepted ...
  EXPECT_TRUE(ParseHairstyle(
      nlohmann::json::parse(base + R"({"front": 1, "side": 0.05, "back": 1}}})"),
      HairstyleDir(), &s, &error)) << error;
  // ... while front 0.05, side 0.01, back 1 gives a0 = 0.2675, a1 = -0.475, a2 = 0.2575, whose
  // minimum, at cos(phi) = -a1 / (4 a2) = 0.461, is a0 - a2 - a1^2 / (8 a2) = -0.0995 m: refused.
  error.clear();
  EXPECT_FALSE(ParseHairstyle(
      nlohmann::json::parse(base + R"({"front": 0.05, "side": 0.01, "back": 1}}})"),
      HairstyleDir(), &s, &error));
  EXPECT_NE(error.find("hair.length"), std::string::npos) << error;
}

TEST(HairstyleJson, Defaults) {
  const Hairstyle s = MustParse(kMinimal);
  const Hairstyle d;  // the struct's defaults
  // The solver of a hairstyle is GroomSolveOptions: tolerance 1e-6, the automatic method,
  // the stability certificate on.
  const SolveOptions g = GroomSolveOptions();
  EXPECT_EQ(g.tolerance, 1e-6);
  EXPECT_TRUE(g.check_stability);
  EXPECT_EQ(g.method, Method::kAuto);
  EXPECT_EQ(s.solver.method, g.method);
  EXPECT_EQ(s.solver.tolerance, g.tolerance);
  EXPECT_EQ(s.solver.max_iterations, g.max_iterations);
  EXPECT_EQ(s.solver.check_stability, g.check_stability);
  EXPECT_EQ(s.solver.max_stability_restarts, g.max_stability_restarts);
  // A body read from a file gets the default crease blend.
  ASSERT_NE(s.body, nullptr);
  EXPECT_EQ(s.body->blend(), kDefaultBodyBlend);
  // The scalp defaults to the body's "head" sphere (radius 0.1 m at the origin) and the
  // SphereScalp hairline.
  ASSERT_TRUE(std::holds_alternative<SphereScalp>(s.scalp));
  const SphereScalp& scalp = std::get<SphereScalp>(s.scalp);
  const SphereScalp sphere_defaults;
  EXPECT_EQ(scalp.radius, 0.1);
  EXPECT_EQ(scalp.head.centre, Vec3::Zero());
  EXPECT_EQ(scalp.head.up, Vec3::UnitZ());
  EXPECT_EQ(scalp.hairline_front, sphere_defaults.hairline_front);
  EXPECT_EQ(scalp.hairline_side, sphere_defaults.hairline_side);
  EXPECT_EQ(scalp.hairline_back, sphere_defaults.hairline_back);
  // Hair: caucasian, its usual curl (wavy), the default length.
  EXPECT_EQ(s.hair_type.origin, "caucasian");
  EXPECT_EQ(s.hair_type.curl, "wavy");
  EXPECT_EQ(s.length, d.length);
  EXPECT_EQ(s.seed, d.seed);
  // Everything else as in the Hairstyle struct.
  EXPECT_EQ(s.roots.count, d.roots.count);
  EXPECT_EQ(s.roots.seed, d.roots.seed);
  EXPECT_EQ(s.roots.packing, d.roots.packing);
  EXPECT_EQ(s.segments, d.segments);
  EXPECT_EQ(s.grading, 0.0);
  EXPECT_EQ(s.master_points_per_segment, d.master_points_per_segment);
  EXPECT_EQ(s.comb.tilt, d.comb.tilt);
  EXPECT_FALSE(s.comb.parting);
  EXPECT_EQ(s.contact_stiffness, 0.0);
  EXPECT_EQ(s.contact_samples, d.contact_samples);
  EXPECT_EQ(s.layers.count, 4);
  EXPECT_EQ(s.layers.thickness, 0.004);
  EXPECT_EQ(s.wisps.strands_per_wisp, d.wisps.strands_per_wisp);
  EXPECT_EQ(s.wisps.wisp_radius, 0.0);
  EXPECT_EQ(s.wisps.tip_scale, d.wisps.tip_scale);
  EXPECT_TRUE(s.wisps.include_master);
  EXPECT_TRUE(s.spread_roots);
  EXPECT_EQ(s.gravity, Vec3(0, 0, -9.81));
}

TEST(HairstyleJson, SolverFieldsOverrideTheGroomDefaults) {
  const Hairstyle s = MustParse(R"({"body": "../bodies/mannequin.json",
      "solver": {"tolerance": 1e-8, "check_stability": true, "method": "bfgs"}})");
  EXPECT_EQ(s.solver.tolerance, 1e-8);
  EXPECT_TRUE(s.solver.check_stability);
  EXPECT_EQ(s.solver.method, Method::kBfgs);
  EXPECT_EQ(s.solver.max_iterations, GroomSolveOptions().max_iterations);
}

TEST(HairstyleJson, EveryOptionalField) {
  const Hairstyle s = MustParse(R"({
    "description": "all fields",
    "body": {"spheres": [{"name": "head", "center": [0, 0, 1.6], "radius": 0.09}], "blend": 0},
    "scalp": {"head": {"centre": [0, 0, 1.6], "up": [0, 0, 2], "front": [1, 0, 0]}, "radius": 0.09,
              "hairline_front": 1.0, "hairline_side": 1.3, "hairline_back": 1.7},
    "masters": {"count": 25, "seed": 9, "segments": 12, "grading": 2.5, "points_per_segment": 3,
                "packing": 0.4},
    "comb": {"tilt": 0.8, "direction": [0, -1, -1], "fallback_direction": [1, 0, 0],
             "parting": {"normal": [0, 1, 0], "offset": -0.01, "strength": 2}},
    "hair": {"origin": "african", "curl": "curly", "length": 0.12, "seed": 42},
    "wisps": {"strands_per_wisp": 7, "radius": 0.002, "packing_fraction": 0.5, "root_scale": 1.5,
              "tip_scale": 0.3, "profile_exponent": 2, "distance_exponent": 3, "jitter": 0.0005,
              "length_variation": 0.2, "frizz_amplitude": 0.001, "frizz_frequency": 20,
              "points_per_strand": 9, "tip_taper": 0.5, "tip_taper_length": 0.03,
              "include_master": false,
              "spread_roots": false},
    "layers": {"count": 2, "thickness": 0.005},
    "contact": {"stiffness": 3.5, "samples_per_segment": 6},
    "solver": {"max_iterations": 77},
    "gravity": [0, 0, -1.62]
  })");
  EXPECT_EQ(s.body->blend(), 0.0);
  const SphereScalp& scalp = std::get<SphereScalp>(s.scalp);
  EXPECT_EQ(scalp.head.centre, Vec3(0, 0, 1.6));
  EXPECT_EQ(scalp.head.up, Vec3(0, 0, 2));
  EXPECT_EQ(scalp.head.front, Vec3(1, 0, 0));
  EXPECT_EQ(scalp.radius, 0.09);
  EXPECT_EQ(scalp.hairline_back, 1.7);
  EXPECT_EQ(s.roots.count, 25);
  EXPECT_EQ(s.roots.seed, 9u);
  EXPECT_EQ(s.roots.packing, 0.4);
  EXPECT_EQ(s.segments, 12);
  EXPECT_EQ(s.grading, 2.5);
  EXPECT_EQ(s.master_points_per_segment, 3);
  EXPECT_EQ(s.comb.tilt, 0.8);
  EXPECT_EQ(s.comb.direction, Vec3(0, -1, -1));
  EXPECT_EQ(s.comb.fallback_direction, Vec3(1, 0, 0));
  EXPECT_TRUE(s.comb.parting);
  EXPECT_EQ(s.comb.parting_normal, Vec3(0, 1, 0));
  EXPECT_EQ(s.comb.parting_offset, -0.01);
  EXPECT_EQ(s.comb.parting_strength, 2.0);
  EXPECT_EQ(s.hair_type.origin, "african");
  EXPECT_EQ(s.hair_type.curl, "curly");
  EXPECT_EQ(s.length, 0.12);
  EXPECT_EQ(s.seed, 42u);
  EXPECT_EQ(s.wisps.strands_per_wisp, 7);
  EXPECT_EQ(s.wisps.wisp_radius, 0.002);
  EXPECT_EQ(s.wisps.packing_fraction, 0.5);
  EXPECT_EQ(s.wisps.root_scale, 1.5);
  EXPECT_EQ(s.wisps.tip_scale, 0.3);
  EXPECT_EQ(s.wisps.profile_exponent, 2.0);
  EXPECT_EQ(s.wisps.distance_exponent, 3.0);
  EXPECT_EQ(s.wisps.jitter, 0.0005);
  EXPECT_EQ(s.wisps.length_variation, 0.2);
  EXPECT_EQ(s.wisps.frizz_amplitude, 0.001);
  EXPECT_EQ(s.wisps.frizz_frequency, 20.0);
  EXPECT_EQ(s.wisps.points_per_strand, 9);
  EXPECT_EQ(s.wisps.tip_taper, 0.5);
  EXPECT_EQ(s.wisps.tip_taper_length, 0.03);
  EXPECT_FALSE(s.wisps.include_master);
  EXPECT_FALSE(s.spread_roots);
  EXPECT_EQ(s.layers.count, 2);
  EXPECT_EQ(s.layers.thickness, 0.005);
  EXPECT_EQ(s.contact_stiffness, 3.5);
  EXPECT_EQ(s.contact_samples, 6);
  EXPECT_EQ(s.solver.max_iterations, 77);
  EXPECT_EQ(s.solver.tolerance, GroomSolveOptions().tolerance);  // unchanged
  EXPECT_EQ(s.gravity, Vec3(0, 0, -1.62));
}

TEST(HairstyleJson, HeadSphereComesFromTheBody) {
  // No scalp object: the sphere named "head" of an inline body sets centre and radius.
  const Hairstyle s = MustParse(R"({"body": {"spheres": [
      {"name": "torso", "center": [0, 0, 1.2], "radius": 0.2},
      {"name": "head", "center": [0.1, 0, 1.6], "radius": 0.09}]}})");
  const SphereScalp& scalp = std::get<SphereScalp>(s.scalp);
  EXPECT_EQ(scalp.head.centre, Vec3(0.1, 0, 1.6));
  EXPECT_EQ(scalp.radius, 0.09);
  EXPECT_EQ(s.body->blend(), kDefaultBodyBlend);  // inline bodies too
  // "grading": "auto" and "radius": "auto" select the automatic values.
  const Hairstyle a = MustParse(R"({"body": "../bodies/mannequin.json",
      "masters": {"grading": "auto"}, "wisps": {"radius": "auto"}})");
  EXPECT_EQ(a.grading, 0.0);
  EXPECT_EQ(a.wisps.wisp_radius, 0.0);
  EXPECT_FALSE(a.solve_children);  // procedural children by default
  const Hairstyle b = MustParse(R"({"body": "../bodies/mannequin.json",
      "wisps": {"children": "solved"}})");
  EXPECT_TRUE(b.solve_children);
}

// hair.ellipticity, hair.curl_radius, hair.curl_pitch over the type's means (the studio's
// section and curl controls): the spreads scale with them, a radius alone keeps the helix angle,
// the masters' natural curvature follows, a straight type refuses a helix, and the bounds hold.
TEST(HairstyleJson, HairSectionAndCurlOverrideTheTypeMeans) {
  const Hairstyle base = MustParse(R"({"body": "../bodies/mannequin.json",
      "hair": {"origin": "caucasian", "curl": "curly"}})");
  const HairType& t0 = base.hair_type;
  ASSERT_FALSE(t0.IsStraight());
  ASSERT_GT(t0.ellipticity, 1.0);
  const Hairstyle s = MustParse(R"({"body": "../bodies/mannequin.json",
      "hair": {"origin": "caucasian", "curl": "curly", "ellipticity": 1.8,
               "curl_radius": 0.02}})");
  const HairType& t = s.hair_type;
  EXPECT_EQ(t.ellipticity, 1.8);
  EXPECT_NEAR(t.ellipticity_std, t0.ellipticity_std * 0.8 / (t0.ellipticity - 1.0), 1e-15);
  EXPECT_EQ(t.curl_radius, 0.02);
  const double scale = 0.02 / t0.curl_radius;
  EXPECT_NEAR(t.curl_radius_std, t0.curl_radius_std * scale, 1e-15);
  EXPECT_NEAR(t.curl_pitch, t0.curl_pitch * scale, 1e-15);  // the same helix angle
  // The mean helix's curvature R / (R^2 + (p / 2 pi)^2) scales as 1 / R with the angle kept.
  EXPECT_NEAR(t.MeanNaturalCurvature().norm(), t0.MeanNaturalCurvature().norm() / scale, 1e-9);
  const Hairstyle pitched = MustParse(R"({"body": "../bodies/mannequin.json",
      "hair": {"curl": "curly", "curl_pitch": 0.05}})");
  EXPECT_EQ(pitched.hair_type.curl_pitch, 0.05);
  EXPECT_EQ(pitched.hair_type.curl_radius, t0.curl_radius);
  // The masters take it: their mean natural curvature changes with the radius.
  HairstyleMasters a, b;
  std::string error;
  Hairstyle small_base = base, small = s;
  small_base.roots.count = small.roots.count = 40;
  ASSERT_TRUE(BuildMasters(small_base, &a, &error)) << error;
  ASSERT_TRUE(BuildMasters(small, &b, &error)) << error;
  double ka = 0.0, kb = 0.0;
  for (size_t i = 0; i < a.models.size(); ++i) {
    ka += a.models[i].NaturalCurvature(0).norm();
    kb += b.models[i].NaturalCurvature(0).norm();
  }
  ASSERT_GT(std::abs(std::log(scale)), 0.3);  // not vacuous: the radius changed by > 35 %
  EXPECT_NEAR(kb / ka, 1.0 / scale, 0.2 / scale);  // per-strand variation around the means

  for (const auto& [text, message] : std::vector<std::pair<std::string, std::string>>{
           {R"("hair": {"curl": "straight", "curl_radius": 0.01})",
            "hair.curl_radius: the curl type \"straight\" has no helix"},
           {R"("hair": {"curl": "straight", "curl_pitch": 0.01})",
            "hair.curl_pitch: the curl type \"straight\" has no helix"},
           {R"("hair": {"ellipticity": 0.9})",
            "hair.ellipticity: expected a finite a/b in [1, 10]"},
           {R"("hair": {"curl_radius": 1e-9})",
            "hair.curl_radius: expected a finite helix radius in [1e-4, 10] (m)"},
           {R"("hair": {"curl_pitch": -1})",
            "hair.curl_pitch: expected a finite helix pitch in [0, 10] (m)"},
           {R"("hair": {"curl": "straight", "curl_spread": 0.1})",
            "hair.curl_spread: the curl type \"straight\" has no helix"},
           {R"("hair": {"curl_spread": 1.5})",
            "hair.curl_spread: expected a finite relative standard deviation in [0, 1]"}}) {
    Hairstyle bad;
    std::string why;
    const std::string document = R"({"body": "../bodies/mannequin.json", )" + text + "}";
    EXPECT_FALSE(ParseHairstyle(json::parse(document), HairstyleDir(), &bad, &why))
        << text;
    EXPECT_EQ(why.rfind(message, 0), 0u) << why;
  }
}

TEST(HairstyleJson, MeshScalpTakesTheTrianglesInsideTheHairline) {
  const Hairstyle s = MustParse(R"({"body": "../bodies/mannequin_mesh.json",
      "scalp": {"mesh": "head", "hairline_front": 1.0, "hairline_side": 1.4,
                "hairline_back": 1.8}})");
  ASSERT_TRUE(std::holds_alternative<MeshScalp>(s.scalp));
  const MeshScalp& scalp = std::get<MeshScalp>(s.scalp);
  ASSERT_FALSE(scalp.triangles.empty());
  // Reference: the same hairline on a sphere, applied to each triangle's centroid.
  SphereScalp hairline;
  hairline.hairline_front = 1.0;
  hairline.hairline_side = 1.4;
  hairline.hairline_back = 1.8;
  const TriangleMesh* head = nullptr;
  for (const TriangleMesh& m : s.body->meshes()) {
    if (m.name() == "head") head = &m;
  }
  ASSERT_NE(head, nullptr);
  size_t inside = 0;
  for (const auto& t : head->triangles()) {
    const Vec3 c = (head->vertices()[t[0]] + head->vertices()[t[1]] + head->vertices()[t[2]]) / 3;
    inside += InScalp(hairline, c);
  }
  EXPECT_EQ(scalp.triangles.size(), inside);
  EXPECT_LT(scalp.triangles.size(), head->triangles().size());  // the face is left out
  for (const auto& t : scalp.triangles) {
    const Vec3 c = (scalp.vertices[t[0]] + scalp.vertices[t[1]] + scalp.vertices[t[2]]) / 3;
    EXPECT_TRUE(InScalp(hairline, c));
  }
}

TEST(HairstyleJson, BodyPathIsRelativeToTheHairstyleFile) {
  TempDirectory dir;
  ASSERT_FALSE(dir.path().empty());
  dir.Write("bodies/ball.json",
            R"({"spheres": [{"name": "head", "center": [0, 0, 0.5], "radius": 0.08}]})");
  const std::string file = dir.Write("styles/ball_hair.json",
                                     R"({"body": "../bodies/ball.json", "masters": {"count": 5}})");
  Hairstyle s;
  std::string error;
  ASSERT_TRUE(LoadHairstyle(file, &s, &error)) << error;
  EXPECT_EQ(std::get<SphereScalp>(s.scalp).radius, 0.08);
  EXPECT_EQ(s.roots.count, 5);
}

// ---------------------------------------------------------------------------------------------
// Bad input: one line naming the field, *style untouched.

struct BadCase {
  const char* name;
  std::string document;           // JSON text, parsed with base directory examples/hairstyles
  std::string field;              // the message starts with it
  std::vector<std::string> also;  // further substrings the message must contain
};

// A hairstyle on the sphere mannequin with one member replaced: `{"body": ..., MEMBER}`.
std::string With(const std::string& member) {
  return R"({"body": "../bodies/mannequin.json", )" + member + "}";
}

std::vector<BadCase> BadCases() {
  const std::string mesh_body = R"({"body": "../bodies/mannequin_mesh.json", )";
  return {
      // Presets, with the list of valid names.
      {"unknown_origin",
       With(R"("hair": {"origin": "martian"})"),
       "hair.origin",
       {"martian", "asian", "caucasian", "african"}},
      {"unknown_curl",
       With(R"("hair": {"origin": "asian", "curl": "frizzy"})"),
       "hair.curl",
       {"frizzy", "straight", "wavy", "curly", "kinky"}},
      {"origin_not_a_string", With(R"("hair": {"origin": 3})"), "hair.origin", {}},
      {"children_unknown", With(R"("wisps": {"children": "simulated"})"), "wisps.children",
       {"procedural", "solved", "simulated"}},
      // Scalps that leave nothing to grow on.
      {"hairline_leaves_no_triangle",
       mesh_body + R"("scalp": {"mesh": "head", "hairline_front": 0.001, "hairline_side": 0.001,
                               "hairline_back": 0.001}})",
       "scalp",
       {"head", "hairline"}},
      {"unknown_mesh",
       mesh_body + R"("scalp": {"mesh": "skull"}})",
       "scalp.mesh",
       {"skull", "\"head\""}},
      {"mesh_on_a_sphere_body", With(R"("scalp": {"mesh": "head"})"), "scalp.mesh", {"none"}},
      {"mesh_not_a_string", mesh_body + R"("scalp": {"mesh": 3}})", "scalp.mesh", {}},
      {"zero_hairline", With(R"("scalp": {"hairline_front": 0})"), "scalp.hairline_front", {}},
      {"negative_scalp_radius", With(R"("scalp": {"radius": -0.1})"), "scalp.radius", {}},
      {"parallel_head_axes",
       With(R"("scalp": {"head": {"up": [0, 0, 1], "front": [0, 0, 3]}})"),
       "scalp.head",
       {}},
      // The body.
      {"missing_body", R"({"masters": {"count": 3}})", "body", {"missing"}},
      {"missing_body_file", R"({"body": "no_such_body.json"})", "body", {"no_such_body.json"}},
      {"body_not_a_name", R"({"body": 3})", "body", {}},
      {"body_without_components", R"({"body": {}})", "body", {"sphere or mesh"}},
      {"body_mesh_file_missing",
       R"({"body": {"meshes": [{"obj": "no_such.obj"}]}})",
       "body.meshes[0].obj",
       {"no_such.obj"}},
      {"body_sphere_radius",
       R"({"body": {"spheres": [{"center": [0, 0, 0], "radius": -1}]}})",
       "body.spheres[0].radius",
       {}},
      // Counts.
      {"negative_master_count", With(R"("masters": {"count": -5})"), "masters.count", {"-5"}},
      {"zero_master_count", With(R"("masters": {"count": 0})"), "masters.count", {}},
      {"fractional_master_count", With(R"("masters": {"count": 2.5})"), "masters.count", {}},
      {"zero_strands_per_wisp",
       With(R"("wisps": {"strands_per_wisp": 0})"),
       "wisps.strands_per_wisp",
       {}},
      {"negative_strands_per_wisp",
       With(R"("wisps": {"strands_per_wisp": -3})"),
       "wisps.strands_per_wisp",
       {}},
      {"zero_segments", With(R"("masters": {"segments": 0})"), "masters.segments", {}},
      {"zero_tip_taper_length",
       With(R"("wisps": {"tip_taper_length": 0})"),
       "wisps.tip_taper_length",
       {"> 0 (m)"}},
      {"tip_taper_one", With(R"("wisps": {"tip_taper": 1})"), "wisps.tip_taper", {"[0, 1)"}},
      {"one_point_per_strand",
       With(R"("wisps": {"points_per_strand": 1})"),
       "wisps.points_per_strand",
       {}},
      {"zero_layers", With(R"("layers": {"count": 0})"), "layers.count", {}},
      {"too_many_layers", With(R"("layers": {"count": 65})"), "layers.count", {}},
      // Unknown keys, with a hint.
      {"unknown_top_level_key", With(R"("layer": {"count": 2})"), "layer", {"layers"}},
      {"unknown_masters_key", With(R"("masters": {"cont": 3})"), "masters.cont", {"count"}},
      {"unknown_wisps_key", With(R"("wisps": {"radious": 0.001})"), "wisps.radious", {"radius"}},
      {"unknown_hair_key", With(R"("hair": {"colour": "red"})"), "hair.colour", {}},
      {"unknown_parting_key", With(R"("comb": {"parting": {"side": 1}})"), "comb.parting.side", {}},
      // Wrong types.
      {"top_level_array", "[1, 2]", "", {"JSON object"}},
      {"length_as_text", With(R"("hair": {"length": "30 cm"})"), "hair.length", {"\"30 cm\""}},
      {"zero_length", With(R"("hair": {"length": 0})"), "hair.length", {}},
      {"layers_not_an_object", With(R"("layers": 4)"), "layers", {"an object"}},
      {"gravity_two_numbers", With(R"("gravity": [0, -9.81])"), "gravity", {}},
      {"tilt_as_text", With(R"("comb": {"tilt": "steep"})"), "comb.tilt", {}},
      {"tilt_beyond_right_angle", With(R"("comb": {"tilt": 2})"), "comb.tilt", {}},
      {"include_master_as_text",
       With(R"("wisps": {"include_master": "yes"})"),
       "wisps.include_master",
       {}},
      {"description_not_a_string", With(R"("description": 5)"), "description", {}},
      {"wisp_radius_as_text", With(R"("wisps": {"radius": "big"})"), "wisps.radius", {"auto"}},
      {"packing_fraction_above_one",
       With(R"("wisps": {"packing_fraction": 1.5})"),
       "wisps.packing_fraction",
       {}},
      {"negative_contact_stiffness",
       With(R"("contact": {"stiffness": -1})"),
       "contact.stiffness",
       {}},
      {"unknown_solver_method", With(R"("solver": {"method": "sgd"})"), "solver.method", {"lbfgs"}},
      {"zero_solver_tolerance", With(R"("solver": {"tolerance": 0})"), "solver.tolerance", {}},
      // Seeds: integers in [0, 2^53].
      {"negative_seed", With(R"("masters": {"seed": -1})"), "masters.seed", {"integer"}},
      {"fractional_seed", With(R"("masters": {"seed": 1.5})"), "masters.seed", {}},
      {"seed_as_text", With(R"("masters": {"seed": "one"})"), "masters.seed", {}},
      {"huge_seed", With(R"("masters": {"seed": 1e20})"), "masters.seed", {}},
      {"negative_hair_seed", With(R"("hair": {"seed": -2})"), "hair.seed", {}},
      // Issue 16: read as integers, 2^53 + 1 is not rounded to 2^53.
      {"seed_beyond_2p53",
       With(R"("masters": {"seed": 9007199254740993})"),
       "masters.seed",
       {"got 9007199254740993"}},
      {"hair_seed_beyond_2p53", With(R"("hair": {"seed": 9007199254740993})"), "hair.seed", {}},
      {"curl_inward_not_bool", With(R"("comb": {"curl_inward": 1})"), "comb.curl_inward",
       {"true or false"}},
      // Grading: "auto" or a ratio >= 1.
      {"grading_below_one", With(R"("masters": {"grading": 0.5})"), "masters.grading", {"auto"}},
      {"grading_zero", With(R"("masters": {"grading": 0})"), "masters.grading", {}},
      {"grading_unknown_word", With(R"("masters": {"grading": "fast"})"), "masters.grading", {}},
      // Layer thickness: [0, 0.1) m.
      {"negative_layer_thickness",
       With(R"("layers": {"thickness": -0.001})"),
       "layers.thickness",
       {"(m)"}},
      {"layer_thickness_ten_centimetres",
       With(R"("layers": {"thickness": 0.1})"),
       "layers.thickness",
       {}},
      {"layer_thickness_as_text",
       With(R"("layers": {"thickness": "thin"})"),
       "layers.thickness",
       {}},
  };
}

TEST(HairstyleJson, BadInputNamesTheField) {
  // The cases on the mesh mannequin share its body, read once (the overload `ringlet batch`
  // uses): reading mannequin.obj and building its distance grid for each of them took ~25 s a
  // case under the sanitizers. Reading that body file is tested by BodyJson.ShippedMannequinsLoad
  // and HairstyleJson.ExamplesParse; here it is the hairstyle's fields.
  const std::string mesh_body_file = "../bodies/mannequin_mesh.json";
  auto mesh_body = std::make_shared<Body>();
  {
    std::string error;
    ASSERT_TRUE(LoadBody(HairstyleDir() + "/" + mesh_body_file, mesh_body.get(), &error)) << error;
  }
  for (const BadCase& c : BadCases()) {
    SCOPED_TRACE(c.name);
    Hairstyle style;
    style.length = 0.123;  // a marker: must survive the failed parse
    std::string error;
    const bool on_mesh = c.document.find(mesh_body_file) != std::string::npos;
    const bool parsed =
        on_mesh ? ParseHairstyle(json::parse(c.document), HairstyleDir(), mesh_body, &style, &error)
                : ParseHairstyle(json::parse(c.document), HairstyleDir(), &style, &error);
    EXPECT_FALSE(parsed) << c.document;
    if (parsed) continue;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    EXPECT_FALSE(error.empty());
    // The message starts with the field, followed by ": " (or is the top level).
    if (!c.field.empty()) {
      EXPECT_EQ(error.rfind(c.field + ": ", 0), 0u) << error;
      EXPECT_EQ(error.rfind(c.field + ": " + c.field + ": ", 0), std::string::npos)
          << "the field is named twice: " << error;
    }
    // Names from inside the library (FindHairType's "hair_type.origin") are not keys of
    // the file and must not leak into the message.
    EXPECT_EQ(error.find("hair_type."), std::string::npos) << error;
    for (const std::string& s : c.also) {
      EXPECT_NE(error.find(s), std::string::npos) << "'" << s << "' not in: " << error;
    }
    EXPECT_EQ(style.length, 0.123);
  }
}

TEST(HairstyleJson, FileErrorsNameTheFileAndPosition) {
  TempDirectory dir;
  ASSERT_FALSE(dir.path().empty());
  Hairstyle style;
  std::string error;
  // A missing hairstyle file.
  const std::string missing = dir.path() + "/missing.json";
  EXPECT_FALSE(LoadHairstyle(missing, &style, &error));
  EXPECT_EQ(error.rfind(missing, 0), 0u) << error;
  // A JSON syntax error: line and column.
  const std::string broken = dir.Write("broken.json", "{\n  \"body\": \"b.json\",,\n}\n");
  EXPECT_FALSE(LoadHairstyle(broken, &style, &error));
  EXPECT_EQ(error.rfind(broken + ": ", 0), 0u) << error;
  EXPECT_NE(error.find("line 2"), std::string::npos) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  // A duplicate key is refused, not silently resolved.
  const std::string twice =
      dir.Write("twice.json", R"({"body": "b.json", "hair": {"length": 0.1, "length": 0.2}})");
  EXPECT_FALSE(LoadHairstyle(twice, &style, &error));
  EXPECT_NE(error.find("hair.length"), std::string::npos) << error;
  // A malformed body file: its own path and position appear after "body: ".
  dir.Write("bad_body.json", "{\"spheres\": [ }");
  const std::string uses_bad_body = dir.Write("uses_bad_body.json", R"({"body": "bad_body.json"})");
  EXPECT_FALSE(LoadHairstyle(uses_bad_body, &style, &error));
  EXPECT_EQ(error.rfind(uses_bad_body + ": body: ", 0), 0u) << error;
  EXPECT_NE(error.find("bad_body.json"), std::string::npos) << error;
  EXPECT_NE(error.find("line 1"), std::string::npos) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  // A body file naming a malformed OBJ mesh.
  dir.Write("bad.obj", "o head\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");  // open: one triangle
  dir.Write("mesh_body.json", R"({"meshes": [{"obj": "bad.obj"}]})");
  const std::string uses_bad_mesh =
      dir.Write("uses_bad_mesh.json", R"({"body": "mesh_body.json"})");
  EXPECT_FALSE(LoadHairstyle(uses_bad_mesh, &style, &error));
  EXPECT_EQ(error.rfind(uses_bad_mesh + ": body: ", 0), 0u) << error;
  EXPECT_NE(error.find("bad.obj"), std::string::npos) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
}

}  // namespace
}  // namespace ringlet
