// `ringlet render INPUT -o IMAGE.png [...]`: an image of a hairstyle (groomed exactly as
// `ringlet groom` does, then hair and body rendered with the file's "render" settings) or of a
// .hair file (hair only, or with --body); command-line options override the settings
// (docs/hairstyle-format.md, "ringlet render").
//
// Exit codes: 0 the image was written, 2 it was written but some master of the hairstyle did not
// reach a stable equilibrium (as `ringlet groom`), 1 bad usage or input (nothing is written).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>

#include "commands.h"
#include "format.h"
#include "outputs.h"
#include "render_image.h"
#include "ringlet/body_json.h"
#include "ringlet/hair_file.h"
#include "ringlet/hairstyle.h"
#include "ringlet/hairstyle_json.h"
#include "ringlet/render_json.h"

namespace ringlet::cli {
namespace {

struct RenderArgs {
  std::string input_path;
  std::string output_path;
  std::string settings_path;  // --settings: a file with a "render" object
  std::string body_path;      // --body, .hair inputs only
  std::string view;           // --view X,Y,Z
  std::string shadows;
  int width = 0, height = 0, spp = 0, max_bounces = 0;
  std::uint64_t seed = 0;
  double eumelanin = 0.0, pheomelanin = 0.0, exposure = 0.0, eccentricity = 0.0;
  double hair_units_per_metre = 1.0;
  double clamp = 0.0;
  std::string sampler;
  int denoise = -1;  // --denoise 1, --no-denoise 0, -1 = the settings'
  int threads = 0;
  bool force = false;
  bool quiet = false;
  // The options, to know which were given (an override) and which keep the file's setting.
  CLI::Option *width_option = nullptr, *height_option = nullptr, *spp_option = nullptr,
              *seed_option = nullptr, *bounces_option = nullptr, *shadows_option = nullptr,
              *eumelanin_option = nullptr, *pheomelanin_option = nullptr,
              *exposure_option = nullptr, *view_option = nullptr, *eccentricity_option = nullptr,
              *clamp_option = nullptr, *sampler_option = nullptr;
};

// "X,Y,Z" -> a non-zero vector of finite numbers.
bool ParseView(const std::string& text, Vec3* view) {
  std::stringstream stream(text);
  std::string item;
  int n = 0;
  while (std::getline(stream, item, ',')) {
    if (n == 3) return false;
    try {
      size_t used = 0;
      (*view)(n++) = std::stod(item, &used);
      if (used != item.size()) return false;
    } catch (const std::exception&) {
      return false;
    }
  }
  return n == 3 && view->allFinite() && view->norm() > 0.0;
}

// Lower-case extension of a path (".json"), empty when it has none.
std::string Extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension;
}

// Command-line options over the file's settings.
bool ApplyOverrides(const RenderArgs& args, RenderSettings* s, std::string* error) {
  if (args.width_option->count()) s->options.width = args.width;
  if (args.height_option->count()) s->options.height = args.height;
  if (args.spp_option->count()) s->options.samples_per_pixel = args.spp;
  if (args.seed_option->count()) s->options.seed = args.seed;
  if (args.bounces_option->count()) s->options.max_bounces = args.max_bounces;
  if (args.shadows_option->count()) ParseShadowMode(args.shadows, &s->options.shadows);
  if (args.eumelanin_option->count()) s->eumelanin = args.eumelanin;
  if (args.pheomelanin_option->count()) s->pheomelanin = args.pheomelanin;
  if (args.exposure_option->count()) s->exposure = args.exposure;
  if (args.clamp_option->count()) s->options.clamp = args.clamp;
  if (args.sampler_option->count()) ParseSamplePattern(args.sampler, &s->options.pattern);
  if (args.denoise >= 0) s->options.denoise = args.denoise == 1;
  if (args.view_option->count()) {
    Vec3 view;
    if (!ParseView(args.view, &view)) {
      *error = "--view: expected a non-zero direction X,Y,Z (three finite numbers), got \"" +
               args.view + "\"";
      return false;
    }
    s->camera.kind = CameraSettings::Kind::kFramed;
    s->camera.view_direction = view;
  }
  return true;
}

int RunRender(const RenderArgs& args) {
  std::string error;
  const std::string extension = Extension(args.input_path);
  const bool is_hairstyle = extension == ".json";
  if (!is_hairstyle && extension != ".hair") {
    PrintError(args.input_path + ": unknown extension \"" + extension +
               "\" (expected a hairstyle .json or a .hair file)");
    return kExitBadInput;
  }
  if (is_hairstyle && !args.body_path.empty()) {
    PrintError("--body: only for .hair inputs (a hairstyle file names its own body)");
    return kExitBadInput;
  }
  if (!CheckImagePath(args.output_path, args.force, &error)) {
    PrintError(error);
    return kExitBadInput;
  }

  // Settings: defaults < the hairstyle's "render" object < --settings < options.
  RenderSettings settings;
  if (is_hairstyle && !LoadRenderSettings(args.input_path, &settings, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  if (!args.settings_path.empty() &&
      !LoadRenderSettings(args.settings_path, &settings, &error, /*required=*/true)) {
    PrintError(error);
    return kExitBadInput;
  }
  if (!ApplyOverrides(args, &settings, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  if (!CheckRenderSize(settings.options.width, settings.options.height,
                       settings.options.samples_per_pixel, &error)) {
    PrintError("--width, --height, --spp (or the settings): " + error);
    return kExitBadInput;
  }

  RenderJob job;
  job.settings = settings;
  job.threads = args.threads;
  job.quiet = args.quiet;
  Hairstyle style;
  Groom groom;
  HairCurves curves;
  bool all_good = true;
  if (is_hairstyle) {
    if (!LoadHairstyle(args.input_path, &style, &error)) {
      PrintError(error);
      return kExitBadInput;
    }
    const auto start = std::chrono::steady_clock::now();
    if (!GroomWithProgress(style, args.threads, args.quiet, &groom, &error)) {
      PrintError(args.input_path + ": " + error);
      return kExitBadInput;
    }
    const GroomSummary& g = groom.summary;
    all_good = g.unconverged == 0 && g.unstable == 0;
    if (!args.quiet) {
      std::printf("groomed %d masters (%d converged, %d unconverged, %d unstable), %d strands, "
                  "%d points in %s\n",
                  g.masters, g.converged, g.unconverged, g.unstable, g.strands, g.points,
                  FormatSeconds(SecondsSince(start)).c_str());
    }
    job.hair = &groom.strands;
    job.body = style.body;
    job.eccentricity = HairTypeEccentricity(style.hair_type);
    job.orientation_seed = style.seed;
  } else {
    HairFileOptions hair_options;
    hair_options.units_per_metre = args.hair_units_per_metre;
    if (!hair_options.IsValid(&error)) {
      PrintError("--hair-units-per-metre: " + error);
      return kExitBadInput;
    }
    if (!ReadHairFile(args.input_path, &curves, &error, args.hair_units_per_metre)) {
      PrintError(error);
      return kExitBadInput;
    }
    job.hair = &curves;
    if (!args.body_path.empty()) {
      auto body = std::make_shared<Body>();
      if (!LoadBody(args.body_path, body.get(), &error)) {
        PrintError("--body: " + error);
        return kExitBadInput;
      }
      job.body = std::move(body);
    }
  }
  if (args.eccentricity_option->count()) job.eccentricity = args.eccentricity;

  Image image;
  RenderStats stats;
  if (!RenderJobImage(job, &image, &stats, &error)) {
    PrintError(args.input_path + ": render: " + error);
    return kExitBadInput;
  }
  if (!WriteJobImage(args.output_path, image, settings.exposure, args.force, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  if (!args.quiet) {
    PrintRenderSummary(image, settings.options.samples_per_pixel, stats, args.output_path);
    if (stats.nan_samples > 0) {
      PrintWarning(Format("%lld samples were NaN or infinite and were discarded",
                          static_cast<long long>(stats.nan_samples)));
    }
    if (!all_good) {
      const GroomSummary& g = groom.summary;
      PrintWarning(Format("%d of %d masters did not reach a stable equilibrium",
                          g.unconverged + g.unstable, g.masters));
    }
  }
  return all_good ? kExitSuccess : kExitUnsolved;
}

}  // namespace

Command AddRenderCommand(CLI::App* parent) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* app = parent->add_subcommand(
      "render",
      "Render a hairstyle (groomed as by 'ringlet groom', with its body) or a .hair file into a "
      "PNG image, with the hairstyle's \"render\" settings (docs/hairstyle-format.md) and the "
      "options below over them. Exit code 0 when the image was written, 2 when it was written "
      "but some master did not reach a stable equilibrium, 1 on bad usage or input (nothing is "
      "written).");
  app->add_option("input", args->input_path,
                  "A hairstyle file (.json, docs/hairstyle-format.md) or a .hair file")
      ->required();
  app->add_option("-o,--output", args->output_path, "Output image (.png)")->required();
  args->width_option = app->add_option("--width", args->width, "Image width (pixels)")
                           ->check(CLI::Range(1, 16384));
  args->height_option = app->add_option("--height", args->height, "Image height (pixels)")
                            ->check(CLI::Range(1, 16384));
  args->spp_option = app->add_option("--spp", args->spp, "Samples per pixel")
                         ->check(CLI::Range(1, 1 << 20));
  // CLI11 would read "-1" into an unsigned integer as 2^64 - 1: only digits are accepted, and
  // only up to 2^53, the limit of the render settings' "seed".
  args->seed_option =
      app->add_option("--seed", args->seed,
                      "Sampling seed, an integer from 0 to 2^53: same seed, same image on any "
                      "thread count")
          ->check(CLI::Validator(
              [](std::string& text) {
                const bool digits = !text.empty() && text.size() <= 16 &&
                                    std::all_of(text.begin(), text.end(),
                                                [](char c) { return c >= '0' && c <= '9'; });
                if (digits && std::stoull(text) <= (std::uint64_t{1} << 53)) return std::string();
                return "expected an integer between 0 and 2^53 (9007199254740992), got \"" + text +
                       "\"";
              },
              "UINT"));
  args->bounces_option = app->add_option("--max-bounces", args->max_bounces,
                                         "Scattering events after the first hit (path_traced)")
                             ->check(CLI::Range(0, 1000));
  args->shadows_option =
      app->add_option("--shadows", args->shadows,
                      "path_traced (default, multiple scattering) or fibre_transmittance "
                      "(direct light through fibres, fast preview)")
          ->check(CLI::IsMember({"path_traced", "fibre_transmittance"}));
  args->eumelanin_option =
      app->add_option("--eumelanin", args->eumelanin,
                      "Eumelanin concentration (black ~8, brown ~1.3, blonde ~0.3)")
          ->check(CLI::Range(0.0, 1e6));
  args->pheomelanin_option =
      app->add_option("--pheomelanin", args->pheomelanin, "Pheomelanin concentration (red ~1-3)")
          ->check(CLI::Range(0.0, 1e6));
  args->exposure_option =
      app->add_option("--exposure", args->exposure, "Linear scale of radiance before sRGB")
          ->check(CLI::PositiveNumber);
  args->clamp_option =
      app->add_option("--clamp", args->clamp,
                      "Firefly clamp of indirect light (radiance; 0 = off, unbiased; default " +
                          std::to_string(kDefaultClamp).substr(0, 3) + ")")
          ->check(CLI::Range(0.0, 1e30));
  args->sampler_option =
      app->add_option("--sampler", args->sampler,
                      "sobol (default, stratified) or independent (random numbers)")
          ->check(CLI::IsMember({"sobol", "independent"}));
  app->add_flag_function(
      "--denoise,!--no-denoise",
      [args](std::int64_t count) { args->denoise = count > 0 ? 1 : 0; },
      "Denoise the image (the default) or not (--no-denoise: the unbiased estimate with "
      "--clamp 0)");
  args->view_option = app->add_option(
      "--view", args->view,
      "Framed camera looking along X,Y,Z (from the camera toward the scene; z up, face +y)");
  app->add_option("--settings", args->settings_path,
                  "A JSON file whose \"render\" object is applied over the input's");
  app->add_option("--body", args->body_path, "Body file (JSON, docs/body.md); .hair inputs only");
  args->eccentricity_option =
      app->add_option("--eccentricity", args->eccentricity,
                      "Fibre eccentricity in [0, 1) (default: the hairstyle's; 0 for .hair)")
          ->check(CLI::Range(0.0, 0.999999));
  app->add_option("--hair-units-per-metre", args->hair_units_per_metre,
                  "Length unit of a .hair input per metre (default 1: metres; 100: cm)");
  app->add_option("--threads", args->threads,
                  "Worker threads (default 0: all cores); the image does not depend on it")
      ->check(CLI::Range(0, 1024));
  app->add_flag("--force", args->force, "Overwrite an existing image");
  app->add_flag("-q,--quiet", args->quiet,
                "Print no summary, progress or warning (errors still go to stderr)");
  return Command{app, [args] { return RunRender(*args); }};
}

}  // namespace ringlet::cli
