// `ringlet style HAIRSTYLE.json [--curl R,P] [--wet] [--dry] [--cut-z Z [--settle]]
// [--grow STEP --steps N] -o OUTDIR/`: virtual hairdressing (paper, section 3.2). Grooms the
// hairstyle, applies the operations in command-line order (each re-solves the masters from the
// previous equilibrium), then writes the files of `ringlet groom` plus, for grow, one
// step_NNN.hair per step and grow.usda with time samples (docs/styling.md).
//
// Exit codes: 0 every master converged, 2 some did not (files are still written), 1 bad usage
// or input (nothing is written).
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
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
#include "ringlet/obj_export.h"
#include "ringlet/result_json.h"
#include "ringlet/styling.h"
#include "ringlet/usd_export.h"

namespace ringlet::cli {
namespace {


// One operation of the command line, in order.
struct StyleOperation {
  enum class Kind { kCurl, kWet, kDry, kCut, kGrow } kind;
  double a = 0.0;  // curl radius, cut z, grow step
  double b = 0.0;  // curl pitch
};

struct StyleArgs {
  std::string hairstyle_path;
  std::string output_dir;
  std::vector<StyleOperation> operations;
  std::string bad_operation;  // first unparsable operation argument, reported after parsing
  bool settle = false;
  int steps = 10;
  bool force = false;
  bool quiet = false;
  int threads = 0;
  double hair_units_per_metre = 1.0;
};

// "R,P" -> (R, P) in metres; "inf" is allowed for R (straighten).
bool ParseCurl(const std::string& text, double* radius, double* pitch) {
  const size_t comma = text.find(',');
  if (comma == std::string::npos) return false;
  try {
    size_t used = 0;
    *radius = std::stod(text.substr(0, comma), &used);
    if (used != comma) return false;
    const std::string rest = text.substr(comma + 1);
    *pitch = std::stod(rest, &used);
    return used == rest.size();
  } catch (const std::exception&) {
    return false;
  }
}

// The names of the files to write, in order, for `grow_steps` grow steps in all.
std::vector<std::string> OutputNames(int grow_steps) {
  std::vector<std::string> names = {"strands.hair", "strands.usda", "strands.obj", "masters.json"};
  for (int t = 1; t <= grow_steps; ++t) names.push_back(Format("step_%03d.hair", t));
  if (grow_steps > 0) names.push_back("grow.usda");
  return names;
}

std::string MastersJson(const StyledHair& state, const std::vector<OperationReport>& reports,
                        double seconds) {
  std::vector<StrandResult> results;
  results.reserve(state.solutions.size());
  for (size_t i = 0; i < state.solutions.size(); ++i) {
    results.push_back(MakeStrandResult(state.masters.models[i], state.solutions[i], 1));
  }
  nlohmann::ordered_json document = ResultToJson(results, seconds);
  nlohmann::ordered_json ops = nlohmann::ordered_json::array();
  for (const OperationReport& r : reports) {
    ops.push_back({{"name", r.name},
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
  if (args.operations.empty()) {
    PrintError("expected at least one operation (--curl, --wet, --dry, --cut-z, --grow)");
    return kExitBadInput;
  }
  int grow_steps = 0;
  for (const StyleOperation& op : args.operations) {
    if (op.kind == StyleOperation::Kind::kGrow) grow_steps += args.steps;
  }
  const std::vector<std::string> names = OutputNames(grow_steps);
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
  Hairstyle style;
  if (!LoadHairstyle(args.hairstyle_path, &style, &error)) {
    PrintError(error);
    return kExitBadInput;
  }

  const auto start = std::chrono::steady_clock::now();
  BatchOptions batch;
  batch.threads = args.threads;
  Groom groom;
  {
    ProgressBar bar("solving masters", !args.quiet);
    BatchOptions groom_batch = batch;
    groom_batch.progress = [&bar](int done, int total) { bar.Update(done, total); };
    if (!GroomHairstyle(style, groom_batch, &groom, &error)) {
      bar.Finish();
      PrintError(args.hairstyle_path + ": " + error);
      return kExitBadInput;
    }
  }
  StyledHair state;
  if (!MakeStyledHair(style, groom, &state, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  groom = Groom{};

  // The operations, in command-line order; every one re-solves from the previous equilibrium.
  std::vector<OperationReport> reports;
  std::vector<HairCurves> grow_frames;
  for (const StyleOperation& op : args.operations) {
    OperationReport report;
    bool ok = true;
    switch (op.kind) {
      case StyleOperation::Kind::kCurl:
        ok = Curl(&state, op.a, op.b, StrandSelection{}, batch, &report, &error);
        break;
      case StyleOperation::Kind::kWet:
        ok = Wet(&state, WetOptions{}, batch, &report, &error);
        break;
      case StyleOperation::Kind::kDry:
        ok = Dry(&state, batch, &report, &error);
        break;
      case StyleOperation::Kind::kCut: {
        CutOptions options;
        options.settle = args.settle;
        ok = CutBelow(&state, op.a, options, batch, &report, &error);
        break;
      }
      case StyleOperation::Kind::kGrow: {
        std::vector<StyledHair> sequence;
        ok = Grow(&state, op.a, args.steps, batch, &sequence, &report, &error);
        for (size_t t = 0; ok && t < sequence.size(); ++t) {
          HairCurves frame;
          ok = StyledStrands(sequence[t], &frame, &error);
          grow_frames.push_back(std::move(frame));
        }
        break;
      }
    }
    if (!ok) {
      PrintError(error);
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
  bool ok = encode("strands.hair", [&](std::string* t) {
    return EncodeHairFile(strands, hair_options, t, &error);
  });
  ok = ok && encode("strands.usda", [&](std::string* t) {
    return EncodeUsda(strands, UsdExportOptions{}, t, &error);
  });
  ok = ok && encode("strands.obj", [&](std::string* t) { return EncodeObj(strands, t, &error); });
  ok = ok && encode("masters.json", [&](std::string* t) {
    *t = MastersJson(state, reports, SecondsSince(start));
    return true;
  });
  for (size_t k = 0; ok && k < grow_frames.size(); ++k) {
    ok = encode(Format("step_%03d.hair", static_cast<int>(k + 1)), [&](std::string* t) {
      return EncodeHairFile(grow_frames[k], hair_options, t, &error);
    });
  }
  if (ok && !grow_frames.empty()) {
    ok = encode("grow.usda", [&](std::string* t) {
      return EncodeUsdaSequence(grow_frames, UsdExportOptions{}, t, &error);
    });
  }
  if (!ok) return kExitBadInput;
  if (!WriteOutputFiles(args.output_dir, files, args.force, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  int unconverged = 0;
  for (const StrandSolution& s : state.solutions) unconverged += s.summary.Converged() ? 0 : 1;
  if (!args.quiet) {
    std::printf("styled %zu masters, %d strands, %d points; total %s -> %s\n",
                state.solutions.size(), strands.NumStrands(), strands.NumPoints(),
                FormatSeconds(SecondsSince(start)).c_str(), args.output_dir.c_str());
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
      "Virtual hairdressing: groom a hairstyle, then curl, wet, dry, cut and grow it, in "
      "command-line order, each operation re-solving from the previous equilibrium; writes the "
      "files of `ringlet groom` (plus step_NNN.hair and grow.usda for --grow). Exit code 0 when "
      "every master converged, 2 when some did not, 1 on bad usage or input.");
  app->add_option("hairstyle", args->hairstyle_path,
                  "Hairstyle file (JSON, see docs/hairstyle-format.md)")
      ->required();
  app->add_option("-o,--output", args->output_dir, "Output directory (created if missing)")
      ->required();
  using Kind = StyleOperation::Kind;
  // Operations are recorded as they are parsed (trigger_on_parse), so their order is kept.
  app->add_option_function<std::string>(
         "--curl",
         [args](const std::string& text) {
           StyleOperation op{Kind::kCurl};
           if (!ParseCurl(text, &op.a, &op.b) && args->bad_operation.empty()) {
             args->bad_operation = "--curl: expected RADIUS,PITCH in metres (e.g. 0.01,0.02), got \"" +
                                   text + "\"";
           }
           args->operations.push_back(op);
         },
         "Set the natural curl: helix radius and pitch (m), e.g. 0.01,0.02")
      ->trigger_on_parse()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app->add_flag_callback(
         "--wet", [args] { args->operations.push_back({Kind::kWet}); },
         "Wet the hair: E / 10, radius x 1.13 (Robbins), water weight, thinner hull layers")
      ->trigger_on_parse();
  app->add_flag_callback(
         "--dry", [args] { args->operations.push_back({Kind::kDry}); },
         "Dry the hair (the exact inverse of --wet)")
      ->trigger_on_parse();
  app->add_option_function<double>(
         "--cut-z", [args](double z) { args->operations.push_back({Kind::kCut, z}); },
         "Cut what hangs below this height (m)")
      ->trigger_on_parse()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app->add_flag("--settle", args->settle,
                "With --cut-z: adjust the cuts until the risen tips settle on the plane");
  app->add_option_function<double>(
         "--grow", [args](double step) { args->operations.push_back({Kind::kGrow, step}); },
         "Grow every master by STEP (m) per step, --steps times")
      ->trigger_on_parse()
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app->add_option("--steps", args->steps, "Steps of --grow (default 10)")
      ->check(CLI::Range(1, 1000));
  app->add_option("--hair-units-per-metre", args->hair_units_per_metre,
                  "Length unit of the .hair files per metre (default 1: metres; 100: cm)");
  app->add_flag("--force", args->force, "Overwrite existing output files");
  app->add_option("--threads", args->threads,
                  "Worker threads (default 0: all cores); results do not depend on it")
      ->check(CLI::Range(0, 1024));
  app->add_flag("-q,--quiet", args->quiet,
                "Print no summary, progress or warning (errors still go to stderr)");
  return Command{app, [args] { return RunStyle(*args); }};
}

}  // namespace ringlet::cli
