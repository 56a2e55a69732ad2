// Independent reference for a rod on a clamp turning at constant angular velocity about a vertical
// axis: the steady relative equilibrium (the shape at rest in the turning frame) of a planar,
// inextensible, unshearable Kirchhoff rod under gravity and the centrifugal load, by shooting.
// Written for the dynamics' validation (tests/dynamics_test.cpp, tools/dynamics_study.cpp),
// independently of the library.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <vector>

namespace ringlet::reference {

// The relative equilibrium of an inextensible, unshearable planar rod (Kirchhoff) clamped at
// (x, z) = (R, 0) with horizontal tangent, turning at Omega about the vertical axis x = 0, in the
// turning frame: per unit length the load is f = rho S (Omega^2 x, -g). With theta the tangent's
// angle above the horizontal, n the internal force (of the part beyond s on the part before) and
// m the bending moment (Antman, Nonlinear Problems of Elasticity, ch. 4: n' + f = 0,
// m' + t x n = 0, m = EI theta'):
//   x' = cos theta, z' = sin theta, theta' = m / EI, m' = -(cos theta n_z - sin theta n_x),
//   n_x' = -rho S Omega^2 x, n_z' = rho S g,
// with x(0) = R, z(0) = 0, theta(0) = 0 and m(L) = n(L) = 0. RK4 on `steps` steps, shooting on the
// three root values (m, n_x, n_z)(0) by Newton with a difference Jacobian, with continuation in
// Omega from 0. Only Eigen; no ringlet code.
struct PlanarRotatingRod {
  double length, radius_of_clamp, omega, rho_s, ei, g;
  int steps = 4000;

  using State = std::array<double, 6>;  // x, z, theta, m, n_x, n_z

  State Derivative(const State& y) const {
    const double c = std::cos(y[2]), s = std::sin(y[2]);
    return {c, s, y[3] / ei, -(c * y[5] - s * y[4]), -rho_s * omega * omega * y[0], rho_s * g};
  }

  // Integrates from the root values; returns the states at every step.
  std::vector<State> Shoot(const std::array<double, 3>& root) const {
    std::vector<State> out;
    State y = {radius_of_clamp, 0.0, 0.0, root[0], root[1], root[2]};
    out.push_back(y);
    const double h = length / steps;
    for (int k = 0; k < steps; ++k) {
      auto add = [](const State& a, const State& b, double t) {
        State c;
        for (int i = 0; i < 6; ++i) c[static_cast<size_t>(i)] = a[static_cast<size_t>(i)] + t * b[static_cast<size_t>(i)];
        return c;
      };
      const State k1 = Derivative(y);
      const State k2 = Derivative(add(y, k1, 0.5 * h));
      const State k3 = Derivative(add(y, k2, 0.5 * h));
      const State k4 = Derivative(add(y, k3, h));
      for (size_t i = 0; i < 6; ++i) y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
      out.push_back(y);
    }
    return out;
  }

  // Continuation in Omega from the straight rod's loads (n(0) = the total load, m(0) = the
  // weight's moment) at Omega = 0: Newton from a nearby solution at each of 20 stages.
  std::vector<State> Solve() const {
    std::array<double, 3> root = {-0.5 * rho_s * g * length * length, 0.0, -rho_s * g * length};
    PlanarRotatingRod stage = *this;
    for (int k = 0; k <= 20; ++k) {
      stage.omega = omega * k / 20.0;
      stage.Newton(&root);
    }
    return Shoot(root);
  }

  // Newton on the tip conditions; returns the last relative residual.
  double Newton(std::array<double, 3>* root_values) const {
    std::array<double, 3>& root = *root_values;
    double residual = 0.0;
    auto miss = [&](const std::array<double, 3>& r) {
      const State tip = Shoot(r).back();
      return std::array<double, 3>{tip[3], tip[4], tip[5]};
    };
    for (int iteration = 0; iteration < 50; ++iteration) {
      const std::array<double, 3> f = miss(root);
      const double scale = rho_s * (g + omega * omega * (radius_of_clamp + length)) * length;
      residual = std::abs(f[0]) / (scale * length) + std::abs(f[1]) / scale + std::abs(f[2]) / scale;
      if (residual < 1e-13) break;
      Eigen::Matrix3d j;
      for (int c = 0; c < 3; ++c) {
        std::array<double, 3> p = root, m = root;
        const double e = 1e-7 * (c == 0 ? scale * length : scale);
        p[static_cast<size_t>(c)] += e;
        m[static_cast<size_t>(c)] -= e;
        const std::array<double, 3> fp = miss(p), fm = miss(m);
        for (int r = 0; r < 3; ++r) j(r, c) = (fp[static_cast<size_t>(r)] - fm[static_cast<size_t>(r)]) / (2.0 * e);
      }
      const Eigen::Vector3d d = j.lu().solve(-Eigen::Vector3d(f[0], f[1], f[2]));
      for (int c = 0; c < 3; ++c) root[static_cast<size_t>(c)] += d(c);
    }
    return residual;
  }
};

}  // namespace ringlet::reference
