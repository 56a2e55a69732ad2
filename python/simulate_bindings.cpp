// ringlet.simulate: hair in motion (simulate.h; docs/dynamics.md, docs/python.md), as
// `ringlet simulate` does it, returning the frames as numpy arrays.
#include <pybind11/stl.h>

#include <stdexcept>
#include <atomic>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "bindings.h"
#include "ringlet/atomic_file.h"
#include "ringlet/motion_json.h"
#include "ringlet/render_json.h"
#include "ringlet/simulate.h"
#include "types.h"

namespace ringlet::python {
namespace {

// Whether a path names a scene (a JSON object with "strands") rather than a hairstyle.
bool PathIsScene(const std::string& path) {
  std::string text, error;
  if (!ReadFile(path, &text, &error)) throw Error(error);
  const nlohmann::json document = nlohmann::json::parse(text, nullptr, false);
  return document.is_object() && document.contains("strands");
}

HeadMotion MotionFrom(py::handle motion, const Vec3& pivot, const Vec3& up, const Vec3& left) {
  std::string error;
  HeadMotion result;
  if (py::isinstance<py::dict>(motion)) {
    if (!ParseMotionText(ToJson(motion, "motion").dump(), pivot, &result, &error)) {
      throw Error("motion: " + error);
    }
    return result;
  }
  if (py::isinstance<py::str>(motion) || py::hasattr(motion, "__fspath__")) {
    const std::string name = py::str(py::module_::import("os").attr("fspath")(motion));
    MotionPreset preset;
    if (MotionPresetFromName(name, &preset)) return HeadMotion::Preset(preset, pivot, up, left);
    if (name.size() < 5 || name.substr(name.size() - 5) != ".json") {
      throw Error("motion: expected nod, shake, turn, walk, none, a motion file (.json) or a "
                  "motion dict, got " + std::string(py::repr(motion)));
    }
    if (!LoadMotion(name, pivot, &result, &error)) throw Error(error);
    return result;
  }
  throw Error("motion: expected nod, shake, turn, walk, none, a motion file (.json) or a "
              "motion dict, got " + std::string(py::repr(motion)));
}

}  // namespace

void BindSimulate(py::module_& m) {
  m.def(
      "simulate",
      [](py::object input, py::object motion, double duration, double fps, long long substeps,
         const std::string& integrator, double model_tolerance, long long mass_points,
         py::object pivot, long long threads,
         const std::string& base_directory, py::object progress) {
        BatchProgress reports(std::move(progress), "progress");
        CheckThreads(threads);
        SimulationOptions options;
        RequireNumber(duration > 0.0, duration, "duration", "a finite number > 0 (s)");
        RequireNumber(fps > 0.0, fps, "fps", "a finite number > 0 (frames per second)");
        if (substeps < 1 || substeps > kMaxSubsteps) {
          throw Error("substeps: expected an integer between 1 and " +
                      std::to_string(kMaxSubsteps) + ", got " + std::to_string(substeps));
        }
        options.duration = duration;
        options.fps = fps;
        options.substeps = static_cast<int>(substeps);
        if (integrator == "bdf2") {
          options.dynamics.integrator = Integrator::kBdf2;
        } else if (integrator != "backward_euler") {
          throw Error("integrator: expected \"backward_euler\" or \"bdf2\", got \"" + integrator +
                      "\"");
        }
        RequireNumber(model_tolerance >= 0.0 && model_tolerance < 1.0, model_tolerance,
                      "model_tolerance", "a number in [0, 1) (0 = Newton to the tolerance)");
        if (mass_points < 1 || mass_points > 8) {
          throw Error("mass_points: expected an integer in 1..8, got " +
                      std::to_string(mass_points));
        }
        options.dynamics.model_tolerance = model_tolerance;
        options.dynamics.mass_points = static_cast<int>(mass_points);
        std::string error;
        if (!options.IsValid(&error)) throw Error(error);

        // The input: a Groom, a hairstyle (Hairstyle, dict, path) or single strands.
        std::shared_ptr<const GroomResult> groomed;
        std::shared_ptr<const HairstyleFile> hairstyle;
        Scene scene;
        bool scene_input = false;
        if (py::isinstance<GroomResult>(input)) {
          groomed = std::make_shared<GroomResult>(input.cast<const GroomResult&>());
          hairstyle = groomed->hairstyle;
        } else if (py::isinstance<HairstyleFile>(input)) {
          hairstyle = input.cast<std::shared_ptr<HairstyleFile>>();
        } else if (py::isinstance<py::dict>(input)) {
          scene_input = input.contains("strands");
          if (scene_input) {
            scene = SceneFrom(input);
          } else {
            hairstyle = HairstyleFrom(input, base_directory);
          }
        } else if (py::isinstance<py::str>(input) || py::hasattr(input, "__fspath__")) {
          const std::string path = py::str(py::module_::import("os").attr("fspath")(input));
          scene_input = PathIsScene(path);
          if (scene_input) {
            scene = SceneFrom(input);
          } else {
            hairstyle = HairstyleFrom(input, base_directory);
          }
        } else {
          scene_input = true;
          scene = SceneFrom(input);  // StrandModel, list of them, Scene; raises otherwise
        }
        Vec3 pivot_point, up, left;
        if (scene_input) {
          if (scene.strands.empty()) throw Error("strands: expected at least one strand");
          StrandsMotionAxes(scene.strands, &pivot_point, &up, &left);
        } else {
          HairstyleMotionAxes(hairstyle->style, &pivot_point, &up, &left);
        }
        if (!pivot.is_none()) {
          const py::array p = RealArray(pivot, "pivot", "3 finite numbers (m)");
          const auto values = p.attr("astype")("float64").attr("ravel")().cast<std::vector<double>>();
          if (values.size() != 3 || !std::isfinite(values[0]) || !std::isfinite(values[1]) ||
              !std::isfinite(values[2])) {
            throw Error("pivot: expected 3 finite numbers (m), got " +
                        std::string(py::repr(pivot)));
          }
          pivot_point = Vec3(values[0], values[1], values[2]);
        }
        const HeadMotion head = MotionFrom(motion, pivot_point, up, left);
        const int frames = options.NumFrames();

        // The work, with the GIL released: the start's equilibria, then frame after frame.
        std::atomic<bool> cancel{false};
        Groom groom;
        Hairstyle style = hairstyle ? hairstyle->style : Hairstyle{};
        style.solve_children = false;  // the children follow their masters (GrowWisps)
        std::vector<float> points;
        std::vector<std::uint32_t> counts;
        std::vector<FrameSummary> summaries;
        bool failed = false;
        RunInterruptibly(
            [&] {
              std::vector<StrandModel> models;
              std::vector<VecX> start;
              BatchOptions batch;
              batch.threads = static_cast<int>(threads);
              batch.cancel = &cancel;
              if (scene_input) {
                for (const StrandSolution& s : SolveStrands(scene.strands, scene.solver, batch)) {
                  start.push_back(s.curvatures);
                }
                if (cancel.load()) return;
                models = scene.strands;
              } else {
                if (groomed) {
                  groom = groomed->groom;
                } else if (!GroomHairstyle(style, batch, &groom, &error)) {
                  failed = true;
                  return;
                }
                models = groom.masters.models;
                for (const StrandSolution& s : groom.solutions) start.push_back(s.curvatures);
              }
              std::unique_ptr<Simulation> owned;
              try {
                owned = std::make_unique<Simulation>(models, start, head, options);
              } catch (const std::invalid_argument& e) {
                error = e.what();
                failed = true;
                return;
              }
              Simulation& simulation = *owned;
              auto record = [&]() -> bool {
                HairCurves curves;
                if (scene_input) {
                  curves = SimulationStrands(simulation, 4);
                } else {
                  std::vector<VecX> q;
                  for (int i = 0; i < simulation.NumStrands(); ++i) {
                    q.push_back(simulation.strand(i).state().curvatures);
                  }
                  if (!GroomFrameStrands(style, groom.masters, q, head, simulation.summary().time,
                                         &curves, &error)) {
                    return false;
                  }
                }
                if (counts.empty()) {
                  counts = curves.point_counts;
                  if (static_cast<long long>(curves.NumPoints()) * frames > kMaxPointFrames) {
                    error = "duration x fps: " + std::to_string(frames) + " frames of " +
                            std::to_string(curves.NumPoints()) + " points exceed " +
                            std::to_string(kMaxPointFrames) + " point samples";
                    return false;
                  }
                }
                for (const Vec3f& x : curves.points) points.insert(points.end(), {x.x(), x.y(), x.z()});
                summaries.push_back(simulation.summary());
                return true;
              };
              if (!record()) {
                failed = true;
                return;
              }
              auto report = reports.Reporter();
              if (report) report(1, frames);
              while (!simulation.Done()) {
                if (!simulation.Advance(static_cast<int>(threads), &cancel)) return;
                if (!record()) {
                  failed = true;
                  return;
                }
                if (report) report(simulation.frame() + 1, frames);
              }
            },
            &cancel, reports.Tick());
        if (failed) throw Error(error);

        const py::ssize_t f = static_cast<py::ssize_t>(summaries.size());
        const py::ssize_t p = f > 0 ? static_cast<py::ssize_t>(points.size()) / (3 * f) : 0;
        std::vector<double> time, kinetic, elastic, gravity, contact, penetration, residual;
        std::vector<std::int64_t> iterations;
        std::vector<std::int32_t> halved, failed_steps;
        py::list messages;
        for (const FrameSummary& s : summaries) {
          time.push_back(s.time);
          kinetic.push_back(s.kinetic);
          elastic.push_back(s.elastic);
          gravity.push_back(s.gravity);
          contact.push_back(s.contact);
          penetration.push_back(s.max_penetration);
          residual.push_back(s.residual);
          iterations.push_back(s.newton_iterations);
          halved.push_back(s.halved_steps);
          failed_steps.push_back(s.failed_steps);
          messages.append(s.message);
        }
        py::dict summary;
        summary["kinetic"] = OwnedArray(std::move(kinetic), {f});
        summary["elastic"] = OwnedArray(std::move(elastic), {f});
        summary["gravity"] = OwnedArray(std::move(gravity), {f});
        summary["contact"] = OwnedArray(std::move(contact), {f});
        summary["max_penetration"] = OwnedArray(std::move(penetration), {f});
        summary["newton_iterations"] = OwnedArray(std::move(iterations), {f});
        summary["halved_steps"] = OwnedArray(std::move(halved), {f});
        summary["failed_steps"] = OwnedArray(std::move(failed_steps), {f});
        summary["residual"] = OwnedArray(std::move(residual), {f});
        summary["message"] = messages;
        py::dict result;
        result["time"] = OwnedArray(std::move(time), {f});
        result["points"] = OwnedArray(std::move(points), {f, p, 3});
        const py::ssize_t strands = static_cast<py::ssize_t>(counts.size());
        result["point_counts"] = OwnedArray(std::move(counts), {strands});
        result["summary"] = summary;
        return result;
      },
      py::arg("input"), py::arg("motion") = "shake", py::arg("duration") = 2.0,
      py::arg("fps") = 24.0, py::arg("substeps") = 1, py::arg("integrator") = "backward_euler",
      py::arg("model_tolerance") = 0.0, py::arg("mass_points") = 6, py::arg("pivot") = py::none(), py::arg("threads") = 0, py::arg("base_directory") = ".",
      py::arg("progress") = py::none(),
      "Simulates hair under a rigid head motion, as `ringlet simulate` does (docs/dynamics.md). "
      "input: a Groom (its masters start from their equilibria), a hairstyle (a Hairstyle, a "
      "dict or a path: groomed first, the children following their masters), or single "
      "strands (a scene dict or path, a StrandModel or a list of them: solved first). motion: "
      "\"nod\", \"shake\", \"turn\", \"walk\", \"none\", a motion file path (.json) or a motion "
      "dict (docs/dynamics.md, \"Motion files\"). duration (s) and fps give frames 0 .. "
      "floor(duration fps); substeps implicit steps per frame; integrator \"backward_euler\" or "
      "\"bdf2\"; model_tolerance in [0, 1): inexact steps (0 = Newton to the tolerance; 0.03 "
      "with mass_points=2 is the fast setting of docs/benchmarks.md); mass_points 1..8 Gauss "
      "points per segment of the kinetic energy; pivot [x, y, z] (m) overrides the default pivot (10 cm below the head "
      "centre, or the mean root of single strands). threads: 0 = all cores (results do not "
      "depend on it). progress(done, total) is called with the frames done about every 20 ms "
      "while it changes, in the calling thread; an exception it raises stops the simulation "
      "and is raised again. Returns a dict: \"time\" (F,), \"points\" (F, P, 3) float32 (every "
      "strand's points, root to tip, strand after strand), \"point_counts\" (S,) uint32, and "
      "\"summary\", a dict of per-frame arrays (kinetic, elastic, gravity, contact in J; "
      "max_penetration in m; newton_iterations, halved_steps, failed_steps; residual in rad) "
      "and a list of messages (\"\" when the frame's steps converged unhalved). Releases the "
      "GIL; Ctrl-C stops it (KeyboardInterrupt).");
}

}  // namespace ringlet::python
