// Inverse statics (inverse.h, docs/inverse.md) for the Python module: the rest shapes that hold
// target polylines under gravity and body contact, as `ringlet invert` computes them, and the
// rest curvatures of a StrandModel. Bindings only: the fit, the inversion and the summary are
// the library's (FitPiecewiseHelices, InvertStrands, InversionSummary).
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "bindings.h"
#include "ringlet/body_json.h"
#include "ringlet/hair_curves.h"
#include "ringlet/hair_type.h"
#include "ringlet/inverse.h"
#include "ringlet/inverse_summary.h"
#include "ringlet/strand_geometry.h"
#include "ringlet/strand_model.h"
#include "types.h"

namespace ringlet::python {

namespace {

// Target polylines from a HairCurves or a sequence of (k, 3) arrays (m, root first).
std::vector<std::vector<Vec3>> PolylinesFrom(py::handle targets) {
  std::vector<std::vector<Vec3>> polylines;
  if (py::isinstance<HairCurves>(targets)) {
    const auto& curves = targets.cast<const HairCurves&>();
    size_t offset = 0;
    for (uint32_t count : curves.point_counts) {
      std::vector<Vec3>& line = polylines.emplace_back();
      for (uint32_t p = 0; p < count; ++p) line.push_back(curves.points[offset + p].cast<double>());
      offset += count;
    }
  } else {
    if (!py::isinstance<py::sequence>(targets) || py::isinstance<py::str>(targets)) {
      throw Error("targets: expected a HairCurves or a list of (k, 3) arrays of points (m)");
    }
    size_t k = 0;
    for (auto item : targets) {
      const std::string where = "targets[" + std::to_string(k++) + "]";
      py::array_t<double, py::array::c_style | py::array::forcecast> a;
      try {
        a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(item);
      } catch (const py::error_already_set&) {
      }
      if (!a || a.ndim() != 2 || a.shape(1) != 3) {
        throw Error(where + ": expected a (k, 3) array of points (m)");
      }
      std::vector<Vec3>& line = polylines.emplace_back();
      for (py::ssize_t j = 0; j < a.shape(0); ++j) {
        const Vec3 p(a.at(j, 0), a.at(j, 1), a.at(j, 2));
        if (!p.allFinite()) {
          throw Error(where + ": point " + std::to_string(j) + " is not finite");
        }
        line.push_back(p);
      }
    }
  }
  if (polylines.empty()) throw Error("targets: expected at least one strand, got none");
  for (size_t k = 0; k < polylines.size(); ++k) {
    if (polylines[k].size() < 2) {
      throw Error("targets[" + std::to_string(k) + "]: expected at least 2 points, got " +
                  std::to_string(polylines[k].size()));
    }
  }
  return polylines;
}

// The JSON summary as Python objects (json.loads of its text).
py::object JsonToPython(const nlohmann::ordered_json& value) {
  return py::module_::import("json").attr("loads")(value.dump());
}

// (k, 3) float64 array of points.
py::array PointsArray(const std::vector<Vec3>& points) {
  std::vector<double> flat;
  flat.reserve(3 * points.size());
  for (const Vec3& p : points) flat.insert(flat.end(), {p.x(), p.y(), p.z()});
  return OwnedArray(std::move(flat), {static_cast<py::ssize_t>(points.size()), 3});
}

}  // namespace

void BindInverse(py::module_& m) {
  // Rest curvatures of a StrandModel (strand_model.h): None for the natural shape.
  auto model_class = py::reinterpret_borrow<py::class_<StrandModel>>(m.attr("StrandModel"));
  model_class.def_property(
      "rest_curvatures",
      [](const StrandModel& model) -> py::object {
        if (model.rest_curvatures.size() == 0) return py::none();
        std::vector<double> q(model.rest_curvatures.data(),
                              model.rest_curvatures.data() + model.rest_curvatures.size());
        return OwnedArray(std::move(q), {model.rest_curvatures.size() / 3, 3});
      },
      [](StrandModel& model, py::object value) {
        if (value.is_none()) {
          model.rest_curvatures.resize(0);
          return;
        }
        const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
        const py::ssize_t n = model.NumSegments();
        if (!a || !((a.ndim() == 2 && a.shape(0) == n && a.shape(1) == 3) ||
                    (a.ndim() == 1 && a.shape(0) == 3 * n))) {
          throw Error("rest_curvatures: expected None or an (n, 3) array of (kappa1, kappa2, "
                      "tau) per segment (1/m), n = " + std::to_string(n));
        }
        VecX q(3 * n);
        for (py::ssize_t i = 0; i < 3 * n; ++i) q[i] = a.data()[i];
        if (!q.allFinite()) throw Error("rest_curvatures: expected finite numbers (1/m)");
        model.rest_curvatures = q;
      },
      "Rest curvatures per segment (kappa1, kappa2, tau) (1/m): an (n, 3) copy, or None for the "
      "natural shape (natural_curvature on every segment). Assign an (n, 3) array or None; "
      "ringlet.invert returns models with the inverted rest shapes.");

  m.def(
      "invert",
      [](py::handle targets, py::object body, const std::string& hair_type, double clearance,
         int segments, double fit_tolerance, bool support_forces, int threads,
         py::object progress) {
        CheckThreads(threads);
        if (!(std::isfinite(clearance) && clearance >= 0.0 && clearance < 0.1)) {
          throw Error("clearance: expected a finite number in [0, 0.1) (m)");
        }
        if (!progress.is_none() && !PyCallable_Check(progress.ptr())) {
          throw Error("progress: expected None or a callable progress(stage, done, total)");
        }
        std::string error;
        FitOptions fit_options;
        fit_options.segments = segments;
        fit_options.tolerance = fit_tolerance;
        if (!fit_options.IsValid(&error)) throw Error("segments / fit_tolerance: " + error);
        const std::vector<std::vector<Vec3>> polylines = PolylinesFrom(targets);
        const std::shared_ptr<const Body> obstacle = BodyFrom(body);
        StrandModel probe;
        if (!ApplyInverseHairType(hair_type, 0, &probe, &error)) {
          throw Error("hair_type: " + error);
        }

        // The work, on a worker thread with the GIL released; progress is reported from the
        // waiting thread, with the GIL, about every 20 ms.
        std::atomic<int> stage{0}, done{0}, total{0};
        std::vector<HelixFit> fits;
        std::vector<StrandModel> models;
        std::vector<VecX> target_curvatures;
        std::vector<InverseResult> results;
        std::vector<double> fit_max, fit_rms;
        double fit_seconds = 0.0, invert_seconds = 0.0;
        std::atomic<bool> cancel{false};
        // Ctrl-C: the next progress report throws, which stops the library's parallel loop
        // (TBB cancels the other tasks and rethrows here); RunInterruptibly then raises the
        // KeyboardInterrupt.
        struct Cancelled {};
        auto report = [&](int s) {
          return [&, s](int d, int t) {
            if (cancel) throw Cancelled{};
            stage = s;
            total = t;
            done = d;
          };
        };
        std::string failure;
        auto work = [&] {
          const auto t0 = std::chrono::steady_clock::now();
          int failed = 0;
          if (!FitPiecewiseHelices(polylines, fit_options, threads, &fits, &failed, &error,
                                   report(1))) {
            failure = "targets[" + std::to_string(failed) + "]: " + error;
            return;
          }
          fit_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
                            .count();
          if (cancel) return;
          for (size_t i = 0; i < fits.size(); ++i) {
            StrandModel model;
            model.segment_lengths = fits[i].segment_lengths;
            model.root_position = fits[i].root_position;
            model.root_frame = fits[i].root_frame;
            ApplyInverseHairType(hair_type, i, &model, nullptr);
            model.contact.obstacle = obstacle;
            model.contact.clearance = clearance;
            std::string why;
            if (!IsValid(model, &why)) {
              failure = "targets[" + std::to_string(i) + "]: " + why;
              return;
            }
            models.push_back(std::move(model));
            target_curvatures.push_back(fits[i].curvatures);
            fit_max.push_back(fits[i].max_distance);
            fit_rms.push_back(fits[i].rms_distance);
          }
          InverseOptions options;
          options.contact_forces = support_forces;
          const auto t1 = std::chrono::steady_clock::now();
          results = InvertStrands(models, target_curvatures, options, threads, report(2));
          invert_seconds =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
        };
        RunInterruptibly(
            [&] {
              try {
                work();
              } catch (const Cancelled&) {
              }
            },
            &cancel,
            [&] {
              if (progress.is_none() || stage == 0) return;
              progress(stage == 1 ? "fit" : "invert", done.load(), total.load());
            });
        if (cancel) throw Error("cancelled");  // not reached: Ctrl-C raised above
        if (!failure.empty()) throw Error(failure);

        py::list rest_shapes, equilibria, naive, curvatures;
        for (size_t i = 0; i < models.size(); ++i) {
          StrandModel inverted = models[i];
          inverted.rest_curvatures = results[i].rest_curvatures;
          inverted.contact.support_offsets = results[i].support_offsets;
          rest_shapes.append(py::cast(std::move(inverted)));
          equilibria.append(
              PointsArray(SampleCentrelineAt(models[i], results[i].equilibrium, fits[i].arc_lengths)));
          naive.append(PointsArray(
              SampleCentrelineAt(models[i], results[i].naive_equilibrium, fits[i].arc_lengths)));
          const VecX& q = target_curvatures[i];
          curvatures.append(OwnedArray(std::vector<double>(q.data(), q.data() + q.size()),
                                       {q.size() / 3, 3}));
        }
        py::dict out;
        out["models"] = rest_shapes;
        out["target_curvatures"] = curvatures;
        out["equilibria"] = equilibria;
        out["naive_equilibria"] = naive;
        out["summary"] = JsonToPython(
            InversionSummary(models, results, fit_max, fit_rms, fit_seconds, invert_seconds));
        return out;
      },
      py::arg("targets"), py::arg("body") = py::none(), py::arg("hair_type") = "",
      py::arg("clearance") = 0.0, py::arg("segments") = 0, py::arg("fit_tolerance") = 1e-3,
      py::arg("support_forces") = true, py::arg("threads") = 0,
      py::arg("progress") = py::none(),
      "Inverse statics, as `ringlet invert` (docs/inverse.md): fits each target polyline (a "
      "HairCurves or a list of (k, 3) arrays, metres, root first) by a G1 piecewise helix "
      "(segments, 0 = the fewest meeting fit_tolerance x L), finds the rest shapes that hold "
      "them under gravity and, with body (a ringlet.Body, a body file path or dict), contact "
      "(support forces as unknowns unless support_forces=False), certifies their stability and verifies them "
      "by the forward solve. hair_type 'ORIGIN' or 'ORIGIN/CURL' gives the section, material "
      "and natural curl (default: the paper's 50-um straight fibre). progress(stage, done, "
      "total) is called with stage 'fit' or 'invert' about every 20 ms. Returns a dict: "
      "'models' (StrandModels with rest_curvatures, the body and its support offsets: "
      "ringlet.solve(models) finds the equilibria again where they are the only stable ones), 'target_curvatures' ((n, 3) arrays), 'equilibria' and 'naive_equilibria' "
      "((k, 3) arrays at the targets' own points) and 'summary' (the summary.json of ringlet "
      "invert). The GIL is released; Ctrl-C stops it.");
}

}  // namespace ringlet::python
