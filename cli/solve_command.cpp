// `ringlet solve SCENE.json -o RESULT.json`: the static equilibrium of every strand of a scene,
// written as JSON (docs/scene-format.md), with a short human summary on stdout.
//
// Exit codes: 0 all strands converged (and are stable when checked), 2 some did not or --check
// found a Kirchhoff residual above tolerance (the results are still written and the summary says
// which), 1 bad usage or input (nothing is written).
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

#include "commands.h"
#include "format.h"
#include "progress.h"
#include "ringlet/atomic_file.h"
#include "ringlet/result_json.h"
#include "ringlet/scene_json.h"
#include "ringlet/solve_strands.h"
#include "ringlet/statics.h"

namespace ringlet::cli {
namespace {

// More centreline samples per segment than this is almost certainly a typo.
constexpr int kMaxPointsPerSegment = 1000;
// The warning of an unsuccessful solve lists at most this many strands.
constexpr int kMaxListedStrands = 5;

struct SolveArgs {
  std::string scene_path;
  std::string output_path;
  int points_per_segment = 1;
  bool force = false;
  bool quiet = false;
  bool check = false;
  double check_tolerance = 1e-6;
  int threads = 0;
};

// The output must not be the scene itself, nor a directory, nor (without --force) an existing
// file: nothing the user had is overwritten silently. Checked before solving so that the user
// does not wait for an error.
bool CheckOutput(const SolveArgs& args, std::string* error) {
  namespace fs = std::filesystem;
  if (args.output_path.empty()) {
    *error = "--output: expected a file name, got an empty string";
    return false;
  }
  std::error_code ec;
  const fs::file_status status = fs::status(args.output_path, ec);
  if (!fs::exists(status)) return true;
  if (fs::equivalent(args.scene_path, args.output_path, ec) && !ec) {
    *error = args.output_path + ": is the scene file itself; choose another output";
    return false;
  }
  if (fs::is_directory(status)) {
    *error = args.output_path + ": is a directory; give a file name to --output";
    return false;
  }
  if (!args.force) {
    *error = args.output_path + ": already exists (use --force to overwrite it)";
    return false;
  }
  // --force replaces regular files only (not a device, FIFO or symbolic link).
  return CheckReplaceable(args.output_path, true, error);
}

// "strand 0: converged, stable, 57 iterations, tip (0.0934, 0, -0.0312) m, energy ... J, ..."
std::string StrandLine(int index, const StrandResult& result) {
  const SolveSummary& s = result.summary;
  const char* stability = !s.stability_checked ? "stability not checked"
                          : s.stable           ? "stable"
                                               : "UNSTABLE";
  const Vec3& tip = result.points.back();
  return Format(
      "strand %d: %s, %s, %d iterations, tip (%.6g, %.6g, %.6g) m, energy %.6g J, "
      "residual %.2g (Kirchhoff %.2g)",
      index, TerminationName(s.termination), stability, s.iterations, tip.x(), tip.y(), tip.z(),
      s.energy.total, s.residual, result.kirchhoff_residual);
}

int RunSolve(const SolveArgs& args) {
  // Input first, then the output path, then the work.
  Scene scene;
  std::string error;
  if (!LoadScene(args.scene_path, &scene, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  if (!CheckOutput(args, &error)) {
    PrintError(error);
    return kExitBadInput;
  }

  // Strands are independent: solved in parallel, results in file order whatever the threads.
  const auto start = std::chrono::steady_clock::now();
  ProgressBar bar("solving", !args.quiet);
  BatchOptions batch;
  batch.threads = args.threads;
  batch.progress = [&bar](int done, int total) { bar.Update(done, total); };
  const std::vector<StrandSolution> solutions = SolveStrands(scene.strands, scene.solver, batch);
  bar.Finish();
  const std::vector<StrandResult> results =
      MakeStrandResults(scene.strands, solutions, args.points_per_segment, args.threads);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  // The text goes to the file in pieces as it is formatted (no 3 kB-per-strand copy in memory).
  if (!WriteFileAtomically(
          args.output_path,
          [&](const FileSink& sink) { WriteResultText(results, seconds, sink); }, args.force,
          &error)) {
    PrintError(error);
    return kExitBadInput;
  }

  const ResultCounts counts = CountResults(results);
  // --check: the independent Kirchhoff certificate of every strand must be below tolerance.
  int failed_checks = 0;
  std::string failed;
  if (args.check) {
    for (size_t i = 0; i < results.size(); ++i) {
      const double r = results[i].kirchhoff_residual;
      if (r <= args.check_tolerance) continue;  // false for NaN too
      if (failed_checks < kMaxListedStrands) {
        failed += Format("%sstrand %d (%.3g)", failed_checks == 0 ? "" : ", ",
                         static_cast<int>(i), r);
      }
      ++failed_checks;
    }
  }
  if (!args.quiet) {
    for (size_t i = 0; i < results.size(); ++i) {
      std::printf("%s\n", StrandLine(static_cast<int>(i), results[i]).c_str());
    }
    std::printf("solved %d strand%s: %d converged, %d stable, %s -> %s\n", counts.strands,
                counts.strands == 1 ? "" : "s", counts.converged, counts.stable,
                FormatSeconds(seconds).c_str(), args.output_path.c_str());
    std::fflush(stdout);
  }
  if (failed_checks > 0) {
    PrintError(Format("equilibrium check failed: kirchhoff_residual above %.3g for %d of %d "
                      "strands: %s%s; results written to %s",
                      args.check_tolerance, failed_checks, counts.strands, failed.c_str(),
                      failed_checks > kMaxListedStrands ? ", ..." : "",
                      args.output_path.c_str()));
    return kExitUnsolved;
  }
  if (counts.succeeded == counts.strands) return kExitSuccess;

  if (!args.quiet) {
    std::string listed;
    int shown = 0;
    for (size_t i = 0; i < results.size() && shown < kMaxListedStrands; ++i) {
      if (results[i].Succeeded()) continue;
      const SolveSummary& s = results[i].summary;
      listed += Format("%sstrand %d %s", shown == 0 ? "" : ", ", static_cast<int>(i),
                       s.Converged() ? "unstable" : TerminationName(s.termination));
      ++shown;
    }
    if (counts.strands - counts.succeeded > shown) listed += ", ...";
    std::fflush(stdout);  // the summary before the warning, also when both go to one pipe
    PrintWarning(
        Format("%d of %d strands did not reach a stable equilibrium (%s); results "
               "written to %s",
               counts.strands - counts.succeeded, counts.strands, listed.c_str(),
               args.output_path.c_str()));
  }
  return kExitUnsolved;
}

}  // namespace

Command AddSolveCommand(CLI::App* parent) {
  auto args = std::make_shared<SolveArgs>();
  CLI::App* app = parent->add_subcommand(
      "solve",
      "Find the static equilibrium of every strand of a scene and write it as JSON. Exit code 0 "
      "when every strand converged to a stable equilibrium, 2 when some did not (results are "
      "still written), 1 on bad usage or input (nothing is written).");
  app->add_option("scene", args->scene_path, "Scene file (JSON, see docs/scene-format.md)")
      ->required();
  app->add_option("-o,--output", args->output_path, "Result file to write (JSON)")->required();
  app->add_option("--points-per-segment", args->points_per_segment,
                  "Centreline samples per segment in the result: n k + 1 points (default 1: the "
                  "segment ends)")
      ->check(CLI::Range(1, kMaxPointsPerSegment));
  app->add_flag("--force", args->force, "Overwrite the output file if it exists");
  app->add_flag("--check", args->check,
                "Fail (exit 2, one error line) when any strand's kirchhoff_residual, the "
                "equilibrium certificate computed independently of the solver, exceeds "
                "--check-tolerance");
  app->add_option("--check-tolerance", args->check_tolerance,
                  "Tolerance of --check on the dimensionless kirchhoff_residual (default 1e-6)")
      ->check(CLI::Range(1e-15, 1.0));
  app->add_option("--threads", args->threads,
                  "Worker threads (default 0: all cores); results do not depend on it")
      ->check(CLI::Range(0, 1024));
  app->add_flag("-q,--quiet", args->quiet,
                "Print no summary or warning (errors still go to stderr)");
  return Command{app, [args] { return RunSolve(*args); }};
}

}  // namespace ringlet::cli
