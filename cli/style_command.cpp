// `ringlet style HAIRSTYLE.json [--curl R,P [--curl-polar MIN,MAX] [--curl-height MIN,MAX]
// [--curl-masters I,J,...]] [--wet] [--dry] [--cut-z Z] [--cut-plane NX,NY,NZ,D]
// [--cut-sphere X,Y,Z,R] [--cut-length L] [--settle] [--grow STEP --steps N] -o OUTDIR/`:
// virtual hairdressing (paper, section 3.2). Grooms the hairstyle, applies the file's
// "operations" list and then the command line's operations in order (each re-solves the masters
// from the previous equilibrium; ApplyOperation, the same code path for both), then writes the
// files of `ringlet groom` plus, for grow, one step_NNN.hair per step and grow.usda with time
// samples (docs/styling.md).
//
// Exit codes: 0 every master converged, 2 some did not (files are still written), 1 bad usage
// or input (nothing is written).
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
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
#include "render_image.h"
#include "ringlet/atomic_file.h"
#include "ringlet/png_image.h"
#include "ringlet/hair_file.h"
#include "ringlet/hairstyle.h"
#include "ringlet/hairstyle_json.h"
#include "ringlet/obj_export.h"
#include "ringlet/render_json.h"
#include "ringlet/result_json.h"
#include "ringlet/strand_export.h"
#include "ringlet/styling.h"
#include "ringlet/usd_export.h"

namespace ringlet::cli {
namespace {

// One operation to apply, in order: from the hairstyle file's "operations" list, then from the
// command line; `from` names its origin in messages ("operations[2]", "--cut-sphere").
struct PlannedOperation {
  StyleOperation op;
  std::string from;
};

struct StyleArgs {
  std::string hairstyle_path;
  std::string output_dir;
  std::vector<PlannedOperation> operations;  // the command line's, in order
  std::string bad_operation;  // first unparsable operation argument, reported after parsing
  bool settle = false;
  int steps = 10;
  OutputOptions outputs;  // --formats, --hair-units-per-metre, --force, --render, --spp, ...
  bool quiet = false;
  int threads = 0;
};

// "A,B,C" -> numbers (std::stod: "inf" and "nan" are read, and rejected later by the checks).
// count = 0 accepts any positive number of values.
bool ParseNumbers(const std::string& text, size_t count, std::vector<double>* values) {
  values->clear();
  size_t begin = 0;
  while (true) {
    const size_t comma = text.find(',', begin);
    const std::string item =
        text.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin);
    try {
      size_t used = 0;
      values->push_back(std::stod(item, &used));
      if (used != item.size()) return false;
    } catch (const std::exception&) {
      return false;
    }
    if (comma == std::string::npos) break;
    begin = comma + 1;
  }
  return count == 0 ? !values->empty() : values->size() == count;
}

// Records the first bad argument: "FLAG: expected WHAT, got "TEXT"".
void BadArgument(StyleArgs* args, const std::string& flag, const std::string& expected,
                 const std::string& text) {
  if (args->bad_operation.empty()) {
    args->bad_operation = flag + ": expected " + expected + ", got \"" + text + "\"";
  }
}

// The names of the files to write, in order, for `grow_steps` grow steps in all: the strand
// files of `formats`, and for a grow its steps as .hair files (with "hair") and as one
// time-sampled USD file (with "usda").
std::vector<std::string> OutputNames(const std::set<std::string>& formats, int grow_steps) {
  std::vector<std::string> names = StrandOutputNames(formats);
  if (formats.count("hair")) {
    for (int t = 1; t <= grow_steps; ++t) names.push_back(Format("step_%03d.hair", t));
  }
  if (grow_steps > 0 && formats.count("usda")) names.push_back("grow.usda");
  return names;
}

std::string MastersJson(const StyledHair& state, const std::vector<OperationReport>& reports,
                        const std::vector<PlannedOperation>& plan, double seconds) {
  std::vector<StrandResult> results;
  results.reserve(state.solutions.size());
  for (size_t i = 0; i < state.solutions.size(); ++i) {
    results.push_back(MakeStrandResult(state.masters.models[i], state.solutions[i], 1));
  }
  nlohmann::ordered_json document = ResultToJson(results, seconds);
  nlohmann::ordered_json ops = nlohmann::ordered_json::array();
  for (size_t k = 0; k < reports.size(); ++k) {
    const OperationReport& r = reports[k];
    ops.push_back({{"name", r.name},
                   {"from", plan[k].from},
                   {"strands", r.strands},
                   {"iterations", r.iterations},
                   {"rounds", r.rounds},
                   {"unconverged", r.unconverged},
                   {"seconds", r.seconds},
                   {"message", r.message}});
  }
  document["style"] = {{"wet", state.wet}, {"operations", std::move(ops)}};
  return document.dump(1) + "\n";
}

int RunStyle(const StyleArgs& args) {
  std::string error;
  if (!args.bad_operation.empty()) {
    PrintError(args.bad_operation);
    return kExitBadInput;
  }
  // The command line's operations: --settle and --steps apply to each, then the parameters are
  // checked before any work (the master index bound waits for the groom).
  std::vector<PlannedOperation> command_line = args.operations;
  for (PlannedOperation& planned : command_line) {
    StyleOperation& op = planned.op;
    if (op.kind == StyleOperation::Kind::kCut &&
        op.cut_region.kind != CutRegion::Kind::kMaxLength) {
      op.cut.settle = args.settle;
    }
    if (op.kind == StyleOperation::Kind::kGrow) op.grow_steps = args.steps;
    if (!op.IsValid(&error)) {
      PrintError(planned.from + ": " + error);
      return kExitBadInput;
    }
  }
  std::set<std::string> formats;
  HairFileOptions hair_options;
  if (!CheckOutputOptions(args.outputs, &formats, &hair_options, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  Hairstyle style;
  std::vector<StyleOperation> from_file;
  if (!LoadHairstyle(args.hairstyle_path, &style, &from_file, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  // The file's operations first, then the command line's (docs/styling.md).
  std::vector<PlannedOperation> plan;
  for (size_t k = 0; k < from_file.size(); ++k) {
    plan.push_back({from_file[k], Format("operations[%d]", static_cast<int>(k))});
  }
  plan.insert(plan.end(), command_line.begin(), command_line.end());
  if (plan.empty()) {
    PrintError(
        "expected at least one operation (--curl, --wet, --dry, --cut-z, --cut-plane, "
        "--cut-sphere, --cut-length, --grow, or an \"operations\" list in " +
        args.hairstyle_path + ")");
    return kExitBadInput;
  }
  int grow_steps = 0;
  for (const PlannedOperation& planned : plan) {
    if (planned.op.kind == StyleOperation::Kind::kGrow) grow_steps += planned.op.grow_steps;
  }
  std::vector<std::string> names = OutputNames(formats, grow_steps);
  // The file's render settings (docs/hairstyle-format.md, "render"), checked now with or
  // without --render (as `ringlet groom` does): their melanins colour the written strands.
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
  if (args.outputs.render) names.push_back(kRenderName);
  if (!CheckOutputDirectory(args.output_dir, names, args.outputs.force, &error)) {
    PrintError(error);
    return kExitBadInput;
  }

  const auto start = std::chrono::steady_clock::now();
  BatchOptions batch;
  batch.threads = args.threads;
  Groom groom;
  if (!GroomWithProgress(style, args.threads, args.quiet, &groom, &error)) {
    PrintError(args.hairstyle_path + ": " + error);
    return kExitBadInput;
  }
  StyledHair state;
  if (!MakeStyledHair(style, groom, &state, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  groom = Groom{};
  // The master indices of the selections, now that the masters are known: before any operation.
  for (const PlannedOperation& planned : plan) {
    if (planned.op.kind == StyleOperation::Kind::kCurl &&
        !planned.op.selection.IsValid(static_cast<int>(state.masters.models.size()), &error)) {
      PrintError(planned.from + ": " + error);
      return kExitBadInput;
    }
  }

  // The operations, in order; every one re-solves from the previous equilibrium.
  std::vector<OperationReport> reports;
  std::vector<HairCurves> grow_frames;
  for (const PlannedOperation& planned : plan) {
    OperationReport report;
    std::vector<StyledHair> sequence;
    bool ok = ApplyOperation(&state, planned.op, batch, &sequence, &report, &error);
    for (size_t t = 0; ok && t < sequence.size(); ++t) {
      HairCurves frame;
      ok = StyledStrands(sequence[t], &frame, &error);
      SetMelaninColours(render_settings, &frame);
      grow_frames.push_back(std::move(frame));
    }
    if (!ok) {
      PrintError(planned.from + ": " + error);
      return kExitBadInput;
    }
    if (!args.quiet) {
      std::printf("%s in %s\n", report.message.c_str(), FormatSeconds(report.seconds).c_str());
      std::fflush(stdout);
    }
    reports.push_back(std::move(report));
  }
  HairCurves strands;
  if (!StyledStrands(state, &strands, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  SetMelaninColours(render_settings, &strands);  // the colour the exporters write
  // --render, before any file is written (a failure writes nothing). The eccentricity is the
  // hair type's: wetting swells both semi-axes by the same factor.
  Image image;
  RenderStats render_stats;
  if (args.outputs.render) {
    const RenderJob job =
        HairstyleRenderJob(style, &strands, render_settings, args.threads, args.quiet);
    if (!RenderJobImage(job, &image, &render_stats, &error)) {
      PrintError(args.hairstyle_path + ": render: " + error);
      return kExitBadInput;
    }
  }

  // Encode everything first, then write each file atomically.
  std::vector<std::pair<std::string, std::string>> files;
  // encode(name, f): f(&contents) encodes and returns false (with error) on failure.
  const auto encode = [&](const std::string& name, const auto& f) {
    std::string contents;
    if (!f(&contents)) {
      PrintError(name + ": " + error);
      return false;
    }
    files.emplace_back(name, std::move(contents));
    return true;
  };
  bool ok = true;
  if (!EncodeStrandOutputs(
          strands, render_settings, formats, hair_options, style.body.get(),
          [&] { return MastersJson(state, reports, plan, SecondsSince(start)); }, &files,
          &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  for (size_t k = 0; ok && formats.count("hair") && k < grow_frames.size(); ++k) {
    ok = encode(Format("step_%03d.hair", static_cast<int>(k + 1)), [&](std::string* t) {
      return EncodeHairstyleStrands(grow_frames[k], render_settings, StrandFormat::kHair,
                                    hair_options, t, &error);
    });
  }
  if (ok && !grow_frames.empty() && formats.count("usda")) {
    ok = encode("grow.usda", [&](std::string* t) {
      return EncodeUsdaSequence(grow_frames, UsdExportOptions{}, t, &error);
    });
  }
  if (!ok) return kExitBadInput;
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
  int unconverged = 0;
  for (const StrandSolution& s : state.solutions) unconverged += s.summary.Converged() ? 0 : 1;
  if (!args.quiet) {
    std::printf("styled %zu masters, %d strands, %d points; total %s -> %s\n",
                state.solutions.size(), strands.NumStrands(), strands.NumPoints(),
                FormatSeconds(SecondsSince(start)).c_str(), args.output_dir.c_str());
    if (args.outputs.render) {
      PrintRenderSummary(image, render_settings.options.samples_per_pixel, render_stats,
                         image_path);
    }
    std::fflush(stdout);
    if (unconverged > 0) {
      PrintWarning(Format("%d of %zu masters did not converge (see masters.json)", unconverged,
                          state.solutions.size()));
    }
  }
  return unconverged == 0 ? kExitSuccess : kExitUnsolved;
}

}  // namespace

Command AddStyleCommand(CLI::App* parent) {
  auto args = std::make_shared<StyleArgs>();
  CLI::App* app = parent->add_subcommand(
      "style",
      "Virtual hairdressing: groom a hairstyle, then curl, wet, dry, cut and grow it: first the "
      "file's \"operations\" list, then the options in command-line order, each operation "
      "re-solving from the previous equilibrium; writes the "
      "files of `ringlet groom` (plus step_NNN.hair and grow.usda for --grow). Exit code 0 when "
      "every master converged, 2 when some did not, 1 on bad usage or input.");
  app->add_option("hairstyle", args->hairstyle_path,
                  "Hairstyle file (JSON, see docs/hairstyle-format.md)")
      ->required();
  app->add_option("-o,--output", args->output_dir, "Output directory (created if missing)")
      ->required();
  using Kind = StyleOperation::Kind;
  // Operations are recorded as they are parsed (trigger_on_parse), so their order is kept.
  const auto add = [args](Kind kind, const std::string& from) -> StyleOperation& {
    StyleOperation op;
    op.kind = kind;
    args->operations.push_back({op, from});
    return args->operations.back().op;
  };
  app->add_option_function<std::string>(
         "--curl",
         [args, add](const std::string& text) {
           StyleOperation& op = add(Kind::kCurl, "--curl");
           std::vector<double> v;
           if (!ParseNumbers(text, 2, &v)) {
             BadArgument(args.get(), "--curl", "RADIUS,PITCH in metres (e.g. 0.01,0.02)", text);
             return;
           }
           op.curl_radius = v[0];
           op.curl_pitch = v[1];
         },
         "Set the natural curl: helix radius and pitch (m), e.g. 0.01,0.02 (radius inf "
         "straightens); on every master, or on those chosen by --curl-polar, --curl-height or "
         "--curl-masters after it")
      ->trigger_on_parse()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  // The selection options refine the --curl just before them.
  const auto selection = [args](const std::string& flag) -> StrandSelection* {
    if (args->operations.empty() || args->operations.back().op.kind != Kind::kCurl) {
      if (args->bad_operation.empty()) {
        args->bad_operation = flag +
                              ": expected after a --curl (it chooses the masters that "
                              "--curl acts on)";
      }
      return nullptr;
    }
    args->operations.back().from += " " + flag;
    return &args->operations.back().op.selection;
  };
  app->add_option_function<std::string>(
         "--curl-polar",
         [args, selection](const std::string& text) {
           StrandSelection* s = selection("--curl-polar");
           std::vector<double> v;
           if (!s) return;
           if (!ParseNumbers(text, 2, &v)) {
             BadArgument(args.get(), "--curl-polar", "MIN,MAX polar angles of the roots (rad)",
                         text);
             return;
           }
           s->indices.clear();
           s->min_polar_angle = v[0];
           s->max_polar_angle = v[1];
         },
         "After --curl: curl only masters whose root polar angle from the head's up axis lies "
         "in [MIN,MAX] (rad), e.g. 0,0.8 (the crown)")
      ->trigger_on_parse()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app->add_option_function<std::string>(
         "--curl-height",
         [args, selection](const std::string& text) {
           StrandSelection* s = selection("--curl-height");
           std::vector<double> v;
           if (!s) return;
           if (!ParseNumbers(text, 2, &v)) {
             BadArgument(args.get(), "--curl-height",
                         "MIN,MAX root heights above the head centre (m)", text);
             return;
           }
           s->indices.clear();
           s->min_height = v[0];
           s->max_height = v[1];
         },
         "After --curl: curl only masters whose root lies MIN to MAX (m) above the head centre")
      ->trigger_on_parse()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app->add_option_function<std::string>(
         "--curl-masters",
         [args, selection](const std::string& text) {
           StrandSelection* s = selection("--curl-masters");
           std::vector<double> v;
           if (!s) return;
           bool ok = ParseNumbers(text, 0, &v);
           for (double x : v) ok = ok && x >= 0.0 && x <= 1e9 && x == std::floor(x);
           if (!ok) {
             BadArgument(args.get(), "--curl-masters", "master indices I,J,... (integers >= 0)",
                         text);
             return;
           }
           s->indices.assign(v.begin(), v.end());
         },
         "After --curl: curl only these masters (indices as in masters.json), e.g. 0,5,7")
      ->trigger_on_parse()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app->add_flag_callback(
         "--wet", [add] { add(Kind::kWet, "--wet"); },
         "Wet the hair: E / 10, radius x 1.13 (Robbins), water weight, thinner hull layers")
      ->trigger_on_parse();
  app->add_flag_callback(
         "--dry", [add] { add(Kind::kDry, "--dry"); }, "Dry the hair (the exact inverse of --wet)")
      ->trigger_on_parse();
  app->add_option_function<double>(
         "--cut-z",
         [add](double z) {
           StyleOperation& op = add(Kind::kCut, "--cut-z");
           op.cut_region.kind = CutRegion::Kind::kAbovePlane;
           op.cut_region.normal = Vec3::UnitZ();
           op.cut_region.offset = z;
         },
         "Cut what hangs below this height (m)")
      ->trigger_on_parse()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app->add_option_function<std::string>(
         "--cut-plane",
         [args, add](const std::string& text) {
           StyleOperation& op = add(Kind::kCut, "--cut-plane");
           std::vector<double> v;
           if (!ParseNumbers(text, 4, &v)) {
             BadArgument(args.get(), "--cut-plane",
                         "NX,NY,NZ,D: keep the side n . r >= D (n normalized, D in m)", text);
             return;
           }
           op.cut_region.kind = CutRegion::Kind::kAbovePlane;
           op.cut_region.normal = Vec3(v[0], v[1], v[2]);
           op.cut_region.offset = v[3];
         },
         "Cut what lies beyond a plane: keep n . r >= D (n = NX,NY,NZ normalized, D in m); "
         "e.g. 0,-1,0,-0.05 cuts a fringe in front of y = 0.05")
      ->trigger_on_parse()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app->add_option_function<std::string>(
         "--cut-sphere",
         [args, add](const std::string& text) {
           StyleOperation& op = add(Kind::kCut, "--cut-sphere");
           std::vector<double> v;
           if (!ParseNumbers(text, 4, &v)) {
             BadArgument(args.get(), "--cut-sphere",
                         "X,Y,Z,R: the kept sphere's centre and radius (m)", text);
             return;
           }
           op.cut_region.kind = CutRegion::Kind::kInsideSphere;
           op.cut_region.centre = Vec3(v[0], v[1], v[2]);
           op.cut_region.radius = v[3];
         },
         "Cut what lies outside the sphere of centre X,Y,Z and radius R (m): a bob")
      ->trigger_on_parse()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app->add_option_function<double>(
         "--cut-length",
         [add](double length) {
           StyleOperation& op = add(Kind::kCut, "--cut-length");
           op.cut_region.kind = CutRegion::Kind::kMaxLength;
           op.cut_region.length = length;
         },
         "Cut every master to at most this length (m)")
      ->trigger_on_parse()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app->add_flag("--settle", args->settle,
                "With --cut-z, --cut-plane, --cut-sphere: adjust the cuts until the risen tips "
                "settle on the boundary");
  app->add_option_function<double>(
         "--grow",
         [add](double step) {
           StyleOperation& op = add(Kind::kGrow, "--grow");
           op.grow_step = step;
         },
         "Grow every master by STEP (m) per step, --steps times")
      ->trigger_on_parse()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app->add_option("--steps", args->steps, "Steps of --grow (default 10)")
      ->check(CLI::Range(1, 1000));
  AddOutputOptions(app, &args->outputs, "the styled hair");
  app->add_option("--threads", args->threads,
                  "Worker threads (default 0: all cores); results do not depend on it")
      ->check(CLI::Range(0, 1024));
  app->add_flag("-q,--quiet", args->quiet,
                "Print no summary, progress or warning (errors still go to stderr)");
  return Command{app, [args] { return RunStyle(*args); }};
}

}  // namespace ringlet::cli
