// Independent reference for the small oscillations of a clamped-free rod under an axial load:
// the Euler-Bernoulli eigenproblem
//   EI w'''' - (T(s) w')' = rho S omega^2 w,   w(0) = w'(0) = 0,  w''(L) = 0,  w'''(L) = 0,
// (the free end carries no load, T(L) = 0) in the dimensionless form (s in [0, 1], EI = rho S =
// L = 1), lambda = rho S omega^2 L^4 / EI:
//   w'''' - (t(s) w')' = lambda w,   t(s) = G (1 - s)   (hanging: the weight below pulls),
//                                     t(s) = -G (1 - s)  (standing: it pushes),
// with G = rho S g L^3 / EI. Solved by Chebyshev collocation (Trefethen, Spectral Methods in
// MATLAB, SIAM 2000, program cheb and chapter 14): the four boundary conditions replace the
// equations at the four points nearest the ends and are eliminated (static condensation), then
// the dense nonsymmetric eigenproblem of the interior values is solved by Eigen. Written for the
// tests of dynamics (tests/dynamics_test.cpp), independently of the library: no ringlet code.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <vector>

namespace ringlet::reference {

/// Chebyshev differentiation matrix on the N + 1 points x_j = cos(pi j / N) of [-1, 1]
/// (Trefethen, program cheb.m, with the negative-sum trick for the diagonal).
inline Eigen::MatrixXd ChebyshevDifferentiation(int n, Eigen::VectorXd* points) {
  constexpr double kPi = 3.14159265358979323846;
  Eigen::VectorXd x(n + 1);
  for (int j = 0; j <= n; ++j) x(j) = std::cos(kPi * j / n);
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(n + 1, n + 1);
  auto c = [&](int j) { return ((j == 0 || j == n) ? 2.0 : 1.0) * ((j % 2) ? -1.0 : 1.0); };
  for (int i = 0; i <= n; ++i) {
    for (int j = 0; j <= n; ++j) {
      if (i != j) d(i, j) = c(i) / c(j) / (x(i) - x(j));
    }
  }
  for (int i = 0; i <= n; ++i) d(i, i) = -d.row(i).sum();
  *points = x;
  return d;
}

enum class AxialLoad { kHanging, kStanding };

/// The lowest `count` eigenvalues lambda (ascending) of the clamped-free rod with the
/// dimensionless load G, by Chebyshev collocation on n + 1 points.
inline std::vector<double> BeamEigenvalues(double load, AxialLoad kind, int n, int count) {
  Eigen::VectorXd x;
  // s = (1 - x) / 2 maps x = 1 (index 0) to the clamp s = 0 and x = -1 (index n) to the free
  // end s = 1; d/ds = -2 d/dx.
  const Eigen::MatrixXd d1 = -2.0 * ChebyshevDifferentiation(n, &x);
  const Eigen::MatrixXd d2 = d1 * d1;
  const Eigen::MatrixXd d3 = d2 * d1;
  const Eigen::MatrixXd d4 = d2 * d2;
  const double sign = kind == AxialLoad::kHanging ? 1.0 : -1.0;
  Eigen::VectorXd t(n + 1), dt(n + 1);
  for (int j = 0; j <= n; ++j) {
    const double s = 0.5 * (1.0 - x(j));
    t(j) = sign * load * (1.0 - s);
    dt(j) = -sign * load;
  }
  // A w = w'''' - t w'' - t' w'.
  const Eigen::MatrixXd a = d4 - t.asDiagonal() * d2 - dt.asDiagonal() * d1;
  // Boundary rows: w(0) = 0 and w'(0) = 0 at the clamp (index 0), w''(1) = w'''(1) = 0 at the
  // free end (index n); they replace the equations at indices 0, 1, n - 1, n.
  const int m = n + 1;
  const std::vector<int> boundary = {0, 1, n - 1, n};
  std::vector<int> interior;
  for (int j = 2; j <= n - 2; ++j) interior.push_back(j);
  Eigen::MatrixXd c(4, m);
  c.row(0) = Eigen::RowVectorXd::Unit(m, 0);
  c.row(1) = d1.row(0);
  c.row(2) = d2.row(n);
  c.row(3) = d3.row(n);
  Eigen::MatrixXd cb(4, 4), ci(4, interior.size());
  for (int r = 0; r < 4; ++r) {
    for (int k = 0; k < 4; ++k) cb(r, k) = c(r, boundary[static_cast<size_t>(k)]);
    for (size_t k = 0; k < interior.size(); ++k) ci(r, static_cast<Eigen::Index>(k)) = c(r, interior[k]);
  }
  // w_b = -cb^(-1) ci w_i.
  const Eigen::MatrixXd elimination = -cb.fullPivLu().solve(ci);
  const Eigen::Index ni = static_cast<Eigen::Index>(interior.size());
  Eigen::MatrixXd aii(ni, ni), aib(ni, 4);
  for (Eigen::Index r = 0; r < ni; ++r) {
    for (Eigen::Index k = 0; k < ni; ++k) aii(r, k) = a(interior[static_cast<size_t>(r)], interior[static_cast<size_t>(k)]);
    for (int k = 0; k < 4; ++k) aib(r, k) = a(interior[static_cast<size_t>(r)], boundary[static_cast<size_t>(k)]);
  }
  const Eigen::MatrixXd reduced = aii + aib * elimination;
  Eigen::EigenSolver<Eigen::MatrixXd> solver(reduced, false);
  std::vector<double> values;
  for (Eigen::Index k = 0; k < ni; ++k) {
    const std::complex<double> v = solver.eigenvalues()(k);
    // The low modes are real; spurious high ones may come in complex pairs.
    if (std::abs(v.imag()) <= 1e-8 * std::max(1.0, std::abs(v.real()))) values.push_back(v.real());
  }
  std::sort(values.begin(), values.end());
  values.resize(std::min(values.size(), static_cast<size_t>(count)));
  return values;
}

}  // namespace ringlet::reference
