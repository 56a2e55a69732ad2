// Render settings (src/io/render_json.cpp, docs/hairstyle-format.md "render"): the documented
// defaults, every field reaching RenderSettings (degrees converted to radians), the "render"
// member of hairstyle files accepted by ParseHairstyle, and bad inputs rejected with one line
// naming the field, leaving the settings untouched.
#include "ringlet/render_json.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "ringlet/hair_type.h"
#include "ringlet/hairstyle_json.h"

namespace ringlet {
namespace {

using nlohmann::json;

constexpr double kDegree = M_PI / 180.0;

RenderSettings MustParse(const std::string& text) {
  RenderSettings settings;
  std::string error;
  EXPECT_TRUE(ParseRenderSettings(json::parse(text), "render", &settings, &error))
      << text << "\n" << error;
  return settings;
}

// The error for a bad render object; the settings must stay as they were.
std::string ErrorOf(const std::string& text) {
  RenderSettings settings;
  settings.options.width = 123;  // a marker: a failed parse must not touch the settings
  std::string error;
  EXPECT_FALSE(ParseRenderSettings(json::parse(text), "render", &settings, &error)) << text;
  EXPECT_EQ(settings.options.width, 123) << text;
  EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  return error;
}

TEST(RenderJson, Defaults) {
  const RenderSettings s = MustParse("{}");
  // RenderOptions' defaults (render.h).
  EXPECT_EQ(s.options.width, 800);
  EXPECT_EQ(s.options.height, 800);
  EXPECT_EQ(s.options.samples_per_pixel, 16);
  EXPECT_EQ(s.options.seed, 1u);
  EXPECT_EQ(s.options.max_bounces, 16);
  EXPECT_EQ(s.options.shadows, ShadowMode::kPathTraced);
  // Clean pictures by default (docs/rendering.md, "Noise"): stratified samples, the firefly
  // clamp and the denoiser; RenderOptions itself defaults to the unbiased estimate.
  EXPECT_EQ(s.options.pattern, SamplePattern::kSobol);
  EXPECT_EQ(s.options.clamp, kDefaultClamp);
  EXPECT_TRUE(s.options.denoise);
  EXPECT_EQ(RenderOptions().clamp, 0.0);
  EXPECT_FALSE(RenderOptions().denoise);
  EXPECT_EQ(s.optics.water_eta, 1.333);
  // A framed camera from the front (+y, the face), the right (+x) and above (+z): the view
  // direction points from the camera toward the head, so each component is negative.
  EXPECT_EQ(s.camera.kind, CameraSettings::Kind::kFramed);
  EXPECT_LT(s.camera.view_direction.x(), 0.0);
  EXPECT_LT(s.camera.view_direction.y(), 0.0);
  EXPECT_LT(s.camera.view_direction.z(), 0.0);
  EXPECT_NEAR(s.camera.vertical_fov, 30.0 * kDegree, 1e-15);
  // The key light comes from above and in front (direction toward the light), unit length.
  EXPECT_GT(s.key.direction.y(), 0.0);
  EXPECT_GT(s.key.direction.z(), 0.0);
  EXPECT_NEAR(s.key.direction.norm(), 1.0, 1e-15);
  EXPECT_EQ(s.key.irradiance, KeyLight().irradiance);
  EXPECT_EQ(s.key.angular_radius, KeyLight().angular_radius);
  EXPECT_EQ(s.environment.top, Environment().top);
  EXPECT_EQ(s.environment.bottom, Environment().bottom);
  // Brown hair (Chiang et al. 2016: eumelanin ~1.3), Chiang's model, Marschner's eta.
  EXPECT_EQ(s.eumelanin, 1.3);
  EXPECT_EQ(s.pheomelanin, 0.2);
  EXPECT_EQ(s.optics.model, HairScatteringModel::kChiang2016);
  EXPECT_EQ(s.optics.eta, 1.55);
  EXPECT_EQ(s.optics.eccentricity, 0.0);
  EXPECT_EQ(s.exposure, 1.0);
  EXPECT_EQ(s.body_albedo, RenderScene().body_albedo);
}

TEST(RenderJson, EveryField) {
  const RenderSettings s = MustParse(R"({
    "width": 640, "height": 480, "samples_per_pixel": 64, "seed": 9, "max_bounces": 3,
    "shadows": "fibre_transmittance", "exposure": 1.5,
    "sampler": "independent", "clamp": 0, "denoise": false,
    "camera": {"view_direction": [0, 2, -0.2], "fov_degrees": 45},
    "key_light": {"direction": [0, 0, 2], "angular_radius_degrees": 1.2, "irradiance": [3, 2, 1]},
    "environment": {"top": [0.5, 0.6, 0.7], "bottom": [0.1, 0.2, 0.3]},
    "hair": {"eumelanin": 8, "pheomelanin": 0.5, "model": "marschner2003", "eta": 1.6,
             "longitudinal_roughness": 0.25, "azimuthal_roughness": 0.5,
             "cuticle_tilt_degrees": 3, "water_eta": 1.34},
    "body_albedo": [0.2, 0.3, 0.4]})");
  EXPECT_EQ(s.options.pattern, SamplePattern::kIndependent);
  EXPECT_EQ(s.options.clamp, 0.0);
  EXPECT_FALSE(s.options.denoise);
  EXPECT_EQ(s.optics.water_eta, 1.34);
  EXPECT_EQ(s.options.width, 640);
  EXPECT_EQ(s.options.height, 480);
  EXPECT_EQ(s.options.samples_per_pixel, 64);
  EXPECT_EQ(s.options.seed, 9u);
  EXPECT_EQ(s.options.max_bounces, 3);
  EXPECT_EQ(s.options.shadows, ShadowMode::kFibreTransmittance);
  EXPECT_EQ(s.exposure, 1.5);
  EXPECT_EQ(s.camera.kind, CameraSettings::Kind::kFramed);
  EXPECT_EQ(s.camera.view_direction, Vec3(0, 2, -0.2));
  EXPECT_NEAR(s.camera.vertical_fov, M_PI / 4, 1e-15);
  EXPECT_EQ(s.key.direction, Vec3(0, 0, 1));  // normalized
  EXPECT_NEAR(s.key.angular_radius, 1.2 * kDegree, 1e-15);
  EXPECT_EQ(s.key.irradiance, Rgb(3, 2, 1));
  EXPECT_EQ(s.environment.top, Rgb(0.5, 0.6, 0.7));
  EXPECT_EQ(s.environment.bottom, Rgb(0.1, 0.2, 0.3));
  EXPECT_EQ(s.eumelanin, 8.0);
  EXPECT_EQ(s.pheomelanin, 0.5);
  EXPECT_EQ(s.optics.model, HairScatteringModel::kMarschner2003);
  EXPECT_EQ(s.optics.eta, 1.6);
  EXPECT_EQ(s.optics.longitudinal_roughness, 0.25);
  EXPECT_EQ(s.optics.azimuthal_roughness, 0.5);
  EXPECT_NEAR(s.optics.cuticle_tilt, 3 * kDegree, 1e-15);
  EXPECT_EQ(s.body_albedo, Rgb(0.2, 0.3, 0.4));
}

TEST(RenderJson, ExplicitCamera) {
  const RenderSettings s = MustParse(
      R"({"camera": {"position": [0, 1, 0.1], "look_at": [0, 0, -0.05], "fov_degrees": 20}})");
  EXPECT_EQ(s.camera.kind, CameraSettings::Kind::kExplicit);
  EXPECT_EQ(s.camera.position, Vec3(0, 1, 0.1));
  EXPECT_EQ(s.camera.look_at, Vec3(0, 0, -0.05));
  EXPECT_EQ(s.camera.up, Vec3::UnitZ());  // the default up
  EXPECT_NEAR(s.camera.vertical_fov, 20 * kDegree, 1e-15);
  const RenderSettings t =
      MustParse(R"({"camera": {"position": [0, 0, 1], "look_at": [0, 0, 0], "up": [0, 3, 0]}})");
  EXPECT_EQ(t.camera.up, Vec3::UnitY());
  EXPECT_NEAR(t.camera.vertical_fov, 30 * kDegree, 1e-15);  // default kept
}

TEST(RenderJson, FieldsNotGivenKeepTheirValues) {
  RenderSettings settings;
  settings.options.width = 77;
  settings.exposure = 3.0;
  std::string error;
  ASSERT_TRUE(ParseRenderSettings(json::parse(R"({"height": 5})"), "render", &settings, &error));
  EXPECT_EQ(settings.options.width, 77);
  EXPECT_EQ(settings.options.height, 5);
  EXPECT_EQ(settings.exposure, 3.0);
}

TEST(RenderJson, BadInputsNameTheField) {
  EXPECT_EQ(ErrorOf("[1, 2]"),
            "render: expected an object {\"width\": ..., \"camera\": ..., ...}, got [1,2]");
  EXPECT_EQ(ErrorOf(R"({"widht": 5})"), "render.widht: unknown field (did you mean \"width\"?)");
  EXPECT_EQ(ErrorOf(R"({"width": 0})"),
            "render.width: expected an integer between 1 and 16384, got 0");
  EXPECT_EQ(ErrorOf(R"({"height": 10.5})"),
            "render.height: expected an integer between 1 and 16384, got 10.5");
  EXPECT_EQ(ErrorOf(R"({"samples_per_pixel": "many"})"),
            "render.samples_per_pixel: expected an integer between 1 and 1048576, got \"many\"");
  EXPECT_EQ(ErrorOf(R"({"seed": -1})"),
            "render.seed: expected an integer between 0 and 2^53, got -1");
  EXPECT_EQ(ErrorOf(R"({"max_bounces": -1})"),
            "render.max_bounces: expected an integer between 0 and 1000, got -1");
  EXPECT_EQ(ErrorOf(R"({"shadows": "deep"})"),
            "render.shadows: expected one of \"path_traced\", \"fibre_transmittance\", got "
            "\"deep\"");
  EXPECT_EQ(ErrorOf(R"({"shadows": 1})"),
            "render.shadows: expected one of \"path_traced\", \"fibre_transmittance\", got 1");
  EXPECT_EQ(ErrorOf(R"({"exposure": 0})"), "render.exposure: expected a finite number > 0, got 0");
  EXPECT_EQ(ErrorOf(R"({"clamp": -1})"),
            "render.clamp: expected a finite number >= 0 (radiance; 0 = no clamp), got -1");
  EXPECT_EQ(ErrorOf(R"({"denoise": 1})"), "render.denoise: expected true or false, got 1");
  EXPECT_EQ(ErrorOf(R"({"sampler": "halton"})"),
            "render.sampler: expected one of \"sobol\", \"independent\", got \"halton\"");
  EXPECT_EQ(ErrorOf(R"({"hair": {"water_eta": 1}})"),
            "render.hair.water_eta: expected a finite number > 1 (refractive index), got 1");
  EXPECT_EQ(ErrorOf(R"({"body_albedo": [0.5, 1.5, 0]})"),
            "render.body_albedo: expected an array of 3 numbers in [0, 1] (reflectance), got "
            "[0.5,1.5,0]");
  EXPECT_EQ(ErrorOf(R"({"body_albedo": [0.5, 0.5]})"),
            "render.body_albedo: expected an array of 3 finite numbers (reflectance), got "
            "[0.5,0.5]");
}

TEST(RenderJson, BadCamerasNameTheField) {
  EXPECT_EQ(ErrorOf(R"({"camera": 3})"), "render.camera: expected an object, got 3");
  EXPECT_EQ(ErrorOf(R"({"camera": {"fov": 30}})"),
            "render.camera.fov: unknown field (known fields: view_direction, position, look_at, "
            "up, fov_degrees)");
  EXPECT_EQ(ErrorOf(R"({"camera": {"fov_degrees": 180}})"),
            "render.camera.fov_degrees: expected a finite number in (0, 180) (degrees), got 180");
  EXPECT_EQ(ErrorOf(R"({"camera": {"view_direction": [0, 0, 0]}})"),
            "render.camera.view_direction: expected a non-zero direction [x, y, z], got [0,0,0]");
  EXPECT_EQ(ErrorOf(R"({"camera": {"view_direction": [0, 1, 0], "position": [0, 1, 0]}})"),
            "render.camera: give either view_direction (a framed camera) or position, look_at "
            "and up (an explicit camera), not both");
  EXPECT_EQ(ErrorOf(R"({"camera": {"position": [0, 1, 0]}})"),
            "render.camera.look_at: missing required field (expected an array of 3 finite "
            "numbers (m))");
  EXPECT_EQ(ErrorOf(R"({"camera": {"look_at": [0, 1, 0]}})"),
            "render.camera.position: missing required field (expected an array of 3 finite "
            "numbers (m))");
  EXPECT_EQ(ErrorOf(R"({"camera": {"position": [0, 1, 0], "look_at": [0, 1, 0]}})"),
            "render.camera.look_at: must differ from position (the camera looks from position "
            "toward look_at)");
  EXPECT_EQ(ErrorOf(R"({"camera": {"position": [0, 0, 1], "look_at": [0, 0, 0]}})"),
            "render.camera.up: must not be parallel to look_at - position");
}

TEST(RenderJson, BadLightsAndOpticsNameTheField) {
  EXPECT_EQ(ErrorOf(R"({"key_light": {"direction": [0, 0, 0]}})"),
            "render.key_light.direction: expected a non-zero direction [x, y, z], got [0,0,0]");
  EXPECT_EQ(ErrorOf(R"({"key_light": {"angular_radius_degrees": 0}})"),
            "render.key_light.angular_radius_degrees: expected a finite number in (0, 90) "
            "(degrees), got 0");
  EXPECT_EQ(ErrorOf(R"({"key_light": {"irradiance": [1, -1, 1]}})"),
            "render.key_light.irradiance: expected an array of 3 finite numbers >= 0 (W/m^2), "
            "got [1,-1,1]");
  EXPECT_EQ(ErrorOf(R"({"key_light": {"radius": 1}})"),
            "render.key_light.radius: unknown field (known fields: direction, "
            "angular_radius_degrees, irradiance)");
  EXPECT_EQ(ErrorOf(R"({"environment": {"top": [1, 1, "x"]}})"),
            "render.environment.top: expected an array of 3 finite numbers (radiance, W sr^-1 "
            "m^-2), got [1,1,\"x\"]");
  EXPECT_EQ(ErrorOf(R"({"environment": {"middle": [1, 1, 1]}})"),
            "render.environment.middle: unknown field (known fields: top, bottom)");
  EXPECT_EQ(ErrorOf(R"({"hair": {"eumelanin": -1}})"),
            "render.hair.eumelanin: expected a finite number >= 0 (concentration), got -1");
  EXPECT_EQ(ErrorOf(R"({"hair": {"pheomelanin": null}})"),
            "render.hair.pheomelanin: expected a finite number >= 0 (concentration), got null");
  EXPECT_EQ(ErrorOf(R"({"hair": {"model": "kajiya"}})"),
            "render.hair.model: expected one of \"chiang2016\", \"marschner2003\", got \"kajiya\"");
  EXPECT_EQ(ErrorOf(R"({"hair": {"eta": 1}})"),
            "render.hair.eta: expected a finite number > 1 (refractive index), got 1");
  EXPECT_EQ(ErrorOf(R"({"hair": {"longitudinal_roughness": 0}})"),
            "render.hair.longitudinal_roughness: expected a finite number in (0, 1], got 0");
  EXPECT_EQ(ErrorOf(R"({"hair": {"azimuthal_roughness": 1.5}})"),
            "render.hair.azimuthal_roughness: expected a finite number in (0, 1], got 1.5");
  EXPECT_EQ(ErrorOf(R"({"hair": {"cuticle_tilt_degrees": 30}})"),
            "render.hair.cuticle_tilt_degrees: expected a finite number in [-10, 10] (degrees), "
            "got 30");
  EXPECT_EQ(ErrorOf(R"({"hair": {"eccentricity": 0.5}})"),
            "render.hair.eccentricity: not a render setting: the fibre's eccentricity is the "
            "hairstyle's own (hair.origin), one number for mechanics and optics; for .hair files "
            "use ringlet render --eccentricity");
}

TEST(RenderJson, NamesOfModesAndModels) {
  ShadowMode mode = ShadowMode::kPathTraced;
  EXPECT_TRUE(ParseShadowMode("fibre_transmittance", &mode));
  EXPECT_EQ(mode, ShadowMode::kFibreTransmittance);
  EXPECT_TRUE(ParseShadowMode("path_traced", &mode));
  EXPECT_EQ(mode, ShadowMode::kPathTraced);
  EXPECT_FALSE(ParseShadowMode("Path_Traced", &mode));
  HairScatteringModel model = HairScatteringModel::kChiang2016;
  EXPECT_TRUE(ParseHairScatteringModel("marschner2003", &model));
  EXPECT_EQ(model, HairScatteringModel::kMarschner2003);
  EXPECT_FALSE(ParseHairScatteringModel("", &model));
}

TEST(RenderJson, EccentricityComesFromTheHairType) {
  // e = sqrt(1 - (b/a)^2): a/b = 1 is a circle (e = 0); a/b = 2 gives sqrt(3)/2 = 0.8660254.
  HairType type;
  type.ellipticity = 1.0;
  EXPECT_EQ(HairTypeEccentricity(type), 0.0);
  type.ellipticity = 2.0;
  EXPECT_NEAR(HairTypeEccentricity(type), std::sqrt(3.0) / 2.0, 1e-15);
  // The presets: African hair is the most elliptic (docs/hair-types.md), Asian the least.
  HairType asian, african;
  std::string why;
  ASSERT_TRUE(FindHairType("asian", "", &asian, &why)) << why;
  ASSERT_TRUE(FindHairType("african", "", &african, &why)) << why;
  EXPECT_NEAR(HairTypeEccentricity(african),
              std::sqrt(1.0 - 1.0 / (african.ellipticity * african.ellipticity)), 1e-15);
  EXPECT_GT(HairTypeEccentricity(african), HairTypeEccentricity(asian));
  EXPECT_GT(HairTypeEccentricity(asian), 0.0);
  EXPECT_LT(HairTypeEccentricity(african), 1.0);
}

// ---------------------------------------------------------------------------------------------
// Documents and files.

TEST(RenderJson, MemberOfADocument) {
  RenderSettings settings;
  std::string error;
  ASSERT_TRUE(ParseRenderMember(json::parse(R"({"body": "x"})"), &settings, &error)) << error;
  EXPECT_EQ(settings.options.width, 800);
  ASSERT_TRUE(ParseRenderMember(json::parse(R"({"render": {"width": 64}})"), &settings, &error));
  EXPECT_EQ(settings.options.width, 64);
  EXPECT_FALSE(ParseRenderMember(json::parse("[]"), &settings, &error));
  EXPECT_EQ(error, "expected a JSON object at the top level, got []");
  EXPECT_FALSE(ParseRenderMember(json::parse(R"({"render": {"width": -4}})"), &settings, &error));
  EXPECT_EQ(error, "render.width: expected an integer between 1 and 16384, got -4");
  // Issue 16: a settings file (--settings) must hold settings; a hairstyle need not.
  EXPECT_FALSE(ParseRenderMember(json::parse(R"({"width": 64})"), &settings, &error, true));
  EXPECT_EQ(error.rfind("render: missing required field (expected an object", 0), 0u) << error;
  EXPECT_TRUE(ParseRenderMember(json::parse(R"({"render": {}})"), &settings, &error, true))
      << error;
}

// Issue 16: the seed is read as an integer: 2^53 + 1 is refused, not rounded to 2^53.
TEST(RenderJson, SeedIsReadExactly) {
  RenderSettings settings;
  std::string error;
  ASSERT_TRUE(ParseRenderSettings(json::parse(R"({"seed": 9007199254740992})"), "render", &settings,
                                  &error))
      << error;
  EXPECT_EQ(settings.options.seed, std::uint64_t{1} << 53);
  ASSERT_TRUE(
      ParseRenderSettings(json::parse(R"({"seed": 12345678901})"), "render", &settings, &error))
      << error;
  EXPECT_EQ(settings.options.seed, 12345678901u);
  for (const char* bad : {R"({"seed": 9007199254740993})", R"({"seed": -1})", R"({"seed": 1.5})",
                          R"({"seed": 1e17})"}) {
    EXPECT_FALSE(ParseRenderSettings(json::parse(bad), "render", &settings, &error)) << bad;
    EXPECT_EQ(error.rfind("render.seed: expected an integer between 0 and 2^53, got ", 0), 0u)
        << error;
  }
  EXPECT_EQ(settings.options.seed, 12345678901u);
}

TEST(RenderJson, HairstyleFilesMayHoldRenderSettings) {
  std::string pattern = ::testing::TempDir() + "ringlet_render_json_XXXXXX";
  ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
  const std::string dir = pattern;
  const std::string body = std::string(RINGLET_EXAMPLES_DIR) + "/bodies/mannequin.json";
  const std::string path = dir + "/style.json";
  std::ofstream(path) << R"({"body": ")" << body << R"(", "masters": {"count": 5},
    "render": {"width": 64, "height": 32, "hair": {"eumelanin": 8}}})";
  // ParseHairstyle accepts the member and ignores it ...
  Hairstyle style;
  std::string error;
  EXPECT_TRUE(LoadHairstyle(path, &style, &error)) << error;
  // ... LoadRenderSettings reads it.
  RenderSettings settings;
  ASSERT_TRUE(LoadRenderSettings(path, &settings, &error)) << error;
  EXPECT_EQ(settings.options.width, 64);
  EXPECT_EQ(settings.options.height, 32);
  EXPECT_EQ(settings.eumelanin, 8.0);

  std::ofstream(dir + "/bad.json") << "{\"render\": {\"samples_per_pixel\": 0}}";
  EXPECT_FALSE(LoadRenderSettings(dir + "/bad.json", &settings, &error));
  EXPECT_EQ(error, dir + "/bad.json: render.samples_per_pixel: expected an integer between 1 "
                         "and 1048576, got 0");
  std::ofstream(dir + "/syntax.json") << "{\"render\": {\"width\": 5,, }}";
  EXPECT_FALSE(LoadRenderSettings(dir + "/syntax.json", &settings, &error));
  EXPECT_EQ(error.rfind(dir + "/syntax.json: line 1, column", 0), 0u) << error;
  EXPECT_FALSE(LoadRenderSettings(dir + "/none.json", &settings, &error));
  EXPECT_EQ(error.rfind(dir + "/none.json: cannot open", 0), 0u) << error;
  EXPECT_EQ(settings.options.width, 64);  // untouched by the failures
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ringlet
