// ringlet's offline renderer: hair curves and the body ray traced with Embree 3, fibres shaded by
// a FibreScattering model (Marschner et al. 2003 / Chiang et al. 2016, hair_bsdf.h), lit by a key
// light and an environment; tiles in parallel, deterministic for a seed whatever the threads.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "ringlet/body.h"
#include "ringlet/fibre_scattering.h"
#include "ringlet/hair_curves.h"
#include "ringlet/math.h"

namespace ringlet {

/// A linear-RGB image (radiance, W sr^-1 m^-2 per channel in the renderer's units), row-major,
/// top row first.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<Eigen::Vector3f> pixels;  ///< width * height values

  Eigen::Vector3f& At(int x, int y) { return pixels[static_cast<size_t>(y) * width + x]; }
  const Eigen::Vector3f& At(int x, int y) const {
    return pixels[static_cast<size_t>(y) * width + x];
  }
};

/// A pinhole camera (world coordinates, m).
struct Camera {
  Vec3 position = Vec3(0.0, -1.0, 0.0);
  Vec3 look_at = Vec3::Zero();
  Vec3 up = Vec3::UnitZ();
  double vertical_fov = 0.5;  ///< full vertical field of view (rad), in (0, pi)
};

/// A camera looking along view_direction (from the camera toward the scene) at the centre of the
/// box, far enough that the box's bounding sphere fills the frame (vertical_fov, aspect = width /
/// height) with a small margin; up is world +z.
Camera FrameCamera(const Eigen::AlignedBox3d& box, const Vec3& view_direction,
                   double vertical_fov, double aspect);

/// The key light: a distant disk (the sun, a studio spot far away) of angular radius
/// angular_radius around direction (toward the light), giving irradiance `irradiance` (W/m^2 per
/// channel) on a surface facing it. Its radiance is uniform over the disk, irradiance / (pi
/// sin^2(angular_radius)) (the projected solid angle of a spherical cap is pi sin^2 r, so a
/// surface tilted by theta from direction receives exactly irradiance cos(theta) while the
/// whole disk is above its horizon). Irradiance 0 turns the key light off.
struct KeyLight {
  Vec3 direction = Vec3(-0.5, -1.0, 1.0).normalized();  ///< toward the light, finite, non-zero
  double angular_radius = 0.02;  ///< rad, in (0, pi/2)
  Rgb irradiance = Rgb(3.0, 3.0, 3.0);  ///< W/m^2 per channel, finite, >= 0
};

/// The environment: radiance arriving from infinity, blended from `bottom` (straight down) to
/// `top` (straight up) linearly in the z of the direction. top = bottom = 1 is the white furnace.
struct Environment {
  Rgb top = Rgb(0.35, 0.38, 0.45);     ///< W sr^-1 m^-2 per channel, finite, >= 0
  Rgb bottom = Rgb(0.12, 0.11, 0.10);  ///< W sr^-1 m^-2 per channel, finite, >= 0
};

/// How shadow rays treat hair.
enum class ShadowMode : std::uint8_t {
  /// Fibres block shadow rays; light through hair arrives by path-traced scattering (TT lobes)
  /// over up to max_bounces bounces. Unbiased for the model: the default.
  kPathTraced,
  /// Direct lighting only (no bounces); a shadow ray crossing a fibre is multiplied by the
  /// fibre's FibreScattering::Transmittance. Fast preview in the spirit of deep shadow maps
  /// (Lokovic & Veach 2000), without multiple scattering.
  kFibreTransmittance,
};

/// Largest |coordinate| (m) of anything Render traces: hair points and widths, the body's
/// bounds, the camera's position and look-at point. Embree works in single precision and
/// refuses rays beyond about 1.8e18; 10 km keeps every ray far inside that and still holds any
/// scene of hair (docs/robustness.md).
inline constexpr double kMaxSceneCoordinate = 1e4;

/// What to render. The pointers must outlive the Render call.
struct RenderScene {
  /// May be null (body only). Strands are Embree round linear curves (cones with round
  /// joints) of radius widths / 2; HairCurves::colors is not used (the fibre model decides).
  const HairCurves* hair = nullptr;
  std::shared_ptr<const FibreScattering> fibre;      ///< required when hair is set
  /// May be null (hair only). Rendered as the exact union of its spheres and meshes: the
  /// smooth-union blend of Body::Create (a contact-distance device) is not shown.
  std::shared_ptr<const Body> body;
  Rgb body_albedo = Rgb(0.55, 0.42, 0.36);           ///< Lambertian body reflectance in [0, 1]
  /// Seed of the per-strand cross-section orientation (elliptic fibres), uniform in [0, pi).
  std::uint64_t orientation_seed = 1;
  Camera camera;
  KeyLight key;
  Environment environment;
};

/// How the numbers of a pixel's samples are drawn.
enum class SamplePattern : std::uint8_t {
  /// Every pair of dimensions (pixel position, light sample, scattering sample, ...) of a pixel's
  /// samples is a shuffled Owen-scrambled 2D Sobol sequence (Burley 2020): the samples of a
  /// pixel are stratified in each pair, as independent as random numbers across pairs and
  /// pixels. The default.
  kSobol,
  /// Independent uniform random numbers for every sample (SplitMix64 streams): the reference.
  kIndependent,
};

/// How to render it.
struct RenderOptions {
  int width = 800;              ///< pixels, >= 1
  int height = 800;             ///< pixels, >= 1
  int samples_per_pixel = 16;   ///< >= 1
  std::uint64_t seed = 1;       ///< same seed, same image, whatever the thread count
  /// Scattering events after the first hit (kPathTraced), >= 0: 0 is direct light only (light
  /// sampling and BSDF sampling at the first hit, weighted by MIS). Russian roulette ends
  /// paths from the third bounce on (unbiased).
  int max_bounces = 16;
  ShadowMode shadows = ShadowMode::kPathTraced;
  int threads = 0;              ///< 0 = all cores
  int tile_size = 32;           ///< pixels per tile side, >= 1
  /// true: each sample at a uniform random point of its pixel (box filter); false: every
  /// sample through the pixel's centre (tests that need to know where rays go).
  bool jitter = true;
  /// How sample numbers are drawn (kSobol: stratified; both are unbiased).
  SamplePattern pattern = SamplePattern::kSobol;
  /// Firefly clamp (radiance, W sr^-1 m^-2 per channel), >= 0; 0 turns it off (unbiased).
  /// Every contribution of indirect light (a path with two or more scattering events: light
  /// reaching a vertex after the first, or a bounce ray escaping to a light) whose largest
  /// channel exceeds clamp is scaled down to it, hue kept. The estimate is then biased low by
  /// the mean of (X - clamp)+ over those contributions X; direct light is never clamped
  /// (docs/rendering.md, "Noise").
  double clamp = 0.0;
  /// After sampling, filter the image with the edge-avoiding a-trous denoiser (denoise.h)
  /// guided by the first hits' albedo, normal, depth and the pixels' variance. Off by default
  /// here (unbiased); the render settings turn it on (render_json.h).
  bool denoise = false;
  /// Called after each finished tile with (tiles done, tiles total), never concurrently; with
  /// passes, the tiles of every pass count (total = tiles x passes).
  std::function<void(long, long)> progress;
  /// Progressive rendering (the studio's render panel): when set, the samples of every pixel
  /// are taken in passes of 1, 1, 2, 4, 8, ... (each pass doubles the samples taken, the last
  /// one is what is left of samples_per_pixel) and this is called after each pass, never
  /// concurrently, with the image so far (each pixel the mean of its samples taken) and the
  /// samples per pixel taken. The final image is bit-identical to a render without passes:
  /// sample s of a pixel has the same random stream and the per-pixel sums are taken in the same
  /// order.
  std::function<void(const Image&, int)> pass_done;
  /// When not null and set (by another thread), the render stops after the tiles in flight and
  /// Render returns false with the error "cancelled", leaving the image untouched.
  const std::atomic<bool>* cancel = nullptr;
};

/// Most pixels of an image, width x height: 2^26 (8192 x 8192). The image takes 12 bytes per
/// pixel (float RGB, 805 MB at the limit) plus 3 per pixel for the 8-bit PNG rows.
inline constexpr std::int64_t kMaxRenderPixels = std::int64_t{1} << 26;
/// Most camera samples of a render, width x height x samples_per_pixel: 2^30 (e.g. 2048 x 2048
/// at 256 spp). At the ~0.4 million camera samples per second measured on 2 cores for a full
/// head (docs/benchmarks.md, path traced with bounces) that is about 45 minutes.
inline constexpr std::int64_t kMaxRenderSamples = std::int64_t{1} << 30;

/// Checks the products of the image size and sampling against kMaxRenderPixels and
/// kMaxRenderSamples (the sides and the samples per pixel are each >= 1); false with one line
/// naming the fields ("width x height x samples_per_pixel = ... camera samples, more than the
/// limit of 2^30"). Called by Render, the render settings reader and the commands before any
/// work.
bool CheckRenderSize(int width, int height, int samples_per_pixel, std::string* why);

/// What a render did, for summaries: nothing numerical is hidden.
struct RenderStats {
  double seconds = 0.0;              ///< wall time of the whole call (s)
  double build_seconds = 0.0;        ///< of which building the Embree scene (s)
  std::int64_t camera_rays = 0;
  std::int64_t rays = 0;            ///< all rays traced (camera, bounce, shadow)
  std::int64_t nan_samples = 0;     ///< samples discarded because they were NaN or infinite
  double denoise_seconds = 0.0;     ///< of which denoising (s), 0 without
  int hair_segments = 0;            ///< curve segments given to Embree
  int body_primitives = 0;          ///< spheres + triangles given to Embree
};

/// Renders the scene. Returns false with a one-line message in error (Embree failures, invalid
/// options naming the field, coordinates beyond kMaxSceneCoordinate, "cancelled") and leaves
/// image untouched.
bool Render(const RenderScene& scene, const RenderOptions& options, Image* image,
            RenderStats* stats, std::string* error);

/// Per-pixel labels of a view, the ground truth hair reconstruction methods train on
/// (docs/batch.md, "Labels"): one ray through each pixel's centre, its first hit.
struct RenderLabels {
  int width = 0;
  int height = 0;
  /// 1 where the first hit is a hair fibre, 0 elsewhere (body or background); row-major, top
  /// row first, as Image.
  std::vector<std::uint8_t> hair;
  /// Distance (m) of the first hit (hair or body) along the camera's forward axis (z-depth, the
  /// convention of depth maps), 0 where the ray meets nothing.
  std::vector<float> depth;
  /// Hair pixels: the fibre's tangent at the hit, root to tip, projected on the image plane and
  /// normalized, in image axes (x to the right, y up); (0, 0) elsewhere and where the fibre
  /// points along the ray (projected length below 1e-6).
  std::vector<Eigen::Vector2f> direction;
};

/// The labels of the scene's camera for a width x height image (options: width, height and
/// threads are used; the labels do not depend on the threads). Fibres are traced at least
/// min_width_pixels wide: each point's width w becomes max(w, min_width_pixels x the footprint of
/// a pixel at the point's depth z along the camera's forward axis, 2 z tan(fov / 2) / height),
/// so that the mask shows every strand as a line of at least that many pixels, as strand
/// rasterizers draw them (a 70-um fibre covers a few percent of a millimetre-wide pixel and a
/// single ray would mostly miss it); 0 traces the true widths. Checks the scene and options as
/// Render does. Returns false with one line in error.
bool RenderLabelMaps(const RenderScene& scene, const RenderOptions& options,
                     double min_width_pixels, RenderLabels* labels, std::string* error);

}  // namespace ringlet
