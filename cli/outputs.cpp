#include "outputs.h"

#include <CLI/CLI.hpp>
#include <filesystem>
#include <sstream>
#include <system_error>

#include "ringlet/atomic_file.h"
#include "ringlet/obj_export.h"
#include "ringlet/strand_export.h"
#include "ringlet/usd_export.h"

namespace ringlet::cli {

namespace fs = std::filesystem;

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

bool CheckOutputDirectory(const std::string& directory, const std::vector<std::string>& names,
                          bool force, std::string* error) {
  if (directory.empty()) {
    *error = "--output: expected a directory name, got an empty string";
    return false;
  }
  std::error_code ec;
  const fs::file_status status = fs::status(directory, ec);
  if (!fs::exists(status)) return true;
  if (!fs::is_directory(status)) {
    *error = directory + ": exists and is not a directory; give a directory to --output";
    return false;
  }
  for (const std::string& name : names) {
    const fs::path file = fs::path(directory) / name;
    // --force replaces regular files only (not a device, FIFO or symbolic link).
    if (force) {
      if (!CheckReplaceable(file.string(), true, error)) return false;
    } else if (fs::exists(fs::symlink_status(file, ec))) {
      *error = file.string() + ": already exists (use --force to overwrite it)";
      return false;
    }
  }
  return true;
}

bool WriteOutputFiles(const std::string& directory,
                      const std::vector<std::pair<std::string, std::string>>& files, bool force,
                      std::string* error) {
  return WriteFilesAtomically(directory, files, force, error);
}

}  // namespace ringlet::cli

namespace ringlet::cli {

void AddOutputOptions(CLI::App* app, OutputOptions* options, const std::string& what) {
  app->add_option("--formats", options->formats,
                  "Comma-separated files to write: hair, usda, obj, body, json (default: all)");
  app->add_option("--hair-units-per-metre", options->hair_units_per_metre,
                  "Length unit of the .hair files per metre (default 1: metres; 100: cm)");
  app->add_flag("--force", options->force, "Overwrite existing output files");
  app->add_flag("--render", options->render,
                "Also render " + what +
                    " (hair and body) into render.png with the file's \"render\" settings "
                    "(docs/hairstyle-format.md)");
  app->add_option("--spp", options->spp, "With --render: samples per pixel (default: the file's)")
      ->check(CLI::Range(1, 1 << 20));
  app->add_option("--width", options->width, "With --render: image width in pixels")
      ->check(CLI::Range(1, 16384));
  app->add_option("--height", options->height, "With --render: image height in pixels")
      ->check(CLI::Range(1, 16384));
  app->add_flag_function(
      "--denoise,!--no-denoise",
      [options](std::int64_t count) { options->denoise = count > 0 ? 1 : 0; },
      "With --render: denoise the image (default: the file's, on) or not (--no-denoise: the "
      "unbiased estimate, docs/rendering.md)");
  app->add_option("--clamp", options->clamp,
                  "With --render: firefly clamp of indirect light (radiance; 0 = off, unbiased)")
      ->check(CLI::Range(0.0, 1e30));
}

bool CheckOutputOptions(const OutputOptions& options, std::set<std::string>* formats,
                        HairFileOptions* hair_options, std::string* error) {
  std::stringstream stream(options.formats);
  std::string item;
  std::string valid;
  for (const OutputFile& o : kStrandOutputs) {
    valid += std::string(valid.empty() ? "" : ", ") + o.format;
  }
  formats->clear();
  while (std::getline(stream, item, ',')) {
    bool known = false;
    for (const OutputFile& o : kStrandOutputs) known = known || item == o.format;
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
  if (!options.render && (options.spp || options.width || options.height ||
                          options.denoise >= 0 || options.clamp >= 0.0)) {
    *error = std::string(options.spp             ? "--spp"
                         : options.width         ? "--width"
                         : options.height        ? "--height"
                         : options.denoise == 1  ? "--denoise"
                         : options.denoise == 0  ? "--no-denoise"
                                                 : "--clamp") +
             ": only with --render";
    return false;
  }
  hair_options->units_per_metre = options.hair_units_per_metre;
  if (!hair_options->IsValid(error)) {
    *error = "--hair-units-per-metre: " + *error;
    return false;
  }
  return true;
}

void ApplyRenderOverrides(const OutputOptions& options, RenderSettings* settings) {
  if (options.spp) settings->options.samples_per_pixel = options.spp;
  if (options.width) settings->options.width = options.width;
  if (options.height) settings->options.height = options.height;
  if (options.denoise >= 0) settings->options.denoise = options.denoise == 1;
  if (options.clamp >= 0.0) settings->options.clamp = options.clamp;
}

std::vector<std::string> StrandOutputNames(const std::set<std::string>& formats) {
  std::vector<std::string> names;
  for (const OutputFile& o : kStrandOutputs) {
    if (formats.count(o.format)) names.push_back(o.name);
  }
  return names;
}

bool EncodeStrandOutputs(const HairCurves& strands, const RenderSettings& render,
                         const std::set<std::string>& formats,
                         const HairFileOptions& hair_options, const Body* body,
                         const std::function<std::string()>& masters_json,
                         std::vector<std::pair<std::string, std::string>>* files,
                         std::string* error) {
  for (const OutputFile& o : kStrandOutputs) {
    if (!formats.count(o.format)) continue;
    std::string contents;
    bool ok = true;
    const std::string format = o.format;
    StrandFormat strand_format;
    if (format == "body") {
      if (body) EncodeBodyObj(*body, &contents);
    } else if (StrandFormatFromPath(o.name, &strand_format, nullptr)) {
      // strands.hair, .usda, .obj: the library's one code path (the studio's Export uses it too).
      ok = EncodeHairstyleStrands(strands, render, strand_format, hair_options, &contents, error);
    } else {
      contents = masters_json();
    }
    if (!ok) {
      *error = std::string(o.name) + ": " + *error;
      return false;
    }
    files->emplace_back(o.name, std::move(contents));
  }
  return true;
}

}  // namespace ringlet::cli
