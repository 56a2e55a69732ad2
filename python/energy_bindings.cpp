// The energy of one configuration (energy.h, strand_hessian.h) for the Python module: the terms
// of E = E_e + E_g + E_c (paper eqs. 2-5 and section 3.1), their exact gradient and exact dense
// Hessian in the curvature coordinates. Bindings only: StrandEnergy and ComputeStrandHessian.
#include <pybind11/stl.h>

#include <cmath>
#include <string>
#include <vector>

#include "bindings.h"
#include "ringlet/energy.h"
#include "ringlet/statics.h"
#include "ringlet/strand_hessian.h"
#include "ringlet/strand_model.h"

namespace ringlet::python {

namespace {

// The model (checked: IsValid) and the curvatures of a configuration: an (n, 3) array of
// (kappa1, kappa2, tau) per segment or the flat (3n,) vector (1/m), finite.
struct Configuration {
  StrandModel model;  // a copy: the work runs without the GIL
  VecX curvatures;
};

Configuration ConfigurationFrom(const StrandModel& model, py::handle curvatures) {
  Configuration c{model, VecX()};
  std::string why;
  if (!IsValid(c.model, &why)) throw Error("model: " + why);
  const py::ssize_t n = c.model.NumSegments();
  const char* expected = "an (n, 3) or (3n,) array of (kappa1, kappa2, tau) per segment (1/m)";
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(
      RealArray(curvatures, "curvatures", expected));
  if (!a || !((a.ndim() == 2 && a.shape(0) == n && a.shape(1) == 3) ||
              (a.ndim() == 1 && a.shape(0) == 3 * n))) {
    throw Error(std::string("curvatures: expected ") + expected + ", n = " + std::to_string(n) +
                " segments, got shape " +
                std::string(py::str(py::module_::import("numpy").attr("shape")(curvatures))));
  }
  c.curvatures.resize(3 * n);
  for (py::ssize_t i = 0; i < 3 * n; ++i) {
    c.curvatures[i] = a.data()[i];
    if (!std::isfinite(c.curvatures[i])) {
      throw Error("curvatures: expected finite numbers (1/m), got " +
                  std::string(py::repr(py::float_(a.data()[i]))) + " at segment " +
                  std::to_string(i / 3));
    }
  }
  return c;
}

py::array Flat(const VecX& v) {
  return OwnedArray(std::vector<double>(v.data(), v.data() + v.size()), {v.size()});
}

}  // namespace

void BindEnergy(py::module_& m) {
  m.def(
      "energy",
      [](const StrandModel& model, py::handle curvatures) {
        Configuration c = ConfigurationFrom(model, curvatures);
        EnergyTerms terms;
        {
          py::gil_scoped_release release;
          StrandEnergy(c.model).Evaluate(c.curvatures, nullptr, &terms);
        }
        return terms;
      },
      py::arg("model"), py::arg("curvatures"),
      "The energy terms (J) of the configuration `curvatures` ((n, 3) or (3n,) (kappa1, "
      "kappa2, tau) per segment, 1/m) of model (StrandEnergy, energy.h): elastic (eq. 3, 0 at "
      "the rest shape), gravity (eqs. 4-5, measured from the root: -f . int (r(s) - r(0)) ds), "
      "contact (the body penalty of section 3.1, 0 without a body) and their total: the "
      "function the solver minimizes.");
  m.def(
      "gradient",
      [](const StrandModel& model, py::handle curvatures) {
        Configuration c = ConfigurationFrom(model, curvatures);
        VecX g;
        {
          py::gil_scoped_release release;
          StrandEnergy(c.model).Evaluate(c.curvatures, &g, nullptr);
        }
        return Flat(g);
      },
      py::arg("model"), py::arg("curvatures"),
      "The exact gradient dE/dq of the total energy (J m) at curvatures q ((n, 3) or (3n,), "
      "1/m): a (3n,) float64 array, (kappa1, kappa2, tau) of segment 0 first (StrandEnergy: "
      "the closed-form derivatives of eqs. 3-5 and of the contact penalty, one reverse sweep). "
      "Zero at an equilibrium.");
  m.def(
      "hessian",
      [](const StrandModel& model, py::handle curvatures) {
        Configuration c = ConfigurationFrom(model, curvatures);
        std::string why;
        if (!CheckMethodSegments(c.model.NumSegments(), Method::kBfgs, &why)) {
          throw Error("model: the dense Hessian (3n x 3n): " + why);
        }
        MatX dense;
        {
          py::gil_scoped_release release;
          StrandHessian h;
          ComputeStrandHessian(c.model, c.curvatures, &h);
          dense = h.Dense();
        }
        // The matrix itself, not a copy: Eigen's column-major storage as a Fortran-ordered
        // array (a row-major copy cost 1 s at n = 1000, one cache miss per element).
        const auto size = static_cast<py::ssize_t>(dense.rows());
        auto* owned = new MatX(std::move(dense));
        py::capsule owner(owned, [](void* p) { delete static_cast<MatX*>(p); });
        return py::array(py::dtype::of<double>(), {size, size},
                         {static_cast<py::ssize_t>(sizeof(double)),
                          static_cast<py::ssize_t>(sizeof(double)) * size},
                         owned->data(), owner);
      },
      py::arg("model"), py::arg("curvatures"),
      "The exact Hessian d^2E/dq^2 of the total energy (J m^2) at curvatures q ((n, 3) or "
      "(3n,), 1/m): a dense symmetric (3n, 3n) float64 array, Fortran-ordered "
      "(ComputeStrandHessian, "
      "strand_hessian.h: closed-form second derivatives of every helical segment, the body's "
      "own distance Hessian for contact; exact to rounding, not finite differences). The "
      "solver's stability certificate factors the same matrix. At most 1000 segments (the "
      "dense matrix takes 72 n^2 bytes). The contact penalty is C^1: its Hessian jumps where a "
      "sample enters or leaves contact.");
}

}  // namespace ringlet::python
