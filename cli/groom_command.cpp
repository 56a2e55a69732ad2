// `ringlet groom HAIRSTYLE.json -o OUTDIR/`: a full head of hair from a hairstyle file (paper,
// section 3): master strands solved in parallel with body contact and hull layers, wisps around
// them, written as .hair, .usda, .obj and JSON (docs/hairstyle-format.md, docs/file-formats.md),
// and with --render an image of it (render_image.h).
//
// Exit codes: 0 every master converged to a stable equilibrium, 2 some did not (files are still
// written and the summary says how many), 1 bad usage or input (nothing is written).
#include <CLI/CLI.hpp>
#include <chrono>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "commands.h"
#include "format.h"
#include "outputs.h"
#include "progress.h"
#include "ringlet/atomic_file.h"
#include "ringlet/png_image.h"
#include "ringlet/hair_file.h"
#include "ringlet/hairstyle.h"
#include "ringlet/hairstyle_json.h"
#include "render_image.h"
#include "ringlet/obj_export.h"
#include "ringlet/render_json.h"
#include "ringlet/result_json.h"
#include "ringlet/strand_export.h"
#include "ringlet/styling.h"
#include "ringlet/usd_export.h"

namespace ringlet::cli {
namespace {

struct GroomArgs {
  std::string hairstyle_path;
  std::string output_dir;
  OutputOptions outputs;  // --formats, --hair-units-per-metre, --force, --render, --spp, ...
  bool quiet = false;
  int threads = 0;
};

// masters.json: the result document of the masters (docs/scene-format.md, "Result format") with
// a "groom" object of counts and times.
std::string MastersJson(const Groom& groom, double seconds) {
  std::vector<StrandResult> results;
  results.reserve(groom.solutions.size());
  for (size_t i = 0; i < groom.solutions.size(); ++i) {
    results.push_back(MakeStrandResult(groom.masters.models[i], groom.solutions[i], 1));
  }
  nlohmann::ordered_json document = ResultToJson(results, seconds);
  const GroomSummary& s = groom.summary;
  nlohmann::ordered_json layers = nlohmann::ordered_json::array();
  for (int layer : groom.masters.layers) layers.push_back(layer);
  nlohmann::ordered_json radii = nlohmann::ordered_json::array();
  for (double r : groom.masters.wisp_radii) radii.push_back(r);
  document["groom"] = {{"masters", s.masters},
                       {"strands", s.strands},
                       {"points", s.points},
                       {"converged", s.converged},
                       {"unconverged", s.unconverged},
                       {"unstable", s.unstable},
                       {"iterations", s.iterations},
                       {"max_penetration", s.max_penetration},
                       {"solve_seconds", s.solve_seconds},
                       {"wisp_seconds", s.wisp_seconds},
                       {"children_solved", s.children_solved},
                       {"children_unconverged", s.children_unconverged},
                       {"children_unstable", s.children_unstable},
                       {"children_iterations", s.children_iterations},
                       {"children_max_penetration", s.children_max_penetration},
                       {"children_seconds", s.children_seconds},
                       {"roots", groom.masters.root_summary.message},
                       {"layers", std::move(layers)},
                       {"wisp_radii", std::move(radii)}};
  return document.dump(1) + "\n";
}

int RunGroom(const GroomArgs& args) {
  std::string error;
  std::set<std::string> formats;
  HairFileOptions hair_options;
  if (!CheckOutputOptions(args.outputs, &formats, &hair_options, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  Hairstyle style;
  // A file's styling operations are checked but not applied: groom makes the unstyled hair
  // (`ringlet style` applies them).
  std::vector<StyleOperation> operations;
  if (!LoadHairstyle(args.hairstyle_path, &style, &operations, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  // The file's render settings are checked with or without --render: a mistake in them is
  // found at once (docs/hairstyle-format.md, "render").
  RenderSettings render_settings;
  if (!LoadRenderSettings(args.hairstyle_path, &render_settings, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  ApplyRenderOverrides(args.outputs, &render_settings);
  if (args.outputs.render &&
      !CheckRenderSize(render_settings.options.width, render_settings.options.height,
                       render_settings.options.samples_per_pixel, &error)) {
    PrintError("--width, --height, --spp (or the file's render settings): " + error);
    return kExitBadInput;
  }
  std::vector<std::string> names = StrandOutputNames(formats);
  if (args.outputs.render) names.push_back(kRenderName);
  if (!CheckOutputDirectory(args.output_dir, names, args.outputs.force, &error)) {
    PrintError(error);
    return kExitBadInput;
  }

  const auto start = std::chrono::steady_clock::now();
  Groom groom;
  if (!GroomWithProgress(style, args.threads, args.quiet, &groom, &error)) {
    PrintError(args.hairstyle_path + ": " + error);
    return kExitBadInput;
  }
  // Each strand's colour from the melanins of the file's render settings, so that viewers of the
  // .hair, .usda and .obj files show the hair in its colour (MelaninDisplayColour).
  SetMelaninColours(render_settings, &groom.strands);
  // --render: the image is rendered before any file is written, so that a failure writes
  // nothing.
  Image image;
  RenderStats render_stats;
  if (args.outputs.render) {
    const RenderJob job =
        HairstyleRenderJob(style, &groom.strands, render_settings, args.threads, args.quiet);
    if (!RenderJobImage(job, &image, &render_stats, &error)) {
      PrintError(args.hairstyle_path + ": render: " + error);
      return kExitBadInput;
    }
  }

  // Encode everything first, then write each file atomically: on an encoding error nothing is
  // written.
  const auto write_start = std::chrono::steady_clock::now();
  std::vector<std::pair<std::string, std::string>> files;  // (name, contents)
  if (!EncodeStrandOutputs(
          groom.strands, render_settings, formats, hair_options, style.body.get(),
          [&] { return MastersJson(groom, SecondsSince(start)); }, &files, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  const std::string image_path = (std::filesystem::path(args.output_dir) / kRenderName).string();
  if (args.outputs.render) {
    std::string png;
    if (!EncodePng(image, render_settings.exposure, &png, &error)) {
      PrintError(image_path + ": " + error);
      return kExitBadInput;
    }
    files.emplace_back(kRenderName, std::move(png));
  }
  // All files or none (a failure while renaming says which ones are missing).
  if (!WriteOutputFiles(args.output_dir, files, args.outputs.force, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  const double write_seconds = SecondsSince(write_start);

  const GroomSummary& s = groom.summary;
  const bool all_good = s.unconverged == 0 && s.unstable == 0 && s.children_unconverged == 0 &&
                        s.children_unstable == 0;
  if (!args.quiet) {
    std::printf("%s\n", groom.masters.root_summary.message.c_str());
    std::printf(
        "groomed %d masters (%d converged, %d unconverged, %d unstable; %ld iterations), "
        "%d strands, %d points\n",
        s.masters, s.converged, s.unconverged, s.unstable, s.iterations, s.strands, s.points);
    std::printf("max penetration %.3g mm; solve %s, wisps %s, write %s, total %s -> %s\n",
                s.max_penetration * 1e3, FormatSeconds(s.solve_seconds).c_str(),
                FormatSeconds(s.wisp_seconds).c_str(), FormatSeconds(write_seconds).c_str(),
                FormatSeconds(SecondsSince(start)).c_str(), args.output_dir.c_str());
    if (s.children_solved > 0) {
      std::printf(
          "solved every child strand: %d children (%d unconverged, %d unstable; %ld "
          "iterations), max penetration %.3g mm, %s\n",
          s.children_solved, s.children_unconverged, s.children_unstable, s.children_iterations,
          s.children_max_penetration * 1e3, FormatSeconds(s.children_seconds).c_str());
    }
    if (!operations.empty()) {
      std::printf(
          "the file's %zu styling operations were not applied (unstyled hair; use "
          "`ringlet style` to apply them)\n",
          operations.size());
    }
    if (args.outputs.render) {
      PrintRenderSummary(image, render_settings.options.samples_per_pixel, render_stats,
                         image_path);
    }
    std::fflush(stdout);  // the summary before the warning, also when both go to one pipe
    if (s.unconverged + s.unstable > 0) {
      PrintWarning(Format("%d of %d masters did not reach a stable equilibrium (see masters.json)",
                          s.unconverged + s.unstable, s.masters));
    }
    if (s.children_unconverged + s.children_unstable > 0) {
      PrintWarning(Format("%d of %d solved children did not reach a stable equilibrium",
                          s.children_unconverged + s.children_unstable, s.children_solved));
    }
  }
  return all_good ? kExitSuccess : kExitUnsolved;
}

}  // namespace

bool GroomWithProgress(const Hairstyle& style, int threads, bool quiet, Groom* groom,
                       std::string* error) {
  ProgressBar bar("solving masters", !quiet);
  BatchOptions batch;
  batch.threads = threads;
  batch.progress = [&bar](int done, int total) { bar.Update(done, total); };
  return GroomHairstyle(style, batch, groom, error);
}

Command AddGroomCommand(CLI::App* parent) {
  auto args = std::make_shared<GroomArgs>();
  CLI::App* app = parent->add_subcommand(
      "groom",
      "Groom a full head of hair from a hairstyle file: master strands solved with body "
      "contact, wisps around them; writes strands.hair, strands.usda, strands.obj, body.obj and "
      "masters.json into the output directory. Exit code 0 when every master converged to a "
      "stable equilibrium, 2 when some did not (files are still written), 1 on bad usage or "
      "input (nothing is written).");
  app->add_option("hairstyle", args->hairstyle_path,
                  "Hairstyle file (JSON, see docs/hairstyle-format.md)")
      ->required();
  app->add_option("-o,--output", args->output_dir, "Output directory (created if missing)")
      ->required();
  AddOutputOptions(app, &args->outputs, "the groom");
  app->add_option("--threads", args->threads,
                  "Worker threads (default 0: all cores); results do not depend on it")
      ->check(CLI::Range(0, 1024));
  app->add_flag("-q,--quiet", args->quiet,
                "Print no summary, progress or warning (errors still go to stderr)");
  return Command{app, [args] { return RunGroom(*args); }};
}

}  // namespace ringlet::cli
