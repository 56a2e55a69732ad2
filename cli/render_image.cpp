// Rendering from the command line (render_image.h).
#include "render_image.h"

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "format.h"
#include "progress.h"
#include "ringlet/atomic_file.h"
#include "ringlet/png_image.h"
#include "ringlet/render_json.h"

namespace ringlet::cli {

RenderJob HairstyleRenderJob(const Hairstyle& style, const HairCurves* strands,
                             const RenderSettings& settings, int threads, bool quiet) {
  RenderJob job;
  job.hair = strands;
  job.body = style.body;
  job.eccentricity = HairTypeEccentricity(style.hair_type);
  job.orientation_seed = style.seed;
  job.settings = settings;
  job.threads = threads;
  job.quiet = quiet;
  return job;
}

bool CheckImagePath(const std::string& path, bool force, std::string* error) {
  namespace fs = std::filesystem;
  std::string extension = fs::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension != ".png") {
    *error = "--output: expected a .png file name, got \"" + path + "\"";
    return false;
  }
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (fs::is_directory(status)) {
    *error = path + ": is a directory, not a file";
    return false;
  }
  if (fs::exists(status) && !force) {
    *error = path + ": already exists (use --force to overwrite)";
    return false;
  }
  // --force replaces regular files only (not a device, FIFO or symbolic link).
  return CheckReplaceable(path, true, error);
}

bool RenderJobImage(const RenderJob& job, Image* image, RenderStats* stats, std::string* error) {
  const RenderSettings& s = job.settings;
  RenderScene scene;
  if (!MakeRenderScene(s, job.hair, job.body, job.eccentricity, job.orientation_seed, &scene,
                       error)) {
    return false;
  }
  RenderOptions options = s.options;
  options.threads = job.threads;
  ProgressBar bar("rendering", !job.quiet);
  options.progress = [&bar](long done, long total) { bar.Update(done, total); };
  const bool ok = Render(scene, options, image, stats, error);
  bar.Finish();
  return ok;
}

bool WriteJobImage(const std::string& path, const Image& image, double exposure, bool force,
                   std::string* error) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty() && !std::filesystem::is_directory(parent, ec)) {
    std::filesystem::create_directories(parent, ec);
    if (ec) {
      *error = parent.string() + ": cannot create the directory: " + ec.message();
      return false;
    }
  }
  return WritePng(path, image, exposure, force, error);
}

void PrintRenderSummary(const Image& image, int samples_per_pixel, const RenderStats& stats,
                        const std::string& path) {
  const std::string denoised =
      stats.denoise_seconds > 0.0 ? "denoised in " + FormatSeconds(stats.denoise_seconds) + ", "
                                  : std::string();
  std::printf("rendered %d x %d at %d spp in %s: %lld rays (%lld camera), %lld NaN samples, "
              "%s%d hair segments, %d body primitives -> %s\n",
              image.width, image.height, samples_per_pixel, FormatSeconds(stats.seconds).c_str(),
              static_cast<long long>(stats.rays), static_cast<long long>(stats.camera_rays),
              static_cast<long long>(stats.nan_samples), denoised.c_str(), stats.hair_segments,
              stats.body_primitives, path.c_str());
  std::fflush(stdout);
}

}  // namespace ringlet::cli
