// An independent reference for the planar heavy elastica: a clamped, inextensible rod bending in a
// vertical plane under its own weight, solved as a two-point boundary value problem by shooting
// with an adaptive Dormand-Prince 5(4) integrator. It shares no code with the ringlet rod model (no
// helices, no energy minimization, no Eigen): only the standard library, so that it can check the
// 3D solver.
//
// Problem (dimensionless: lengths in units of L, s in [0, 1]; gravity along -z):
//   theta''(s) = lambda (1 - s) cos theta,    theta(0) = theta0,    theta'(1) = k,
//   x' = cos theta,   z' = sin theta,         x(0) = z(0) = 0,
// with theta the angle of the tangent above the horizontal, lambda = w L^3 / EI the load (w the
// weight per unit length, EI the bending stiffness in the plane of bending) and k = kappa0 L the
// natural curvature in that plane. With natural curvature the moment is EI (theta' - kappa0), whose
// derivative is EI theta'' since kappa0 is constant; the free tip carries no moment, theta'(1) = k.
// This is the Euler-Lagrange equation of the energy (units of EI / L)
//   E = 1/2 int (theta' - k)^2 ds + lambda int z ds,
// where lambda int z ds = lambda int (1 - s) sin theta is the gravity energy measured from the
// root, exactly as ringlet measures it.
//
// Variables. Write theta = phi - pi/2 (phi = 0 hangs straight down):
//   phi'' = lambda (1 - s) sin phi.
// A heavy rod hangs with phi ~ 0 over most of its length and phi is exponentially small at a
// straight tip (4e-9 at lambda = 1000); storing phi rather than theta keeps it to full relative
// precision (theta + pi/2 would cancel).
//
// Why not plain forward shooting on theta'(0): a heavy rod has a bending layer of width
// ~ 1/sqrt(lambda) at the root, and the linearized equation phi'' = lambda (1 - s) phi has modes
// growing like exp(+-2/3 sqrt(lambda) (1 - (1 - s)^(3/2))): a forward shot must control
// exp(21) ~ 1e9 at lambda = 1000 (and exp(sqrt(lambda) s) near the root): hopeless.
//
// Two methods, which the tests compare with each other:
//  - kBackwardShooting: shoot from the tip, unknown phi(1) = delta with phi'(1) = k known,
//    integrate to s = 0 and solve phi(0; delta) = theta0 + pi/2 by safeguarded Newton. For a
//    straight (k = 0) rod this is well conditioned at any load: the solution is the growing mode
//    itself and delta carries its amplitude. With natural curvature the curled, lightly loaded tip
//    makes delta O(1) while the hanging part needs an exponentially small combination of it:
//    d phi(0) / d delta ~ exp(2/3 sqrt(lambda)): above lambda ~ 400 (k = 2) the continuation
//    jumps to unstable equilibria (which the Jacobi certificate below flags) or fails.
//  - kMultipleShooting (default): M intervals, each short enough that the modes grow by about e
//    over it; the unknowns are (phi, phi') at the interior nodes and phi'(0); Newton on the
//    matching conditions with the exact Jacobian (the 2x2 transfer matrices from the variational
//    equation), solved by dense Gaussian elimination with partial pivoting. Well conditioned at
//    any load.
// Both raise the load by continuation from lambda = 0, where the natural arc theta = theta0 + k s
// is exact, so the equilibrium found is the one connected to the natural shape, like a minimizer
// started from the natural shape.
//
// Stability (an independent certificate): the second variation
//   int J'^2 + lambda (1 - s) cos phi J^2,   J(0) = 0, free tip,
// is positive definite iff the Jacobi field J'' = lambda (1 - s) cos phi J with J(1) = 1,
// J'(1) = 0 has no zero on [0, 1] (Jacobi's condition with a free end). It is integrated from the
// tip with the final shape. This is stability against perturbations IN the plane only.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace ringlet::reference {

/// The dimensionless planar heavy elastica (lengths in units of the rod length L).
struct HeavyElasticaProblem {
  /// Load lambda = w L^3 / EI >= 0 (dimensionless): w the weight per unit length (N/m), EI the
  /// bending stiffness in the plane of bending (N m^2).
  double load = 0.0;
  /// Clamp angle theta0 of the root tangent above the horizontal (rad).
  double root_angle = 0.0;
  /// Natural curvature k = kappa0 L in the vertical plane (dimensionless); positive curls upward
  /// (counter-clockwise seen with x to the right and z up).
  double natural_curvature = 0.0;
};

/// How the boundary value problem is solved (see the file comment).
enum class ShootingMethod { kMultipleShooting, kBackwardShooting };

/// Accuracy and budget of the reference solve.
struct HeavyElasticaOptions {
  ShootingMethod method = ShootingMethod::kMultipleShooting;
  /// Relative tolerance of each Dormand-Prince step, per state component.
  double relative_tolerance = 1e-12;
  /// Absolute tolerance of each step, per state component (angles in rad, lengths in L).
  double absolute_tolerance = 1e-12;
  /// Newton stops when the largest boundary / matching residual is below this (rad, or 1/L for
  /// curvatures). It cannot be much below the integration error.
  double residual_tolerance = 1e-11;
  /// Integrator budget per integration.
  int max_steps = 1000000;
  /// Newton budget per continuation step.
  int max_newton_iterations = 50;
  /// Continuation steps in the load (before any step halving); 0 chooses 8 + 2 sqrt(lambda).
  int continuation_steps = 0;
  /// Multiple-shooting intervals; 0 chooses 4 + ceil(sqrt(lambda)).
  int intervals = 0;
};

/// The reference equilibrium. Lengths are in units of L, energies in units of EI / L.
struct HeavyElasticaSolution {
  bool converged = false;       ///< the boundary value problem was solved at the full load
  std::string message;          ///< one sentence: what happened
  double tip_angle = 0.0;       ///< theta(1) (rad), continuous from theta0 along the rod
  double root_curvature = 0.0;  ///< theta'(0) L (dimensionless)
  double tip_x = 0.0;           ///< x(1) - x(0) (units of L)
  double tip_z = 0.0;           ///< z(1) - z(0) (units of L)
  double elastic_energy = 0.0;  ///< 1/2 int (theta' - k)^2 ds (units of EI / L)
  double gravity_energy = 0.0;  ///< lambda int z ds (units of EI / L)
  /// Global moment balance theta'(0) - k + lambda int x ds (dimensionless): zero at an exact
  /// equilibrium (the root moment equals the moment of the weight about the root), so its size
  /// measures the solution error.
  double moment_balance = 0.0;
  /// |theta(0) - theta0| (rad) after integrating the final shape back from the tip to the root.
  double root_angle_error = 0.0;
  bool stable = false;         ///< the Jacobi field has no zero on [0, 1]
  double min_jacobi = 0.0;     ///< smallest J(s) over the integration steps (J(1) = 1)
  int newton_iterations = 0;   ///< over all continuation steps
  int continuation_steps = 0;  ///< loads solved on the way to the full load
  int integrator_steps = 0;    ///< accepted Dormand-Prince steps of the final tip-to-root sweep
  /// The shape as nodes s_0 = 0 < ... < s_M = 1 with phi = theta + pi/2 and phi' there; the final
  /// sweep (and SampleHeavyElastica) integrates each interval back from its right node.
  std::vector<double> node_s, node_phi, node_dphi;
};

/// A point of the reference centreline.
struct ElasticaPoint {
  double s = 0.0;      ///< arc length from the root (units of L)
  double theta = 0.0;  ///< tangent angle above the horizontal (rad)
  double x = 0.0;      ///< horizontal position relative to the root (units of L)
  double z = 0.0;      ///< vertical position relative to the root (units of L)
};

namespace internal {

constexpr double kPi = 3.14159265358979323846;
constexpr double kHalfPi = 0.5 * kPi;

// The state integrated along s, in either direction:
//   0 phi, 1 phi', 2 X = x(s) - x(s_start), 3 Z = z(s) - z(s_start), 4 A = int_start^s X,
//   5 B = int_start^s Z, 6 W = int_start^s 1/2 (phi' - k)^2,
//   7..10 the transfer matrix V = d(phi, phi')(s) / d(phi, phi')(s_start), column-major.
constexpr int kDim = 11;
using State = std::array<double, kDim>;

inline State Derivative(double s, const State& y, double lambda, double k) {
  const double sin_phi = std::sin(y[0]);
  const double cos_phi = std::cos(y[0]);
  const double load = lambda * (1.0 - s);
  const double bend = y[1] - k;
  const double stiffness = load * cos_phi;  // d(phi'')/d(phi)
  State d;
  d[0] = y[1];
  d[1] = load * sin_phi;  // phi'' = lambda (1 - s) cos theta, cos theta = sin phi
  d[2] = sin_phi;         // x' = cos theta
  d[3] = -cos_phi;        // z' = sin theta
  d[4] = y[2];
  d[5] = y[3];
  d[6] = 0.5 * bend * bend;
  d[7] = y[8];  // V' = [[0, 1], [stiffness, 0]] V
  d[8] = stiffness * y[7];
  d[9] = y[10];
  d[10] = stiffness * y[9];
  return d;
}

// The state at the start of an integration: (phi, phi'), zero integrals, V = I.
inline State StartState(double phi, double dphi) {
  State y{};
  y[0] = phi;
  y[1] = dphi;
  y[7] = 1.0;
  y[10] = 1.0;
  return y;
}

// Dormand-Prince 5(4) (Hairer, Norsett & Wanner, Solving ODE I, table II.5.2), FSAL, with the
// standard step-size control (safety 0.9, factor in [0.2, 5], error in the RMS norm of
// err_i / (atol + rtol max(|y_i|, |y_new_i|))). Integrates *y from s0 to s1 (either direction).
// Steps are cut to land exactly on each point of stops (ordered from s0 towards s1, strictly
// inside), and on_step(s, y) is called after every accepted step. Returns false if the step size
// collapses, the budget runs out or the state becomes non-finite.
template <typename OnStep>
bool Integrate(double lambda, double k, double s0, double s1, State* state,
               const HeavyElasticaOptions& options, const std::vector<double>& stops,
               OnStep&& on_step, int* steps) {
  static constexpr double c2 = 1.0 / 5, c3 = 3.0 / 10, c4 = 4.0 / 5, c5 = 8.0 / 9;
  static constexpr double a21 = 1.0 / 5;
  static constexpr double a31 = 3.0 / 40, a32 = 9.0 / 40;
  static constexpr double a41 = 44.0 / 45, a42 = -56.0 / 15, a43 = 32.0 / 9;
  static constexpr double a51 = 19372.0 / 6561, a52 = -25360.0 / 2187, a53 = 64448.0 / 6561,
                          a54 = -212.0 / 729;
  static constexpr double a61 = 9017.0 / 3168, a62 = -355.0 / 33, a63 = 46732.0 / 5247,
                          a64 = 49.0 / 176, a65 = -5103.0 / 18656;
  static constexpr double b1 = 35.0 / 384, b3 = 500.0 / 1113, b4 = 125.0 / 192, b5 = -2187.0 / 6784,
                          b6 = 11.0 / 84;
  // Error weights: the 5th-order minus the embedded 4th-order weights.
  static constexpr double e1 = 71.0 / 57600, e3 = -71.0 / 16695, e4 = 71.0 / 1920,
                          e5 = -17253.0 / 339200, e6 = 22.0 / 525, e7 = -1.0 / 40;

  State& y = *state;
  const double direction = s1 > s0 ? 1.0 : -1.0;
  double s = s0;
  // Initial step: well inside the bending layer (width ~ 1/sqrt(lambda)).
  // h_free is the step the error control proposes; the step taken, h, may be cut to land on a
  // stop, which must not shrink the following steps (nor count as a collapse).
  double h_free = direction * std::min(1e-2, 1e-2 / std::sqrt(1.0 + lambda));
  size_t next_stop = 0;
  State k1 = Derivative(s, y, lambda, k), k2, k3, k4, k5, k6, k7, tmp, y_new;
  while (s != s1) {
    if (*steps >= options.max_steps) return false;
    // Land exactly on the next stop or on s1 (a repeated stop gives a step of zero: recorded
    // again).
    const double target = next_stop < stops.size() ? stops[next_stop] : s1;
    const bool lands = direction * (s + h_free - target) >= 0.0;
    const double h = lands ? target - s : h_free;
    for (int i = 0; i < kDim; ++i) tmp[i] = y[i] + h * a21 * k1[i];
    k2 = Derivative(s + c2 * h, tmp, lambda, k);
    for (int i = 0; i < kDim; ++i) tmp[i] = y[i] + h * (a31 * k1[i] + a32 * k2[i]);
    k3 = Derivative(s + c3 * h, tmp, lambda, k);
    for (int i = 0; i < kDim; ++i) tmp[i] = y[i] + h * (a41 * k1[i] + a42 * k2[i] + a43 * k3[i]);
    k4 = Derivative(s + c4 * h, tmp, lambda, k);
    for (int i = 0; i < kDim; ++i) {
      tmp[i] = y[i] + h * (a51 * k1[i] + a52 * k2[i] + a53 * k3[i] + a54 * k4[i]);
    }
    k5 = Derivative(s + c5 * h, tmp, lambda, k);
    for (int i = 0; i < kDim; ++i) {
      tmp[i] = y[i] + h * (a61 * k1[i] + a62 * k2[i] + a63 * k3[i] + a64 * k4[i] + a65 * k5[i]);
    }
    const double s_new = lands ? target : s + h;
    k6 = Derivative(s_new, tmp, lambda, k);
    for (int i = 0; i < kDim; ++i) {
      y_new[i] = y[i] + h * (b1 * k1[i] + b3 * k3[i] + b4 * k4[i] + b5 * k5[i] + b6 * k6[i]);
    }
    k7 = Derivative(s_new, y_new, lambda, k);
    double err = 0.0;
    for (int i = 0; i < kDim; ++i) {
      const double e =
          h * (e1 * k1[i] + e3 * k3[i] + e4 * k4[i] + e5 * k5[i] + e6 * k6[i] + e7 * k7[i]);
      const double scale =
          options.absolute_tolerance +
          options.relative_tolerance * std::max(std::abs(y[i]), std::abs(y_new[i]));
      err += (e / scale) * (e / scale);
    }
    err = std::sqrt(err / kDim);
    if (!std::isfinite(err)) return false;
    if (err <= 1.0) {
      s = s_new;
      y = y_new;
      k1 = k7;  // first same as last
      ++*steps;
      if (lands && next_stop < stops.size()) ++next_stop;
      on_step(s, y);
    }
    const double factor = err == 0.0 ? 5.0 : std::clamp(0.9 * std::pow(err, -0.2), 0.2, 5.0);
    if (err > 1.0) {
      h_free = h * std::min(factor, 1.0);
    } else if (!lands) {
      h_free = h * factor;
    }  // else: a landing step no longer than h_free was accepted; keep h_free
    if (std::abs(h_free) < 1e-15) return false;  // the step size collapsed
  }
  return true;
}

// The final sweep from the tip to the root through the nodes: interval j is integrated back from
// node j + 1, restarting (phi, phi') at the node value but carrying the position integrals and the
// Jacobi field (the first column of the accumulated transfer matrix, J(1) = 1, J'(1) = 0).
struct Sweep {
  bool ok = false;
  State root{};             // at s = 0: positions relative to the tip, integrals from the tip
  double min_jacobi = 1.0;  // smallest J over the accepted steps
  int steps = 0;
  std::vector<State> at_stops;  // the state at each requested stop, in the order of stops
};

inline Sweep SweepToRoot(double lambda, double k, const std::vector<double>& node_s,
                         const std::vector<double>& node_phi, const std::vector<double>& node_dphi,
                         const HeavyElasticaOptions& options,
                         const std::vector<double>& stops = {}) {
  Sweep sweep;
  const int m = static_cast<int>(node_s.size()) - 1;
  State y = StartState(node_phi[m], node_dphi[m]);
  // Jacobi field (J, J') carried across nodes: J = V (1, 0) with V accumulated.
  double j_value = 1.0, j_slope = 0.0;
  size_t stop = 0;
  while (stop < stops.size() && stops[stop] >= 1.0) {
    sweep.at_stops.push_back(y);
    ++stop;
  }
  for (int i = m - 1; i >= 0; --i) {
    // Restart phi, phi' and V at node i + 1 (the integrals carry on).
    const double jv = j_value, js = j_slope;
    if (i < m - 1) {
      y[0] = node_phi[i + 1];
      y[1] = node_dphi[i + 1];
    }
    y[7] = 1.0;
    y[8] = 0.0;
    y[9] = 0.0;
    y[10] = 1.0;
    std::vector<double> inner;
    size_t first = stop;
    while (stop < stops.size() && stops[stop] > node_s[i]) inner.push_back(stops[stop++]);
    // Stops at the node itself are recorded after the interval.
    size_t recorded = first;
    auto on_step = [&](double s, const State& state) {
      const double jacobi = state[7] * jv + state[9] * js;
      sweep.min_jacobi = std::min(sweep.min_jacobi, jacobi);
      if (recorded < first + inner.size() && s == stops[recorded]) {
        sweep.at_stops.push_back(state);
        ++recorded;
      }
    };
    if (!Integrate(lambda, k, node_s[i + 1], node_s[i], &y, options, inner, on_step,
                   &sweep.steps)) {
      return sweep;
    }
    j_value = y[7] * jv + y[9] * js;
    j_slope = y[8] * jv + y[10] * js;
    while (stop < stops.size() && stops[stop] >= node_s[i]) {
      sweep.at_stops.push_back(y);
      ++stop;
    }
  }
  sweep.root = y;
  sweep.ok = sweep.at_stops.size() == stops.size();
  return sweep;
}

// Solves the dense system a x = b (n x n, row-major) by Gaussian elimination with partial
// pivoting; false if singular.
inline bool SolveDense(std::vector<double> a, std::vector<double>* b) {
  const int n = static_cast<int>(b->size());
  std::vector<double>& x = *b;
  for (int c = 0; c < n; ++c) {
    int pivot = c;
    for (int r = c + 1; r < n; ++r) {
      if (std::abs(a[r * n + c]) > std::abs(a[pivot * n + c])) pivot = r;
    }
    if (a[pivot * n + c] == 0.0 || !std::isfinite(a[pivot * n + c])) return false;
    if (pivot != c) {
      for (int j = 0; j < n; ++j) std::swap(a[c * n + j], a[pivot * n + j]);
      std::swap(x[c], x[pivot]);
    }
    for (int r = c + 1; r < n; ++r) {
      const double f = a[r * n + c] / a[c * n + c];
      if (f == 0.0) continue;
      for (int j = c; j < n; ++j) a[r * n + j] -= f * a[c * n + j];
      x[r] -= f * x[c];
    }
  }
  for (int r = n - 1; r >= 0; --r) {
    double sum = x[r];
    for (int j = r + 1; j < n; ++j) sum -= a[r * n + j] * x[j];
    x[r] = sum / a[r * n + r];
  }
  return true;
}

// Multiple shooting at one load. Unknowns u = (phi'_0, phi_1, phi'_1, ..., phi_{M-1}, phi'_{M-1});
// phi_0 = theta0 + pi/2 is given. Residuals: for each interval i < M - 1 the mismatch of the
// integrated (phi, phi')(s_{i+1}) with node i + 1, and for the last interval phi'(1) - k.
// Damped Newton from the nodes given; on success the nodes hold the solution, including the tip
// node (phi(1), k) from the last interval.
inline bool SolveMultipleShooting(double lambda, double k, const std::vector<double>& node_s,
                                  std::vector<double>* node_phi, std::vector<double>* node_dphi,
                                  const HeavyElasticaOptions& options, int* iterations) {
  const int m = static_cast<int>(node_s.size()) - 1;
  const int n = 2 * m - 1;
  std::vector<double> phi = *node_phi, dphi = *node_dphi;
  // Residuals and transfer matrices of all intervals at the current nodes.
  std::vector<State> ends(m);
  auto evaluate = [&](const std::vector<double>& p, const std::vector<double>& dp,
                      std::vector<double>* r) {
    r->assign(n, 0.0);
    int steps = 0;
    for (int i = 0; i < m; ++i) {
      State y = StartState(p[i], dp[i]);
      if (!Integrate(
              lambda, k, node_s[i], node_s[i + 1], &y, options, {}, [](double, const State&) {},
              &steps)) {
        return false;
      }
      ends[i] = y;
      if (i < m - 1) {
        (*r)[2 * i] = y[0] - p[i + 1];
        (*r)[2 * i + 1] = y[1] - dp[i + 1];
      } else {
        (*r)[2 * i] = y[1] - k;
      }
    }
    return true;
  };
  auto norm = [](const std::vector<double>& r) {
    double v = 0.0;
    for (double x : r) v = std::max(v, std::abs(x));
    return v;
  };
  std::vector<double> r;
  if (!evaluate(phi, dphi, &r)) return false;
  double r_norm = norm(r);
  // Column of unknown (node j, component c): phi'_0 -> 0, (phi_j, phi'_j) -> 2j - 1, 2j.
  auto column = [](int j, int c) { return j == 0 ? 0 : 2 * j - 1 + c; };
  for (int it = 0; it < options.max_newton_iterations; ++it) {
    if (r_norm <= options.residual_tolerance) {
      *node_phi = phi;
      *node_dphi = dphi;
      node_phi->back() = ends[m - 1][0];
      node_dphi->back() = ends[m - 1][1];
      return true;
    }
    ++*iterations;
    // Jacobian: rows of interval i are V_i d(phi_i, phi'_i) - d(phi_{i+1}, phi'_{i+1}).
    std::vector<double> a(static_cast<size_t>(n) * n, 0.0);
    for (int i = 0; i < m; ++i) {
      const State& y = ends[i];
      const double v[2][2] = {{y[7], y[9]}, {y[8], y[10]}};  // v[row][col]
      const int rows = i < m - 1 ? 2 : 1;
      for (int row = 0; row < rows; ++row) {
        const int eq = 2 * i + row;
        const int vrow = i < m - 1 ? row : 1;  // the last equation is the phi' one
        for (int c = 0; c < 2; ++c) {
          if (i == 0 && c == 0) continue;  // phi_0 is fixed
          a[eq * n + column(i, c)] += v[vrow][c];
        }
        if (i < m - 1) a[eq * n + column(i + 1, row)] -= 1.0;
      }
    }
    std::vector<double> step = r;
    if (!SolveDense(a, &step)) return false;
    // Damped update: halve until the residual decreases.
    double t = 1.0;
    bool improved = false;
    std::vector<double> trial_phi, trial_dphi, trial_r;
    for (int halvings = 0; halvings < 30; ++halvings, t *= 0.5) {
      trial_phi = phi;
      trial_dphi = dphi;
      trial_dphi[0] -= t * step[0];
      for (int j = 1; j < m; ++j) {
        trial_phi[j] -= t * step[column(j, 0)];
        trial_dphi[j] -= t * step[column(j, 1)];
      }
      if (evaluate(trial_phi, trial_dphi, &trial_r) && norm(trial_r) < r_norm) {
        improved = true;
        break;
      }
    }
    if (!improved) {
      // At the noise floor of the integration the residual cannot decrease any more.
      if (r_norm <= 1e2 * options.residual_tolerance) {
        evaluate(phi, dphi, &r);
        *node_phi = phi;
        *node_dphi = dphi;
        node_phi->back() = ends[m - 1][0];
        node_dphi->back() = ends[m - 1][1];
        return true;
      }
      return false;
    }
    phi = trial_phi;
    dphi = trial_dphi;
    r = trial_r;
    r_norm = norm(r);
  }
  return false;
}

// Backward shooting at one load: solves phi(0; delta) = phi0 for the tip value delta, starting
// from delta0. The derivative d phi(0) / d delta is J(0), the (1,1) entry of the transfer matrix
// from the tip. Bracket the root by stepping outward from delta0, starting with the Newton step
// (phi(0) increases with delta on a stable branch, where J(0) > 0): a coarse first step would jump
// over neighbouring roots, since d phi(0) / d delta can be huge. Then safeguarded Newton inside the
// bracket (Numerical Recipes' rtsafe).
inline bool SolveBackwardShooting(double lambda, double k, double phi0, double delta0,
                                  const HeavyElasticaOptions& options, double* delta,
                                  int* iterations) {
  struct Value {
    double residual = 0.0, derivative = 0.0;
    bool ok = false;
  };
  auto shoot = [&](double d) {
    Value v;
    State y = StartState(d, k);
    int steps = 0;
    v.ok = Integrate(
        lambda, k, 1.0, 0.0, &y, options, {}, [](double, const State&) {}, &steps);
    v.residual = y[0] - phi0;
    v.derivative = y[7];
    ++*iterations;
    return v;
  };
  const Value v0 = shoot(delta0);
  if (!v0.ok) return false;
  if (std::abs(v0.residual) <= options.residual_tolerance) {
    *delta = delta0;
    return true;
  }
  double lo = delta0, hi = delta0, r_lo = v0.residual, r_hi = v0.residual;
  double step = v0.derivative > 0.0 ? 1.1 * std::abs(v0.residual / v0.derivative) : 0.0;
  step = std::max(step, 1e-15 * std::max(std::abs(delta0), 1e-300));
  for (int tries = 0;; ++tries, step *= 2.0) {
    if (tries > 200 || step > 4.0 * kPi) return false;
    const double trial = v0.residual > 0.0 ? delta0 - step : delta0 + step;
    const Value v = shoot(trial);
    if (!v.ok) return false;
    if (v0.residual > 0.0) {
      lo = trial;
      r_lo = v.residual;
      if (r_lo <= 0.0) break;
    } else {
      hi = trial;
      r_hi = v.residual;
      if (r_hi >= 0.0) break;
    }
  }
  double x = std::abs(r_lo) < std::abs(r_hi) ? lo : hi;
  for (int it = 0; it < options.max_newton_iterations; ++it) {
    const Value v = shoot(x);
    if (!v.ok) return false;
    if (std::abs(v.residual) <= options.residual_tolerance) {
      *delta = x;
      return true;
    }
    if (v.residual < 0.0) {
      lo = x;
    } else {
      hi = x;
    }
    double next = v.derivative != 0.0 ? x - v.residual / v.derivative : lo - 1.0;
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    // The bracket has shrunk to rounding: as good as double precision allows.
    if (next == lo || next == hi) {
      *delta = x;
      return std::abs(v.residual) <= 1e2 * options.residual_tolerance;
    }
    x = next;
  }
  return false;
}

}  // namespace internal

/// Solves the heavy elastica by continuation in the load from the natural arc (lambda = 0, exact)
/// with the chosen shooting method at each load (see the file comment). Never throws: failure is
/// reported in converged and message.
inline HeavyElasticaSolution SolveHeavyElastica(const HeavyElasticaProblem& problem,
                                                const HeavyElasticaOptions& options = {}) {
  using internal::kHalfPi;
  HeavyElasticaSolution solution;
  const double lambda = problem.load;
  const double k = problem.natural_curvature;
  if (!(std::isfinite(lambda) && lambda >= 0.0 && std::isfinite(k) &&
        std::isfinite(problem.root_angle))) {
    solution.message = "load must be finite and >= 0, angle and curvature finite";
    return solution;
  }
  const double phi0 = problem.root_angle + kHalfPi;
  const bool multiple = options.method == ShootingMethod::kMultipleShooting;

  // Nodes: multiple shooting spaces them evenly in 1 - (1 - s)^(3/2), the growth exponent of the
  // linearized modes, so that each interval sees about the same growth; backward shooting has
  // the root and the tip only.
  int m = 1;
  if (multiple) {
    m = options.intervals > 0 ? options.intervals
                              : 4 + static_cast<int>(std::ceil(std::sqrt(lambda)));
  }
  std::vector<double>& s = solution.node_s;
  s.resize(m + 1);
  for (int i = 0; i <= m; ++i) {
    s[i] = 1.0 - std::pow(1.0 - static_cast<double>(i) / m, 2.0 / 3.0);
  }
  s[0] = 0.0;
  s[m] = 1.0;
  // lambda = 0: the natural arc phi = phi0 + k s, phi' = k.
  std::vector<double> phi(m + 1), dphi(m + 1, k);
  for (int i = 0; i <= m; ++i) phi[i] = phi0 + k * s[i];

  // Continuation in t with lambda_t = lambda t^2 (the layer width 1/sqrt(lambda_t) shrinks
  // evenly); a failed step is retried at half the increment.
  const int planned = lambda == 0.0 ? 0
                      : options.continuation_steps > 0
                          ? options.continuation_steps
                          : 8 + static_cast<int>(2.0 * std::sqrt(lambda));
  double t = 0.0;
  double dt = planned > 0 ? 1.0 / planned : 1.0;
  int failures = 0;
  while (planned > 0 && t < 1.0) {
    const double t_next = std::min(1.0, t + dt);
    const double lambda_t = lambda * t_next * t_next;
    std::vector<double> trial_phi = phi, trial_dphi = dphi;
    bool ok = false;
    if (multiple) {
      ok = internal::SolveMultipleShooting(lambda_t, k, s, &trial_phi, &trial_dphi, options,
                                           &solution.newton_iterations);
    } else {
      double delta = phi[1];
      ok = internal::SolveBackwardShooting(lambda_t, k, phi0, phi[1], options, &delta,
                                           &solution.newton_iterations);
      trial_phi[1] = delta;
    }
    if (ok) {
      t = t_next;
      phi = trial_phi;
      dphi = trial_dphi;
      ++solution.continuation_steps;
      dt = std::min(1.5 * dt, 1.0 / planned);  // recover the planned step after a failure
    } else {
      dt *= 0.5;
      ++failures;
    }
    // Give up on a fold or a hopeless conditioning rather than crawl (at most 4x the plan).
    if (t < 1.0 && (dt < 1e-3 / planned || solution.continuation_steps + failures > 4 * planned)) {
      solution.message = "continuation failed at load " + std::to_string(lambda_t) + " after " +
                         std::to_string(solution.continuation_steps) + " steps";
      return solution;
    }
  }

  // Final sweep from the tip to the root: shape, energies and certificates.
  dphi[m] = k;
  const internal::Sweep sweep = internal::SweepToRoot(lambda, k, s, phi, dphi, options);
  if (!sweep.ok) {
    solution.message = "final integration failed";
    return solution;
  }
  const internal::State& y = sweep.root;
  solution.node_phi = phi;
  solution.node_dphi = dphi;
  solution.node_dphi[0] = y[1];
  solution.root_angle_error = std::abs(y[0] - phi0);
  solution.tip_angle = phi[m] - kHalfPi;
  solution.root_curvature = y[1];
  solution.tip_x = -y[2];
  solution.tip_z = -y[3];
  // int_0^1 x ds with x(s) = X(s) - X(0) and int_0^1 X = -A(0); the same for z.
  const double int_x = -y[4] - y[2];
  const double int_z = -y[5] - y[3];
  solution.elastic_energy = -y[6];
  solution.gravity_energy = lambda * int_z;
  solution.moment_balance = y[1] - k + lambda * int_x;
  solution.min_jacobi = sweep.min_jacobi;
  solution.stable = sweep.min_jacobi > 0.0;
  solution.integrator_steps = sweep.steps;
  solution.converged = solution.root_angle_error <= 1e3 * options.residual_tolerance;
  solution.message = solution.converged ? "converged" : "root angle error too large";
  return solution;
}

/// The centreline of a solved reference at arc lengths s_values (units of L, each in [0, 1], any
/// order): angle and position relative to the root, by one more tip-to-root sweep that lands
/// exactly on each requested point. Returns an empty vector if the integration fails.
inline std::vector<ElasticaPoint> SampleHeavyElastica(const HeavyElasticaProblem& problem,
                                                      const HeavyElasticaSolution& solution,
                                                      std::vector<double> s_values,
                                                      const HeavyElasticaOptions& options = {}) {
  std::sort(s_values.begin(), s_values.end(), std::greater<double>());
  const internal::Sweep sweep =
      internal::SweepToRoot(problem.load, problem.natural_curvature, solution.node_s,
                            solution.node_phi, solution.node_dphi, options, s_values);
  if (!sweep.ok) return {};
  std::vector<ElasticaPoint> points;
  for (size_t i = s_values.size(); i-- > 0;) {
    const internal::State& y = sweep.at_stops[i];
    ElasticaPoint p;
    p.s = s_values[i];
    p.theta = y[0] - internal::kHalfPi;
    p.x = y[2] - sweep.root[2];
    p.z = y[3] - sweep.root[3];
    points.push_back(p);
  }
  return points;
}

}  // namespace ringlet::reference
