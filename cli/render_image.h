// Rendering from the command line, shared by `ringlet render` and `ringlet groom --render`:
// render settings + hair + body -> RenderScene and RenderOptions -> Render (with a progress bar)
// -> PNG, and the summary line.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "ringlet/body.h"
#include "ringlet/hair_curves.h"
#include "ringlet/hairstyle.h"
#include "ringlet/render.h"
#include "ringlet/render_json.h"

namespace ringlet::cli {

/// What to render and how.
struct RenderJob {
  const HairCurves* hair = nullptr;   ///< may be null or empty (body only)
  std::shared_ptr<const Body> body;   ///< may be null (hair only)
  /// The fibres' cross-section eccentricity in [0, 1): the hairstyle's (HairTypeEccentricity)
  /// or --eccentricity for .hair files.
  double eccentricity = 0.0;
  std::uint64_t orientation_seed = 1;  ///< RenderScene::orientation_seed
  RenderSettings settings;
  int threads = 0;      ///< 0 = all cores
  bool quiet = false;   ///< no progress bar
};

/// The job of a groomed or styled hairstyle's strands: its body, its hair type's eccentricity
/// (HairTypeEccentricity), its seed for the fibres' fallback orientation.
RenderJob HairstyleRenderJob(const Hairstyle& style, const HairCurves* strands,
                             const RenderSettings& settings, int threads, bool quiet);

/// Checks an image output path before any work: a ".png" name, not a directory, and not an
/// existing file unless force. On failure *error gets one line.
bool CheckImagePath(const std::string& path, bool force, std::string* error);

/// Builds the scene (MakeRenderScene: camera from the settings, HairBsdf from the optics with
/// the job's eccentricity and AbsorptionFromMelanin) and renders it, drawing a progress bar over the tiles
/// unless quiet. Returns false with one line in *error (invalid optics, nothing to render,
/// Render's own errors).
bool RenderJobImage(const RenderJob& job, Image* image, RenderStats* stats, std::string* error);

/// Writes the image as PNG with the settings' exposure (creating missing parent directories),
/// replacing an existing file only when force. On failure *error gets one line.
bool WriteJobImage(const std::string& path, const Image& image, double exposure, bool force,
                   std::string* error);

/// "rendered 64 x 64 at 2 spp in 1.23 s: 123,456 rays, 0 NaN samples, denoised in 0.01 s, ...
/// -> out.png" on stdout (the denoising time only when the image was denoised).
void PrintRenderSummary(const Image& image, int samples_per_pixel, const RenderStats& stats,
                        const std::string& path);

}  // namespace ringlet::cli
