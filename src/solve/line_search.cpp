#include "solve/line_search.h"

#include <algorithm>
#include <cmath>

namespace ringlet::internal {
namespace {

// Minimizer of the cubic interpolating (a, fa, da) and (b, fb, db) (Nocedal & Wright eq. 3.59),
// kept inside [lo + 0.1 w, hi - 0.1 w] of the bracket; bisection when the cubic has no minimizer.
double CubicStep(const LineSample& a, const LineSample& b) {
  const double lo = std::min(a.alpha, b.alpha), hi = std::max(a.alpha, b.alpha);
  const double width = hi - lo;
  double t = 0.5 * (lo + hi);
  if (a.finite && b.finite) {
    const double d1 = a.slope + b.slope - 3.0 * (a.value - b.value) / (a.alpha - b.alpha);
    const double disc = d1 * d1 - a.slope * b.slope;
    if (disc >= 0.0) {
      const double d2 = std::copysign(std::sqrt(disc), b.alpha - a.alpha);
      const double denom = b.slope - a.slope + 2.0 * d2;
      if (denom != 0.0) {
        const double c = b.alpha - (b.alpha - a.alpha) * (b.slope + d2 - d1) / denom;
        if (std::isfinite(c)) t = c;
      }
    }
  }
  return std::clamp(t, lo + 0.1 * width, hi - 0.1 * width);
}

}  // namespace

LineSearchResult StrongWolfeSearch(const std::function<LineSample(double)>& evaluate,
                                   const LineSample& at_zero, double alpha_init, double alpha_max,
                                   const LineSearchOptions& options) {
  const double f0 = at_zero.value, d0 = at_zero.slope;
  const double noise = options.value_noise * std::max(1.0, std::abs(f0)) + 1e-300;
  LineSearchResult result;
  result.best = at_zero;

  // Armijo's sufficient decrease, or, where values are within rounding of f0, its approximate
  // form on slopes (exact for a quadratic): phi'(alpha) <= (2 c1 - 1) phi'(0).
  auto sufficient = [&](const LineSample& s) {
    if (s.value <= f0 + options.sufficient_decrease * s.alpha * d0) return true;
    return s.value <= f0 + noise && s.slope <= (2.0 * options.sufficient_decrease - 1.0) * d0;
  };
  auto curvature_ok = [&](const LineSample& s) {
    return std::abs(s.slope) <= -options.curvature * d0;
  };
  // Whether s is no better than the bracket end lo: by value, or by slope inside the noise band.
  auto not_lower = [&](const LineSample& s, const LineSample& lo) {
    if (std::abs(s.value - lo.value) > noise) return s.value >= lo.value;
    return s.slope * (s.alpha - lo.alpha) > 0.0;  // already ascending past lo
  };

  auto zoom = [&](LineSample lo, LineSample hi) {
    while (result.evaluations < options.max_evaluations) {
      const LineSample s = evaluate(CubicStep(lo, hi));
      ++result.evaluations;
      if (!s.finite || !sufficient(s) || not_lower(s, lo)) {
        hi = s;
      } else {
        if (curvature_ok(s)) {
          result.success = true;
          result.best = s;
          return;
        }
        if (s.slope * (hi.alpha - lo.alpha) >= 0.0) hi = lo;
        lo = s;
      }
      if (lo.alpha > 0.0 && sufficient(lo)) result.best = lo;
      if (std::abs(hi.alpha - lo.alpha) <= 1e-14 * std::max(lo.alpha, hi.alpha)) break;
    }
    // Out of budget or bracket collapsed: accept a step that decreased the energy, if any.
    result.success = result.best.alpha > 0.0;
  };

  LineSample prev = at_zero;
  double alpha = std::min(alpha_init, alpha_max);
  while (result.evaluations < options.max_evaluations) {
    const LineSample s = evaluate(alpha);
    ++result.evaluations;
    if (!s.finite || !sufficient(s) || (prev.alpha > 0.0 && not_lower(s, prev))) {
      zoom(prev, s);
      return result;
    }
    if (curvature_ok(s)) {
      result.success = true;
      result.best = s;
      return result;
    }
    if (s.slope >= 0.0) {
      zoom(s, prev);
      return result;
    }
    result.best = s;
    if (alpha >= alpha_max) {
      result.success = true;  // largest allowed step, still descending: take it
      return result;
    }
    prev = s;
    alpha = std::min(4.0 * alpha, alpha_max);
  }
  result.success = result.best.alpha > 0.0;
  return result;
}

}  // namespace ringlet::internal
