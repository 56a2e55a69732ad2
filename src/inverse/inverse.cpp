// Inverse statics: rest shapes from target configurations, certificate, verification
// (inverse.h, docs/inverse.md).
#include "ringlet/inverse.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <sstream>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "ringlet/energy.h"
#include "ringlet/kirchhoff.h"
#include "ringlet/strand_geometry.h"
#include "ringlet/strand_hessian.h"

namespace ringlet {
namespace {

std::string Number(double x) {
  std::ostringstream s;
  s.precision(3);
  s << x;
  return s.str();
}

}  // namespace

bool InverseOptions::IsValid(std::string* why) const {
  if (points_per_segment < 1 || points_per_segment > 1024) {
    if (why) *why = "points_per_segment: expected 1 to 1024";
    return false;
  }
  std::string reason;
  if (!solver.IsValid(&reason)) {
    if (why) *why = "solver: " + reason;
    return false;
  }
  return true;
}

VecX InverseRestCurvatures(const StrandModel& model, const VecX& target) {
  const int n = model.NumSegments();
  assert(target.size() == 3 * n);
  // dE_ext/dq at the target: gravity and contact in one sweep (StrandEnergy's), the elastic
  // gradient subtracted. Evaluating with the rest shape q0 = target makes the elastic gradient
  // exactly zero, so the total gradient is the external one.
  StrandModel at_target = model;
  at_target.rest_curvatures = target;
  VecX gradient;
  StrandEnergy(at_target).Evaluate(target, &gradient);
  // q0_i = q_i + (l_i K)^(-1) dE_ext/dq_i (inverse.h): the stationarity l_i K (q_i - q0_i) +
  // dE_ext/dq_i = 0 solved for q0_i, K = diag(E I1, E I2, mu J).
  const Vec3 k = model.Stiffness();
  VecX rest(3 * n);
  for (int i = 0; i < n; ++i) {
    rest.segment<3>(3 * i) = target.segment<3>(3 * i) +
                             gradient.segment<3>(3 * i).cwiseQuotient(model.segment_lengths[i] * k);
  }
  return rest;
}

double CentrelineDeviation(const StrandModel& model, const VecX& a, const VecX& b,
                           int points_per_segment) {
  const std::vector<Vec3> pa = SampleCentreline(model, a, points_per_segment);
  const std::vector<Vec3> pb = SampleCentreline(model, b, points_per_segment);
  double deviation = 0.0;
  for (size_t j = 0; j < pa.size(); ++j) {
    const double d = (pa[j] - pb[j]).norm();
    deviation = std::isnan(d) ? d : std::max(deviation, d);
    if (std::isnan(deviation)) break;
  }
  return deviation;
}

InverseResult InvertStrand(const StrandModel& model, const VecX& target,
                           const InverseOptions& options) {
  assert(target.size() == 3 * model.NumSegments());
  InverseResult result;
  result.rest_curvatures = InverseRestCurvatures(model, target);
  StrandModel inverted = model;
  inverted.rest_curvatures = result.rest_curvatures;

  // The certificate: the Hessian at the target (independent of q0) factored from tip to root.
  StrandHessian hessian;
  ComputeStrandHessian(inverted, target, &hessian);
  StrandHessianFactor factor;
  result.stable = factor.Factor(hessian, 0.0);
  result.failed_segment = factor.failed_segment();
  result.min_eigenvalue = MinScaledHessianEigenvalue(inverted, target);
  result.kirchhoff_residual = KirchhoffResidual(inverted, target);
  const double length = model.Length();

  if (options.verify) {
    StrandSolution forward = SolveStrand(inverted, options.solver, &target);
    result.deviation =
        CentrelineDeviation(model, target, forward.curvatures, options.points_per_segment);
    result.equilibrium = std::move(forward.curvatures);
    result.forward = std::move(forward.summary);
  }
  if (options.naive) {
    StrandModel naive = model;
    naive.rest_curvatures = target;
    StrandSolution sagged = SolveStrand(naive, options.solver, &target);
    result.naive_deviation =
        CentrelineDeviation(model, target, sagged.curvatures, options.points_per_segment);
    result.naive_equilibrium = std::move(sagged.curvatures);
    result.naive_forward = std::move(sagged.summary);
  }

  std::string m = result.stable ? "stable target" : "UNSTABLE target (pivot of segment " +
                                                         std::to_string(result.failed_segment) +
                                                         " not positive definite)";
  m += ", min scaled eigenvalue " + Number(result.min_eigenvalue) + ", Kirchhoff residual " +
       Number(result.kirchhoff_residual);
  if (options.verify) {
    m += "; forward solve " + std::string(TerminationName(result.forward.termination)) +
         ", deviation " + Number(result.deviation / length) + " L";
    if (!result.stable) m += " (the closest stable equilibrium of the inverted rest shape)";
  }
  if (options.naive) {
    m += "; naive rest shape sags " + Number(result.naive_deviation / length) + " L";
  }
  result.message = m;
  return result;
}

std::vector<InverseResult> InvertStrands(const std::vector<StrandModel>& models,
                                         const std::vector<VecX>& targets,
                                         const InverseOptions& options, int threads) {
  assert(models.size() == targets.size());
  std::vector<InverseResult> results(models.size());
  const int total = static_cast<int>(models.size());
  // Each result depends on its strand alone, so any split gives the same results.
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, total), [&](const tbb::blocked_range<int>& r) {
      for (int i = r.begin(); i < r.end(); ++i) {
        results[static_cast<size_t>(i)] =
            InvertStrand(models[static_cast<size_t>(i)], targets[static_cast<size_t>(i)], options);
      }
    });
  });
  return results;
}

}  // namespace ringlet
