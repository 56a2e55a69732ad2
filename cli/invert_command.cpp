// `ringlet invert TARGET -o OUTDIR/`: inverse statics (issue 13, docs/inverse.md). Reads target
// strands (ringlet's own result / masters JSON as exact piecewise helices, or polylines from
// .hair, .data, .usda or .obj files, strand_targets.h, fitted by G1 piecewise helices), computes the rest shapes that hold them under
// gravity (and body contact with --body), certifies their stability, verifies them by the forward
// solve, compares with the naive rest shape, and writes:
//   rest_shapes.json   a scene file (docs/scene-format.md) with per-strand rest_curvatures:
//                      `ringlet solve rest_shapes.json` reproduces the equilibrium
//   equilibrium.hair   the forward equilibria from the inverted rest shapes
//   naive.hair         the forward equilibria from the naive rest shapes (the sag)
//   summary.json       counts, fit errors, deviations, unstable strands, times
// and with --body a sag-free groom (AddHairstyleOutputs):
//   hairstyle.json     a hairstyle whose masters are the inverted strands, given by
//   explicit_masters.json  (rest shapes, the targets as the solves' start): `ringlet groom`,
//                      `ringlet style` and the studio read it
//
// Exit codes: 0 every target held stably, 2 some target is unstable or a forward solve did not
// converge (files written, the summary says which), 1 bad usage or input (nothing written).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <future>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include "commands.h"
#include "format.h"
#include "outputs.h"
#include "progress.h"
#include "ringlet/body.h"
#include "ringlet/body_json.h"
#include "ringlet/cross_section.h"
#include "ringlet/hair_file.h"
#include "ringlet/hair_type.h"
#include "ringlet/inverse.h"
#include "ringlet/inverse_summary.h"
#include "ringlet/masters_json.h"
#include "ringlet/result_targets.h"
#include "ringlet/scene_json.h"
#include "ringlet/strand_geometry.h"
#include "ringlet/strand_targets.h"

namespace ringlet::cli {
namespace {

struct InvertArgs {
  std::string target_path;
  std::string output_dir;
  std::string body_path;
  std::string hair_type;  // "origin" or "origin/curl"
  int segments = 0;
  double fit_tolerance = 1e-3;
  double units_per_metre = 1.0;
  std::string up = "z";
  bool units_given = false;  // --units-per-metre or --up on the command line
  bool ignore_usda_metadata = false;
  double clearance = 0.0;
  int threads = 0;
  int points_per_segment = 0;  // 0: at the target's own points (polylines), else k per segment
  bool no_support_forces = false;  // contact forces as unknowns off (docs/inverse.md)
  bool no_naive = false;  // skip the naive rest shape's forward solve and naive.hair
  bool force = false;
  bool quiet = false;
};

constexpr const char* kOutputs[] = {"rest_shapes.json", "equilibrium.hair", "naive.hair",
                                    "summary.json"};
// With --body: a sag-free groom (docs/inverse.md, "The sag-free groom").
constexpr const char* kHairstyleOutputs[] = {"hairstyle.json", "explicit_masters.json"};

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// The sag-free groom of the inverted strands (with --body only: a hairstyle needs a body):
// hairstyle.json, whose masters are given by explicit_masters.json (docs/hairstyle-format.md,
// "Explicit masters"), each with its inverted rest shape, the target as the start of its solve
// (so `ringlet groom` finds the inverted equilibrium, not another one), invert's section,
// material, natural curl and contact clearance, and one hull layer (invert's contact has no
// layer offset). `ringlet groom hairstyle.json` then reproduces the equilibria, and `ringlet
// style` can cut, wet or grow them.
void AddHairstyleOutputs(const InvertArgs& args, const std::vector<StrandModel>& inverted,
                         const std::vector<VecX>& targets,
                         std::vector<std::pair<std::string, std::string>>* files) {
  namespace fs = std::filesystem;
  std::vector<ExplicitMaster> masters(inverted.size());
  for (size_t i = 0; i < inverted.size(); ++i) {
    ExplicitMaster& e = masters[i];
    e = ExplicitMasterOf(inverted[i]);
    e.start_curvatures = targets[i];
    e.clearance = inverted[i].contact.clearance;
  }
  // The body file relative to the output directory when it can be (the outputs move together).
  std::error_code body_ec, out_ec;
  const fs::path body = fs::weakly_canonical(fs::absolute(args.body_path, body_ec), body_ec);
  const fs::path out = fs::weakly_canonical(fs::absolute(args.output_dir, out_ec), out_ec);
  const bool ec = body_ec || out_ec;
  const fs::path relative = ec ? fs::path() : body.lexically_relative(out);
  nlohmann::ordered_json hairstyle = {
      {"description", "sag-free groom written by ringlet invert from " +
                          fs::path(args.target_path).filename().string() +
                          " (docs/inverse.md)"},
      {"body", !relative.empty() ? relative.string()
               : !body_ec        ? body.string()
                                 : args.body_path},
      {"masters", {{"file", kHairstyleOutputs[1]}}},
      {"layers", {{"count", 1}}}};
  if (!args.hair_type.empty()) {
    const size_t slash = args.hair_type.find('/');
    hairstyle["hair"] = {{"origin", args.hair_type.substr(0, slash)}};
    if (slash != std::string::npos) hairstyle["hair"]["curl"] = args.hair_type.substr(slash + 1);
  }
  files->emplace_back(kHairstyleOutputs[0], hairstyle.dump(2) + "\n");
  files->emplace_back(kHairstyleOutputs[1], MastersToString(masters));
}

int RunInvert(const InvertArgs& args) {
  const auto start = std::chrono::steady_clock::now();
  std::string error;
  if (args.up != "z" && args.up != "y") {
    PrintError("--up: expected y or z, got \"" + args.up + "\"");
    return kExitBadInput;
  }
  if (!(std::isfinite(args.units_per_metre) && args.units_per_metre > 0.0)) {
    PrintError("--units-per-metre: expected a finite number > 0");
    return kExitBadInput;
  }
  FitOptions fit_options;
  fit_options.segments = args.segments;
  fit_options.tolerance = args.fit_tolerance;
  if (!fit_options.IsValid(&error)) {
    PrintError("--segments / --fit-tolerance: " + error);
    return kExitBadInput;
  }
  std::vector<std::string> names(std::begin(kOutputs), std::end(kOutputs));
  if (!args.body_path.empty()) {
    names.insert(names.end(), std::begin(kHairstyleOutputs), std::end(kHairstyleOutputs));
  }
  if (!CheckOutputDirectory(args.output_dir, names, args.force, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  // The body (its distance grid: ~2 s of CPU for a head mesh, partly serial) loads while the
  // targets are read and fitted, which do not need it. Its error still comes first: every error
  // path below waits for it (body_failed) before reporting its own.
  struct BodyLoad {
    std::shared_ptr<Body> body;
    std::string error;
  };
  std::future<BodyLoad> body_future;
  if (!args.body_path.empty()) {
    body_future = std::async(std::launch::async, [path = args.body_path] {
      BodyLoad load;
      load.body = std::make_shared<Body>();
      if (!LoadBody(path, load.body.get(), &load.error)) load.body.reset();
      return load;
    });
  }
  std::shared_ptr<const Body> body;
  bool body_done = false;
  // Waits for the body (once); true (and the body's error printed) if it failed.
  const auto body_failed = [&]() {
    if (body_done || !body_future.valid()) return false;
    body_done = true;
    BodyLoad load = body_future.get();
    if (!load.body) {
      PrintError(load.error);
      return true;
    }
    body = std::move(load.body);
    return false;
  };

  // Targets: exact piecewise helices from ringlet's JSON, or fitted polylines.
  const std::string extension = Lower(std::filesystem::path(args.target_path).extension().string());
  std::vector<StrandModel> models;
  std::vector<VecX> targets;
  std::vector<double> fit_max, fit_rms;
  // Per strand, the arc lengths of the target's points on the fitted curve (polyline targets):
  // where equilibrium.hair and naive.hair are sampled unless --points-per-segment is given.
  std::vector<std::vector<double>> sample_arc_lengths;
  const auto fit_start = std::chrono::steady_clock::now();
  if (extension == ".json") {
    std::vector<ExactTarget> exact;
    if (!ReadResultTargets(args.target_path, &exact, &error)) {
      if (!body_failed()) PrintError(error);
      return kExitBadInput;
    }
    for (size_t i = 0; i < exact.size(); ++i) {
      StrandModel m;
      m.segment_lengths = exact[i].segment_lengths;
      m.root_position = exact[i].root_position;
      m.root_frame = exact[i].frame_from_file
                         ? exact[i].root_frame
                         : DefaultRootFrame(exact[i].root_frame.col(2), fit_options.n1_axis);
      models.push_back(std::move(m));
      targets.push_back(exact[i].curvatures);
      fit_max.push_back(0.0);
      fit_rms.push_back(0.0);
    }
  } else if (extension == ".hair" || extension == ".data" || extension == ".usda" ||
             extension == ".obj") {
    // Polylines (strand_targets.h), in metres z up, every strand checked by the reader.
    StrandTargetOptions read_options;
    read_options.units_per_metre = args.units_per_metre;
    read_options.up_axis =
        args.up == "y" ? StrandTargetOptions::UpAxis::kY : StrandTargetOptions::UpAxis::kZ;
    // .usda: the stage's metersPerUnit and upAxis, unless --ignore-usda-metadata (as `ringlet
    // convert`); a unit or axis flag that would be ignored is an error, not a silent default.
    read_options.ignore_file_metadata = args.ignore_usda_metadata;
    if (extension == ".usda" && args.units_given && !args.ignore_usda_metadata) {
      if (body_failed()) return kExitBadInput;
      PrintError("--units-per-metre / --up: " + args.target_path +
                 " is a .usda stage, whose metersPerUnit and upAxis apply; add "
                 "--ignore-usda-metadata to use the flags instead");
      return kExitBadInput;
    }
    HairCurves curves;
    StrandTargetSummary read_summary;
    if (!ReadStrandTargets(args.target_path, read_options, &curves, &read_summary, &error)) {
      if (!body_failed()) PrintError(error);
      return kExitBadInput;
    }
    if (curves.NumStrands() == 0) {
      if (!body_failed()) PrintError(args.target_path + ": no strands");
      return kExitBadInput;
    }
    std::vector<std::vector<Vec3>> polylines(static_cast<size_t>(curves.NumStrands()));
    size_t offset = 0;
    for (size_t k = 0; k < polylines.size(); ++k) {
      for (uint32_t p = 0; p < curves.point_counts[k]; ++p) {
        polylines[k].push_back(curves.points[offset + p].cast<double>());
      }
      offset += curves.point_counts[k];
    }
    // A body that already failed (a missing or malformed file fails at once) is reported before
    // the fit, not after it.
    if (body_future.valid() &&
        body_future.wait_for(std::chrono::seconds(0)) == std::future_status::ready &&
        body_failed()) {
      return kExitBadInput;
    }
    std::vector<HelixFit> fits;
    int failed = 0;
    ProgressBar fit_bar("fitting", !args.quiet);
    const bool fitted = FitPiecewiseHelices(
        polylines, fit_options, args.threads, &fits, &failed, &error,
        [&fit_bar](int done, int total) { fit_bar.Update(done, total); });
    fit_bar.Finish();
    if (!fitted) {
      const size_t k = static_cast<size_t>(failed);
      const uint64_t file_index = k < read_summary.file_strand_index.size()
                                      ? read_summary.file_strand_index[k]
                                      : static_cast<uint64_t>(k);
      if (!body_failed()) {
        PrintError(args.target_path + ": strand " + std::to_string(file_index) + ", " + error);
      }
      return kExitBadInput;
    }
    for (const HelixFit& fit : fits) {
      StrandModel m;
      m.segment_lengths = fit.segment_lengths;
      m.root_position = fit.root_position;
      m.root_frame = fit.root_frame;
      models.push_back(std::move(m));
      targets.push_back(fit.curvatures);
      fit_max.push_back(fit.max_distance);
      fit_rms.push_back(fit.rms_distance);
      sample_arc_lengths.push_back(fit.arc_lengths);
    }
  } else {
    if (body_failed()) return kExitBadInput;
    PrintError(args.target_path + ": unknown target format \"" + extension +
               "\" (expected .json: a ringlet result or masters file, or polylines: .hair, "
               ".data, .usda or .obj)");
    return kExitBadInput;
  }
  const double fit_seconds = SecondsSince(fit_start);
  if (body_failed()) return kExitBadInput;
  for (size_t i = 0; i < models.size(); ++i) {
    // The hair type's section, material and natural curl (or the paper's defaults).
    if (!ApplyInverseHairType(args.hair_type, i, &models[i], &error)) {
      PrintError("--hair-type: " + error);
      return kExitBadInput;
    }
    models[i].contact.obstacle = body;
    models[i].contact.clearance = args.clearance;
    std::string why;
    if (!IsValid(models[i], &why)) {
      PrintError(args.target_path + ": strand " + std::to_string(i) + ": " + why);
      return kExitBadInput;
    }
  }

  const auto invert_start = std::chrono::steady_clock::now();
  InverseOptions inverse_options;
  inverse_options.contact_forces = !args.no_support_forces;
  inverse_options.naive = !args.no_naive;
  ProgressBar invert_bar("inverting", !args.quiet);
  const std::vector<InverseResult> results =
      InvertStrands(models, targets, inverse_options, args.threads,
                    [&invert_bar](int done, int total) { invert_bar.Update(done, total); });
  invert_bar.Finish();
  const double invert_seconds = SecondsSince(invert_start);

  // Outputs, encoded before anything is written. Each file is encoded by its own task (the
  // scene, the masters and the summary are ~5 s of serial work for 50,000 strands), the curves
  // strand by strand in parallel; every output is the same on any thread count.
  tbb::task_arena arena(args.threads > 0 ? args.threads : tbb::task_arena::automatic);
  std::vector<StrandModel> inverted = models;
  for (size_t i = 0; i < models.size(); ++i) {
    inverted[i].rest_curvatures = results[i].rest_curvatures;
    inverted[i].contact.support_offsets = results[i].support_offsets;
  }
  // Per strand, its points in equilibrium.hair and naive.hair: at the target's points (a point
  // per target point, at its arc length on the fitted curve), or k points per helical segment
  // (--points-per-segment; exact targets: 4).
  std::vector<std::vector<Vec3>> equilibrium_points(models.size()), naive_points(models.size());
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, models.size()),
                      [&](const tbb::blocked_range<size_t>& range) {
                        for (size_t i = range.begin(); i < range.end(); ++i) {
                          const InverseResult& r = results[i];
                          const auto sample = [&](const VecX& q) {
                            return args.points_per_segment == 0 && i < sample_arc_lengths.size()
                                       ? SampleCentrelineAt(models[i], q, sample_arc_lengths[i])
                                       : SampleCentreline(models[i], q,
                                                          args.points_per_segment > 0
                                                              ? args.points_per_segment
                                                              : 4);
                          };
                          equilibrium_points[i] = sample(r.equilibrium);
                          if (!args.no_naive) naive_points[i] = sample(r.naive_equilibrium);
                        }
                      });
  });
  HairCurves equilibrium, naive;
  for (auto [curves, points] :
       {std::pair{&equilibrium, &equilibrium_points}, std::pair{&naive, &naive_points}}) {
    if (curves == &naive && args.no_naive) continue;
    for (size_t i = 0; i < models.size(); ++i) {
      const std::vector<Vec3>& strand = (*points)[i];
      curves->point_counts.push_back(static_cast<uint32_t>(strand.size()));
      for (const Vec3& p : strand) {
        curves->points.push_back(p.cast<float>());
        curves->widths.push_back(static_cast<float>(2.0 * models[i].section.MeanRadius()));
      }
    }
    std::vector<std::vector<Vec3>>().swap(*points);  // copied into the curves: freed
  }
  nlohmann::ordered_json summary;
  std::string scene_text;
  std::vector<std::pair<std::string, std::string>> hair_files(2), hairstyle_files;
  std::string hair_errors[2];
  HairFileOptions hair_options;
  hair_options.units_per_metre = args.units_per_metre;
  arena.execute([&] {
    tbb::task_group group;
    group.run([&] {
      summary = InversionSummary(models, results, fit_max, fit_rms, fit_seconds, invert_seconds);
    });
    group.run([&] { scene_text = SceneToString(inverted); });
    if (!args.body_path.empty()) {
      group.run([&] { AddHairstyleOutputs(args, inverted, targets, &hairstyle_files); });
    }
    for (int k = 0; k < 2; ++k) {
      if (k == 1 && args.no_naive) continue;
      group.run([&, k] {
        hair_files[static_cast<size_t>(k)].first = k == 0 ? "equilibrium.hair" : "naive.hair";
        if (!EncodeHairFile(k == 0 ? equilibrium : naive, hair_options,
                            &hair_files[static_cast<size_t>(k)].second,
                            &hair_errors[static_cast<size_t>(k)])) {
          hair_files[static_cast<size_t>(k)].first.clear();
        }
      });
    }
    group.wait();
  });
  const int n = summary["strands"].get<int>();
  const int unstable = summary["unstable"].get<int>();
  const int unconverged = summary["unconverged"].get<int>();
  const double max_fit = summary["fit_max_distance"].get<double>();
  const double max_fit_l = summary["fit_max_distance_per_length"].get<double>();
  const double max_dev = summary["max_deviation"].get<double>();
  const double max_dev_l = summary["max_deviation_per_length"].get<double>();
  const double max_naive = summary["naive_max_deviation"].get<double>();
  const double max_naive_l = summary["naive_max_deviation_per_length"].get<double>();
  summary["naive"] = !args.no_naive;
  if (args.no_naive) {
    // No naive solve: no naive deviations (0 would read as "the naive rest shape holds").
    summary.erase("naive_max_deviation");
    summary.erase("naive_max_deviation_per_length");
    for (auto& strand : summary["strand_results"]) strand.erase("naive_deviation");
  }
  std::vector<std::pair<std::string, std::string>> files;
  files.emplace_back("rest_shapes.json", std::move(scene_text));
  for (int k = 0; k < 2; ++k) {
    if (k == 1 && args.no_naive) continue;
    if (hair_files[static_cast<size_t>(k)].first.empty()) {
      PrintError(std::string(k == 0 ? "equilibrium.hair" : "naive.hair") + ": " +
                 hair_errors[static_cast<size_t>(k)]);
      return kExitBadInput;
    }
    files.push_back(std::move(hair_files[static_cast<size_t>(k)]));
  }
  for (auto& file : hairstyle_files) files.push_back(std::move(file));
  summary["seconds"] = SecondsSince(start);
  files.emplace_back("summary.json", summary.dump(1) + "\n");
  if (!WriteOutputFiles(args.output_dir, files, args.force, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  if (args.no_naive) {
    // A naive.hair of an earlier run (only there with --force: CheckOutputDirectory) would be
    // read as this run's.
    std::error_code ec;
    std::filesystem::remove(std::filesystem::path(args.output_dir) / "naive.hair", ec);
  }
  if (!args.quiet) {
    const std::string naive_text =
        args.no_naive ? std::string(" (naive solve skipped)")
                      : Format(", with the naive ones %.3g m (%.3g L)", max_naive, max_naive_l);
    std::printf(
        "inverted %d strands: fit max %.3g m (%.3g L), deviation with the inverted rest shapes "
        "max %.3g m (%.3g L)%s; %d unstable, %d unconverged; fit %s, inversion %s, total %s -> "
        "%s\n",
        n, max_fit, max_fit_l, max_dev, max_dev_l, naive_text.c_str(), unstable, unconverged,
        FormatSeconds(fit_seconds).c_str(), FormatSeconds(invert_seconds).c_str(),
        FormatSeconds(SecondsSince(start)).c_str(), args.output_dir.c_str());
    std::fflush(stdout);
    if (unstable + unconverged > 0) {
      // Without a body, nothing holds a strand that lies on the head: the likely fix.
      PrintWarning(Format("%d of %d targets cannot be held stably (see summary.json)%s",
                          unstable + unconverged, n,
                          args.body_path.empty()
                              ? "; without --body nothing supports strands that rest on the "
                                "head or body: pass --body BODY.json (docs/inverse.md)"
                              : ""));
    }
  }
  return unstable + unconverged == 0 ? kExitSuccess : kExitUnsolved;
}

}  // namespace

Command AddInvertCommand(CLI::App* parent) {
  auto args = std::make_shared<InvertArgs>();
  CLI::App* app = parent->add_subcommand(
      "invert",
      "Inverse statics: rest shapes that hold target strands under gravity (and body contact), "
      "certified stable and verified by the forward solve; writes rest_shapes.json (a scene), "
      "equilibrium.hair, naive.hair and summary.json, and with --body hairstyle.json + "
      "explicit_masters.json (a sag-free groom for ringlet groom / style). Exit code 0 when "
      "every target holds stably, 2 when some cannot (files still written), 1 on bad usage or "
      "input.");
  app->add_option("target", args->target_path,
                  "Target strands: a ringlet result or masters JSON (exact), or polylines "
                  "(fitted): .hair, .data (USC-HairSalon), .usda (linear BasisCurves), .obj")
      ->required();
  app->add_option("-o,--output", args->output_dir, "Output directory (created if missing)")
      ->required();
  app->add_option("--body", args->body_path,
                  "Body file (JSON, docs/body.md) for contact; also writes hairstyle.json and "
                  "explicit_masters.json, a sag-free groom on that body");
  app->add_option("--clearance", args->clearance, "Contact clearance (m), default 0")
      ->check(CLI::Range(0.0, 0.1));
  app->add_option("--hair-type", args->hair_type,
                  "Hair type ORIGIN or ORIGIN/CURL (docs/hair-types.md) for the section, material "
                  "and natural curl; default: the paper's 50-um straight fibre");
  app->add_option("--segments", args->segments,
                  "Segments per fitted polyline (default 0: the fewest meeting --fit-tolerance)")
      ->check(CLI::Range(0, kMaxSegments));
  app->add_option("--fit-tolerance", args->fit_tolerance,
                  "Largest fit distance in units of the strand length (default 1e-3)");
  CLI::Option* units = app->add_option(
      "--units-per-metre", args->units_per_metre,
      "Length units per metre of polyline targets (.hair, .data, .obj; .usda only with "
      "--ignore-usda-metadata), default 1 (100: cm); also the unit of the written .hair files");
  CLI::Option* up = app->add_option(
      "--up", args->up,
      "Up axis of polyline targets: z (default) or y, rotated to z up by (x, y, z) -> "
      "(x, -z, y) (.usda only with --ignore-usda-metadata)");
  app->add_flag("--ignore-usda-metadata", args->ignore_usda_metadata,
                "Use --units-per-metre and --up for a .usda target instead of its stage's "
                "metersPerUnit and upAxis");
  app->add_flag("--no-support-forces", args->no_support_forces,
                "Do not treat the body's contact forces as unknowns: use the penalty forces the "
                "forward model gives at the target (zero unless it enters the clearance layer)");
  app->add_flag("--no-naive", args->no_naive,
                "Skip the forward solve of the naive rest shape (rest = target), the comparison "
                "that shows the sag: no naive.hair, no naive deviations in summary.json (a "
                "quarter of the inversion's time on hair lying on a body)");
  app->add_flag("--force", args->force, "Overwrite existing output files");
  app->add_option("--threads", args->threads, "Worker threads (default 0: all cores)")
      ->check(CLI::Range(0, 1024));
  app->add_option("--points-per-segment", args->points_per_segment,
                  "Points per helical segment in equilibrium.hair and naive.hair (default 0: a "
                  "point for each target point, at its arc length, for polyline targets; 4 for "
                  "exact JSON targets)")
      ->check(CLI::Range(0, 1000));
  app->add_flag("-q,--quiet", args->quiet, "Print no summary (errors still go to stderr)");
  return Command{app, [args, units, up] {
                   args->units_given = units->count() + up->count() > 0;
                   return RunInvert(*args);
                 }};
}

}  // namespace ringlet::cli
