// `ringlet simulate INPUT -o OUTDIR/ --motion MOTION`: hair in motion (docs/dynamics.md,
// "ringlet simulate"). INPUT is a hairstyle (its masters groomed to their certified equilibrium,
// then simulated; the children follow their masters each frame) or a scene of single strands
// (each solved, then simulated). The head moves rigidly by a preset or a motion file; every
// frame goes into one time-sampled hair.usda and a line of frames.jsonl, optionally a .hair and
// a rendered PNG per frame and an MP4 through ffmpeg. The files are streamed as the frames come
// into a staging directory put in place at the end, all or none (StagedDirectory).
//
// Exit codes: 0 every step converged (halved steps are reported, not failures), 2 some step
// failed even after halving (files are still written, frames.jsonl says where), 1 bad usage or
// input (nothing is written).
#include <CLI/CLI.hpp>
#include <sys/wait.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "commands.h"
#include "format.h"
#include "outputs.h"
#include "progress.h"
#include "render_image.h"
#include "ringlet/atomic_file.h"
#include "ringlet/hair_file.h"
#include "ringlet/hairstyle.h"
#include "ringlet/hairstyle_json.h"
#include "ringlet/motion.h"
#include "ringlet/motion_json.h"
#include "ringlet/png_image.h"
#include "ringlet/render.h"
#include "ringlet/render_json.h"
#include "ringlet/scene_json.h"
#include "ringlet/simulate.h"
#include "ringlet/split_body.h"
#include "ringlet/strand_export.h"
#include "ringlet/styling.h"
#include "ringlet/usd_export.h"

namespace ringlet::cli {
namespace {

namespace fs = std::filesystem;

struct SimulateArgs {
  std::string input_path;
  std::string output_dir;
  std::string motion = "";
  double duration = 2.0;
  double fps = 24.0;
  int substeps = 1;
  std::string integrator = "backward_euler";
  double model_tolerance = 0.0;  // DynamicsOptions::model_tolerance
  int mass_points = 6;           // DynamicsOptions::mass_points
  std::vector<double> pivot;  // empty: the default pivot
  bool hair_per_frame = false;
  bool render = false;
  int width = 320;
  int height = 320;
  int spp = 4;
  bool force = false;
  bool quiet = false;
  int threads = 0;
};

// After a failure once the outputs are being written: the staging directory is removed.
constexpr const char* kNothingWritten = " (nothing was written)";

// Points per segment of the strands of a scene (SimulationStrands).
constexpr int kScenePointsPerSegment = 4;

std::string FrameName(int frame, const char* extension) {
  char name[64];
  std::snprintf(name, sizeof name, "frame_%04d.%s", frame, extension);
  return name;
}

// One line of frames.jsonl.
std::string FrameLine(const FrameSummary& s) {
  nlohmann::ordered_json line = {{"frame", s.frame},
                                 {"time", s.time},
                                 {"kinetic", s.kinetic},
                                 {"elastic", s.elastic},
                                 {"gravity", s.gravity},
                                 {"contact", s.contact},
                                 {"max_penetration", s.max_penetration},
                                 {"newton_iterations", s.newton_iterations},
                                 {"halved_steps", s.halved_steps},
                                 {"failed_steps", s.failed_steps},
                                 {"residual", s.residual}};
  if (!s.message.empty()) line["message"] = s.message;
  return line.dump() + "\n";
}

bool IsScene(const std::string& path, bool* scene, std::string* error) {
  std::string text;
  if (!ReadFile(path, &text, error)) return false;
  const nlohmann::json document = nlohmann::json::parse(text, nullptr, false);
  *scene = document.is_object() && document.contains("strands");
  return true;
}

// Runs ffmpeg on DIRECTORY/frame_%04d.png (the staging directory) into a temporary file
// outside it, then writes the video as hair.mp4 of the output. False with a one-line reason.
bool EncodeVideo(const std::string& directory, double fps, StagedDirectory* output,
                 std::string* error) {
  char temporary[] = "/tmp/ringlet_simulate_XXXXXX.mp4";
  const int fd = mkstemps(temporary, 4);
  if (fd < 0) {
    *error = "hair.mp4: cannot create a temporary file";
    return false;
  }
  close(fd);
  const std::string pattern = (fs::path(directory) / "frame_%04d.png").string();
  const std::string rate = Format("%.17g", fps);
  const pid_t pid = fork();
  if (pid == 0) {
    execlp("ffmpeg", "ffmpeg", "-loglevel", "error", "-y", "-framerate", rate.c_str(),
           "-start_number", "0", "-i", pattern.c_str(), "-c:v", "libx264", "-pix_fmt", "yuv420p",
           "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", temporary, static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  if (pid < 0 || waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::remove(temporary);
    *error = "hair.mp4: ffmpeg failed (exit status " +
             std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) + ")";
    return false;
  }
  std::string video;
  const bool read = ReadFile(temporary, &video, error, kMaxHairFileBytes);
  std::remove(temporary);
  if (!read) return false;
  return output->WriteFile("hair.mp4", video, error);
}

bool OnPath(const char* program) {
  const char* path = std::getenv("PATH");
  if (!path) return false;
  std::string list = path;
  size_t start = 0;
  while (start <= list.size()) {
    const size_t end = std::min(list.find(':', start), list.size());
    const fs::path candidate = fs::path(list.substr(start, end - start)) / program;
    if (access(candidate.c_str(), X_OK) == 0) return true;
    start = end + 1;
  }
  return false;
}

int RunSimulate(const SimulateArgs& args) {
  std::string error;
  // Options first (no file read), then the input, then the outputs, then the work.
  SimulationOptions options;
  options.duration = args.duration;
  options.fps = args.fps;
  options.substeps = args.substeps;
  if (args.integrator == "bdf2") {
    options.dynamics.integrator = Integrator::kBdf2;
  } else if (args.integrator != "backward_euler") {
    PrintError("--integrator: expected backward_euler or bdf2, got \"" + args.integrator + "\"");
    return kExitBadInput;
  }
  if (!(std::isfinite(args.model_tolerance) && args.model_tolerance >= 0.0 &&
        args.model_tolerance < 1.0)) {
    PrintError("--model-tolerance: expected a number in [0, 1) (0 = Newton to the tolerance), "
               "got " + Format("%g", args.model_tolerance));
    return kExitBadInput;
  }
  if (args.mass_points < 1 || args.mass_points > 8) {
    PrintError("--mass-points: expected an integer in 1..8, got " +
               std::to_string(args.mass_points));
    return kExitBadInput;
  }
  options.dynamics.model_tolerance = args.model_tolerance;
  options.dynamics.mass_points = args.mass_points;
  if (!options.IsValid(&error)) {
    PrintError("--" + error);
    return kExitBadInput;
  }
  if (!args.pivot.empty() && args.pivot.size() != 3) {
    PrintError("--pivot: expected 3 numbers X,Y,Z (m)");
    return kExitBadInput;
  }
  if (!args.render && (args.width != 320 || args.height != 320 || args.spp != 4)) {
    PrintError("--width, --height, --spp: only with --render");
    return kExitBadInput;
  }
  if (args.render && !CheckRenderSize(args.width, args.height, args.spp, &error)) {
    PrintError("--width, --height, --spp: " + error);
    return kExitBadInput;
  }
  MotionPreset preset = MotionPreset::kNone;
  const bool motion_file = !MotionPresetFromName(args.motion, &preset);
  if (motion_file && fs::path(args.motion).extension() != ".json") {
    PrintError("--motion: expected nod, shake, turn, walk, none or a motion file (.json), got \"" +
               args.motion + "\"");
    return kExitBadInput;
  }

  bool scene_input = false;
  if (!IsScene(args.input_path, &scene_input, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  Scene scene;
  Hairstyle style;
  RenderSettings render_settings;
  Vec3 pivot = Vec3::Zero(), up = Vec3::UnitZ(), left = -Vec3::UnitX();
  if (scene_input) {
    if (!LoadScene(args.input_path, &scene, &error)) {
      PrintError(error);
      return kExitBadInput;
    }
    StrandsMotionAxes(scene.strands, &pivot, &up, &left);
  } else {
    std::vector<StyleOperation> operations;
    if (!LoadHairstyle(args.input_path, &style, &operations, &error) ||
        !LoadRenderSettings(args.input_path, &render_settings, &error)) {
      PrintError(error);
      return kExitBadInput;
    }
    HairstyleMotionAxes(style, &pivot, &up, &left);
  }
  if (!args.pivot.empty()) pivot = Vec3(args.pivot[0], args.pivot[1], args.pivot[2]);
  HeadMotion motion;
  if (motion_file) {
    if (!LoadMotion(args.motion, pivot, &motion, &error)) {
      PrintError(error);
      return kExitBadInput;
    }
  } else {
    motion = HeadMotion::Preset(preset, pivot, up, left);
  }
  const int frames = options.NumFrames();
  std::vector<std::string> names = {"hair.usda", "frames.jsonl"};
  for (int f = 0; args.hair_per_frame && f < frames; ++f) names.push_back(FrameName(f, "hair"));
  for (int f = 0; args.render && f < frames; ++f) names.push_back(FrameName(f, "png"));
  if (args.render) names.push_back("hair.mp4");
  if (!CheckOutputDirectory(args.output_dir, names, args.force, &error)) {
    PrintError(error);
    return kExitBadInput;
  }

  // The start: certified equilibria.
  const auto start = std::chrono::steady_clock::now();
  std::vector<StrandModel> models;
  std::vector<VecX> equilibria;
  Groom groom;
  int unconverged = 0;
  if (scene_input) {
    ProgressBar bar("solving", !args.quiet);
    BatchOptions batch;
    batch.threads = args.threads;
    batch.progress = [&bar](int done, int total) { bar.Update(done, total); };
    const std::vector<StrandSolution> solutions = SolveStrands(scene.strands, scene.solver, batch);
    bar.Finish();
    models = scene.strands;
    for (const StrandSolution& s : solutions) {
      equilibria.push_back(s.curvatures);
      if (!s.summary.Converged()) ++unconverged;
    }
  } else {
    Hairstyle procedural = style;
    procedural.solve_children = false;  // the children follow their masters (GrowWisps)
    if (!GroomWithProgress(procedural, args.threads, args.quiet, &groom, &error)) {
      PrintError(args.input_path + ": " + error);
      return kExitBadInput;
    }
    style = procedural;
    models = groom.masters.models;
    for (const StrandSolution& s : groom.solutions) equilibria.push_back(s.curvatures);
    unconverged = groom.summary.unconverged + groom.summary.unstable;
  }
  if (models.empty()) {
    PrintError(args.input_path + ": no strand to simulate");
    return kExitBadInput;
  }

  std::unique_ptr<Simulation> simulation;
  try {
    simulation = std::make_unique<Simulation>(models, equilibria, motion, options);
  } catch (const std::invalid_argument& e) {
    PrintError(args.input_path + ": " + e.what());
    return kExitBadInput;
  }

  // The strands of the current frame. A groom's: GroomFrameStrands' result, computed without
  // reallocating a full head's arrays every frame: the wisps at rest are grown once
  // (GrowWisps) and then regrown in place for every master (RegrowWisps: bit-identical to
  // GrowWisps, wisps in parallel), then carried by the head pose (PoseStrands, as
  // GroomFrameStrands). The rest pose (for rendering) is the
  // wisps at rest themselves: GroomFrameStrands at the identity pose changes no value (at most
  // the sign of a zero coordinate; the rendered PNGs are cmp-identical to main's).
  HairCurves wisps;
  bool wisps_grown = false;
  std::vector<int> all_masters;
  std::vector<StrandSolution> frame_solutions;
  auto frame_strands = [&](HairCurves* curves, HairCurves* rest) -> bool {
    if (scene_input) {
      *curves = SimulationStrands(*simulation, kScenePointsPerSegment);
      if (rest) {
        // The strands carried back to the head at rest (rendering: the body does not move).
        const RigidPose pose = motion.Pose(simulation->summary().time);
        *rest = *curves;
        const Vec3 shift = motion.pivot() + pose.translation;
        for (Vec3f& x : rest->points) {
          x = (motion.pivot() + pose.rotation.transpose() * (x.cast<double>() - shift)).cast<float>();
        }
        for (Vec3f& a : rest->major_axes) a = pose.rotation.transpose().cast<float>() * a;
      }
      return true;
    }
    const int n = simulation->NumStrands();
    frame_solutions.resize(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) {
      frame_solutions[static_cast<size_t>(i)].curvatures = simulation->strand(i).state().curvatures;
    }
    if (!wisps_grown) {
      if (!GrowWisps(style, groom.masters, frame_solutions, &wisps, &error)) return false;
      wisps_grown = true;
      all_masters.resize(static_cast<size_t>(n));
      for (int i = 0; i < n; ++i) all_masters[static_cast<size_t>(i)] = i;
    } else if (!RegrowWisps(style, groom.masters, frame_solutions, all_masters, &wisps, &error)) {
      return false;
    }
    *curves = wisps;  // the same sizes every frame: no reallocation
    PoseStrands(motion, simulation->summary().time, curves);
    SetMelaninColours(render_settings, curves);
    if (rest) *rest = wisps;
    return true;
  };

  HairCurves first;
  if (!frame_strands(&first, nullptr)) {
    PrintError(args.input_path + ": " + error);
    return kExitBadInput;
  }

  // Rendering: in the frame of the head at rest (the body does not move there), with the
  // camera and the key light carried by the inverse head pose, so that the picture is the one
  // of a fixed camera watching the head move (docs/dynamics.md, "Rendering").
  RenderSettings frame_settings = render_settings;
  frame_settings.options.width = args.width;
  frame_settings.options.height = args.height;
  frame_settings.options.samples_per_pixel = args.spp;
  frame_settings.options.threads = args.threads;
  Camera camera;
  bool have_camera = false;
  std::shared_ptr<const Body> render_body = scene_input ? scene.body : style.body;
  auto render_frame = [&](const HairCurves& rest, std::string* png) -> bool {
    const RigidPose pose = motion.Pose(simulation->summary().time);
    const Mat3 back = pose.rotation.transpose();
    // A torso that does not turn with the head (split_body.h) is drawn where it is: in the
    // head's rest frame, turned back by R^T about the pivot.
    std::shared_ptr<const Body> frame_body = render_body;
    if (render_body && render_body->HasTorsoPart() && pose.rotation != Mat3::Identity()) {
      auto moved = std::make_shared<Body>();
      if (!MoveBodyParts(*render_body, Mat3::Identity(), Vec3::Zero(), back,
                         motion.pivot() - back * motion.pivot(), moved.get(), &error)) {
        return false;
      }
      frame_body = std::move(moved);
    }
    RenderScene render_scene;
    const double eccentricity = scene_input ? 0.0 : HairTypeEccentricity(style.hair_type);
    if (!MakeRenderScene(frame_settings, &rest, frame_body, eccentricity, style.seed,
                         &render_scene, &error)) {
      return false;
    }
    if (!have_camera) {
      camera = render_scene.camera;  // framed on frame 0, then fixed in the world
      have_camera = true;
    }
    const Vec3 shift = motion.pivot() + pose.translation;
    auto to_rest = [&](const Vec3& x) { return Vec3(motion.pivot() + back * (x - shift)); };
    render_scene.camera = camera;
    render_scene.camera.position = to_rest(camera.position);
    render_scene.camera.look_at = to_rest(camera.look_at);
    render_scene.camera.up = back * camera.up;
    render_scene.key.direction = back * render_scene.key.direction;
    Image image;
    RenderStats stats;
    if (!Render(render_scene, frame_settings.options, &image, &stats, &error)) return false;
    return EncodePng(image, frame_settings.exposure, png, &error);
  };

  // The outputs are written as the frames come, into a staging directory put in place at the
  // end, all or none (StagedDirectory; SIGINT / SIGTERM remove it): memory does not grow with
  // the frame count.
  StagedDirectory output;
  if (!output.Open(args.output_dir, args.force, &error)) {
    PrintError(error);
    return kExitBadInput;
  }
  StagedDirectory::File usda_file, jsonl_file;
  UsdaSequenceWriter usda;
  UsdExportOptions usd;
  usd.start_time_code = 0;
  usd.time_codes_per_second = options.fps;
  if (!output.Create("hair.usda", &usda_file, &error) ||
      !output.Create("frames.jsonl", &jsonl_file, &error)) {
    PrintError(error + kNothingWritten);
    return kExitBadInput;
  }
  // A failed write names the file and the reason (a full disk); the encoder's own message
  // otherwise.
  auto usda_error = [&](const std::string& why) {
    std::string reason;
    if (!usda_file.Close(&reason)) return reason;
    return "hair.usda: " + why;
  };
  {
    const FileSink sink = [&usda_file](std::string_view piece) { return usda_file.Write(piece); };
    if (!usda.Begin(first, frames, usd, sink, &error)) {
      PrintError(usda_error(error) + kNothingWritten);
      return kExitBadInput;
    }
  }
  HairFileOptions hair_options;
  int halved_frames = 0, failed_frames = 0;
  long halved_total = 0, newton_total = 0;
  bool first_pending = true;  // frame 0's strands are `first`
  HairCurves curves, rest;     // kept from frame to frame: their arrays are reused
  auto record = [&]() -> bool {
    const FrameSummary& s = simulation->summary();
    if (!jsonl_file.Write(FrameLine(s))) return jsonl_file.Close(&error);
    newton_total += s.newton_iterations;
    if (first_pending && !args.render) {
      curves = std::move(first);
    } else if (!frame_strands(&curves, args.render ? &rest : nullptr)) {
      return false;
    }
    first_pending = false;
    if (args.hair_per_frame) {
      std::string bytes;
      if (!EncodeStrands(curves, StrandFormat::kHair, hair_options, &bytes, &error) ||
          !output.WriteFile(FrameName(s.frame, "hair"), bytes, &error)) {
        return false;
      }
    }
    if (args.render) {
      std::string png;
      if (!render_frame(rest, &png)) {
        error = FrameName(s.frame, "png") + ": " + error;
        return false;
      }
      if (!output.WriteFile(FrameName(s.frame, "png"), png, &error)) return false;
    }
    if (!usda.Append(curves, &error)) {
      error = usda_error(error);
      return false;
    }
    if (s.halved_steps > 0 || s.failed_steps > 0) {
      if (s.halved_steps > 0) ++halved_frames;
      if (s.failed_steps > 0) ++failed_frames;
      halved_total += s.halved_steps;
      if (!args.quiet) {
        PrintWarning(Format("frame %d (t = %.6g s): %d strands halved their step, %d failed (%s)",
                            s.frame, s.time, s.halved_steps, s.failed_steps, s.message.c_str()));
      }
    }
    return true;
  };

  // The frame's strands and files on --threads threads (the step makes its own arena).
  tbb::task_arena arena(args.threads > 0 ? args.threads : tbb::task_arena::automatic);
  auto record_in_arena = [&]() {
    bool ok = false;
    arena.execute([&] { ok = record(); });
    return ok;
  };

  const auto simulate_start = std::chrono::steady_clock::now();
  {
    ProgressBar bar("simulating", !args.quiet);
    if (!record_in_arena()) {
      PrintError(error + kNothingWritten);
      return kExitBadInput;
    }
    bar.Update(1, frames);
    while (!simulation->Done()) {
      simulation->Advance(args.threads);
      if (!record_in_arena()) {
        PrintError(error + kNothingWritten);
        return kExitBadInput;
      }
      bar.Update(simulation->frame() + 1, frames);
    }
  }
  const double simulate_seconds = SecondsSince(simulate_start);

  if (!usda.Finish(&error)) {
    PrintError(usda_error(error) + kNothingWritten);
    return kExitBadInput;
  }
  if (!usda_file.Close(&error) || !jsonl_file.Close(&error)) {
    PrintError(error + kNothingWritten);
    return kExitBadInput;
  }
  bool video = false;
  if (args.render) {
    if (!OnPath("ffmpeg")) {
      PrintWarning("ffmpeg is not on PATH: no hair.mp4 (the PNG frames are written; on Debian: "
                   "apt-get install ffmpeg)");
    } else if (!EncodeVideo(output.staging(), options.fps, &output, &error)) {
      PrintWarning(error + "; the PNG frames are written");
    } else {
      video = true;
    }
  }
  if (!output.Commit(&error)) {
    PrintError(error);
    return kExitBadInput;
  }
  if (args.render && !video) {
    // With --force, a video of an earlier run must not stay beside the new frames.
    std::error_code ignored;
    const fs::path stale = fs::path(args.output_dir) / "hair.mp4";
    if (fs::is_regular_file(fs::symlink_status(stale, ignored))) fs::remove(stale, ignored);
  }

  if (!args.quiet) {
    std::printf("simulated %d strand%s (%s motion) for %d frames at %g fps: %ld Newton "
                "iterations, %ld halved steps in %d frames, %d frames with failed steps; "
                "simulation %s, total %s -> %s%s\n",
                simulation->NumStrands(), simulation->NumStrands() == 1 ? "" : "s",
                motion_file ? "file" : MotionPresetName(preset), frames, options.fps,
                newton_total, halved_total, halved_frames, failed_frames,
                FormatSeconds(simulate_seconds).c_str(), FormatSeconds(SecondsSince(start)).c_str(),
                args.output_dir.c_str(), video ? " (with hair.mp4)" : "");
    std::fflush(stdout);
    if (unconverged > 0) {
      PrintWarning(Format("%d strands did not reach a stable equilibrium before the motion; "
                          "they start where their solve ended",
                          unconverged));
    }
  }
  return failed_frames > 0 ? kExitUnsolved : kExitSuccess;
}

}  // namespace

Command AddSimulateCommand(CLI::App* parent) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* app = parent->add_subcommand(
      "simulate",
      "Hair in motion: the strands of a hairstyle (masters from their certified equilibrium, "
      "children following them) or of a scene, with the head moving by a preset or a motion "
      "file; writes hair.usda (time-sampled) and frames.jsonl into the output directory, "
      "optionally a .hair and a PNG per frame and hair.mp4. Exit code 0 when every step "
      "converged, 2 when some failed even after halving (files are still written), 1 on bad "
      "usage or input (nothing is written).");
  app->add_option("input", args->input_path,
                  "Hairstyle file or scene file (JSON; docs/hairstyle-format.md, "
                  "docs/scene-format.md)")
      ->required();
  app->add_option("-o,--output", args->output_dir, "Output directory (created if missing)")
      ->required();
  app->add_option("--motion", args->motion,
                  "nod, shake, turn, walk, none, or a motion file (.json, docs/dynamics.md)")
      ->required();
  app->add_option("--duration", args->duration, "Simulated time (s; default 2)");
  app->add_option("--fps", args->fps, "Frames per second (default 24)");
  app->add_option("--substeps", args->substeps, "Implicit steps per frame (default 1)");
  app->add_option("--integrator", args->integrator, "backward_euler (default) or bdf2");
  app->add_option("--model-tolerance", args->model_tolerance,
                  "Inexact steps: a Newton update whose decrease of the step's potential matches "
                  "its quadratic model within this fraction ends the step (default 0: Newton to "
                  "the tolerance; 0.03 with --mass-points 2 is the fast setting of "
                  "docs/benchmarks.md)");
  app->add_option("--mass-points", args->mass_points,
                  "Gauss points per segment of the kinetic energy, 1..8 (default 6)");
  app->add_option("--pivot", args->pivot,
                  "Pivot of the head motion X,Y,Z (m; default: 10 cm below the head centre, or "
                  "the mean root of a scene)")
      ->delimiter(',')
      ->expected(3);
  app->add_flag("--hair-per-frame", args->hair_per_frame, "Also write frame_NNNN.hair");
  app->add_flag("--render", args->render,
                "Also render frame_NNNN.png (and hair.mp4 when ffmpeg is on PATH)");
  app->add_option("--width", args->width, "Rendered width (pixels; default 320)");
  app->add_option("--height", args->height, "Rendered height (pixels; default 320)");
  app->add_option("--spp", args->spp, "Samples per pixel of the renders (default 4)");
  app->add_option("--threads", args->threads,
                  "Worker threads (default 0: all cores); results do not depend on it")
      ->check(CLI::Range(0, 1024));
  app->add_flag("--force", args->force, "Overwrite existing files in the output directory");
  app->add_flag("-q,--quiet", args->quiet,
                "Print no summary, progress or warning (errors still go to stderr)");
  return Command{app, [args] { return RunSimulate(*args); }};
}

}  // namespace ringlet::cli
