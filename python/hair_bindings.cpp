// Hair curves, hairstyles, grooming, styling and the hair file readers and writers
// (hair_curves.h, hairstyle.h, hairstyle_json.h, styling.h, hair_file.h, usd_export.h,
// obj_export.h) for the Python module; docs/python.md.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "bindings.h"
#include "io/json_reader.h"
#include "ringlet/atomic_file.h"
#include "ringlet/hair_curves.h"
#include "ringlet/hair_file.h"
#include "ringlet/strand_targets.h"
#include "ringlet/usc_data.h"
#include "ringlet/hairstyle.h"
#include "ringlet/hairstyle_json.h"
#include "ringlet/obj_export.h"
#include "ringlet/render_json.h"
#include "ringlet/styling.h"
#include "ringlet/usd_export.h"
#include "types.h"

namespace ringlet::python {

namespace {

// What ringlet.StyledHair holds: the styled state, its hairstyle and the worker threads.
struct Styled {
  std::shared_ptr<const HairstyleFile> hairstyle;
  StyledHair state;
  int threads = 0;
  /// An operation is running (on a worker, the GIL released): a second one started from
  /// another Python thread would work on the same old state and one result would be lost.
  bool busy = false;
};

// A float32 (count, 3) view of Vec3f storage (empty storage gives shape (0, 3)).
py::array Vec3fView(std::vector<Vec3f>& v, py::handle owner) {
  return View(v.empty() ? nullptr : v[0].data(), {static_cast<py::ssize_t>(v.size()), 3},
              {sizeof(Vec3f), sizeof(float)}, owner, true);
}

// Copies an (n, 3) array of real numbers into Vec3f storage; None gives an empty vector.
std::vector<Vec3f> ToVec3f(const py::handle& value, const char* field) {
  std::vector<Vec3f> out;
  if (value.is_none()) return out;
  auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(
      RealArray(value, field, "an array of shape (n, 3)"));
  if (!a || a.ndim() != 2 || a.shape(1) != 3) {
    throw Error(std::string(field) + ": expected an array of shape (n, 3)");
  }
  out.resize(static_cast<size_t>(a.shape(0)));
  if (!out.empty()) std::memcpy(out[0].data(), a.data(), out.size() * sizeof(Vec3f));
  return out;
}

// Copies a 1-D array of real numbers into float storage; None gives an empty vector.
std::vector<float> ToFloats(const py::handle& value, const char* field, const char* expected) {
  std::vector<float> out;
  if (value.is_none()) return out;
  auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(
      RealArray(value, field, expected));
  if (!a || a.ndim() != 1) throw Error(std::string(field) + ": expected " + expected);
  out.assign(a.data(), a.data() + a.shape(0));
  return out;
}

// The point counts of a 1-D array of integers, each in [2, 2^32 - 1] (the uint32 of .hair
// files and HairCurves); integral floats are taken below 2^31, as the JSON readers take "15.0"
// (kMaxFloatInteger). numpy's cast used to turn 2^32 + 2 into 2 and 2.5 into 2.
std::vector<std::uint32_t> ToPointCounts(const py::handle& value) {
  const char* expected = "a 1-D array of integers >= 2";
  py::array a = RealArray(value, "point_counts", expected);
  if (a.ndim() != 1) throw Error(std::string("point_counts: ") + expected);
  std::vector<std::uint32_t> out(static_cast<size_t>(a.shape(0)));
  const auto bad = [](size_t k, const std::string& got) {
    return Error("point_counts[" + std::to_string(k) + "]: expected an integer in [2, " +
                 std::to_string(UINT32_MAX) + "], got " + got);
  };
  const char kind = a.dtype().kind();
  if (kind == 'u') {
    auto u = py::array_t<std::uint64_t, py::array::c_style | py::array::forcecast>::ensure(a);
    for (size_t k = 0; k < out.size(); ++k) {
      const std::uint64_t v = u.data()[k];
      if (v < 2 || v > UINT32_MAX) throw bad(k, std::to_string(v));
      out[k] = static_cast<std::uint32_t>(v);
    }
  } else if (kind == 'i') {
    auto i = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
    for (size_t k = 0; k < out.size(); ++k) {
      const std::int64_t v = i.data()[k];
      if (v < 2 || v > std::int64_t{UINT32_MAX}) throw bad(k, std::to_string(v));
      out[k] = static_cast<std::uint32_t>(v);
    }
  } else {
    auto f = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
    for (size_t k = 0; k < out.size(); ++k) {
      const double v = f.data()[k];
      if (!(v >= 2.0 && v < internal::kMaxFloatInteger && v == std::floor(v))) {
        throw bad(k, std::string(py::repr(py::float_(v))));
      }
      out[k] = static_cast<std::uint32_t>(v);
    }
  }
  return out;
}

// What the HairCurves constructor checks beyond CheckHairCurves (the doc's promises, as the
// strand readers check them, strand_targets.cpp): colours in [0, 1], major axes non-zero.
void CheckCurveAttributes(const HairCurves& c) {
  for (size_t k = 0; k < c.colors.size(); ++k) {
    for (int i = 0; i < 3; ++i) {
      if (!(c.colors[k][i] >= 0.0f && c.colors[k][i] <= 1.0f)) {
        throw Error("colors[" + std::to_string(k) + "]: expected linear RGB in [0, 1], got " +
                    std::string(py::repr(py::make_tuple(c.colors[k][0], c.colors[k][1],
                                                         c.colors[k][2]))));
      }
    }
  }
  for (size_t k = 0; k < c.major_axes.size(); ++k) {
    if (!c.major_axes[k].allFinite() || !(c.major_axes[k].squaredNorm() > 0.0f)) {
      throw Error("major_axes[" + std::to_string(k) + "]: expected a finite, non-zero major "
                  "axis, got " + std::string(py::repr(py::make_tuple(
                      c.major_axes[k][0], c.major_axes[k][1], c.major_axes[k][2]))));
    }
  }
}

// "operations[0].cut.z: ..." -> "cut.z: ..." (the operation came from a method, not a list).
std::string WithoutListPrefix(const std::string& message) {
  const std::string prefix = "operations[0].";
  return message.rfind(prefix, 0) == 0 ? message.substr(prefix.size()) : message;
}

// Runs one operation on a copy of the state (a cancelled operation leaves its state partly
// edited, styling.h) and keeps the copy only when it succeeded.
OperationReport Run(Styled* styled, const StyleOperation& operation) {
  if (styled->busy) {
    throw Error("StyledHair: expected one operation at a time, got another while one is "
                "running (from another thread)");
  }
  styled->busy = true;
  struct Done {
    bool* busy;
    ~Done() { *busy = false; }
  } done{&styled->busy};
  StyledHair copy = styled->state;
  OperationReport report;
  std::string error;
  bool ok = false;
  std::atomic<bool> cancel{false};
  RunInterruptibly(
      [&] {
        BatchOptions batch;
        batch.threads = styled->threads;
        batch.cancel = &cancel;
        ok = ApplyOperation(&copy, operation, batch, nullptr, &report, &error);
      },
      &cancel);
  if (!ok) throw Error(error);
  styled->state = std::move(copy);
  return report;
}

// One operation object in the file's schema ({"curl": {...}}), parsed by ParseStyleOperations.
OperationReport RunJson(Styled* styled, const nlohmann::json& operation) {
  std::vector<StyleOperation> operations;
  std::string error;
  const nlohmann::json document = {{"operations", nlohmann::json::array({operation})}};
  if (!ParseStyleOperations(document, &operations, &error)) {
    throw Error(WithoutListPrefix(error));
  }
  return Run(styled, operations.at(0));
}

// {name: kwargs} as an operation object.
OperationReport RunNamed(Styled* styled, const std::string& name, const py::kwargs& kwargs) {
  nlohmann::json fields = nlohmann::json::object();
  for (auto item : kwargs) {
    const std::string key = item.first.cast<std::string>();
    fields[key] = ToJson(item.second, name + "." + key);
  }
  return RunJson(styled, {{name, fields}});
}

HairCurves ReadHair(const std::string& path, double units_per_metre) {
  HairCurves curves;
  std::string error;
  if (!ReadHairFile(path, &curves, &error, units_per_metre)) throw Error(error);
  return curves;
}

HairFileOptions HairOptions(double units_per_metre, const std::optional<std::string>& info,
                            bool store_thickness, bool store_colors) {
  HairFileOptions options;
  options.units_per_metre = units_per_metre;
  if (info) options.info = *info;
  options.store_thickness = store_thickness;
  options.store_colors = store_colors;
  std::string why;
  if (!options.IsValid(&why)) throw Error(why);
  return options;
}

template <class T>
py::list References(std::vector<T>& items, py::handle owner) {
  py::list list;
  for (T& item : items) list.append(py::cast(&item, py::return_value_policy::reference_internal, owner));
  return list;
}

}  // namespace

std::shared_ptr<const HairstyleFile> HairstyleFrom(py::handle hairstyle,
                                                   const std::string& base_directory) {
  if (py::isinstance<HairstyleFile>(hairstyle)) {
    return hairstyle.cast<std::shared_ptr<HairstyleFile>>();
  }
  auto file = std::make_shared<HairstyleFile>();
  std::string error;
  if (py::isinstance<py::dict>(hairstyle)) {
    const nlohmann::json document = ToJson(hairstyle, "hairstyle");
    if (!ParseHairstyle(document, base_directory, &file->style, &error) ||
        !ParseStyleOperations(document, &file->operations, &error) ||
        !ParseRenderMember(document, &file->render, &error)) {
      throw Error(error);
    }
    file->document_text = document.dump();  // numbers as the shortest text that reads back
    file->base_directory = AbsoluteDirectory(base_directory);
    return file;
  }
  if (py::isinstance<py::str>(hairstyle) || py::hasattr(hairstyle, "__fspath__")) {
    const std::string path = py::str(py::module_::import("os").attr("fspath")(hairstyle));
    if (!LoadHairstyle(path, &file->style, &file->operations, &error) ||
        !LoadRenderSettings(path, &file->render, &error) ||
        !ReadFile(path, &file->document_text, &error)) {
      throw Error(error);
    }
    file->base_directory =
        AbsoluteDirectory(std::filesystem::path(path).parent_path().string());
    return file;
  }
  throw Error("hairstyle: expected a Hairstyle, a hairstyle dict or a path to a hairstyle file");
}

std::shared_ptr<const HairstyleFile> HairstyleFromText(const std::string& text,
                                                       const std::string& base_directory) {
  // Parsing a hairstyle reads its body (3.5 s for the mannequin of examples/hairstyles/wavy.json);
  // a worker unpickling one Groom per task would pay it every time. Hairstyles are immutable,
  // so the ones still alive in this process are shared (SharedWhileAlive).
  return SharedWhileAlive<HairstyleFile>(text, base_directory, [&] {
    auto file = std::make_shared<HairstyleFile>();
    nlohmann::json document;
    std::string error;
    if (!internal::ParseJsonText(text, &document, &error) ||
        !ParseHairstyle(document, base_directory, &file->style, &error) ||
        !ParseStyleOperations(document, &file->operations, &error) ||
        !ParseRenderMember(document, &file->render, &error)) {
      throw Error("Hairstyle (unpickling, relative paths from " + base_directory + "): " + error);
    }
    file->document_text = text;
    file->base_directory = base_directory;
    return file;
  });
}

void BindHair(py::module_& m) {
  py::class_<HairCurves>(
      m, "HairCurves",
      "Strands as polylines stored flat (hair_curves.h), the layout of .hair files and USD "
      "BasisCurves: strand k has point_counts[k] >= 2 consecutive points. The arrays are "
      "writable numpy views of the curves (edit in place; their sizes are fixed).")
      .def(py::init([](py::handle points, py::handle point_counts, py::handle widths,
                       py::handle colors, py::handle major_axes, py::handle wetness) {
             HairCurves curves;
             curves.points = ToVec3f(points, "points");
             curves.point_counts = ToPointCounts(point_counts);
             if (widths.is_none()) throw Error("widths: required, one diameter per point (m)");
             curves.widths = ToFloats(widths, "widths", "a 1-D array (m)");
             curves.colors = ToVec3f(colors, "colors");
             curves.major_axes = ToVec3f(major_axes, "major_axes");
             curves.wetness = ToFloats(wetness, "wetness", "a 1-D array, one value per strand");
             std::string why;
             if (!CheckHairCurves(curves, "curves", &why)) throw Error(why);
             CheckCurveAttributes(curves);
             return curves;
           }),
           py::arg("points"), py::arg("point_counts"), py::arg("widths"),
           py::arg("colors") = py::none(), py::arg("major_axes") = py::none(),
           py::arg("wetness") = py::none(),
           "Curves from arrays (copied as float32/uint32): points (K, 3) (m), point_counts (N,), "
           "widths (K,) fibre diameters (m), optional colors (N, 3) linear RGB in [0, 1], "
           "major_axes (K, 3) unit vectors and wetness (N,) in [0, 1]. Checked "
           "(CheckHairCurves; colours in [0, 1], axes finite and non-zero); point counts must "
           "be integers (2.5 or 2**32 + 2 are errors, never rounded or wrapped).")
      .def_property_readonly(
          "points", [](py::object self) { return Vec3fView(self.cast<HairCurves&>().points, self); },
          "Centreline points root to tip, strand after strand (m, world, z up): view (K, 3) "
          "float32.")
      .def_property_readonly(
          "point_counts",
          [](py::object self) {
            auto& c = self.cast<HairCurves&>().point_counts;
            return View(c.data(), {static_cast<py::ssize_t>(c.size())}, {sizeof(std::uint32_t)},
                        self, true);
          },
          "Points per strand (each >= 2): view (N,) uint32.")
      .def_property_readonly(
          "widths",
          [](py::object self) {
            auto& w = self.cast<HairCurves&>().widths;
            return View(w.data(), {static_cast<py::ssize_t>(w.size())}, {sizeof(float)}, self,
                        true);
          },
          "Fibre diameter at each point (m; the radius is half): view (K,) float32.")
      .def_property_readonly(
          "colors", [](py::object self) { return Vec3fView(self.cast<HairCurves&>().colors, self); },
          "Per-strand linear RGB in [0, 1]: view (N, 3) float32, or (0, 3) when absent.")
      .def_property_readonly(
          "major_axes",
          [](py::object self) { return Vec3fView(self.cast<HairCurves&>().major_axes, self); },
          "Per-point unit direction of the section's major axis (the material frame's n1, "
          "world): view (K, 3) float32, or (0, 3) when absent.")
      .def_property_readonly(
          "wetness",
          [](py::object self) {
            auto& w = self.cast<HairCurves&>().wetness;
            return View(w.data(), {static_cast<py::ssize_t>(w.size())}, {sizeof(float)}, self,
                        true);
          },
          "Per-strand wetness in [0, 1] (the fraction of the fibre under a water film; the "
          "styled strands of wet masters have 1): view (N,) float32, or (0,) when all dry.")
      .def(
          "offsets",
          [](const HairCurves& c) {
            std::vector<std::int64_t> offsets(c.point_counts.size() + 1, 0);
            for (size_t k = 0; k < c.point_counts.size(); ++k) {
              offsets[k + 1] = offsets[k] + c.point_counts[k];
            }
            const auto n = static_cast<py::ssize_t>(offsets.size());
            return OwnedArray(std::move(offsets), {n});
          },
          "Index of each strand's first point, and the total at the end: new array (N + 1,) "
          "int64; strand k is points[offsets[k]:offsets[k + 1]].")
      .def("num_strands", &HairCurves::NumStrands, "Number of strands N.")
      .def("num_points", &HairCurves::NumPoints, "Number of points K.")
      .def(
          "validate",
          [](const HairCurves& c) {
            std::string why;
            if (!CheckHairCurves(c, "curves", &why)) throw Error(why);
          },
          "Raises ringlet.Error naming the first inconsistency (CheckHairCurves).");

  py::class_<HairstyleFile, std::shared_ptr<HairstyleFile>>(
      m, "Hairstyle",
      "A hairstyle file (docs/hairstyle-format.md): the hair, its styling operations and its "
      "render settings. Made by load_hairstyle or parse_hairstyle.")
      .def_property_readonly(
          "length", [](const HairstyleFile& h) { return h.style.length; },
          "Mean strand length before the per-strand factor (m).")
      .def_property_readonly(
          "segments", [](const HairstyleFile& h) { return h.style.segments; },
          "Segments per master strand.")
      .def_property_readonly(
          "seed", [](const HairstyleFile& h) { return h.style.seed; },
          "Seed of the per-strand variation and the wisps.")
      .def_property_readonly(
          "num_operations", [](const HairstyleFile& h) { return h.operations.size(); },
          "Styling operations in the file's \"operations\" list.")
      .def_property_readonly(
          "eccentricity", [](const HairstyleFile& h) { return HairTypeEccentricity(h.style.hair_type); },
          "The hair type's fibre eccentricity in [0, 1) (mechanics and optics).")
      .def_property_readonly(
          "body",
          [](const HairstyleFile& h) -> py::object {
            if (!h.style.body) return py::none();
            // The body as built (no rebuild), with the document it came from for pickling:
            // the body file's text (read now) or the inline object.
            nlohmann::json document;
            std::string error;
            if (!internal::ParseJsonText(h.document_text, &document, &error)) throw Error(error);
            const nlohmann::json& member = document.at("body");
            if (member.is_string()) {
              std::filesystem::path file(member.get<std::string>());
              if (file.is_relative()) file = std::filesystem::path(h.base_directory) / file;
              std::string text;
              if (!ReadFile(file.string(), &text, &error)) throw Error("body: " + error);
              return py::cast(std::const_pointer_cast<BodyFile>(AdoptBody(
                  text, AbsoluteDirectory(file.parent_path().string()), h.style.body)));
            }
            return py::cast(std::const_pointer_cast<BodyFile>(
                AdoptBody(member.dump(), h.base_directory, h.style.body)));
          },
          "The hairstyle's body as a ringlet.Body (the one it was parsed with, not built "
          "again; its pickle carries the body file's text as read when asked), or None.");
  m.def(
      "load_hairstyle",
      [](const std::string& path) {
        return std::const_pointer_cast<HairstyleFile>(HairstyleFrom(py::str(path), ""));
      },
      py::arg("path"),
      "Reads a hairstyle file (relative paths from its directory). Every field, the operations "
      "and the render settings are checked; errors are ringlet.Error starting with the path.");
  m.def(
      "parse_hairstyle",
      [](const py::dict& document, const std::string& base_directory) {
        return std::const_pointer_cast<HairstyleFile>(HairstyleFrom(document, base_directory));
      },
      py::arg("document"), py::arg("base_directory") = ".",
      "A hairstyle from a dict in the file's JSON schema; relative paths (body file, meshes) "
      "are taken from base_directory. Errors are the command's lines (ringlet.Error).");

  py::class_<GroomSummary>(m, "GroomSummary", "What grooming did (hairstyle.h).")
      .def_readonly("masters", &GroomSummary::masters, "Master strands solved.")
      .def_readonly("strands", &GroomSummary::strands, "Strands generated.")
      .def_readonly("points", &GroomSummary::points, "Points of all strands.")
      .def_readonly("converged", &GroomSummary::converged, "Masters that converged.")
      .def_readonly("unconverged", &GroomSummary::unconverged, "Masters that did not.")
      .def_readonly("unstable", &GroomSummary::unstable, "Converged masters found unstable.")
      .def_readonly("iterations", &GroomSummary::iterations, "Minimizer iterations, all masters.")
      .def_readonly("max_penetration", &GroomSummary::max_penetration,
                    "Deepest master point below the body surface (m).")
      .def_readonly("solve_seconds", &GroomSummary::solve_seconds, "Master solve wall time (s).")
      .def_readonly("wisp_seconds", &GroomSummary::wisp_seconds, "Wisp generation wall time (s).")
      .def_readonly("children_solved", &GroomSummary::children_solved,
                    "Child strands solved as rods (\"children\": \"solved\").")
      .def_readonly("children_unconverged", &GroomSummary::children_unconverged,
                    "Of those, unconverged.")
      .def_readonly("children_unstable", &GroomSummary::children_unstable, "Of those, unstable.")
      .def_readonly("children_iterations", &GroomSummary::children_iterations,
                    "Their minimizer iterations.")
      .def_readonly("children_max_penetration", &GroomSummary::children_max_penetration,
                    "Their deepest point below the body (m).")
      .def_readonly("children_seconds", &GroomSummary::children_seconds,
                    "Their wall time (s).");

  py::class_<GroomResult>(m, "Groom", "A groomed head: masters, their solutions and the strands.")
      .def_property_readonly(
          "strands",
          [](py::object self) {
            return py::cast(&self.cast<GroomResult&>().groom.strands,
                            py::return_value_policy::reference_internal, self);
          },
          "Every strand, wisp by wisp in master order (HairCurves, viewed, not copied).")
      .def_property_readonly(
          "summary", [](const GroomResult& g) { return g.groom.summary; },
          "Counts and times (GroomSummary).")
      .def_property_readonly(
          "solutions",
          [](py::object self) { return References(self.cast<GroomResult&>().groom.solutions, self); },
          "One StrandSolution per master.")
      .def_property_readonly(
          "models", [](const GroomResult& g) { return g.groom.masters.models; },
          "One StrandModel per master: copies (the groom is done; its pickle rebuilds its "
          "masters from the hairstyle, so an edit could not travel with it).")
      .def_property_readonly(
          "root_positions",
          [](py::object self) {
            auto& roots = self.cast<GroomResult&>().groom.masters.roots;
            return View(roots.empty() ? nullptr : roots[0].position.data(),
                        {static_cast<py::ssize_t>(roots.size()), 3},
                        {sizeof(Root), sizeof(double)}, self, false);
          },
          "Master roots on the scalp (m): read-only strided view (M, 3) float64.")
      .def_property_readonly(
          "layers",
          [](py::object self) {
            auto& l = self.cast<GroomResult&>().groom.masters.layers;
            return View(l.data(), {static_cast<py::ssize_t>(l.size())}, {sizeof(int)}, self, false);
          },
          "Hull layer of each master: read-only view (M,) int32.")
      .def_property_readonly(
          "wisp_radii",
          [](py::object self) {
            auto& r = self.cast<GroomResult&>().groom.masters.wisp_radii;
            return View(r.data(), {static_cast<py::ssize_t>(r.size())}, {sizeof(double)}, self,
                        false);
          },
          "Wisp radius r_w of each master (m): read-only view (M,).")
      .def_property_readonly(
          "hairstyle", [](const GroomResult& g) { return std::const_pointer_cast<HairstyleFile>(g.hairstyle); },
          "The Hairstyle it was groomed from.");
  m.def(
      "groom",
      [](py::object hairstyle, long long threads, const std::string& base_directory,
         py::object progress) {
        BatchProgress reports(std::move(progress), "progress");
        auto result = std::make_unique<GroomResult>();
        result->hairstyle = HairstyleFrom(hairstyle, base_directory);
        CheckThreads(threads);
        std::string error;
        bool ok = false;
        std::atomic<bool> cancel{false};
        RunInterruptibly(
            [&] {
              BatchOptions batch;
              batch.threads = static_cast<int>(threads);
              batch.cancel = &cancel;
              batch.progress = reports.Reporter();
              ok = GroomHairstyle(result->hairstyle->style, batch, &result->groom, &error);
            },
            &cancel, reports.Tick());
        if (!ok) throw Error(error);
        // The display colour of the file's melanins, as `ringlet groom` writes it.
        SetMelaninColours(result->hairstyle->render, &result->groom.strands);
        return result;
      },
      py::arg("hairstyle"), py::arg("threads") = 0, py::arg("base_directory") = ".",
      py::arg("progress") = py::none(),
      "Grooms a hairstyle (GroomHairstyle, as `ringlet groom`: the unstyled hair, each strand "
      "coloured by the file's melanins, MelaninDisplayColour): a "
      "Hairstyle, a path or a dict (relative paths from base_directory). threads: 0 = all "
      "cores (results do not depend on it). progress(done, total), when given, is called with "
      "the number of strands solved (the masters, then the solved children when the "
      "hairstyle solves them: total grows by their count when they start) about every 20 ms "
      "while it changes, in the calling thread, and last with (total, total); an exception it "
      "raises stops the groom and is raised again. Returns a Groom. Releases the GIL; Ctrl-C "
      "stops it (KeyboardInterrupt).");

  py::class_<OperationReport>(m, "OperationReport", "What one styling operation did.")
      .def_readonly("name", &OperationReport::name, "\"curl\", \"wet\", \"dry\", \"cut\", \"grow\".")
      .def_readonly("strands", &OperationReport::strands, "Masters changed.")
      .def_readonly("iterations", &OperationReport::iterations, "Minimizer iterations.")
      .def_readonly("seconds", &OperationReport::seconds, "Wall time (s).")
      .def_readonly("unconverged", &OperationReport::unconverged,
                    "Masters whose re-solve did not converge (kept, reported).")
      .def_readonly("rounds", &OperationReport::rounds, "Re-solve rounds.")
      .def_readonly("message", &OperationReport::message, "One human line.")
      .def("__repr__", [](const OperationReport& r) {
        return "OperationReport(name=" + std::string(py::repr(py::str(r.name))) +
               ", strands=" + std::to_string(r.strands) + ", iterations=" +
               std::to_string(r.iterations) + ", unconverged=" + std::to_string(r.unconverged) +
               ", message=" + std::string(py::repr(py::str(r.message))) + ")";
      });

  py::class_<Styled>(
      m, "StyledHair",
      "A styled head (styling.h): the masters' current equilibria, changed by curl, wet, dry, "
      "cut and grow. Each operation edits the models and re-solves warm-started; the keyword "
      "arguments are the fields of the operation in docs/hairstyle-format.md (\"operations\"), "
      "checked with the same messages. A failed or interrupted operation leaves the hair as it "
      "was. Operations release the GIL; Ctrl-C stops them (KeyboardInterrupt).")
      .def(py::init([](const GroomResult& groom, long long threads) {
             CheckThreads(threads);
             Styled styled;
             styled.hairstyle = groom.hairstyle;
             styled.threads = static_cast<int>(threads);
             std::string error;
             if (!MakeStyledHair(groom.hairstyle->style, groom.groom, &styled.state, &error)) {
               throw Error(error);
             }
             return styled;
           }),
           py::arg("groom"), py::arg("threads") = 0,
           "The styled state of a groom (MakeStyledHair); threads: 0 = all cores.")
      .def(
          "apply_operation",
          [](Styled& s, const py::dict& operation) {
            return RunJson(&s, ToJson(operation, "operation"));
          },
          py::arg("operation"),
          "Applies one operation object of the file schema, e.g. {\"cut\": {\"z\": -0.1}} "
          "(ApplyOperation). Returns an OperationReport.")
      .def(
          "apply_operations",
          [](Styled& s) {
            std::vector<OperationReport> reports;
            for (const StyleOperation& op : s.hairstyle->operations) reports.push_back(Run(&s, op));
            return reports;
          },
          "Applies the hairstyle file's \"operations\" list in order, as `ringlet style FILE` "
          "does. Returns one OperationReport per operation.")
      .def(
          "curl",
          [](Styled& s, double radius, double pitch, py::object select) {
            nlohmann::json fields = {{"pitch", ToJson(py::float_(pitch), "curl.pitch")}};
            if (std::isinf(radius) && radius > 0) {
              fields["radius"] = "inf";
            } else {
              fields["radius"] = ToJson(py::float_(radius), "curl.radius");  // NaN: an error
            }
            if (!select.is_none()) fields["select"] = ToJson(select, "curl.select");
            return RunJson(&s, {{"curl", fields}});
          },
          py::arg("radius"), py::arg("pitch"), py::arg("select") = py::none(),
          "Curl: natural curvature of the helix of radius R (m, inf = straight) and pitch p (m, "
          "< 0 left-handed) on the selected masters (select: {\"indices\": [...]} or "
          "{\"polar_angle\": [min, max]} (rad) and/or {\"height\": [min, max]} (m)).")
      .def(
          "wet", [](Styled& s, const py::kwargs& kw) { return RunNamed(&s, "wet", kw); },
          "Wet: stiffness_factor (E_wet/E_dry, default 0.1), swelling (radius factor, 1.13), "
          "water_density (kg/m^3, 998.2), layer_factor (hull-layer offset factor, 0.5).")
      .def(
          "dry", [](Styled& s) { return RunJson(&s, {{"dry", nlohmann::json::object()}}); },
          "Dry: restores the dry parameters bit for bit and re-solves.")
      .def(
          "cut", [](Styled& s, const py::kwargs& kw) { return RunNamed(&s, "cut", kw); },
          "Cut: one region, z=height (m, keep above), plane={\"normal\": [...], \"offset\": d} "
          "(m), sphere={\"centre\": [...], \"radius\": r} (m) or length=L (m, keep arc lengths "
          "<= L); settle=True re-cuts until the risen tips lie on the boundary.")
      .def(
          "grow", [](Styled& s, const py::kwargs& kw) { return RunNamed(&s, "grow", kw); },
          "Grow: steps (integer) of step (m) each at the tips, re-solved after each step.")
      .def(
          "strands",
          [](const Styled& s) {
            HairCurves curves;
            std::string error;
            if (!StyledStrands(s.state, &curves, &error)) throw Error(error);
            SetMelaninColours(s.hairstyle->render, &curves);  // as `ringlet style` writes them
            return curves;
          },
          "The strands of the current state (masters sampled and wisps grown, coloured by the "
          "hairstyle's melanins as `ringlet style` writes them): a new HairCurves.")
      .def_property_readonly(
          "wet_state", [](const Styled& s) { return s.state.wet; }, "True between wet and dry.")
      .def_property_readonly(
          "solutions", [](const Styled& s) { return s.state.solutions; },
          "One StrandSolution per master, the current equilibria: copies (every operation "
          "replaces the state; a kept copy stays as it was).")
      .def_property_readonly(
          "models", [](const Styled& s) { return s.state.masters.models; },
          "One StrandModel per master, as edited: copies (editing them does not change the "
          "styled hair; a kept copy stays as it was).")
      .def_property_readonly(
          "hairstyle", [](const Styled& s) { return std::const_pointer_cast<HairstyleFile>(s.hairstyle); },
          "The Hairstyle it came from.")
      .def("__repr__", [](const Styled& s) {
        return "StyledHair(masters=" + std::to_string(s.state.solutions.size()) +
               ", wet=" + (s.state.wet ? "True" : "False") + ")";
      });

  // Readers and writers, one function each, named as their C++ function.
  m.def("read_hair_file", &ReadHair, py::arg("path"), py::arg("units_per_metre") = 1.0,
        "Reads a Cem Yuksel .hair file (hair_file.h) into HairCurves (m: file values divided by "
        "units_per_metre). Every count and size is checked; errors start with the path.");
  m.def(
      "decode_hair_file",
      [](const py::bytes& bytes, double units_per_metre) {
        HairCurves curves;
        std::string error;
        if (!DecodeHairFile(std::string_view(bytes), &curves, &error, units_per_metre)) {
          throw Error(error);
        }
        return curves;
      },
      py::arg("data"), py::arg("units_per_metre") = 1.0, "The bytes of a .hair file -> HairCurves.");
  m.def(
      "encode_hair_file",
      [](const HairCurves& curves, double units_per_metre, std::optional<std::string> info,
         bool store_thickness, bool store_colors) {
        std::string bytes, error;
        const HairFileOptions options =
            HairOptions(units_per_metre, info, store_thickness, store_colors);
        if (!EncodeHairFile(curves, options, &bytes, &error)) throw Error(error);
        return py::bytes(bytes);
      },
      py::arg("curves"), py::arg("units_per_metre") = 1.0, py::arg("info") = py::none(),
      py::arg("store_thickness") = true, py::arg("store_colors") = true,
      "The bytes of the .hair file write_hair_file writes.");
  m.def(
      "write_hair_file",
      [](const std::string& path, const HairCurves& curves, double units_per_metre,
         std::optional<std::string> info, bool store_thickness, bool store_colors,
         bool overwrite) {
        std::string error;
        const HairFileOptions options =
            HairOptions(units_per_metre, info, store_thickness, store_colors);
        if (!WriteHairFile(path, curves, options, overwrite, &error)) throw Error(error);
      },
      py::arg("path"), py::arg("curves"), py::arg("units_per_metre") = 1.0,
      py::arg("info") = py::none(), py::arg("store_thickness") = true,
      py::arg("store_colors") = true, py::arg("overwrite") = false,
      "Writes a .hair file atomically (HairFileOptions: file units per metre, the 88-byte info "
      "text (default: the library's), thickness and colour arrays). An existing file is an "
      "error unless overwrite.");
  m.def(
      "write_usda",
      [](const std::string& path, const HairCurves& curves, const std::string& prim_name,
         bool overwrite) {
        UsdExportOptions options;
        options.prim_name = prim_name;
        std::string error;
        if (!WriteUsda(path, curves, options, overwrite, &error)) throw Error(error);
      },
      py::arg("path"), py::arg("curves"), py::arg("prim_name") = "hair",
      py::arg("overwrite") = false,
      "Writes USD text: one BasisCurves prim (metres, z up), atomically (usd_export.h).");
  m.def(
      "write_usda_sequence",
      [](const std::string& path, const std::vector<HairCurves>& frames,
         const std::string& prim_name, int start_time_code, double time_codes_per_second,
         bool overwrite) {
        UsdExportOptions options;
        options.prim_name = prim_name;
        options.start_time_code = start_time_code;
        options.time_codes_per_second = time_codes_per_second;
        std::string error;
        if (!WriteUsdaSequence(path, frames, options, overwrite, &error)) throw Error(error);
      },
      py::arg("path"), py::arg("frames"), py::arg("prim_name") = "hair",
      py::arg("start_time_code") = 1, py::arg("time_codes_per_second") = 24.0,
      py::arg("overwrite") = false,
      "Writes a time-sampled BasisCurves prim, frame i at start_time_code + i (frames per "
      "second: time_codes_per_second, 1/s).");
  m.def(
      "write_obj",
      [](const std::string& path, const HairCurves& curves, bool overwrite) {
        std::string error;
        if (!WriteObj(path, curves, overwrite, &error)) throw Error(error);
      },
      py::arg("path"), py::arg("curves"), py::arg("overwrite") = false,
      "Writes OBJ polylines (metres, z up; obj_export.h), atomically.");

  // Strands read as targets (strand_targets.h) and the USC-HairSalon .data format (usc_data.h).
  auto target_options = [](double units_per_metre, const std::string& up, double default_width,
                           bool ignore_file_metadata) {
    StrandTargetOptions o;
    o.units_per_metre = units_per_metre;
    if (up == "z" || up == "Z") {
      o.up_axis = StrandTargetOptions::UpAxis::kZ;
    } else if (up == "y" || up == "Y") {
      o.up_axis = StrandTargetOptions::UpAxis::kY;
    } else {
      throw Error("up: expected \"z\" or \"y\", got \"" + up + "\"");
    }
    o.default_width = default_width;
    o.ignore_file_metadata = ignore_file_metadata;
    std::string why;
    if (!o.IsValid(&why)) throw Error(why);
    return o;
  };
  m.def(
      "read_strand_targets",
      [target_options](const std::string& path, double units_per_metre, const std::string& up,
                       double default_width, bool ignore_file_metadata) {
        const StrandTargetOptions o =
            target_options(units_per_metre, up, default_width, ignore_file_metadata);
        HairCurves curves;
        std::string error;
        bool ok = false;
        {
          py::gil_scoped_release release;  // a large file takes seconds
          ok = ReadStrandTargets(path, o, &curves, &error);
        }
        if (!ok) throw Error(error);
        return curves;
      },
      py::arg("path"), py::arg("units_per_metre") = 1.0, py::arg("up") = "z",
      py::arg("default_width") = 70e-6, py::arg("ignore_file_metadata") = false,
      "Reads strands from .hair, .data (USC-HairSalon), .usda (linear BasisCurves) or .obj "
      "(l polylines) by extension (ReadStrandTargets, docs/file-formats.md): metres, z up "
      "(file values divided by units_per_metre; up=\"y\" rotates a y-up file, (x, y, z) -> "
      "(x, -z, y)); default_width (m) for files without widths. Every strand is checked; errors "
      "name the file, strand and point.");
  m.def(
      "decode_usc_data",
      [target_options](const py::bytes& bytes, double units_per_metre, const std::string& up,
                       double default_width) {
        const StrandTargetOptions o = target_options(units_per_metre, up, default_width, false);
        HairCurves curves;
        std::string error;
        if (!DecodeUscData(std::string_view(bytes), o, &curves, nullptr, &error)) {
          throw Error(error);
        }
        return curves;
      },
      py::arg("data"), py::arg("units_per_metre") = 1.0, py::arg("up") = "y",
      py::arg("default_width") = 70e-6,
      "The bytes of a USC-HairSalon .data file -> HairCurves (metres, z up; the database is y "
      "up, hence up=\"y\" by default). Strands of 0 or 1 vertex (no hair) are skipped.");
  m.def(
      "encode_usc_data",
      [target_options](const HairCurves& curves, double units_per_metre, const std::string& up) {
        const StrandTargetOptions o = target_options(units_per_metre, up, 70e-6, false);
        std::string bytes, error;
        if (!EncodeUscData(curves, o, &bytes, &error)) throw Error(error);
        return py::bytes(bytes);
      },
      py::arg("curves"), py::arg("units_per_metre") = 1.0, py::arg("up") = "y",
      "The bytes of the .data file write_usc_data writes (points only: the format has no "
      "widths or colours).");
  m.def(
      "write_usc_data",
      [target_options](const std::string& path, const HairCurves& curves, double units_per_metre,
                       const std::string& up, bool overwrite) {
        const StrandTargetOptions o = target_options(units_per_metre, up, 70e-6, false);
        std::string error;
        if (!WriteUscData(path, curves, o, overwrite, &error)) throw Error(error);
      },
      py::arg("path"), py::arg("curves"), py::arg("units_per_metre") = 1.0, py::arg("up") = "y",
      py::arg("overwrite") = false,
      "Writes a USC-HairSalon .data file atomically (y up by default, as the database). An "
      "existing file is an error unless overwrite.");
}

}  // namespace ringlet::python
