// Pickling, copying and repr of the Python module's values (docs/python.md, "Pickling and
// copying"):
// __getstate__/__setstate__ (py::pickle), __copy__ and __deepcopy__ for the models, scenes,
// hairstyles, results and hair curves, so that they go through multiprocessing, joblib and
// distributed sweeps. Round trips are bit-exact: every number travels as a numpy array or a
// Python float of the same bits (never as decimal text, except a hairstyle's own JSON document,
// whose numbers nlohmann writes as the shortest text that reads back to the same double).
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "bindings.h"
#include "ringlet/energy.h"
#include "ringlet/contact.h"
#include "ringlet/hair_curves.h"
#include "ringlet/hairstyle.h"
#include "ringlet/render.h"
#include "ringlet/result_json.h"
#include "ringlet/styling.h"
#include "ringlet/scene_json.h"
#include "ringlet/statics.h"
#include "ringlet/strand_model.h"
#include "types.h"

namespace ringlet::python {

namespace {

// The first item of every state: a pickle of another layout is refused with a clear message
// instead of being read field by field into nonsense.
constexpr int kStateVersion = 1;

// ---------------------------------------------------------------------------------------------
// Arrays in states: new numpy arrays holding copies of the bits.

py::array Doubles(const double* data, size_t n) {
  std::vector<double> copy(data, data + n);
  return OwnedArray(std::move(copy), {static_cast<py::ssize_t>(n)});
}
py::array Doubles(const std::vector<double>& v) { return Doubles(v.data(), v.size()); }
py::array Doubles(const VecX& v) { return Doubles(v.data(), static_cast<size_t>(v.size())); }
template <int N>
py::array Doubles(const Eigen::Matrix<double, N, 1>& v) { return Doubles(v.data(), N); }
py::array Doubles(const Mat3& m) { return Doubles(m.data(), 9); }  // column-major bits

// The scalars of a vector of numbers or of fixed-size Eigen vectors and matrices, flat.
template <class Scalar, class T>
py::array Raw(const std::vector<T>& v, size_t scalars_per_item) {
  std::vector<Scalar> copy(v.size() * scalars_per_item);
  if (!copy.empty()) std::memcpy(copy.data(), v.data(), copy.size() * sizeof(Scalar));
  return OwnedArray(std::move(copy), {static_cast<py::ssize_t>(copy.size())});
}

// The state's array back as scalars; `what` names the field in errors.
template <class Scalar>
std::vector<Scalar> ScalarsFrom(const py::handle& value, const char* what) {
  auto a = py::array_t<Scalar, py::array::c_style>::ensure(value);
  if (!a || a.ndim() != 1) {
    throw Error(std::string("unpickling: ") + what + ": expected a 1-D array");
  }
  return std::vector<Scalar>(a.data(), a.data() + a.shape(0));
}

VecX VecFrom(const py::handle& value, const char* what) {
  const std::vector<double> v = ScalarsFrom<double>(value, what);
  VecX out(static_cast<Eigen::Index>(v.size()));
  if (!v.empty()) std::memcpy(out.data(), v.data(), v.size() * sizeof(double));
  return out;
}

template <class Fixed>
Fixed FixedFrom(const py::handle& value, const char* what) {
  const std::vector<double> v = ScalarsFrom<double>(value, what);
  Fixed out;
  if (v.size() != static_cast<size_t>(out.size())) {
    throw Error(std::string("unpickling: ") + what + ": expected " +
                std::to_string(out.size()) + " numbers, got " + std::to_string(v.size()));
  }
  std::memcpy(out.data(), v.data(), v.size() * sizeof(double));
  return out;
}

template <class T>
std::vector<T> ItemsFrom(const py::handle& value, const char* what) {
  using Scalar = typename T::Scalar;
  constexpr size_t per = static_cast<size_t>(T::SizeAtCompileTime);
  const std::vector<Scalar> v = ScalarsFrom<Scalar>(value, what);
  if (v.size() % per != 0) {
    throw Error(std::string("unpickling: ") + what + ": expected a multiple of " +
                std::to_string(per) + " numbers, got " + std::to_string(v.size()));
  }
  std::vector<T> out(v.size() / per);
  if (!out.empty()) std::memcpy(out[0].data(), v.data(), v.size() * sizeof(Scalar));
  return out;
}

// The tuple of a state after its version, with the expected number of items.
py::tuple Fields(const py::tuple& state, size_t count, const char* type) {
  if (state.size() != count + 1 || state[0].cast<int>() != kStateVersion) {
    throw Error(std::string("unpickling ") + type + ": expected a state of version " +
                std::to_string(kStateVersion) + " with " + std::to_string(count) +
                " fields (a pickle of another ringlet version?)");
  }
  py::tuple fields(count);
  for (size_t i = 0; i < count; ++i) fields[i] = state[i + 1];
  return fields;
}

template <class... T>
py::tuple State(T&&... fields) {
  return py::make_tuple(kStateVersion, std::forward<T>(fields)...);
}

// ---------------------------------------------------------------------------------------------
// The values.

py::tuple SectionState(const CrossSection& s) { return State(s.a, s.b); }
CrossSection SectionFrom(const py::tuple& state) {
  const py::tuple f = Fields(state, 2, "CrossSection");
  return CrossSection{f[0].cast<double>(), f[1].cast<double>()};
}

py::tuple MaterialState(const Material& m) {
  return State(m.young_modulus, m.poisson_ratio, m.density);
}
Material MaterialFrom(const py::tuple& state) {
  const py::tuple f = Fields(state, 3, "Material");
  return Material{f[0].cast<double>(), f[1].cast<double>(), f[2].cast<double>()};
}

py::tuple OptionsState(const SolveOptions& o) {
  return State(static_cast<int>(o.method), o.max_iterations, o.tolerance, o.check_stability,
               o.max_stability_restarts);
}
SolveOptions OptionsFrom(const py::tuple& state) {
  const py::tuple f = Fields(state, 5, "SolveOptions");
  SolveOptions o;
  o.method = static_cast<Method>(f[0].cast<int>());
  o.max_iterations = f[1].cast<int>();
  o.tolerance = f[2].cast<double>();
  o.check_stability = f[3].cast<bool>();
  o.max_stability_restarts = f[4].cast<int>();
  return o;
}

// A model with an obstacle (a groom's master: its body) is pickled without it only inside a
// Groom, which gives the body back; alone it is refused rather than silently losing contact.
py::tuple ModelState(const StrandModel& m, bool inside_groom) {
  if (m.contact.obstacle && !inside_groom) {
    throw Error("StrandModel: a model with contact (a groom's master, whose obstacle is the "
                "body) cannot be pickled alone: pickle the Groom, or make a model without "
                "contact");
  }
  return State(Doubles(m.segment_lengths), SectionState(m.section), MaterialState(m.material),
               Doubles(m.natural_curvature), Doubles(m.rest_curvatures),
               Doubles(m.root_position), Doubles(m.root_frame), Doubles(m.gravity),
               m.contact.clearance, m.contact.stiffness, m.contact.samples_per_segment,
               Doubles(m.contact.support_offsets), static_cast<bool>(m.contact.obstacle));
}
StrandModel ModelFrom(const py::tuple& state, std::shared_ptr<const Obstacle> obstacle) {
  const py::tuple f = Fields(state, 13, "StrandModel");
  StrandModel m;
  m.segment_lengths = ScalarsFrom<double>(f[0], "segment_lengths");
  m.section = SectionFrom(f[1]);
  m.material = MaterialFrom(f[2]);
  m.natural_curvature = FixedFrom<Vec3>(f[3], "natural_curvature");
  m.rest_curvatures = VecFrom(f[4], "rest_curvatures");
  m.root_position = FixedFrom<Vec3>(f[5], "root_position");
  m.root_frame = FixedFrom<Mat3>(f[6], "root_frame");
  m.gravity = FixedFrom<Vec3>(f[7], "gravity");
  m.contact.clearance = f[8].cast<double>();
  m.contact.stiffness = f[9].cast<double>();
  m.contact.samples_per_segment = f[10].cast<int>();
  m.contact.support_offsets = ScalarsFrom<double>(f[11], "support_offsets");
  if (f[12].cast<bool>()) {
    if (!obstacle) throw Error("unpickling StrandModel: a model with contact needs its Groom");
    m.contact.obstacle = std::move(obstacle);
  }
  return m;
}

py::tuple SummaryState(const SolveSummary& s) {
  return State(static_cast<int>(s.termination), s.message, s.iterations, s.evaluations,
               s.hessian_evaluations, s.energy.elastic, s.energy.gravity, s.energy.contact,
               s.energy.total, s.gradient_norm, s.residual, s.stability_checked, s.stable,
               s.min_eigenvalue, s.stability_restarts, s.contact.max_penetration,
               s.contact.max_clearance_violation, s.contact.samples_in_contact);
}
SolveSummary SummaryFrom(const py::tuple& state) {
  const py::tuple f = Fields(state, 18, "SolveSummary");
  SolveSummary s;
  s.termination = static_cast<Termination>(f[0].cast<int>());
  s.message = f[1].cast<std::string>();
  s.iterations = f[2].cast<int>();
  s.evaluations = f[3].cast<int>();
  s.hessian_evaluations = f[4].cast<int>();
  s.energy.elastic = f[5].cast<double>();
  s.energy.gravity = f[6].cast<double>();
  s.energy.contact = f[7].cast<double>();
  s.energy.total = f[8].cast<double>();
  s.gradient_norm = f[9].cast<double>();
  s.residual = f[10].cast<double>();
  s.stability_checked = f[11].cast<bool>();
  s.stable = f[12].cast<bool>();
  s.min_eigenvalue = f[13].cast<double>();
  s.stability_restarts = f[14].cast<int>();
  s.contact.max_penetration = f[15].cast<double>();
  s.contact.max_clearance_violation = f[16].cast<double>();
  s.contact.samples_in_contact = f[17].cast<int>();
  return s;
}

py::tuple EnergyState(const EnergyTerms& e) { return State(e.elastic, e.gravity, e.contact, e.total); }
EnergyTerms EnergyFrom(const py::tuple& state) {
  const py::tuple f = Fields(state, 4, "EnergyTerms");
  return EnergyTerms{f[0].cast<double>(), f[1].cast<double>(), f[2].cast<double>(),
                     f[3].cast<double>()};
}

py::tuple ContactState(const ContactMeasure& c) {
  return State(c.max_penetration, c.max_clearance_violation, c.samples_in_contact);
}
ContactMeasure ContactFrom(const py::tuple& state) {
  const py::tuple f = Fields(state, 3, "ContactMeasure");
  ContactMeasure c;
  c.max_penetration = f[0].cast<double>();
  c.max_clearance_violation = f[1].cast<double>();
  c.samples_in_contact = f[2].cast<int>();
  return c;
}

py::tuple ReportState(const OperationReport& r) {
  return State(r.name, r.strands, r.iterations, r.seconds, r.unconverged, r.rounds, r.message);
}
OperationReport ReportFrom(const py::tuple& state) {
  const py::tuple f = Fields(state, 7, "OperationReport");
  OperationReport r;
  r.name = f[0].cast<std::string>();
  r.strands = f[1].cast<int>();
  r.iterations = f[2].cast<long>();
  r.seconds = f[3].cast<double>();
  r.unconverged = f[4].cast<int>();
  r.rounds = f[5].cast<int>();
  r.message = f[6].cast<std::string>();
  return r;
}

py::tuple RenderStatsState(const RenderStats& r) {
  return State(r.seconds, r.build_seconds, r.camera_rays, r.rays, r.nan_samples,
               r.denoise_seconds, r.hair_segments, r.body_primitives);
}
RenderStats RenderStatsFrom(const py::tuple& state) {
  const py::tuple f = Fields(state, 8, "RenderStats");
  RenderStats r;
  r.seconds = f[0].cast<double>();
  r.build_seconds = f[1].cast<double>();
  r.camera_rays = f[2].cast<std::int64_t>();
  r.rays = f[3].cast<std::int64_t>();
  r.nan_samples = f[4].cast<std::int64_t>();
  r.denoise_seconds = f[5].cast<double>();
  r.hair_segments = f[6].cast<int>();
  r.body_primitives = f[7].cast<int>();
  return r;
}

py::tuple SolutionState(const StrandSolution& s) {
  return State(Doubles(s.curvatures), SummaryState(s.summary));
}
StrandSolution SolutionFrom(const py::tuple& state) {
  const py::tuple f = Fields(state, 2, "StrandSolution");
  StrandSolution s;
  s.curvatures = VecFrom(f[0], "curvatures");
  s.summary = SummaryFrom(f[1]);
  return s;
}

py::tuple ResultState(const SolvedStrand& s) {
  const StrandResult& r = s.result;
  return State(Raw<double>(r.points, 3), Doubles(r.curvatures), Doubles(r.segment_lengths),
               Doubles(r.rest_curvatures), SummaryState(r.summary), r.kirchhoff_residual,
               Raw<double>(s.frames, 9));
}
SolvedStrand ResultFrom(const py::tuple& state) {
  const py::tuple f = Fields(state, 7, "StrandResult");
  SolvedStrand s;
  s.result.points = ItemsFrom<Vec3>(f[0], "points");
  s.result.curvatures = VecFrom(f[1], "curvatures");
  s.result.segment_lengths = ScalarsFrom<double>(f[2], "segment_lengths");
  s.result.rest_curvatures = VecFrom(f[3], "rest_curvatures");
  s.result.summary = SummaryFrom(f[4]);
  s.result.kirchhoff_residual = f[5].cast<double>();
  s.frames = ItemsFrom<Mat3>(f[6], "material_frames");
  return s;
}

py::tuple CurvesState(const HairCurves& c) {
  // Refused here rather than in the worker that unpickles it (the arrays are writable views).
  std::string why;
  if (!CheckHairCurves(c, "HairCurves", &why)) throw Error("pickling " + why);
  return State(Raw<std::uint32_t>(c.point_counts, 1), Raw<float>(c.points, 3),
               Raw<float>(c.widths, 1), Raw<float>(c.colors, 3), Raw<float>(c.major_axes, 3),
               Raw<float>(c.wetness, 1));
}
HairCurves CurvesFrom(const py::tuple& state) {
  const py::tuple f = Fields(state, 6, "HairCurves");
  HairCurves c;
  c.point_counts = ScalarsFrom<std::uint32_t>(f[0], "point_counts");
  c.points = ItemsFrom<Vec3f>(f[1], "points");
  c.widths = ScalarsFrom<float>(f[2], "widths");
  c.colors = ItemsFrom<Vec3f>(f[3], "colors");
  c.major_axes = ItemsFrom<Vec3f>(f[4], "major_axes");
  c.wetness = ScalarsFrom<float>(f[5], "wetness");
  std::string why;
  if (!CheckHairCurves(c, "unpickling HairCurves", &why)) throw Error(why);
  return c;
}

py::tuple GroomSummaryState(const GroomSummary& s) {
  return State(s.masters, s.strands, s.points, s.converged, s.unconverged, s.unstable,
               s.iterations, s.max_penetration, s.solve_seconds, s.wisp_seconds,
               s.children_solved, s.children_unconverged, s.children_unstable,
               s.children_iterations, s.children_max_penetration, s.children_seconds);
}
GroomSummary GroomSummaryFrom(const py::tuple& state) {
  const py::tuple f = Fields(state, 16, "GroomSummary");
  GroomSummary s;
  s.masters = f[0].cast<int>();
  s.strands = f[1].cast<int>();
  s.points = f[2].cast<int>();
  s.converged = f[3].cast<int>();
  s.unconverged = f[4].cast<int>();
  s.unstable = f[5].cast<int>();
  s.iterations = f[6].cast<long>();
  s.max_penetration = f[7].cast<double>();
  s.solve_seconds = f[8].cast<double>();
  s.wisp_seconds = f[9].cast<double>();
  s.children_solved = f[10].cast<int>();
  s.children_unconverged = f[11].cast<int>();
  s.children_unstable = f[12].cast<int>();
  s.children_iterations = f[13].cast<long>();
  s.children_max_penetration = f[14].cast<double>();
  s.children_seconds = f[15].cast<double>();
  return s;
}

py::tuple HairstyleState(const HairstyleFile& h) {
  return State(h.document_text, h.base_directory);
}
std::shared_ptr<HairstyleFile> HairstyleStateFrom(const py::tuple& state) {
  const py::tuple f = Fields(state, 2, "Hairstyle");
  return std::const_pointer_cast<HairstyleFile>(
      HairstyleFromText(f[0].cast<std::string>(), f[1].cast<std::string>()));
}

py::tuple BodyState(const BodyFile& b) { return State(b.document_text, b.base_directory); }
std::shared_ptr<BodyFile> BodyStateFrom(const py::tuple& state) {
  const py::tuple f = Fields(state, 2, "Body");
  return std::const_pointer_cast<BodyFile>(
      BodyFromText(f[0].cast<std::string>(), f[1].cast<std::string>()));
}

// The masters of a groom are rebuilt from its hairstyle (BuildMasters: deterministic, no solve;
// GroomHairstyle uses them as built), and checked bit for bit against the pickled roots and
// segment lengths: a body file changed since pickling is an error, not a different head.
py::tuple GroomState(const GroomResult& g) {
  py::list solutions;
  for (const StrandSolution& s : g.groom.solutions) solutions.append(SolutionState(s));
  std::vector<double> roots, lengths;
  for (const Root& r : g.groom.masters.roots) roots.insert(roots.end(), r.position.data(), r.position.data() + 3);
  for (const StrandModel& m : g.groom.masters.models) {
    lengths.insert(lengths.end(), m.segment_lengths.begin(), m.segment_lengths.end());
  }
  return State(HairstyleState(*g.hairstyle), solutions, CurvesState(g.groom.strands),
               GroomSummaryState(g.groom.summary), Doubles(roots), Doubles(lengths));
}
std::unique_ptr<GroomResult> GroomFrom(const py::tuple& state) {
  const py::tuple f = Fields(state, 6, "Groom");
  auto g = std::make_unique<GroomResult>();
  g->hairstyle = HairstyleStateFrom(f[0]);
  std::string why;
  if (!BuildMasters(g->hairstyle->style, &g->groom.masters, &why)) {
    throw Error("unpickling Groom: " + why);
  }
  std::vector<double> roots, lengths;
  for (const Root& r : g->groom.masters.roots) roots.insert(roots.end(), r.position.data(), r.position.data() + 3);
  for (const StrandModel& m : g->groom.masters.models) {
    lengths.insert(lengths.end(), m.segment_lengths.begin(), m.segment_lengths.end());
  }
  const std::vector<double> pickled_roots = ScalarsFrom<double>(f[4], "roots");
  const std::vector<double> pickled_lengths = ScalarsFrom<double>(f[5], "segment_lengths");
  if (roots.size() != pickled_roots.size() || lengths.size() != pickled_lengths.size() ||
      std::memcmp(roots.data(), pickled_roots.data(), roots.size() * sizeof(double)) != 0 ||
      std::memcmp(lengths.data(), pickled_lengths.data(), lengths.size() * sizeof(double)) != 0) {
    throw Error("unpickling Groom: the hairstyle's masters built again differ from the pickled "
                "ones (its body or masters file under " + g->hairstyle->base_directory +
                " changed since pickling)");
  }
  for (auto item : f[1].cast<py::list>()) {
    g->groom.solutions.push_back(SolutionFrom(item.cast<py::tuple>()));
  }
  if (g->groom.solutions.size() != g->groom.masters.models.size()) {
    throw Error("unpickling Groom: expected one solution per master");
  }
  for (size_t i = 0; i < g->groom.solutions.size(); ++i) {
    if (g->groom.solutions[i].curvatures.size() != 3 * g->groom.masters.models[i].NumSegments()) {
      throw Error("unpickling Groom: solutions[" + std::to_string(i) +
                  "]: expected 3 curvatures per segment of its master");
    }
  }
  g->groom.strands = CurvesFrom(f[2]);
  g->groom.summary = GroomSummaryFrom(f[3]);
  return g;
}

py::tuple SceneState(const Scene& s) {
  py::list strands;
  for (const StrandModel& m : s.strands) strands.append(ModelState(m, false));
  return State(strands, OptionsState(s.solver));
}
Scene SceneStateFrom(const py::tuple& state) {
  const py::tuple f = Fields(state, 2, "Scene");
  Scene s;
  for (auto item : f[0].cast<py::list>()) s.strands.push_back(ModelFrom(item.cast<py::tuple>(), nullptr));
  s.solver = OptionsFrom(f[1]);
  return s;
}

// Adds pickling and copy.copy / copy.deepcopy (both deep: the values own their storage) to
// the registered class `name`.
template <class T, class Holder = std::unique_ptr<T>, class Get, class Set>
void AddPickle(py::module_& m, const char* name, Get get, Set set) {
  auto cls = py::reinterpret_borrow<py::class_<T, Holder>>(m.attr(name));
  cls.def(py::pickle(get, set));
  cls.def("__copy__", [](const T& self) { return T(self); },
          "A copy (deep: the copy owns its arrays).");
  cls.def(
      "__deepcopy__", [](const T& self, py::dict) { return T(self); }, py::arg("memo"),
      "A deep copy.");
}

// repr(x) of a Python value (floats as Python prints them: shortest round-trip text).
std::string Repr(const py::object& value) { return py::repr(value); }
std::string Repr(double value) { return Repr(py::float_(value)); }
std::string Repr(const Vec3& v) { return "(" + Repr(v[0]) + ", " + Repr(v[1]) + ", " + Repr(v[2]) + ")"; }

template <class T, class F>
void AddRepr(py::module_& m, const char* name, F repr) {
  auto cls = py::reinterpret_borrow<py::object>(m.attr(name));
  // A new function, not an overload added to an earlier __repr__ (which would win).
  py::cpp_function f([repr](const T& self) { return repr(self); }, py::name("__repr__"),
                     py::is_method(cls));
  py::setattr(cls, "__repr__", f);
}

std::string SectionRepr(const CrossSection& s) {
  return "CrossSection(a=" + Repr(s.a) + ", b=" + Repr(s.b) + ")";
}
std::string MaterialRepr(const Material& m) {
  return "Material(young_modulus=" + Repr(m.young_modulus) + ", poisson_ratio=" +
         Repr(m.poisson_ratio) + ", density=" + Repr(m.density) + ")";
}
std::string OptionsRepr(const SolveOptions& o) {
  return std::string("SolveOptions(method='") + MethodName(o.method) +
         "', max_iterations=" + std::to_string(o.max_iterations) + ", tolerance=" +
         Repr(o.tolerance) + ", check_stability=" + (o.check_stability ? "True" : "False") +
         ", max_stability_restarts=" + std::to_string(o.max_stability_restarts) + ")";
}
std::string SummaryRepr(const SolveSummary& s) {
  return std::string("SolveSummary(termination='") + TerminationName(s.termination) +
         "', iterations=" + std::to_string(s.iterations) + ", residual=" + Repr(s.residual) +
         ", stable=" + (s.stable ? "True" : "False") + ")";
}

void BindReprs(py::module_& m) {
  AddRepr<CrossSection>(m, "CrossSection", SectionRepr);
  AddRepr<Material>(m, "Material", MaterialRepr);
  AddRepr<SolveOptions>(m, "SolveOptions", OptionsRepr);
  AddRepr<SolveSummary>(m, "SolveSummary", SummaryRepr);
  AddRepr<StrandModel>(m, "StrandModel", [](const StrandModel& s) {
    return "StrandModel(segments=" + std::to_string(s.NumSegments()) + ", length=" +
           Repr(s.Length()) + ", section=" + SectionRepr(s.section) + ", natural_curvature=" +
           Repr(s.natural_curvature) + ", root_position=" + Repr(s.root_position) +
           (s.contact.obstacle ? ", contact=True" : "") + ")";
  });
  AddRepr<Scene>(m, "Scene", [](const Scene& s) {
    return "Scene(strands=" + std::to_string(s.strands.size()) + ", solver=" +
           OptionsRepr(s.solver) + ")";
  });
  AddRepr<EnergyTerms>(m, "EnergyTerms", [](const EnergyTerms& e) {
    return "EnergyTerms(elastic=" + Repr(e.elastic) + ", gravity=" + Repr(e.gravity) +
           ", contact=" + Repr(e.contact) + ", total=" + Repr(e.total) + ")";
  });
  AddRepr<ContactMeasure>(m, "ContactMeasure", [](const ContactMeasure& c) {
    return "ContactMeasure(max_penetration=" + Repr(c.max_penetration) +
           ", max_clearance_violation=" + Repr(c.max_clearance_violation) +
           ", samples_in_contact=" + std::to_string(c.samples_in_contact) + ")";
  });
  AddRepr<StrandSolution>(m, "StrandSolution", [](const StrandSolution& s) {
    return "StrandSolution(segments=" + std::to_string(s.curvatures.size() / 3) +
           ", summary=" + SummaryRepr(s.summary) + ")";
  });
  AddRepr<SolvedStrand>(m, "StrandResult", [](const SolvedStrand& s) {
    return "StrandResult(points=" + std::to_string(s.result.points.size()) + ", segments=" +
           std::to_string(s.result.segment_lengths.size()) + ", termination='" +
           TerminationName(s.result.summary.termination) + "', succeeded=" +
           (s.result.Succeeded() ? "True" : "False") + ", kirchhoff_residual=" +
           Repr(s.result.kirchhoff_residual) + ")";
  });
  AddRepr<HairCurves>(m, "HairCurves", [](const HairCurves& c) {
    return "HairCurves(strands=" + std::to_string(c.point_counts.size()) + ", points=" +
           std::to_string(c.points.size()) + ", colors=" + (c.colors.empty() ? "False" : "True") +
           ", major_axes=" + (c.major_axes.empty() ? "False" : "True") + ", wetness=" +
           (c.wetness.empty() ? "False" : "True") + ")";
  });
  AddRepr<HairstyleFile>(m, "Hairstyle", [](const HairstyleFile& h) {
    return "Hairstyle(length=" + Repr(h.style.length) + ", segments=" +
           std::to_string(h.style.segments) + ", seed=" + std::to_string(h.style.seed) +
           ", operations=" + std::to_string(h.operations.size()) + ", base_directory=" +
           Repr(py::str(h.base_directory)) + ")";
  });
  AddRepr<BodyFile>(m, "Body", [](const BodyFile& b) {
    // Every sphere and mesh up to kShown of each, then their count.
    constexpr size_t kShown = 8;
    std::string spheres, meshes;
    const auto& ss = b.body->spheres();
    for (size_t i = 0; i < ss.size() && i < kShown; ++i) {
      spheres += std::string(i ? ", " : "") + "Sphere(name=" + Repr(py::str(ss[i].name)) +
                 ", center=" + Repr(ss[i].center) + ", radius=" + Repr(ss[i].radius) + ")";
    }
    if (ss.size() > kShown) spheres += ", ... (" + std::to_string(ss.size()) + " spheres)";
    const auto& ms = b.body->meshes();
    for (size_t i = 0; i < ms.size() && i < kShown; ++i) {
      meshes += std::string(i ? ", " : "") + "Mesh(name=" + Repr(py::str(ms[i].name())) +
                ", vertices=" + std::to_string(ms[i].vertices().size()) + ", triangles=" +
                std::to_string(ms[i].triangles().size()) + ", volume=" + Repr(ms[i].volume()) +
                ")";
    }
    if (ms.size() > kShown) meshes += ", ... (" + std::to_string(ms.size()) + " meshes)";
    const bool grid = b.body->mesh_distance().mode == MeshDistanceOptions::Mode::kGrid;
    return "Body(spheres=[" + spheres + "], meshes=[" + meshes + "], blend=" +
           Repr(b.body->blend()) + ", mesh_distance='" + (grid ? "grid" : "exact") + "')";
  });
  AddRepr<GroomSummary>(m, "GroomSummary", [](const GroomSummary& s) {
    return "GroomSummary(masters=" + std::to_string(s.masters) + ", strands=" +
           std::to_string(s.strands) + ", points=" + std::to_string(s.points) +
           ", converged=" + std::to_string(s.converged) + ", unconverged=" +
           std::to_string(s.unconverged) + ", unstable=" + std::to_string(s.unstable) + ")";
  });
  AddRepr<RenderStats>(m, "RenderStats", [](const RenderStats& r) {
    return "RenderStats(seconds=" + Repr(r.seconds) + ", camera_rays=" +
           std::to_string(r.camera_rays) + ", rays=" + std::to_string(r.rays) +
           ", nan_samples=" + std::to_string(r.nan_samples) + ")";
  });
  AddRepr<GroomResult>(m, "Groom", [](const GroomResult& g) {
    return "Groom(masters=" + std::to_string(g.groom.solutions.size()) + ", strands=" +
           std::to_string(g.groom.strands.point_counts.size()) + ", points=" +
           std::to_string(g.groom.strands.points.size()) + ")";
  });
}

}  // namespace

void BindValues(py::module_& m) {
  BindReprs(m);
  AddPickle<CrossSection>(m, "CrossSection", SectionState, SectionFrom);
  AddPickle<Material>(m, "Material", MaterialState, MaterialFrom);
  AddPickle<SolveOptions>(m, "SolveOptions", OptionsState, OptionsFrom);
  AddPickle<StrandModel>(
      m, "StrandModel", [](const StrandModel& s) { return ModelState(s, false); },
      [](const py::tuple& t) { return ModelFrom(t, nullptr); });
  AddPickle<Scene>(m, "Scene", SceneState, SceneStateFrom);
  AddPickle<SolveSummary>(m, "SolveSummary", SummaryState, SummaryFrom);
  AddPickle<StrandSolution>(m, "StrandSolution", SolutionState, SolutionFrom);
  AddPickle<SolvedStrand>(m, "StrandResult", ResultState, ResultFrom);
  AddPickle<HairCurves>(m, "HairCurves", CurvesState, CurvesFrom);
  AddPickle<GroomSummary>(m, "GroomSummary", GroomSummaryState, GroomSummaryFrom);
  AddPickle<EnergyTerms>(m, "EnergyTerms", EnergyState, EnergyFrom);
  AddPickle<ContactMeasure>(m, "ContactMeasure", ContactState, ContactFrom);
  AddPickle<OperationReport>(m, "OperationReport", ReportState, ReportFrom);
  AddPickle<RenderStats>(m, "RenderStats", RenderStatsState, RenderStatsFrom);
  // Shared, immutable values: a copy is the same object.
  auto hairstyle =
      py::reinterpret_borrow<py::class_<HairstyleFile, std::shared_ptr<HairstyleFile>>>(
          m.attr("Hairstyle"));
  hairstyle.def(py::pickle([](const HairstyleFile& h) { return HairstyleState(h); },
                           [](const py::tuple& t) { return HairstyleStateFrom(t); }));
  hairstyle.def("__copy__", [](py::object self) { return self; },
                "The same object (a Hairstyle is immutable).");
  hairstyle.def(
      "__deepcopy__", [](py::object self, py::dict) { return self; }, py::arg("memo"),
      "The same object (a Hairstyle is immutable).");
  auto body =
      py::reinterpret_borrow<py::class_<BodyFile, std::shared_ptr<BodyFile>>>(m.attr("Body"));
  body.def(py::pickle([](const BodyFile& b) { return BodyState(b); },
                      [](const py::tuple& t) { return BodyStateFrom(t); }));
  body.def("__copy__", [](py::object self) { return self; },
           "The same object (a Body is immutable).");
  body.def(
      "__deepcopy__", [](py::object self, py::dict) { return self; }, py::arg("memo"),
      "The same object (a Body is immutable).");
  auto groom = py::reinterpret_borrow<py::class_<GroomResult>>(m.attr("Groom"));
  groom.def(py::pickle([](const GroomResult& g) { return GroomState(g); },
                       [](const py::tuple& t) { return GroomFrom(t); }));
  groom.def("__copy__", [](const GroomResult& g) { return GroomResult(g); },
            "A copy (deep: the copy owns its arrays; the Hairstyle is shared).");
  groom.def(
      "__deepcopy__", [](const GroomResult& g, py::dict) { return GroomResult(g); },
      py::arg("memo"), "A deep copy (the immutable Hairstyle is shared).");
}

}  // namespace ringlet::python
