// Render settings in JSON: the "render" object of a hairstyle file, or of a file of its own
// (docs/hairstyle-format.md, "render"), and the RenderScene they describe (MakeRenderScene),
// used by `ringlet render`, `ringlet groom --render` and the Python module.
#pragma once

#include <cstdint>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "ringlet/body.h"
#include "ringlet/fibre_scattering.h"
#include "ringlet/hair_bsdf.h"
#include "ringlet/hair_curves.h"
#include "ringlet/hair_type.h"
#include "ringlet/math.h"
#include "ringlet/render.h"

namespace ringlet {

/// How the camera is placed.
struct CameraSettings {
  enum class Kind : std::uint8_t {
    /// FrameCamera: looking along view_direction at the framed box (render.h), which fills the
    /// frame. The default.
    kFramed,
    /// A pinhole camera at position looking at look_at, up vector up.
    kExplicit,
  };
  Kind kind = Kind::kFramed;
  /// From the camera toward the scene (kFramed; any length > 0). The default looks at the face
  /// (+y, the mannequin's convention: z up, face toward +y) from the front-right, slightly
  /// above: the camera sits at +x, +y, +z of the head.
  Vec3 view_direction = Vec3(-0.5, -1.0, -0.25);
  Vec3 position = Vec3(0.0, 1.0, 0.0);  ///< camera centre (m, kExplicit)
  Vec3 look_at = Vec3::Zero();          ///< point at the image centre (m, kExplicit)
  Vec3 up = Vec3::UnitZ();              ///< up in the image (kExplicit), not parallel to the view
  double vertical_fov = 30.0 * M_PI / 180.0;  ///< full vertical field of view (rad), in (0, pi)
};

/// The firefly clamp of the render settings' default (RenderOptions::clamp; radiance): see
/// docs/rendering.md, "Noise", for how it was chosen and the bias it adds.
inline constexpr double kDefaultClamp = 4.0;

/// Everything a "render" object sets. Eccentricity is not a render setting: it is the
/// hairstyle's (mechanical) one, HairTypeEccentricity below.
struct RenderSettings {
  /// Image size, samples, seed, bounces, shadow mode, sampler, clamp and denoise; threads,
  /// tile_size and progress are not file settings (they keep RenderOptions' defaults and are set
  /// by the command). Defaults: RenderOptions' except clamp = kDefaultClamp and denoise = true
  /// (clean pictures; "clamp": 0 and "denoise": false give the unbiased estimate).
  RenderOptions options = DefaultOptions();
  CameraSettings camera;
  /// The key light: by default from above, in front and to the face's left (-x), so that the
  /// default camera sees the hair lit from the side with soft modelling.
  KeyLight key = DefaultKeyLight();
  Environment environment;
  /// Fibre optics; optics.eccentricity and optics.sigma_a are not read from the file (sigma_a
  /// comes from the melanins below through AbsorptionFromMelanin).
  HairOptics optics;
  double eumelanin = 1.3;    ///< eumelanin concentration (dimensionless, >= 0): brown hair
  double pheomelanin = 0.2;  ///< pheomelanin concentration (dimensionless, >= 0)
  double exposure = 1.0;     ///< linear scale applied to radiance before sRGB encoding, > 0
  Rgb body_albedo = Rgb(0.55, 0.42, 0.36);  ///< Lambertian reflectance of the body in [0, 1]

  static KeyLight DefaultKeyLight();
  static RenderOptions DefaultOptions();
};

/// Parses a render object ({"width": 800, "camera": {...}, "hair": {...}, ...}) into *settings,
/// starting from the defaults of RenderSettings: every field is optional, unknown fields are
/// errors. path is the object's location in its document and prefixes every message ("render"
/// gives "render.camera.fov_degrees: expected a finite number in (0, 180) (degrees), got 200").
/// On failure leaves *settings untouched, writes one line into *error and returns false. Never
/// throws.
bool ParseRenderSettings(const nlohmann::json& object, const std::string& path,
                         RenderSettings* settings, std::string* error);

/// The "render" member of a document (a hairstyle file or a file holding only
/// {"render": {...}}): when absent, the defaults, or an error when required (a settings file
/// without settings is a mistake). Other members are not looked at.
bool ParseRenderMember(const nlohmann::json& document, RenderSettings* settings, std::string* error,
                       bool required = false);

/// Parses the text of a document (a hairstyle or settings file) and its "render" member
/// (ParseRenderMember, required or not). Syntax errors give line and column; messages carry no
/// file name. Never throws.
bool ParseRenderSettingsText(const std::string& text, RenderSettings* settings,
                             std::string* error, bool required = false);

/// Reads the file at path and parses its "render" member (ParseRenderMember, required or not).
/// Syntax errors give line and column; every message starts with the path. Never throws.
bool LoadRenderSettings(const std::string& path, RenderSettings* settings, std::string* error,
                        bool required = false);

/// Gives every strand of curves the display colour of the settings' melanins
/// (MelaninDisplayColour(eumelanin, pheomelanin), one colour per strand), which the exporters
/// write (.hair colour array, USD primvars:displayColor, OBJ vertex colours). The renderer does
/// not read it (it computes absorption from the melanins itself).
void SetMelaninColours(const RenderSettings& settings, HairCurves* curves);

/// "sobol" / "independent" -> SamplePattern; false for other names.
bool ParseSamplePattern(const std::string& name, SamplePattern* pattern);
/// "path_traced" / "fibre_transmittance" -> ShadowMode; false for other names.
bool ParseShadowMode(const std::string& name, ShadowMode* mode);
/// "chiang2016" / "marschner2003" -> HairScatteringModel; false for other names.
bool ParseHairScatteringModel(const std::string& name, HairScatteringModel* model);

/// The box the framed camera looks at: the hair's points together with the body's sphere or
/// mesh named "head" (so that short hair still shows the whole head and face); the body's bounds
/// when there is no hair. Empty when there is neither.
Eigen::AlignedBox3d FramingBox(const HairCurves* hair, const Body* body);

/// The scene of the settings, shared by every front end (`ringlet render`, `ringlet groom
/// --render`, the Python module): hair (may be null or empty) shaded by a HairBsdf from
/// settings.optics with the given eccentricity in [0, 1) and sigma_a = AbsorptionFromMelanin of
/// the settings' melanins, the body (may be null), the key light and environment, and the camera
/// (kFramed: FrameCamera around FramingBox with the image's aspect; kExplicit: as given).
/// scene->hair points to *hair, which must outlive the scene. Returns false with one line in
/// *error for invalid optics ("hair optics: ...") or nothing to render.
bool MakeRenderScene(const RenderSettings& settings, const HairCurves* hair,
                     std::shared_ptr<const Body> body, double eccentricity,
                     std::uint64_t orientation_seed, RenderScene* scene, std::string* error);

/// The eccentricity e = sqrt(1 - b^2/a^2) = sqrt(1 - 1/ellipticity^2) of a hair type's mean
/// section (ellipticity = a/b >= 1, hair_type.h): the one number for the fibre's mechanics and
/// optics (the paper, section 4). 0 for a circular section.
double HairTypeEccentricity(const HairType& type);

}  // namespace ringlet
