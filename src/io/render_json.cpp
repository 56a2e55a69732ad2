// Render settings: JSON "render" object -> validated RenderSettings (docs/hairstyle-format.md).
//
// Every field is checked where it is read (io/json_reader.h) so that an error names the field,
// what was expected and what was found, in one line. Angles are degrees in the file (what people
// type) and radians in the structs (SI, like the rest of ringlet).
#include "ringlet/render_json.h"

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "io/json_reader.h"
#include "ringlet/atomic_file.h"

namespace ringlet {
namespace {

using nlohmann::json;
using internal::Member;
using internal::NumberRule;
using internal::Reader;

constexpr double kDegree = M_PI / 180.0;

constexpr NumberRule kFovRule{"a finite number in (0, 180) (degrees)",
                              [](double x) { return x > 0.0 && x < 180.0; }};
constexpr NumberRule kAngularRadiusRule{"a finite number in (0, 90) (degrees)",
                                        [](double x) { return x > 0.0 && x < 90.0; }};
constexpr NumberRule kExposureRule{"a finite number > 0", [](double x) { return x > 0.0; }};
constexpr NumberRule kMelaninRule{"a finite number >= 0 (concentration)",
                                  [](double x) { return x >= 0.0; }};
constexpr NumberRule kClampRule{"a finite number >= 0 (radiance; 0 = no clamp)",
                                [](double x) { return x >= 0.0; }};
constexpr NumberRule kEtaRule{"a finite number > 1 (refractive index)",
                              [](double x) { return x > 1.0; }};
constexpr NumberRule kRoughnessRule{"a finite number in (0, 1]",
                                    [](double x) { return x > 0.0 && x <= 1.0; }};
constexpr NumberRule kTiltRule{"a finite number in [-10, 10] (degrees)",
                               [](double x) { return x >= -10.0 && x <= 10.0; }};

// Largest image side (pixels) and sample count accepted from a file.
constexpr int kMaxImageSide = 16384;
constexpr int kMaxSamplesPerPixel = 1 << 20;
constexpr int kMaxBounces = 1000;

// An optional RGB triple with every component in [0, max] (max may be infinity).
bool ReadRgb(Reader& reader, const json& object, const std::string& path, const char* key,
             double max, const char* unit, Rgb* out) {
  Rgb value = *out;
  if (!reader.ReadVector<3>(object, path, key, unit, false, &value)) return false;
  if ((value.array() < 0.0).any() || (value.array() > max).any()) {
    const std::string expected = std::isinf(max)
                                     ? std::string("an array of 3 finite numbers >= 0 (") + unit + ")"
                                     : std::string("an array of 3 numbers in [0, 1] (") + unit + ")";
    return reader.Expected(Member(path, key), expected, object.at(key));
  }
  *out = value;
  return true;
}

// An optional direction: 3 finite numbers, not all zero; stored normalized when normalize.
bool ReadDirection(Reader& reader, const json& object, const std::string& path, const char* key,
                   bool normalize, Vec3* out) {
  Vec3 value = *out;
  if (!reader.ReadVector<3>(object, path, key, "a direction", false, &value)) return false;
  if (!(value.norm() > 0.0) || !std::isfinite(value.norm())) {
    return reader.Expected(Member(path, key), "a non-zero direction [x, y, z]", object.at(key));
  }
  *out = normalize ? Vec3(value.normalized()) : value;
  return true;
}

// A name out of a list; *name keeps its value when absent.
bool ReadName(Reader& reader, const json& object, const std::string& path, const char* key,
              const char* expected, std::string* name, bool* present) {
  *present = false;
  const auto it = object.find(key);
  if (it == object.end()) return true;
  if (!it->is_string()) return reader.Expected(Member(path, key), expected, *it);
  *name = it->get<std::string>();
  *present = true;
  return true;
}

bool ParseCamera(Reader& reader, const json& render, const std::string& render_path,
                 CameraSettings* camera) {
  const json* object = nullptr;
  if (!OptionalObject(reader, render, render_path, "camera", &object)) return false;
  if (!object) return true;
  const std::string path = Member(render_path, "camera");
  if (!reader.CheckFields(*object, path,
                          {"view_direction", "position", "look_at", "up", "fov_degrees"})) {
    return false;
  }
  double fov_degrees = camera->vertical_fov / kDegree;
  if (!reader.ReadNumber(*object, path, "fov_degrees", kFovRule, false, &fov_degrees)) {
    return false;
  }
  camera->vertical_fov = fov_degrees * kDegree;
  const bool framed = object->contains("view_direction");
  const bool placed = object->contains("position") || object->contains("look_at") ||
                      object->contains("up");
  if (framed && placed) {
    return reader.Fail(path, "give either view_direction (a framed camera) or position, look_at "
                             "and up (an explicit camera), not both");
  }
  if (framed) {
    camera->kind = CameraSettings::Kind::kFramed;
    return ReadDirection(reader, *object, path, "view_direction", false, &camera->view_direction);
  }
  if (!placed) return true;
  // An explicit camera: position and look_at required, up optional.
  const char* unit = "m";
  CameraSettings explicit_camera = *camera;
  explicit_camera.up = Vec3::UnitZ();
  if (!reader.ReadVector<3>(*object, path, "position", unit, true, &explicit_camera.position) ||
      !reader.ReadVector<3>(*object, path, "look_at", unit, true, &explicit_camera.look_at) ||
      !ReadDirection(reader, *object, path, "up", true, &explicit_camera.up)) {
    return false;
  }
  const Vec3 view = explicit_camera.look_at - explicit_camera.position;
  if (!(view.norm() > 0.0)) {
    return reader.Fail(Member(path, "look_at"), "must differ from position (the camera looks "
                                                "from position toward look_at)");
  }
  // Parallel up and view leave the image's roll undefined (1e-6 rad is far below any real use).
  if (view.normalized().cross(explicit_camera.up).norm() < 1e-6) {
    return reader.Fail(Member(path, "up"), "must not be parallel to look_at - position");
  }
  explicit_camera.kind = CameraSettings::Kind::kExplicit;
  *camera = explicit_camera;
  return true;
}

bool ParseKeyLight(Reader& reader, const json& render, const std::string& render_path,
                   KeyLight* key) {
  const json* object = nullptr;
  if (!OptionalObject(reader, render, render_path, "key_light", &object)) return false;
  if (!object) return true;
  const std::string path = Member(render_path, "key_light");
  double radius_degrees = key->angular_radius / kDegree;
  if (!reader.CheckFields(*object, path, {"direction", "angular_radius_degrees", "irradiance"}) ||
      !ReadDirection(reader, *object, path, "direction", true, &key->direction) ||
      !reader.ReadNumber(*object, path, "angular_radius_degrees", kAngularRadiusRule, false,
                         &radius_degrees) ||
      !ReadRgb(reader, *object, path, "irradiance", INFINITY, "W/m^2", &key->irradiance)) {
    return false;
  }
  key->angular_radius = radius_degrees * kDegree;
  return true;
}

bool ParseEnvironment(Reader& reader, const json& render, const std::string& render_path,
                      Environment* environment) {
  const json* object = nullptr;
  if (!OptionalObject(reader, render, render_path, "environment", &object)) return false;
  if (!object) return true;
  const std::string path = Member(render_path, "environment");
  return reader.CheckFields(*object, path, {"top", "bottom"}) &&
         ReadRgb(reader, *object, path, "top", INFINITY, "radiance, W sr^-1 m^-2",
                 &environment->top) &&
         ReadRgb(reader, *object, path, "bottom", INFINITY, "radiance, W sr^-1 m^-2",
                 &environment->bottom);
}

bool ParseHairOptics(Reader& reader, const json& render, const std::string& render_path,
                     RenderSettings* settings) {
  const json* object = nullptr;
  if (!OptionalObject(reader, render, render_path, "hair", &object)) return false;
  if (!object) return true;
  const std::string path = Member(render_path, "hair");
  // Eccentricity belongs to the hair type: say so rather than "unknown field".
  if (object->contains("eccentricity")) {
    return reader.Fail(Member(path, "eccentricity"),
                       "not a render setting: the fibre's eccentricity is the hairstyle's own "
                       "(hair.origin), one number for mechanics and optics; for .hair files use "
                       "ringlet render --eccentricity");
  }
  HairOptics& optics = settings->optics;
  double tilt_degrees = optics.cuticle_tilt / kDegree;
  if (!reader.CheckFields(*object, path,
                          {"eumelanin", "pheomelanin", "model", "eta", "longitudinal_roughness",
                           "azimuthal_roughness", "cuticle_tilt_degrees", "water_eta"}) ||
      !reader.ReadNumber(*object, path, "eumelanin", kMelaninRule, false, &settings->eumelanin) ||
      !reader.ReadNumber(*object, path, "pheomelanin", kMelaninRule, false,
                         &settings->pheomelanin) ||
      !reader.ReadNumber(*object, path, "eta", kEtaRule, false, &optics.eta) ||
      !reader.ReadNumber(*object, path, "water_eta", kEtaRule, false, &optics.water_eta) ||
      !reader.ReadNumber(*object, path, "longitudinal_roughness", kRoughnessRule, false,
                         &optics.longitudinal_roughness) ||
      !reader.ReadNumber(*object, path, "azimuthal_roughness", kRoughnessRule, false,
                         &optics.azimuthal_roughness) ||
      !reader.ReadNumber(*object, path, "cuticle_tilt_degrees", kTiltRule, false,
                         &tilt_degrees)) {
    return false;
  }
  optics.cuticle_tilt = tilt_degrees * kDegree;
  std::string model;
  bool present = false;
  const char* expected = "one of \"chiang2016\", \"marschner2003\"";
  if (!ReadName(reader, *object, path, "model", expected, &model, &present)) return false;
  if (present && !ParseHairScatteringModel(model, &optics.model)) {
    return reader.Expected(Member(path, "model"), expected, object->at("model"));
  }
  return true;
}

bool ParseRenderObject(Reader& reader, const json& object, const std::string& path,
                       RenderSettings* out) {
  if (!object.is_object()) {
    return reader.Expected(path, "an object {\"width\": ..., \"camera\": ..., ...}", object);
  }
  if (!reader.CheckFields(object, path,
                          {"width", "height", "samples_per_pixel", "seed", "max_bounces",
                           "shadows", "exposure", "camera", "key_light", "environment", "hair",
                           "body_albedo", "sampler", "clamp", "denoise"})) {
    return false;
  }
  RenderSettings settings = *out;
  RenderOptions& options = settings.options;
  if (!reader.ReadInteger(object, path, "width", 1, kMaxImageSide, &options.width) ||
      !reader.ReadInteger(object, path, "height", 1, kMaxImageSide, &options.height) ||
      !reader.ReadInteger(object, path, "samples_per_pixel", 1, kMaxSamplesPerPixel,
                          &options.samples_per_pixel) ||
      !reader.ReadUnsigned(object, path, "seed", internal::kMaxExactInteger, "2^53",
                           &options.seed) ||
      !reader.ReadInteger(object, path, "max_bounces", 0, kMaxBounces, &options.max_bounces) ||
      !reader.ReadNumber(object, path, "exposure", kExposureRule, false, &settings.exposure) ||
      !ReadRgb(reader, object, path, "body_albedo", 1.0, "reflectance", &settings.body_albedo) ||
      !reader.ReadNumber(object, path, "clamp", kClampRule, false, &options.clamp) ||
      !reader.ReadBool(object, path, "denoise", &options.denoise)) {
    return false;
  }
  // The products (pixels, camera samples), before anything is rendered (render.h).
  std::string size_error;
  if (!CheckRenderSize(options.width, options.height, options.samples_per_pixel, &size_error)) {
    return reader.Fail(path, size_error);
  }
  std::string shadows;
  bool present = false;
  const char* expected = "one of \"path_traced\", \"fibre_transmittance\"";
  if (!ReadName(reader, object, path, "shadows", expected, &shadows, &present)) return false;
  if (present && !ParseShadowMode(shadows, &options.shadows)) {
    return reader.Expected(Member(path, "shadows"), expected, object.at("shadows"));
  }
  std::string sampler;
  const char* expected_sampler = "one of \"sobol\", \"independent\"";
  if (!ReadName(reader, object, path, "sampler", expected_sampler, &sampler, &present)) {
    return false;
  }
  if (present && !ParseSamplePattern(sampler, &options.pattern)) {
    return reader.Expected(Member(path, "sampler"), expected_sampler, object.at("sampler"));
  }
  if (!ParseCamera(reader, object, path, &settings.camera) ||
      !ParseKeyLight(reader, object, path, &settings.key) ||
      !ParseEnvironment(reader, object, path, &settings.environment) ||
      !ParseHairOptics(reader, object, path, &settings)) {
    return false;
  }
  *out = std::move(settings);
  return true;
}

}  // namespace

KeyLight RenderSettings::DefaultKeyLight() {
  KeyLight key;
  key.direction = Vec3(-0.4, 0.8, 1.0).normalized();
  return key;
}

RenderOptions RenderSettings::DefaultOptions() {
  RenderOptions options;
  options.clamp = kDefaultClamp;
  options.denoise = true;
  return options;
}

bool ParseSamplePattern(const std::string& name, SamplePattern* pattern) {
  if (name == "sobol") {
    *pattern = SamplePattern::kSobol;
  } else if (name == "independent") {
    *pattern = SamplePattern::kIndependent;
  } else {
    return false;
  }
  return true;
}

bool ParseShadowMode(const std::string& name, ShadowMode* mode) {
  if (name == "path_traced") {
    *mode = ShadowMode::kPathTraced;
  } else if (name == "fibre_transmittance") {
    *mode = ShadowMode::kFibreTransmittance;
  } else {
    return false;
  }
  return true;
}

bool ParseHairScatteringModel(const std::string& name, HairScatteringModel* model) {
  if (name == "chiang2016") {
    *model = HairScatteringModel::kChiang2016;
  } else if (name == "marschner2003") {
    *model = HairScatteringModel::kMarschner2003;
  } else {
    return false;
  }
  return true;
}

double HairTypeEccentricity(const HairType& type) {
  // e^2 = 1 - (b/a)^2 with a/b = ellipticity >= 1 (cross_section.h).
  const double ratio = type.ellipticity >= 1.0 ? 1.0 / type.ellipticity : 1.0;
  return std::sqrt(std::max(0.0, 1.0 - ratio * ratio));
}

bool ParseRenderSettings(const nlohmann::json& object, const std::string& path,
                         RenderSettings* settings, std::string* error) {
  Reader reader;
  try {
    if (ParseRenderObject(reader, object, path, settings)) return true;
  } catch (const std::exception& e) {
    reader.Fail(path, std::string("cannot read the render settings: ") + e.what());
  }
  if (error) *error = reader.error();
  return false;
}

bool ParseRenderMember(const nlohmann::json& document, RenderSettings* settings, std::string* error,
                       bool required) {
  if (!document.is_object()) {
    if (error) *error = "expected a JSON object at the top level, got " + internal::Show(document);
    return false;
  }
  const auto it = document.find("render");
  if (it == document.end()) {
    if (required && error) {
      *error =
          "render: missing required field (expected an object of render settings "
          "{\"width\": ..., \"camera\": ..., ...})";
    }
    return !required;
  }
  return ParseRenderSettings(*it, "render", settings, error);
}

bool LoadRenderSettings(const std::string& path, RenderSettings* settings, std::string* error,
                        bool required) {
  std::string text, why;
  if (!ReadFile(path, &text, error)) return false;
  if (!ParseRenderSettingsText(text, settings, &why, required)) {
    if (error) *error = path + ": " + why;
    return false;
  }
  return true;
}

bool ParseRenderSettingsText(const std::string& text, RenderSettings* settings,
                             std::string* error, bool required) {
  json document;
  return internal::ParseJsonText(text, &document, error) &&
         ParseRenderMember(document, settings, error, required);
}

Eigen::AlignedBox3d FramingBox(const HairCurves* hair, const Body* body) {
  Eigen::AlignedBox3d box;  // empty
  if (hair) {
    for (const Vec3f& p : hair->points) box.extend(p.cast<double>());
  }
  if (body) {
    if (box.isEmpty()) return body->Bounds();
    if (const Sphere* head = body->FindSphere("head")) {
      box.extend(head->center - Vec3::Constant(head->radius));
      box.extend(head->center + Vec3::Constant(head->radius));
    }
    // A mesh body's head (examples/bodies/head.json): its mesh named "head" (face, ears, neck).
    for (const TriangleMesh& mesh : body->meshes()) {
      if (mesh.name() != "head") continue;
      for (const Vec3& v : mesh.vertices()) box.extend(v);
    }
  }
  return box;
}

bool MakeRenderScene(const RenderSettings& settings, const HairCurves* hair,
                     std::shared_ptr<const Body> body, double eccentricity,
                     std::uint64_t orientation_seed, RenderScene* scene, std::string* error) {
  const RenderSettings& s = settings;
  const bool has_hair = hair && hair->NumStrands() > 0;
  RenderScene made;
  if (has_hair) {
    made.hair = hair;
    HairOptics optics = s.optics;
    optics.eccentricity = eccentricity;
    optics.sigma_a = AbsorptionFromMelanin(s.eumelanin, s.pheomelanin);
    const std::string why = CheckHairOptics(optics);
    if (!why.empty()) {
      *error = "hair optics: " + why;
      return false;
    }
    made.fibre = std::make_shared<HairBsdf>(optics);
  }
  made.body = std::move(body);
  if (!has_hair && !made.body) {
    *error = "nothing to render: no strands and no body";
    return false;
  }
  made.body_albedo = s.body_albedo;
  made.orientation_seed = orientation_seed;
  made.key = s.key;
  made.environment = s.environment;
  const double aspect = static_cast<double>(s.options.width) / s.options.height;
  if (s.camera.kind == CameraSettings::Kind::kFramed) {
    const Eigen::AlignedBox3d box = FramingBox(hair, made.body.get());
    made.camera = FrameCamera(box, s.camera.view_direction, s.camera.vertical_fov, aspect);
  } else {
    made.camera.position = s.camera.position;
    made.camera.look_at = s.camera.look_at;
    made.camera.up = s.camera.up;
    made.camera.vertical_fov = s.camera.vertical_fov;
  }
  *scene = std::move(made);
  return true;
}

void SetMelaninColours(const RenderSettings& settings, HairCurves* curves) {
  const Vec3f colour = MelaninDisplayColour(settings.eumelanin, settings.pheomelanin).cast<float>();
  curves->colors.assign(curves->point_counts.size(), colour);
}

}  // namespace ringlet
