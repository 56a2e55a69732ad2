// Rendering from the command line (render_image.h).
#include "render_image.h"

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "format.h"
#include "progress.h"
#include "ringlet/atomic_file.h"
#include "ringlet/hair_bsdf.h"
#include "ringlet/png_image.h"

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
  const bool has_hair = job.hair && job.hair->NumStrands() > 0;
  RenderScene scene;
  if (has_hair) {
    scene.hair = job.hair;
    HairOptics optics = s.optics;
    optics.eccentricity = job.eccentricity;
    optics.sigma_a = AbsorptionFromMelanin(s.eumelanin, s.pheomelanin);
    const std::string why = CheckHairOptics(optics);
    if (!why.empty()) {
      *error = "hair optics: " + why;
      return false;
    }
    scene.fibre = std::make_shared<HairBsdf>(optics);
  }
  scene.body = job.body;
  if (!has_hair && !scene.body) {
    *error = "nothing to render: no strands and no body";
    return false;
  }
  scene.body_albedo = s.body_albedo;
  scene.orientation_seed = job.orientation_seed;
  scene.key = s.key;
  scene.environment = s.environment;
  const double aspect = static_cast<double>(s.options.width) / s.options.height;
  if (s.camera.kind == CameraSettings::Kind::kFramed) {
    const Eigen::AlignedBox3d box = FramingBox(job.hair, job.body.get());
    scene.camera = FrameCamera(box, s.camera.view_direction, s.camera.vertical_fov, aspect);
  } else {
    scene.camera.position = s.camera.position;
    scene.camera.look_at = s.camera.look_at;
    scene.camera.up = s.camera.up;
    scene.camera.vertical_fov = s.camera.vertical_fov;
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
  std::printf("rendered %d x %d at %d spp in %s: %lld rays (%lld camera), %lld NaN samples, "
              "%d hair segments, %d body primitives -> %s\n",
              image.width, image.height, samples_per_pixel, FormatSeconds(stats.seconds).c_str(),
              static_cast<long long>(stats.rays), static_cast<long long>(stats.camera_rays),
              static_cast<long long>(stats.nan_samples), stats.hair_segments,
              stats.body_primitives, path.c_str());
  std::fflush(stdout);
}

}  // namespace ringlet::cli
