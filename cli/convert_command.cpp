// `ringlet convert IN OUT`: hair strands from any format ReadStrandTargets reads (.hair, .data,
// .usda, .obj) to any format ringlet writes (.hair, .data, .usda, .obj), through metres, z up
// (docs/file-formats.md). The output is checked before reading, encoded in memory and written
// atomically: on any error nothing is written and the exit code is 1.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "ringlet/atomic_file.h"
#include "ringlet/hair_file.h"
#include "ringlet/obj_export.h"
#include "ringlet/strand_targets.h"
#include "ringlet/usc_data.h"
#include "ringlet/usd_export.h"

namespace ringlet::cli {
namespace {

struct ConvertArgs {
  std::string input_path;
  std::string output_path;
  double in_units_per_metre = 1.0;
  std::string in_up_axis = "z";
  bool ignore_usda_metadata = false;
  double width = 70e-6;
  double out_units_per_metre = 1.0;
  std::string out_up_axis = "z";
  bool force = false;
  bool quiet = false;
  CLI::Option *out_units_option = nullptr, *out_up_option = nullptr;
};

// The extension after the last dot, in lower case.
std::string Extension(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  for (char& c : ext) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return ext;
}

StrandTargetOptions::UpAxis Axis(const std::string& text) {
  return text == "y" ? StrandTargetOptions::UpAxis::kY : StrandTargetOptions::UpAxis::kZ;
}

int RunConvert(const ConvertArgs& args) {
  const std::string out_ext = Extension(args.output_path);
  if (out_ext != ".hair" && out_ext != ".data" && out_ext != ".usda" && out_ext != ".obj") {
    PrintError(args.output_path + ": unknown output extension \"" + out_ext +
               "\" (expected .hair, .data, .usda or .obj)");
    return kExitBadInput;
  }
  // .usda and .obj say "metres, z up" in the file; .hair has no axis field.
  if (args.out_units_option->count() > 0 && out_ext != ".hair" && out_ext != ".data") {
    PrintError("--out-units-per-metre: only for .hair and .data outputs (" + out_ext +
               " files are written in metres)");
    return kExitBadInput;
  }
  if (args.out_up_option->count() > 0 && out_ext != ".data") {
    PrintError("--out-up-axis: only for .data outputs (" + out_ext + " files are written z up)");
    return kExitBadInput;
  }
  std::string error;
  if (!CheckReplaceable(args.output_path, args.force, &error)) {
    PrintError(error);
    return kExitBadInput;
  }

  StrandTargetOptions in;
  in.units_per_metre = args.in_units_per_metre;
  in.up_axis = Axis(args.in_up_axis);
  in.default_width = args.width;
  in.ignore_file_metadata = args.ignore_usda_metadata;
  if (!in.IsValid(&error)) {
    PrintError("input options: " + error);
    return kExitBadInput;
  }
  HairCurves curves;
  StrandTargetSummary summary;
  if (!ReadStrandTargets(args.input_path, in, &curves, &summary, &error)) {
    PrintError(error);
    return kExitBadInput;
  }

  bool written = false;
  if (out_ext == ".hair") {
    HairFileOptions options;
    options.units_per_metre = args.out_units_per_metre;
    if (options.units_per_metre != 1.0) {
      char info[80];
      std::snprintf(info, sizeof(info), "ringlet hair curves; %.6g units per metre; z up",
                    options.units_per_metre);
      options.info = info;
    }
    written = WriteHairFile(args.output_path, curves, options, args.force, &error);
  } else if (out_ext == ".data") {
    StrandTargetOptions options;
    options.units_per_metre = args.out_units_per_metre;
    options.up_axis = Axis(args.out_up_axis);
    written = WriteUscData(args.output_path, curves, options, args.force, &error);
  } else if (out_ext == ".usda") {
    written = WriteUsda(args.output_path, curves, UsdExportOptions(), args.force, &error);
  } else {
    written = WriteObj(args.output_path, curves, args.force, &error);
  }
  if (!written) {
    PrintError(error);
    return kExitBadInput;
  }
  if (!args.quiet) {
    std::printf("converted %d strand%s, %d points (%.6g m per input unit, %s up)%s -> %s\n",
                curves.NumStrands(), curves.NumStrands() == 1 ? "" : "s", curves.NumPoints(),
                summary.metres_per_unit,
                summary.up_axis == StrandTargetOptions::UpAxis::kY ? "y" : "z",
                summary.skipped_empty_strands > 0
                    ? (", " + std::to_string(summary.skipped_empty_strands) +
                       " empty strands skipped")
                          .c_str()
                    : "",
                args.output_path.c_str());
  }
  return kExitSuccess;
}

}  // namespace

Command AddConvertCommand(CLI::App* parent) {
  auto args = std::make_shared<ConvertArgs>();
  CLI::App* app = parent->add_subcommand(
      "convert",
      "Convert hair strands between formats: .hair, .data (USC-HairSalon), .usda (linear "
      "BasisCurves) or .obj (polylines) in, any of them out, through metres with z up "
      "(docs/file-formats.md). Exit code 0 when the output was written, 1 on bad usage or "
      "input (nothing is written).");
  app->add_option("input", args->input_path, "Input strands (.hair, .data, .usda or .obj)")
      ->required();
  app->add_option("output", args->output_path, "Output file (.hair, .data, .usda or .obj)")
      ->required();
  app->add_option("--units-per-metre", args->in_units_per_metre,
                  "Input length units per metre (default 1: metres; 100: cm); not for .usda, "
                  "whose stage says it");
  app->add_option("--up-axis", args->in_up_axis,
                  "Input up axis: z (default) or y (rotated to z up: (x, y, z) -> (x, -z, y)); "
                  "USC-HairSalon .data files are y up; not for .usda, whose stage says it")
      ->check(CLI::IsMember({"z", "y"}));
  app->add_flag("--ignore-usda-metadata", args->ignore_usda_metadata,
                "Use --units-per-metre and --up-axis for a .usda input instead of its "
                "metersPerUnit and upAxis");
  app->add_option("--width", args->width,
                  "Fibre diameter (m) of inputs without widths (.data, .obj); default 7e-05");
  args->out_units_option = app->add_option("--out-units-per-metre", args->out_units_per_metre,
                                           "Output length units per metre (.hair, .data)");
  args->out_up_option =
      app->add_option("--out-up-axis", args->out_up_axis,
                      "Output up axis of a .data file: z (default) or y (USC-HairSalon's)")
          ->check(CLI::IsMember({"z", "y"}));
  app->add_flag("--force", args->force, "Overwrite an existing output file");
  app->add_flag("-q,--quiet", args->quiet, "Print no summary (errors still go to stderr)");
  return Command{app, [args] { return RunConvert(*args); }};
}

}  // namespace ringlet::cli
