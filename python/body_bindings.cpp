// Bodies (body.h, body_json.h, docs/body.md) for the Python module: ringlet.Body from a body
// file or dict, its signed distance, gradient and Hessian at many points at once (numpy
// arrays), and the shared conversion of the module's `body` arguments. Bindings only: every
// number is Body::SignedDistance / Body::SignedDistanceHessian.
#include <pybind11/stl.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bindings.h"
#include "ringlet/atomic_file.h"
#include "ringlet/body_json.h"
#include "types.h"

namespace ringlet::python {

namespace {

// Points this many or more are queried with the GIL released (below it, releasing and taking
// the GIL back costs more than the queries: a sphere query is ~10 ns).
constexpr py::ssize_t kReleaseGilPoints = 1024;

// The body of a document text (relative OBJ paths from base_directory): one still alive in
// this process parsed from the same text and directory (SharedWhileAlive), else build(), which
// throws ringlet.Error on bad input.
std::shared_ptr<const BodyFile> CachedBody(
    const std::string& text, const std::string& base_directory,
    const std::function<std::shared_ptr<const Body>()>& build) {
  return SharedWhileAlive<BodyFile>(text, base_directory, [&] {
    auto file = std::make_shared<BodyFile>();
    file->body = build();
    file->document_text = text;
    file->base_directory = base_directory;
    return file;
  });
}

// Builds the body of a document text; errors are prefixed by `where` when not empty.
std::function<std::shared_ptr<const Body>()> FromText(const std::string& text,
                                                      const std::string& base_directory,
                                                      const std::string& where) {
  return [&text, &base_directory, where] {
    auto body = std::make_shared<Body>();
    std::string error;
    if (!ParseBodyText(text, base_directory, body.get(), &error)) {
      throw Error(where.empty() ? error : where + ": " + error);
    }
    return std::shared_ptr<const Body>(std::move(body));
  };
}

bool IsPath(py::handle value) {
  return py::isinstance<py::str>(value) || py::hasattr(value, "__fspath__");
}

// A Body from a path or a dict (relative OBJ paths from base_directory).
std::shared_ptr<const BodyFile> BodyFileFrom(py::handle source, const std::string& field,
                                             const std::string& base_directory) {
  if (py::isinstance<BodyFile>(source)) return source.cast<std::shared_ptr<BodyFile>>();
  if (IsPath(source)) {
    const std::string path = py::str(py::module_::import("os").attr("fspath")(source));
    std::string text, error;
    if (!ReadFile(path, &text, &error)) throw Error(field + ": " + error);
    const std::string directory =
        AbsoluteDirectory(std::filesystem::path(path).parent_path().string());
    return CachedBody(text, directory, FromText(text, directory, field + ": " + DisplayPath(path)));
  }
  if (py::isinstance<py::dict>(source)) {
    // The dict as JSON text: nlohmann writes each double as the shortest text that reads back
    // to the same bits, so the body parsed again from it (pickling) is the same body.
    const nlohmann::json document = ToJson(source, field);
    const std::string directory = AbsoluteDirectory(base_directory);
    return CachedBody(document.dump(), directory, [&] {
      auto body = std::make_shared<Body>();
      std::string error;
      if (!ParseBody(document, field, directory, body.get(), &error)) throw Error(error);
      return std::shared_ptr<const Body>(std::move(body));
    });
  }
  throw Error(field +
              ": expected a ringlet.Body, a body file path or a body dict "
              "{\"spheres\": [...], \"meshes\": [...]}, got " +
              std::string(py::str(source.get_type().attr("__name__"))));
}

// The points of a query: an array of real numbers whose last axis has 3 coordinates (m), all
// finite. Returns a C-contiguous float64 array.
py::array_t<double, py::array::c_style> QueryPoints(py::handle points) {
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(
      RealArray(points, "points", "an array of shape (..., 3) (m)"));
  if (!a || a.ndim() < 1 || a.shape(a.ndim() - 1) != 3) {
    throw Error("points: expected an array of shape (..., 3) (m), got shape " +
                std::string(py::str(py::module_::import("numpy").attr("shape")(points))));
  }
  const double* x = a.data();
  for (py::ssize_t i = 0; i < a.size(); ++i) {
    if (!std::isfinite(x[i])) {
      throw Error("points: expected finite coordinates (m), got " +
                  std::string(py::repr(py::float_(x[i]))) + " in point " + std::to_string(i / 3));
    }
  }
  return a;
}

// The shape of the query without its last axis, plus `extra`.
std::vector<py::ssize_t> ResultShape(const py::array& points, std::vector<py::ssize_t> extra) {
  std::vector<py::ssize_t> shape(points.shape(), points.shape() + points.ndim() - 1);
  shape.insert(shape.end(), extra.begin(), extra.end());
  return shape;
}

// Signed distances (and gradients, Hessians when wanted) at every point: one loop over the
// points with the GIL released when there are many.
py::object Query(const BodyFile& file, py::handle points, bool want_gradient, bool want_hessian) {
  const auto x = QueryPoints(points);
  const py::ssize_t k = x.size() / 3;
  std::vector<double> distance(static_cast<size_t>(k));
  std::vector<double> gradient(want_gradient ? 3 * static_cast<size_t>(k) : 0);
  std::vector<double> hessian(want_hessian ? 9 * static_cast<size_t>(k) : 0);
  const Body& body = *file.body;
  const double* p = x.data();
  auto run = [&] {
    for (py::ssize_t i = 0; i < k; ++i) {
      const Vec3 xi(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
      Vec3 g;
      if (want_hessian) {
        Mat3 h;
        distance[i] = body.SignedDistanceHessian(xi, &g, &h);
        // Row-major (3, 3) per point: h(r, c) at [i, r, c] (h is symmetric anyway).
        for (int r = 0; r < 3; ++r) {
          for (int c = 0; c < 3; ++c) hessian[9 * i + 3 * r + c] = h(r, c);
        }
      } else {
        distance[i] = body.SignedDistance(xi, want_gradient ? &g : nullptr);
      }
      if (want_gradient) {
        for (int a = 0; a < 3; ++a) gradient[3 * i + a] = g[a];
      }
    }
  };
  if (k >= kReleaseGilPoints) {
    py::gil_scoped_release release;
    run();
  } else {
    run();
  }
  const bool single = x.ndim() == 1;
  py::object d = single ? py::object(py::float_(distance[0]))
                        : py::object(OwnedArray(std::move(distance), ResultShape(x, {})));
  if (!want_gradient) return d;
  py::object g = OwnedArray(std::move(gradient), ResultShape(x, {3}));
  if (!want_hessian) return py::make_tuple(d, g);
  return py::make_tuple(d, g, OwnedArray(std::move(hessian), ResultShape(x, {3, 3})));
}

py::array Vec3Array(const Vec3& v) {
  return OwnedArray(std::vector<double>{v.x(), v.y(), v.z()}, {3});
}

}  // namespace

std::shared_ptr<const BodyFile> BodyFromText(const std::string& text,
                                             const std::string& base_directory) {
  return CachedBody(text, base_directory,
                    FromText(text, base_directory,
                             "Body (unpickling, relative paths from " + base_directory + ")"));
}

std::shared_ptr<const BodyFile> AdoptBody(const std::string& text,
                                          const std::string& base_directory,
                                          std::shared_ptr<const Body> body) {
  return CachedBody(text, base_directory, [&] { return body; });
}

std::shared_ptr<const Body> BodyFrom(py::handle body, const std::string& field,
                                     const std::string& base_directory) {
  if (body.is_none()) return nullptr;
  return BodyFileFrom(body, field, base_directory)->body;
}

void BindBody(py::module_& m) {
  py::class_<BodyFile, std::shared_ptr<BodyFile>>(
      m, "Body",
      "A body hair rests on (body.h, docs/body.md): a union of spheres and closed triangle "
      "meshes, folded with a smooth minimum of radius `blend`, seen through its signed "
      "distance (m, negative inside). Immutable; queries are vectorized over (..., 3) arrays "
      "of points and release the GIL for large inputs. Accepted wherever the module takes a "
      "body (render(body=...), invert(body=...)). Pickles as its JSON document and the "
      "absolute directory of its OBJ files (parsed again: the mesh files must still be there).")
      .def(py::init([](py::object source, const std::string& base_directory) {
             return std::const_pointer_cast<BodyFile>(BodyFileFrom(source, "body", base_directory));
           }),
           py::arg("source"), py::arg("base_directory") = ".",
           "A body from a body file path or a body dict in the file's JSON schema "
           "(docs/body.md: {\"spheres\": [{\"name\", \"center\", \"radius\"}], \"meshes\": "
           "[{\"obj\": PATH}], \"blend\", \"mesh_distance\", \"grid_spacing\", "
           "\"grid_band\"}; blend defaults to 0.005 m and mesh distances to the grid, as in "
           "files). A dict's relative OBJ paths are taken from base_directory. Every field is "
           "checked; errors are ringlet.Error naming it.")
      .def(
          "signed_distance",
          [](const BodyFile& self, py::handle points) { return Query(self, points, false, false); },
          py::arg("points"),
          "Signed distance (m, negative inside) at points (..., 3) (m): an array of shape "
          "(...,), or a float for a single point (3,). Body::SignedDistance: exact for spheres "
          "(|x - c| - r) and exact mesh queries, the grid's B-spline for grid meshes, folded by "
          "the smooth minimum where components are within `blend` of each other.")
      .def(
          "signed_distance_gradient",
          [](const BodyFile& self, py::handle points) { return Query(self, points, true, false); },
          py::arg("points"),
          "(distance, gradient): the signed distance as signed_distance and its gradient, the "
          "outward unit normal of the closest surface point (..., 3) (dimensionless; a convex "
          "combination of the components' normals on the smooth union's creases, |g| <= 1).")
      .def(
          "signed_distance_hessian",
          [](const BodyFile& self, py::handle points) { return Query(self, points, true, true); },
          py::arg("points"),
          "(distance, gradient, hessian): as signed_distance_gradient plus the Hessian of the "
          "distance (..., 3, 3) (1/m), Body::SignedDistanceHessian: (I - n n^T) / |x - c| for "
          "a sphere, the smooth minimum's own Hessian on the creases (docs/body.md).")
      .def_property_readonly(
          "spheres",
          [](const BodyFile& self) {
            py::list out;
            for (size_t i = 0; i < self.body->spheres().size(); ++i) {
              const Sphere& s = self.body->spheres()[i];
              py::dict d;
              d["name"] = s.name;
              d["center"] = Vec3Array(s.center);
              d["radius"] = s.radius;
              d["moves_with"] = BodyPartName(self.body->sphere_part(i));
              out.append(d);
            }
            return out;
          },
          "The spheres in file order: dicts {\"name\", \"center\" (3,) (m), \"radius\" (m), "
          "\"moves_with\" (\"head\" or \"torso\": the part it moves with when the head moves, "
          "docs/body.md)} (copies).")
      .def_property_readonly(
          "meshes",
          [](const BodyFile& self) {
            py::list out;
            for (size_t k = 0; k < self.body->meshes().size(); ++k) {
              const TriangleMesh& mesh = self.body->meshes()[k];
              std::vector<double> v;
              v.reserve(3 * mesh.vertices().size());
              for (const Vec3& p : mesh.vertices()) v.insert(v.end(), {p.x(), p.y(), p.z()});
              std::vector<std::int32_t> t;
              t.reserve(3 * mesh.triangles().size());
              for (const auto& tri : mesh.triangles()) t.insert(t.end(), tri.begin(), tri.end());
              py::dict d;
              d["name"] = mesh.name();
              d["vertices"] =
                  OwnedArray(std::move(v), {static_cast<py::ssize_t>(mesh.vertices().size()), 3});
              d["triangles"] =
                  OwnedArray(std::move(t), {static_cast<py::ssize_t>(mesh.triangles().size()), 3});
              d["volume"] = mesh.volume();
              d["moves_with"] = BodyPartName(self.body->mesh_part(k));
              out.append(d);
            }
            return out;
          },
          "The closed meshes (one per OBJ object or group): dicts {\"name\", \"vertices\" "
          "(V, 3) float64 (m), \"triangles\" (T, 3) int32 (counter-clockwise seen from "
          "outside), \"volume\" (m^3), \"moves_with\" (\"head\" or \"torso\")} (copies).")
      .def_property_readonly(
          "blend", [](const BodyFile& self) { return self.body->blend(); },
          "Radius of the smooth union (m; 0 = exact minimum).")
      .def_property_readonly(
          "mesh_distance",
          [](const BodyFile& self) {
            return std::string(self.body->mesh_distance().mode == MeshDistanceOptions::Mode::kGrid
                                   ? "grid"
                                   : "exact");
          },
          "\"grid\" (a B-spline of exact distances on a grid, C^2) or \"exact\" (closest-point "
          "queries) for the meshes.")
      .def_property_readonly(
          "grid_spacing", [](const BodyFile& self) { return self.body->mesh_distance().spacing; },
          "Grid spacing h (m), used in grid mode with meshes.")
      .def_property_readonly(
          "grid_band", [](const BodyFile& self) { return self.body->mesh_distance().band; },
          "Half-width of the grid's exact band (m): distances are clamped to +-band.")
      .def_property_readonly(
          "bounds",
          [](const BodyFile& self) {
            const Box3& b = self.body->Bounds();
            return OwnedArray(std::vector<double>{b.min().x(), b.min().y(), b.min().z(),
                                                  b.max().x(), b.max().y(), b.max().z()},
                              {2, 3});
          },
          "Box around all the components: (2, 3) array of its min and max corners (m).")
      .def_property_readonly(
          "base_directory", [](const BodyFile& self) { return self.base_directory; },
          "Absolute directory of its relative OBJ paths.")
      .def(
          "document",
          [](const BodyFile& self) {
            return py::module_::import("json").attr("loads")(self.document_text);
          },
          "The body's JSON document as a dict (a new dict: the file's, or the one given).");
}

}  // namespace ringlet::python
