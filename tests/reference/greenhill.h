// An independent reference for Greenhill's heavy column: a rod clamped at its foot pointing
// straight up, which buckles under its own weight above the critical load w L^3 / EI = 7.8373
// (Greenhill 1881). It gives the critical load three ways and the buckled (post-buckling) branch.
// Like heavy_elastica.h, whose Dormand-Prince integrator and state it reuses, it shares no code
// with the ringlet rod model: only the standard library.
//
// Problem (dimensionless, lengths in units of L, s in [0, 1] from the root). The heavy-elastica
// equation of heavy_elastica.h with the root pointing up and no natural curvature:
//   theta'' = lambda (1 - s) cos theta,   theta(0) = pi/2,   theta'(1) = 0,
// theta the tangent angle above the horizontal. With alpha = pi/2 - theta, the angle of the tangent
// from the upward vertical,
//   alpha'' = -lambda (1 - s) sin alpha,   alpha(0) = 0,   alpha'(1) = 0,
// and in heavy_elastica.h's variable phi = theta + pi/2 = pi - alpha. alpha = 0 (straight up)
// solves it at every load; it is stable up to the critical load lambda_c and unstable above.
//
// Critical load. Linearizing, alpha = eps y: y'' + lambda (1 - s) y = 0, y(0) = 0, y'(1) = 0. With
// x = 1 - s measured from the tip and the tip normalized to y = 1, y'(tip) = 0, the solution is
// the power series
//   y(x) = sum_k a_k x^(3k),   a_0 = 1,   a_k = -lambda a_(k-1) / ((3k)(3k - 1)),
// and lambda_c is the smallest root of y(root) = sum_k a_k = 0. In Bessel functions,
// y = sqrt(x) J_(-1/3)(2/3 sqrt(lambda) x^(3/2)) (up to a constant), so lambda_c = (9/4) j^2 with
// j = 1.86635... the first zero of J_(-1/3): 7.83734744... This header computes lambda_c from the
// series and, separately, by shooting on the linearized equation with the numerical integrator
// (the Jacobi field of the straight state); the test compares both with the Bessel form and with
// the published 7.8373.
//
// Buckled branch. Shoot from the tip: alpha(1) = a, alpha'(1) = 0, integrate to the root and solve
// F(a) = alpha(0; a) = 0 for a in (0, pi). a = 0 is the trivial root at every load, so the
// equation solved is G(a) = F(a) / a = 0, whose limit at a -> 0 is the linearized tip-to-root
// ratio y(root) (negative between lambda_c and the second critical load 55.98). G is bracketed by a
// scan of a over (0, pi) and the root polished by safeguarded Newton (dF/da is the Jacobi field,
// carried by the integrator's transfer matrix). No continuation is needed: the problem is
// not stiff at these loads (the linearized modes oscillate rather than grow), so each load is
// solved on its own, and the scan reports how many buckled equilibria it bracketed (one, between
// the first and second critical loads). Near threshold the branch is a supercritical pitchfork:
// a^2 ~ C (lambda / lambda_c - 1), with C = 8.7934 from perturbation theory
// (GreenhillPitchforkCoefficient), which the test checks against the branch.
//
// Certificates: the global moment balance theta'(0) + lambda int x ds = 0 (the root moment equals
// the moment of the weight about the root), and in-plane stability by Jacobi's condition (the
// Jacobi field with J(1) = 1, J'(1) = 0 has no zero on [0, 1]), as in heavy_elastica.h.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "heavy_elastica.h"

namespace ringlet::reference {

/// Greenhill's critical load as usually published (Greenhill 1881; Wang): w L^3 / EI = 7.8373.
inline constexpr double kGreenhillPublished = 7.8373;

/// The linearized column y'' + lambda (1 - s) y = 0 with y = 1, y' = 0 at the tip: the value y at
/// the root, from the power series in x = 1 - s (see the file comment). Zero exactly at the
/// critical loads. Terms are summed until they no longer change the sum (at most 200).
inline double GreenhillLinearRootValue(double load) {
  double term = 1.0, sum = 1.0;
  for (int k = 1; k <= 200; ++k) {
    term *= -load / ((3.0 * k) * (3.0 * k - 1.0));
    const double next = sum + term;
    if (next == sum && std::abs(term) < 1e-300 + 1e-17 * std::abs(sum)) break;
    sum = next;
  }
  return sum;
}

/// The same value by integrating the linearized equation from the tip with heavy_elastica.h's
/// Dormand-Prince integrator: the Jacobi field of the straight state phi = pi (the (1,1) entry of
/// the transfer matrix from tip to root). Returns NaN if the integration fails.
inline double GreenhillLinearRootValueByShooting(double load,
                                                 const HeavyElasticaOptions& options = {}) {
  internal::State y = internal::StartState(internal::kPi, 0.0);
  int steps = 0;
  if (!internal::Integrate(
          load, 0.0, 1.0, 0.0, &y, options, {}, [](double, const internal::State&) {}, &steps)) {
    return std::nan("");
  }
  return y[7];
}

/// The smallest positive root of root_value(lambda) (a continuous function with root_value(0) = 1):
/// scan lambda in steps of `step` up to `max_load`, then bisection with the Illinois (modified
/// regula falsi) update to |bracket| <= tolerance. NaN if no sign change is found.
template <typename Function>
double SmallestCriticalLoad(Function&& root_value, double step = 0.25, double max_load = 100.0,
                            double tolerance = 1e-13) {
  double lo = 0.0, f_lo = root_value(0.0);
  double hi = lo, f_hi = f_lo;
  for (double load = step; load <= max_load; load += step) {
    const double f = root_value(load);
    if (!std::isfinite(f)) return std::nan("");
    if ((f < 0.0) != (f_lo < 0.0)) {
      hi = load;
      f_hi = f;
      break;
    }
    lo = load;
    f_lo = f;
  }
  if (hi == lo) return std::nan("");
  int side = 0;
  for (int it = 0; it < 200 && hi - lo > tolerance; ++it) {
    double mid = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
    if (!(mid > lo && mid < hi)) mid = 0.5 * (lo + hi);
    const double f = root_value(mid);
    if (f == 0.0) return mid;
    if ((f < 0.0) == (f_lo < 0.0)) {
      lo = mid;
      f_lo = f;
      if (side == -1) f_hi *= 0.5;  // Illinois: the same end moved twice, halve the other
      side = -1;
    } else {
      hi = mid;
      f_hi = f;
      if (side == +1) f_lo *= 0.5;
      side = +1;
    }
  }
  return 0.5 * (lo + hi);
}

/// Greenhill's critical load from the power series (to ~1e-13).
inline double GreenhillCriticalLoadSeries() {
  return SmallestCriticalLoad([](double load) { return GreenhillLinearRootValue(load); });
}

/// Greenhill's critical load by shooting on the linearized equation (to the integrator's accuracy).
inline double GreenhillCriticalLoadByShooting(const HeavyElasticaOptions& options = {}) {
  return SmallestCriticalLoad(
      [&](double load) { return GreenhillLinearRootValueByShooting(load, options); });
}

/// The coefficient C of the supercritical pitchfork, tip angle^2 ~ C (lambda / lambda_c - 1) as
/// lambda -> lambda_c+, by perturbation theory (Lyapunov-Schmidt). Write alpha = a y1 + a^3 y3 and
/// lambda = lambda_c + a^2 lambda2 with y1 the critical mode normalized to y1(tip) = 1 and
/// y3(tip) = 0 (so that a is the tip angle). At order a^3, using sin alpha = alpha - alpha^3 / 6,
///   y3'' + lambda_c (1 - s) y3 = -lambda2 (1 - s) y1 + lambda_c (1 - s) y1^3 / 6,
/// and the operator on the left is self-adjoint with these boundary conditions, so the right side
/// is orthogonal to y1: lambda2 / lambda_c = int (1 - s) y1^4 / (6 int (1 - s) y1^2), i.e.
///   C = lambda_c / lambda2 = 6 int x y1^2 dx / int x y1^4 dx   (x = 1 - s).
/// y1 is the power series of GreenhillLinearRootValue at lambda_c; the integrals use composite
/// Simpson with `intervals` (even) intervals (error ~1e-13 at the default).
inline double GreenhillPitchforkCoefficient(int intervals = 2000) {
  const double critical = GreenhillCriticalLoadSeries();
  auto mode = [&](double x) {  // y1(x) = sum_k a_k x^(3k)
    const double x3 = x * x * x;
    double term = 1.0, sum = 1.0;
    for (int k = 1; k <= 200; ++k) {
      term *= -critical * x3 / ((3.0 * k) * (3.0 * k - 1.0));
      sum += term;
      if (std::abs(term) < 1e-18) break;
    }
    return sum;
  };
  double second = 0.0, fourth = 0.0;
  for (int i = 0; i <= intervals; ++i) {
    const double x = static_cast<double>(i) / intervals;
    const double weight = (i == 0 || i == intervals) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
    const double y2 = mode(x) * mode(x);
    second += weight * x * y2;
    fourth += weight * x * y2 * y2;
  }
  return 6.0 * second / fourth;  // the Simpson factors h / 3 cancel
}

/// A point of the buckled branch. Lengths in units of L, energies in units of EI / L.
struct GreenhillSolution {
  bool converged = false;  ///< a buckled equilibrium was found and polished
  std::string message;     ///< one sentence: what happened
  double load = 0.0;       ///< lambda = w L^3 / EI
  /// Angle of the tip tangent from the upward vertical, alpha(1) in (0, pi) (rad). The strand
  /// leans towards +x (theta(1) = pi/2 - alpha(1)).
  double tip_angle = 0.0;
  double root_curvature = 0.0;  ///< theta'(0) L (negative: leaning towards +x)
  double tip_x = 0.0;           ///< horizontal offset of the tip from the root (units of L)
  double tip_z = 0.0;           ///< height of the tip above the root (units of L)
  double elastic_energy = 0.0;  ///< 1/2 int theta'^2 ds (units of EI / L)
  double gravity_energy = 0.0;  ///< lambda int z ds (units of EI / L); lambda / 2 when straight
  /// theta'(0) + lambda int x ds: zero at an exact equilibrium.
  double moment_balance = 0.0;
  bool stable = false;      ///< in-plane: the Jacobi field has no zero on [0, 1]
  double min_jacobi = 0.0;  ///< smallest J(s) over the integration steps (J(1) = 1)
  int buckled_roots = 0;    ///< sign changes of G(a) = alpha(0; a) / a found by the scan of (0, pi)
  int shots = 0;            ///< tip-to-root integrations, scan included
};

namespace internal {

// One shot from the tip with alpha(1) = a (phi(1) = pi - a), phi'(1) = 0, to the root.
struct GreenhillShot {
  bool ok = false;
  State root{};             // the state at s = 0 (positions and integrals relative to the tip)
  double min_jacobi = 1.0;  // smallest J = V(1,1) over the accepted steps
};

inline GreenhillShot ShootGreenhill(double load, double a, const HeavyElasticaOptions& options) {
  GreenhillShot shot;
  State y = StartState(kPi - a, 0.0);
  int steps = 0;
  shot.ok = Integrate(
      load, 0.0, 1.0, 0.0, &y, options, {},
      [&](double, const State& state) { shot.min_jacobi = std::min(shot.min_jacobi, state[7]); },
      &steps);
  shot.root = y;
  return shot;
}

}  // namespace internal

/// The buckled equilibrium of Greenhill's column at the given load (see the file comment). Fails
/// (converged = false, with a message) at and below the critical load, where only the straight
/// state exists. scan_points is the number of intervals of the scan of the tip angle over (0, pi).
inline GreenhillSolution SolveGreenhillBuckled(double load,
                                               const HeavyElasticaOptions& options = {},
                                               int scan_points = 64) {
  using internal::kPi;
  GreenhillSolution solution;
  solution.load = load;
  if (!(std::isfinite(load) && load > 0.0) || scan_points < 2) {
    solution.message = "load must be finite and > 0, scan_points >= 2";
    return solution;
  }
  // G(a) = alpha(0; a) / a and its derivative; alpha(0) = pi - phi(0), d alpha(0) / da = V(1,1).
  struct Value {
    bool ok = false;
    double g = 0.0, dg = 0.0;
  };
  auto evaluate = [&](double a) {
    Value v;
    ++solution.shots;
    if (a == 0.0) {  // the limit: the linearized tip-to-root ratio
      v.g = GreenhillLinearRootValueByShooting(load, options);
      v.ok = std::isfinite(v.g);
      return v;
    }
    const internal::GreenhillShot shot = internal::ShootGreenhill(load, a, options);
    if (!shot.ok) return v;
    const double f = kPi - shot.root[0];
    v.g = f / a;
    v.dg = (shot.root[7] - v.g) / a;
    v.ok = std::isfinite(v.g);
    return v;
  };

  // Scan a over [0, pi) for sign changes of G; keep the first bracket.
  double lo = 0.0, hi = 0.0;
  Value v_prev = evaluate(0.0);
  if (!v_prev.ok) {
    solution.message = "integration failed in the scan";
    return solution;
  }
  double g_lo = 0.0, g_hi = 0.0;
  for (int j = 1; j < scan_points; ++j) {
    const double a = kPi * j / scan_points;
    const Value v = evaluate(a);
    if (!v.ok) {
      solution.message = "integration failed in the scan";
      return solution;
    }
    if ((v.g < 0.0) != (v_prev.g < 0.0)) {
      if (solution.buckled_roots == 0) {
        lo = kPi * (j - 1) / scan_points;
        hi = a;
        g_lo = v_prev.g;
        g_hi = v.g;
      }
      ++solution.buckled_roots;
    }
    v_prev = v;
  }
  if (solution.buckled_roots == 0) {
    solution.message = "no buckled equilibrium (the load is not above the critical load)";
    return solution;
  }

  // Safeguarded Newton in the bracket (Numerical Recipes' rtsafe), on G.
  double a = std::abs(g_lo) < std::abs(g_hi) && lo > 0.0 ? lo : 0.5 * (lo + hi);
  bool polished = false;
  for (int it = 0; it < options.max_newton_iterations; ++it) {
    const Value v = evaluate(a);
    if (!v.ok) break;
    if ((v.g < 0.0) == (g_lo < 0.0)) {
      lo = a;
    } else {
      hi = a;
    }
    double next = v.dg != 0.0 ? a - v.g / v.dg : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    // The residual in alpha(0) is a G: converged when it is at the integration noise, or when
    // the bracket has shrunk to rounding.
    if (std::abs(v.g) * a <= options.residual_tolerance || next == lo || next == hi ||
        std::abs(next - a) <= 1e-15 * a) {
      polished = std::abs(v.g) * a <= 1e2 * options.residual_tolerance;
      break;
    }
    a = next;
  }
  if (!polished) {
    solution.message = "Newton did not converge on the buckled root";
    return solution;
  }

  // The final shot: shape, energies and certificates.
  const internal::GreenhillShot shot = internal::ShootGreenhill(load, a, options);
  ++solution.shots;
  const internal::State& y = shot.root;
  solution.tip_angle = a;
  solution.root_curvature = y[1];  // phi'(0) = theta'(0)
  solution.tip_x = -y[2];
  solution.tip_z = -y[3];
  const double int_x = -y[4] - y[2];
  const double int_z = -y[5] - y[3];
  solution.elastic_energy = -y[6];
  solution.gravity_energy = load * int_z;
  solution.moment_balance = y[1] + load * int_x;
  solution.min_jacobi = shot.min_jacobi;
  solution.stable = shot.min_jacobi > 0.0;
  solution.converged = shot.ok;
  solution.message = shot.ok ? "converged" : "final integration failed";
  return solution;
}

}  // namespace ringlet::reference
