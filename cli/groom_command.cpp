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

// The files of a groom, by format name (--formats).
struct OutputFile {
  const char* format;
  const char* name;
};
constexpr OutputFile kOutputs[] = {
    {"hair", "strands.hair"},   // Cem Yuksel's binary hair format
    {"usda", "strands.usda"},   // USD text, BasisCurves
    {"obj", "strands.obj"},     // OBJ polylines
    {"json", "masters.json"},   // the solved master strands and the summary
};

struct GroomArgs {
  std::string hairstyle_path;
  std::string output_dir;
  std::string formats = "hair,usda,obj,json";
  bool force = false;
  bool quiet = false;
  int threads = 0;
  double hair_units_per_metre = 1.0;
  bool render = false;  // also write render.png
  int spp = 0;          // render overrides; 0 = the file's setting
  int width = 0;
  int height = 0;
};

// The image of --render, next to the other files.
constexpr const char* kRenderName = "render.png";

// "hair,usda" -> {"hair", "usda"}; unknown names are an error naming the valid ones.
bool ParseFormats(const std::string& text, std::set<std::string>* formats, std::string* error) {
  std::stringstream stream(text);
  std::string item;
  std::string valid;
  for (const OutputFile& o : kOutputs) valid += std::string(valid.empty() ? "" : ", ") + o.format;
  while (std::getline(stream, item, ',')) {
    bool known = false;
    for (const OutputFile& o : kOutputs) known = known || item == o.format;
    if (!known) {
      *error = "--formats: unknown format \"" + item + "\" (expected a comma-separated list of " +
               valid + ")";
      return false;
    }
    formats->insert(item);
  }
  if (formats->empty()) {
    *error = "--formats: expected at least one of " + valid;
    return false;
  }
  return true;
}

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
  if (!ParseFormats(args.formats, &formats, &error)) {
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
  if (args.spp) render_settings.options.samples_per_pixel = args.spp;
  if (args.width) render_settings.options.width = args.width;
  if (args.height) render_settings.options.height = args.height;
  if (!args.render && (args.spp || args.width || args.height)) {
    PrintError(std::string(args.spp ? "--spp" : args.width ? "--width" : "--height") +
               ": only with --render");
    return kExitBadInput;
  }
  std::vector<std::string> names;
  for (const OutputFile& o : kOutputs) {
    if (formats.count(o.format)) names.push_back(o.name);
  }
  if (args.render) names.push_back(kRenderName);
  if (!CheckOutputDirectory(args.output_dir, names, args.force, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  HairFileOptions hair_options;
  hair_options.units_per_metre = args.hair_units_per_metre;
  if (!hair_options.IsValid(&error)) {
    PrintError("--hair-units-per-metre: " + error);
    return kExitBadInput;
  }

  const auto start = std::chrono::steady_clock::now();
  Groom groom;
  if (!GroomWithProgress(style, args.threads, args.quiet, &groom, &error)) {
    PrintError(args.hairstyle_path + ": " + error);
    return kExitBadInput;
  }
  // --render: the image is rendered before any file is written, so that a failure writes
  // nothing.
  Image image;
  RenderStats render_stats;
  if (args.render) {
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
  for (const OutputFile& o : kOutputs) {
    if (!formats.count(o.format)) continue;
    std::string contents;
    bool ok = true;
    const std::string format = o.format;
    StrandFormat strand_format;
    if (StrandFormatFromPath(o.name, &strand_format, nullptr)) {
      ok = EncodeStrands(groom.strands, strand_format, hair_options, &contents, &error);
    } else {
      contents = MastersJson(groom, SecondsSince(start));
    }
    if (!ok) {
      PrintError(std::string(o.name) + ": " + error);
      return kExitBadInput;
    }
    files.emplace_back(o.name, std::move(contents));
  }
  if (!WriteOutputFiles(args.output_dir, files, args.force, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  const std::string image_path = (std::filesystem::path(args.output_dir) / kRenderName).string();
  if (args.render &&
      !WriteJobImage(image_path, image, render_settings.exposure, args.force, &error)) {
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
    if (args.render) {
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
      "contact, wisps around them; writes strands.hair, strands.usda, strands.obj and "
      "masters.json into the output directory. Exit code 0 when every master converged to a "
      "stable equilibrium, 2 when some did not (files are still written), 1 on bad usage or "
      "input (nothing is written).");
  app->add_option("hairstyle", args->hairstyle_path,
                  "Hairstyle file (JSON, see docs/hairstyle-format.md)")
      ->required();
  app->add_option("-o,--output", args->output_dir, "Output directory (created if missing)")
      ->required();
  app->add_option("--formats", args->formats,
                  "Comma-separated files to write: hair, usda, obj, json (default: all)");
  app->add_option("--hair-units-per-metre", args->hair_units_per_metre,
                  "Length unit of the .hair file per metre (default 1: metres; 100: cm)");
  app->add_flag("--force", args->force, "Overwrite existing output files");
  app->add_option("--threads", args->threads,
                  "Worker threads (default 0: all cores); results do not depend on it")
      ->check(CLI::Range(0, 1024));
  app->add_flag("--render", args->render,
                "Also render the groom (hair and body) into render.png with the file's \"render\" "
                "settings (docs/hairstyle-format.md)");
  app->add_option("--spp", args->spp, "With --render: samples per pixel (default: the file's)")
      ->check(CLI::Range(1, 1 << 20));
  app->add_option("--width", args->width, "With --render: image width in pixels")
      ->check(CLI::Range(1, 16384));
  app->add_option("--height", args->height, "With --render: image height in pixels")
      ->check(CLI::Range(1, 16384));
  app->add_flag("-q,--quiet", args->quiet,
                "Print no summary, progress or warning (errors still go to stderr)");
  return Command{app, [args] { return RunGroom(*args); }};
}

}  // namespace ringlet::cli
