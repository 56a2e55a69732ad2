// Strands, scenes and the statics solve (strand_model.h, scene_json.h, statics.h,
// solve_strands.h, result_json.h) for the Python module; docs/python.md.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <atomic>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "bindings.h"
#include "ringlet/result_json.h"
#include "ringlet/scene_json.h"
#include "ringlet/solve_strands.h"
#include "ringlet/statics.h"
#include "ringlet/strand_geometry.h"
#include "ringlet/strand_model.h"
#include "types.h"

namespace ringlet::python {

namespace {

// A Vec3 member of an object as a writable numpy view (3 float64, m or 1/m or m/s^2).
py::array Vec3View(Vec3& v, py::handle owner, bool writable) {
  return View(v.data(), {3}, {sizeof(double)}, owner, writable);
}

// A column-major 3x3 matrix as a writable numpy view: element [i, j] is M(i, j).
py::array Mat3View(Mat3& m, py::handle owner, bool writable) {
  return View(m.data(), {3, 3}, {sizeof(double), 3 * sizeof(double)}, owner, writable);
}

// A 3n curvature vector as an (n, 3) numpy view: rows (kappa1, kappa2, tau) (1/m).
py::array CurvatureView(const VecX& q, py::handle owner) {
  return View(q.data(), {q.size() / 3, 3}, {3 * sizeof(double), sizeof(double)}, owner, false);
}

Method MethodFromName(const std::string& name) {
  for (Method m : {Method::kBfgs, Method::kLbfgs, Method::kNewton, Method::kAuto}) {
    if (name == MethodName(m)) return m;
  }
  throw Error("method: expected one of \"bfgs\", \"lbfgs\", \"newton\", \"auto\", got \"" + name +
              "\"");
}

// A Vec3 from any sequence of 3 numbers.
Vec3 ToVec3(const Eigen::Ref<const VecX>& v, const char* field) {
  if (v.size() != 3) {
    throw Error(std::string(field) + ": expected 3 numbers, got " + std::to_string(v.size()));
  }
  return Vec3(v[0], v[1], v[2]);
}

// The file readers' rules (scene_json.cpp: kLengthRule, kEccentricityRule, kEllipticityRule,
// kGradingRule, the material's), applied to the helpers' arguments, which used to return
// nonsense (NaN sections, negative or empty segment lists) instead of raising.
constexpr const char* kPositiveMetres = "a finite number > 0 (metres)";

void CheckSection(const CrossSection& s) {
  RequireNumber(s.a > 0.0, s.a, "a", kPositiveMetres);
  RequireNumber(s.b > 0.0 && s.b <= s.a, s.b, "b",
                "a finite number in (0, a] (metres; the minor semi-axis)");
}

void CheckMaterial(const Material& m) {
  RequireNumber(m.young_modulus > 0.0, m.young_modulus, "young_modulus",
                "a finite number > 0 (pascals)");
  RequireNumber(m.poisson_ratio > -1.0 && m.poisson_ratio <= 0.5, m.poisson_ratio,
                "poisson_ratio", "a finite number in (-1, 0.5]");
  RequireNumber(m.density >= 0.0, m.density, "density", "a finite number >= 0 (kg/m^3)");
}

void CheckSegmentCount(int segments) {
  if (segments < 1 || segments > kMaxSegments) {
    throw Error("segments: expected an integer between 1 and " + std::to_string(kMaxSegments) +
                ", got " + std::to_string(segments));
  }
}

// Segment lengths that underflowed (a tiny length, an extreme ratio), blamed as the scene
// reader blames them.
std::vector<double> CheckedLengths(std::vector<double> lengths, const char* field,
                                   double value) {
  for (double l : lengths) {
    if (!(std::isfinite(l) && l > 0.0)) {
      throw Error(std::string(field) + ": is too " +
                  (std::string(field) == "ratio" ? "large" : "small") + " for " +
                  std::to_string(lengths.size()) +
                  " segments: some segment lengths are not representable, got " +
                  std::string(py::repr(py::float_(value))));
    }
  }
  return lengths;
}

}  // namespace

Scene SceneFrom(py::handle scene) {
  Scene result;
  std::string error;
  if (py::isinstance<Scene>(scene)) return scene.cast<Scene>();
  if (py::isinstance<py::str>(scene) || py::hasattr(scene, "__fspath__")) {
    const std::string path = py::str(py::module_::import("os").attr("fspath")(scene));
    if (!LoadScene(path, &result, &error)) throw Error(error);
    return result;
  }
  if (py::isinstance<py::dict>(scene)) {
    if (!ParseScene(ToJson(scene, "scene"), &result, &error)) throw Error(error);
    return result;
  }
  if (py::isinstance<StrandModel>(scene)) {
    result.strands.push_back(scene.cast<StrandModel>());
    return result;
  }
  if (py::isinstance<py::list>(scene) || py::isinstance<py::tuple>(scene)) {
    for (auto item : scene) {
      if (!py::isinstance<StrandModel>(item)) {
        throw Error("strands: expected a list of StrandModel");
      }
      result.strands.push_back(item.cast<StrandModel>());
    }
    return result;
  }
  throw Error("scene: expected a Scene, a scene dict, a path, a StrandModel or a list of them");
}

void BindSolve(py::module_& m) {
  py::class_<CrossSection>(m, "CrossSection",
                           "An elliptic fibre section: semi-axes a >= b > 0 (m); the major axis "
                           "a lies along the material axis n1 (cross_section.h).")
      .def(py::init([](double a, double b) {
             const CrossSection s{a, b};
             CheckSection(s);
             return s;
           }),
           py::arg("a"), py::arg("b"),
           "Section of semi-axes a (major, along n1) and b (minor) in metres: finite, "
           "a >= b > 0, else ringlet.Error.")
      // Each semi-axis is checked alone when set (a >= b waits for the solve's IsValid: one
      // of the two is set first).
      .def_property(
          "a", [](const CrossSection& s) { return s.a; },
          [](CrossSection& s, double a) {
            RequireNumber(a > 0.0, a, "a", kPositiveMetres);
            s.a = a;
          },
          "Major semi-axis, along n1 (m, finite > 0).")
      .def_property(
          "b", [](const CrossSection& s) { return s.b; },
          [](CrossSection& s, double b) {
            RequireNumber(b > 0.0, b, "b", kPositiveMetres);
            s.b = b;
          },
          "Minor semi-axis, along n2 (m, finite > 0).")
      .def("area", &CrossSection::Area, "Area pi a b (m^2).")
      .def("i1", &CrossSection::I1, "Second moment about n1, pi a b^3 / 4 (m^4): the soft one.")
      .def("i2", &CrossSection::I2, "Second moment about n2, pi a^3 b / 4 (m^4).")
      .def("j", &CrossSection::J, "Torsion constant pi a^3 b^3 / (a^2 + b^2) (m^4).")
      .def("eccentricity", &CrossSection::Eccentricity, "sqrt(1 - b^2/a^2) in [0, 1).")
      .def("mean_radius", &CrossSection::MeanRadius, "sqrt(a b) (m).");
  m.def(
      "section_from_eccentricity",
      [](double mean_radius, double eccentricity) {
        RequireNumber(mean_radius > 0.0, mean_radius, "mean_radius", kPositiveMetres);
        RequireNumber(eccentricity >= 0.0 && eccentricity < 1.0, eccentricity, "eccentricity",
                      "a finite number in [0, 1)");
        const CrossSection s = SectionFromEccentricity(mean_radius, eccentricity);
        std::string why;
        if (!IsValid(s, &why)) {
          throw Error("mean_radius: gives no representable section with eccentricity " +
                      std::string(py::repr(py::float_(eccentricity))) + " (" + why + "), got " +
                      std::string(py::repr(py::float_(mean_radius))));
        }
        return s;
      },
      py::arg("mean_radius"), py::arg("eccentricity"),
      "Section of mean radius sqrt(a b) (m, > 0) and eccentricity in [0, 1).");
  m.def(
      "section_from_ellipticity",
      [](double mean_radius, double ellipticity) {
        RequireNumber(mean_radius > 0.0, mean_radius, "mean_radius", kPositiveMetres);
        RequireNumber(ellipticity >= 1.0, ellipticity, "ellipticity",
                      "a finite number >= 1 (the ratio a/b of the semi-axes)");
        const CrossSection s = SectionFromEllipticity(mean_radius, ellipticity);
        std::string why;
        if (!IsValid(s, &why)) {
          throw Error("mean_radius: gives no representable section with ellipticity " +
                      std::string(py::repr(py::float_(ellipticity))) + " (" + why + "), got " +
                      std::string(py::repr(py::float_(mean_radius))));
        }
        return s;
      },
      py::arg("mean_radius"), py::arg("ellipticity"),
      "Section of mean radius sqrt(a b) (m, > 0) and ellipticity a/b >= 1.");

  py::class_<Material>(m, "Material",
                       "Elastic constants and density of a fibre (SI); defaults are the "
                       "paper's: E = 10 GPa, Poisson ratio 0.3, 1300 kg/m^3.")
      .def(py::init([](double young_modulus, double poisson_ratio, double density) {
             const Material material{young_modulus, poisson_ratio, density};
             CheckMaterial(material);
             return material;
           }),
           py::arg("young_modulus") = 10e9, py::arg("poisson_ratio") = 0.3,
           py::arg("density") = 1300.0)
      // Each field is checked when set, as the constructor checks it.
      .def_property(
          "young_modulus", [](const Material& material) { return material.young_modulus; },
          [](Material& material, double value) {
            Material changed = material;
            changed.young_modulus = value;
            CheckMaterial(changed);
            material = changed;
          },
          "Young's modulus E (Pa, finite > 0).")
      .def_property(
          "poisson_ratio", [](const Material& material) { return material.poisson_ratio; },
          [](Material& material, double value) {
            Material changed = material;
            changed.poisson_ratio = value;
            CheckMaterial(changed);
            material = changed;
          },
          "Poisson's ratio (dimensionless), in (-1, 0.5].")
      .def_property(
          "density", [](const Material& material) { return material.density; },
          [](Material& material, double value) {
            Material changed = material;
            changed.density = value;
            CheckMaterial(changed);
            material = changed;
          },
          "Volumic mass rho (kg/m^3, finite >= 0).")
      .def("shear_modulus", &Material::ShearModulus, "E / (2 (1 + sigma)) (Pa).");

  py::class_<StrandModel>(
      m, "StrandModel",
      "One Kirchhoff rod clamped at its root, n helical segments (strand_model.h). The "
      "3-vectors and the root frame are writable numpy views of the model; segment_lengths is a "
      "read-only view (make a new model to change the segments).")
      .def(py::init([](const std::vector<double>& segment_lengths, const CrossSection& section,
                       const Material& material, const Eigen::Ref<const VecX>& natural_curvature,
                       const Eigen::Ref<const VecX>& root_position, const Mat3& root_frame,
                       const Eigen::Ref<const VecX>& gravity) {
             StrandModel model;
             model.segment_lengths = segment_lengths;
             model.section = section;
             model.material = material;
             model.natural_curvature = ToVec3(natural_curvature, "natural_curvature");
             model.root_position = ToVec3(root_position, "root_position");
             model.root_frame = root_frame;
             model.gravity = ToVec3(gravity, "gravity");
             std::string why;
             if (!IsValid(model, &why)) throw Error(why);
             return model;
           }),
           py::arg("segment_lengths"), py::arg("section"), py::arg("material") = Material{},
           py::arg("natural_curvature") = Vec3(Vec3::Zero()),
           py::arg("root_position") = Vec3(Vec3::Zero()),
           py::arg("root_frame") = Mat3(Mat3::Identity()),
           py::arg("gravity") = Vec3(0.0, 0.0, -9.81),
           "A strand: segment lengths root to tip (m), section, material, natural curvature "
           "(kappa1, kappa2, tau) (1/m), root position (m), root frame world_from_material "
           "(columns n1, n2, t; a proper rotation), gravity (m/s^2). Checked (IsValid): a bad "
           "field raises ringlet.Error naming it.")
      .def_property_readonly(
          "segment_lengths",
          [](py::object self) {
            auto& model = self.cast<StrandModel&>();
            return View(model.segment_lengths.data(),
                        {static_cast<py::ssize_t>(model.segment_lengths.size())},
                        {sizeof(double)}, self, false);
          },
          "Length of each segment, root to tip (m): read-only view, shape (n,).")
      .def_readwrite("section", &StrandModel::section, "Elliptic section (m).")
      .def_readwrite("material", &StrandModel::material, "Elastic constants and density.")
      .def_property_readonly(
          "natural_curvature",
          [](py::object self) { return Vec3View(self.cast<StrandModel&>().natural_curvature, self, true); },
          "Natural (kappa1, kappa2, tau) (1/m), the same on every segment: writable view (3,).")
      .def_property_readonly(
          "root_position",
          [](py::object self) { return Vec3View(self.cast<StrandModel&>().root_position, self, true); },
          "Root position r(0) (m): writable view (3,).")
      .def_property_readonly(
          "root_frame",
          [](py::object self) { return Mat3View(self.cast<StrandModel&>().root_frame, self, true); },
          "Root frame world_from_material, columns (n1, n2, t): writable view (3, 3).")
      .def_property_readonly(
          "gravity",
          [](py::object self) { return Vec3View(self.cast<StrandModel&>().gravity, self, true); },
          "Gravitational acceleration (m/s^2): writable view (3,).")
      .def("num_segments", &StrandModel::NumSegments, "Number of segments n.")
      .def("length", &StrandModel::Length, "Strand length L, the sum of the segments (m).")
      .def("stiffness", &StrandModel::Stiffness, "(E I1, E I2, mu J) (N m^2), the paper's eq. 3.")
      .def("weight_per_length", &StrandModel::WeightPerLength,
           "Weight per unit length rho S g (N/m), a vector along gravity.")
      .def("gravity_parameter", &StrandModel::GravityParameter,
           "Dimensionless load |f| L^3 / (E I1) (Greenhill's parameter; 7.8373 is critical).")
      .def(
          "validate",
          [](const StrandModel& model) {
            std::string why;
            if (!IsValid(model, &why)) throw Error(why);
          },
          "Raises ringlet.Error naming the first bad field (IsValid), else returns None.");
  m.def(
      "uniform_segments",
      [](double length, int segments) {
        RequireNumber(length > 0.0, length, "length", kPositiveMetres);
        CheckSegmentCount(segments);
        return CheckedLengths(UniformSegments(length, segments), "length", length);
      },
      py::arg("length"), py::arg("segments"),
      "n segments (1 to 100000) of equal length L/n (L > 0, m).");
  m.def(
      "graded_segments",
      [](double length, int segments, double ratio) {
        RequireNumber(length > 0.0, length, "length", kPositiveMetres);
        CheckSegmentCount(segments);
        RequireNumber(ratio >= 1.0, ratio, "ratio",
                      "a finite number >= 1 (last/first segment length)");
        return CheckedLengths(GradedSegments(length, segments, ratio),
                              ratio == 1.0 ? "length" : "ratio", ratio == 1.0 ? length : ratio);
      },
      py::arg("length"), py::arg("segments"), py::arg("ratio"),
      "n segment lengths (1 to 100000) growing geometrically root to tip, last/first = ratio "
      ">= 1, sum L (L > 0, m).");
  m.def(
      "recommended_grading_ratio",
      [](double gravity_parameter) {
        RequireNumber(gravity_parameter >= 0.0, gravity_parameter, "gravity_parameter",
                      "a finite number >= 0 (w L^3 / (E I1))");
        return RecommendedGradingRatio(gravity_parameter);
      },
      py::arg("gravity_parameter"),
      "The last/first segment ratio recommended for the load w L^3 / (E I1) >= 0 "
      "(dimensionless).");

  py::class_<SolveOptions>(m, "SolveOptions", "Options of the statics solve (statics.h).")
      .def(py::init([](const std::string& method, int max_iterations, double tolerance,
                       bool check_stability, int max_stability_restarts) {
             SolveOptions o;
             o.method = MethodFromName(method);
             o.max_iterations = max_iterations;
             o.tolerance = tolerance;
             o.check_stability = check_stability;
             o.max_stability_restarts = max_stability_restarts;
             std::string why;
             if (!o.IsValid(&why)) throw Error(why);
             return o;
           }),
           py::arg("method") = "auto", py::arg("max_iterations") = 1000,
           py::arg("tolerance") = 1e-9, py::arg("check_stability") = true,
           py::arg("max_stability_restarts") = 4)
      .def_property(
          "method", [](const SolveOptions& o) { return std::string(MethodName(o.method)); },
          [](SolveOptions& o, const std::string& name) { o.method = MethodFromName(name); },
          "\"auto\" (L-BFGS for light strands, Newton for heavy ones), \"lbfgs\", \"bfgs\" or "
          "\"newton\".")
      .def_readwrite("max_iterations", &SolveOptions::max_iterations,
                     "Iteration budget of one minimization.")
      .def_readwrite("tolerance", &SolveOptions::tolerance,
                     "Tolerance on the dimensionless equilibrium residual.")
      .def_readwrite("check_stability", &SolveOptions::check_stability,
                     "Certify stability with the exact Hessian (and leave unstable equilibria).")
      .def_readwrite("max_stability_restarts", &SolveOptions::max_stability_restarts,
                     "How many unstable equilibria may be left and re-minimized.");

  py::class_<Scene>(m, "Scene",
                    "Strands and solver options of a scene file (scene_json.h, "
                    "docs/scene-format.md). Made by load_scene or parse_scene.")
      .def(py::init([](const std::vector<StrandModel>& strands, const SolveOptions* solver) {
             Scene scene;
             scene.strands = strands;
             if (solver) scene.solver = *solver;
             return scene;
           }),
           py::arg("strands"), py::arg("solver") = nullptr)
      .def_property_readonly(
          "strands",
          [](py::object self) {
            auto& scene = self.cast<Scene&>();
            py::list list;
            for (StrandModel& s : scene.strands) {
              list.append(py::cast(&s, py::return_value_policy::reference_internal, self));
            }
            return list;
          },
          "The strands in file order (the scene's own models, not copies).")
      .def_readwrite("solver", &Scene::solver, "Options of the solve (the file's \"solver\").");
  m.def(
      "parse_scene",
      [](const py::dict& document) {
        Scene scene;
        std::string error;
        if (!ParseScene(ToJson(document, "scene"), &scene, &error)) throw Error(error);
        return scene;
      },
      py::arg("document"),
      "A scene from a dict in the JSON schema of `ringlet solve` (docs/scene-format.md). Every "
      "field is checked; a bad one raises ringlet.Error with the same line as the command.");
  m.def(
      "load_scene",
      [](const std::string& path) {
        Scene scene;
        std::string error;
        if (!LoadScene(path, &scene, &error)) throw Error(error);
        return scene;
      },
      py::arg("path"), "Reads a scene file (JSON); errors start with the path.");

  py::class_<EnergyTerms>(m, "EnergyTerms", "Energy terms at a configuration (J).")
      .def_readonly("elastic", &EnergyTerms::elastic, "Elastic energy, eq. 3 (J).")
      .def_readonly("gravity", &EnergyTerms::gravity, "Gravity energy, eq. 4 (J).")
      .def_readonly("contact", &EnergyTerms::contact, "Contact penalty, section 3.1 (J).")
      .def_readonly("total", &EnergyTerms::total, "Their sum (J).");
  py::class_<ContactMeasure>(m, "ContactMeasure", "Contact at a configuration.")
      .def_readonly("max_penetration", &ContactMeasure::max_penetration,
                    "Largest depth below the body surface (m).")
      .def_readonly("max_clearance_violation", &ContactMeasure::max_clearance_violation,
                    "Largest depth into the clearance layer (m).")
      .def_readonly("samples_in_contact", &ContactMeasure::samples_in_contact,
                    "Samples carrying a contact force.");
  py::class_<SolveSummary>(m, "SolveSummary",
                           "What a solve did and where it ended (statics.h): numerical trouble "
                           "is reported here, never hidden.")
      .def_property_readonly(
          "termination",
          [](const SolveSummary& s) { return std::string(TerminationName(s.termination)); },
          "\"converged\", \"max_iterations\", \"line_search_failed\" or \"non_finite\".")
      .def_readonly("message", &SolveSummary::message, "One human sentence.")
      .def_readonly("iterations", &SolveSummary::iterations, "Minimizer iterations.")
      .def_readonly("evaluations", &SolveSummary::evaluations, "Energy+gradient evaluations.")
      .def_readonly("hessian_evaluations", &SolveSummary::hessian_evaluations,
                    "Exact Hessians evaluated.")
      .def_readonly("energy", &SolveSummary::energy, "Energy terms at the result (J).")
      .def_readonly("gradient_norm", &SolveSummary::gradient_norm, "|dE/dq| at the result (J m).")
      .def_readonly("residual", &SolveSummary::residual,
                    "Dimensionless equilibrium residual (convergence test).")
      .def_readonly("stability_checked", &SolveSummary::stability_checked,
                    "Whether the Hessian test ran.")
      .def_readonly("stable", &SolveSummary::stable,
                    "Converged and the scaled Hessian is positive definite.")
      .def_readonly("min_eigenvalue", &SolveSummary::min_eigenvalue,
                    "Smallest eigenvalue of the stiffness-scaled Hessian (dimensionless; 1 = "
                    "no load).")
      .def_readonly("stability_restarts", &SolveSummary::stability_restarts,
                    "Unstable equilibria left along negative curvature.")
      .def_readonly("contact", &SolveSummary::contact, "Contact at the result.")
      .def("converged", &SolveSummary::Converged, "termination == \"converged\".");

  py::class_<StrandSolution>(m, "StrandSolution", "Curvatures at equilibrium and the summary.")
      .def_property_readonly(
          "curvatures",
          [](py::object self) { return CurvatureView(self.cast<StrandSolution&>().curvatures, self); },
          "(kappa1, kappa2, tau) per segment (1/m): read-only view, shape (n, 3).")
      .def_readonly("summary", &StrandSolution::summary, "The solve's summary.");

  py::class_<SolvedStrand>(m, "StrandResult",
                           "One solved strand (result_json.h), as `ringlet solve` writes it, "
                           "with the material frames at the same samples.")
      .def_property_readonly(
          "points",
          [](py::object self) {
            const auto& r = self.cast<SolvedStrand&>().result;
            return View(r.points.empty() ? nullptr : r.points[0].data(),
                        {static_cast<py::ssize_t>(r.points.size()), 3},
                        {sizeof(Vec3), sizeof(double)}, self, false);
          },
          "Centreline samples root to tip (m): read-only view, shape (N, 3) float64, N = n k + 1 "
          "for k points per segment.")
      .def_property_readonly(
          "curvatures",
          [](py::object self) { return CurvatureView(self.cast<SolvedStrand&>().result.curvatures, self); },
          "Equilibrium (kappa1, kappa2, tau) per segment (1/m): read-only view, shape (n, 3).")
      .def_property_readonly(
          "segment_lengths",
          [](py::object self) {
            const auto& l = self.cast<SolvedStrand&>().result.segment_lengths;
            return View(l.data(), {static_cast<py::ssize_t>(l.size())}, {sizeof(double)}, self,
                        false);
          },
          "Length of each segment (m): read-only view, shape (n,).")
      .def_property_readonly(
          "material_frames",
          [](py::object self) {
            const auto& f = self.cast<SolvedStrand&>().frames;
            return View(f.empty() ? nullptr : f[0].data(),
                        {static_cast<py::ssize_t>(f.size()), 3, 3},
                        {sizeof(Mat3), sizeof(double), 3 * sizeof(double)}, self, false);
          },
          "Material frames world_from_material at the points: read-only view, shape (N, 3, 3); "
          "frames[k][:, 0] = n1 (major axis), [:, 1] = n2, [:, 2] = t (tangent).")
      .def_property_readonly(
          "summary", [](const SolvedStrand& s) { return s.result.summary; },
          "The solver's summary (a copy).")
      .def_property_readonly(
          "kirchhoff_residual", [](const SolvedStrand& s) { return s.result.kirchhoff_residual; },
          "Kirchhoff's moment balance by quadrature, independent of the solver (dimensionless).")
      .def(
          "succeeded", [](const SolvedStrand& s) { return s.result.Succeeded(); },
          "Converged and, when checked, stable.");

  m.def(
      "solve",
      [](py::object scene, const SolveOptions* options, int points_per_segment, long long threads,
         py::object progress) {
        BatchProgress reports(std::move(progress), "progress");
        Scene s = SceneFrom(scene);
        if (options) s.solver = *options;
        std::string why;
        if (!s.solver.IsValid(&why)) throw Error("solver: " + why);
        // The scene reader's limits (scene_json.cpp), for scenes made in Python: the method's
        // segment limit (dense BFGS: 72 n^2 bytes) and kMaxTotalSegments in all strands.
        long total_segments = 0;
        for (size_t i = 0; i < s.strands.size(); ++i) {
          const std::string strand = "strands[" + std::to_string(i) + "]";
          if (!IsValid(s.strands[i], &why)) throw Error(strand + ": " + why);
          const int n = s.strands[i].NumSegments();
          if (!CheckMethodSegments(n, s.solver.method, &why)) {
            throw Error(strand + ".segment_lengths: " + why);
          }
          total_segments += n;
          if (total_segments > kMaxTotalSegments) {
            throw Error(strand + ".segment_lengths: " + std::to_string(n) +
                        " more segments would take the scene beyond its limit of " +
                        std::to_string(kMaxTotalSegments) + " segments in all strands");
          }
        }
        if (points_per_segment < 1 || points_per_segment > 1000) {
          throw Error("points_per_segment: expected an integer in [1, 1000], got " +
                      std::to_string(points_per_segment));
        }
        CheckThreads(threads);
        std::vector<SolvedStrand> solved(s.strands.size());
        std::atomic<bool> cancel{false};
        RunInterruptibly(
            [&] {
              BatchOptions batch;
              batch.threads = static_cast<int>(threads);
              batch.cancel = &cancel;
              batch.progress = reports.Reporter();
              const std::vector<StrandSolution> solutions =
                  SolveStrands(s.strands, s.solver, batch);
              if (cancel.load()) return;
              std::vector<StrandResult> results =
                  MakeStrandResults(s.strands, solutions, points_per_segment, static_cast<int>(threads));
              for (size_t i = 0; i < results.size(); ++i) {
                solved[i].frames = SampleFramedCentreline(s.strands[i], solutions[i].curvatures,
                                                          points_per_segment)
                                       .frames;
                solved[i].result = std::move(results[i]);
              }
            },
            &cancel, reports.Tick());
        return solved;
      },
      py::arg("scene"), py::arg("options") = nullptr, py::arg("points_per_segment") = 1,
      py::arg("threads") = 0, py::arg("progress") = py::none(),
      "Solves every strand (SolveStrands, then MakeStrandResults as `ringlet solve` does). "
      "scene: a Scene, a scene dict (docs/scene-format.md), a path to a scene file, a "
      "StrandModel or a list of them. options: SolveOptions (default: the scene's \"solver\", "
      "else SolveOptions()). points_per_segment k >= 1: centreline samples per segment. "
      "threads: 0 = all cores (results do not depend on it). progress(done, total), when given, "
      "is called with the number of strands solved about every 20 ms while it changes, in "
      "the calling thread, and last with (total, total); an exception it raises stops the "
      "solve and is raised again. Returns a list of StrandResult. Releases the GIL; Ctrl-C "
      "stops it (KeyboardInterrupt).");
}

}  // namespace ringlet::python
