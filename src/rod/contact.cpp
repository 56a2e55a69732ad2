// Penalty contact forces and penetration depths of a configuration (paper, section 3.1).
#include "ringlet/contact.h"

#include <algorithm>

#include "ringlet/helix.h"
#include "ringlet/strand_geometry.h"

namespace ringlet {
namespace {

// Visits every sample (segment i, its index j, arc u, weight w, position x) of ContactModel.
template <typename Visit>
void ForEachSample(const StrandModel& model, const VecX& curvatures, const StrandGeometry& g,
                   Visit visit) {
  const int m = model.contact.samples_per_segment;
  for (int i = 0; i < model.NumSegments(); ++i) {
    const Vec3 omega = curvatures.segment<3>(3 * i);
    const double w = model.segment_lengths[i] / m;
    for (int j = 0; j < m; ++j) {
      const double u = (j + 1) * w;
      visit(i, j, u, w, Vec3(g.points[i] + g.frames[i] * HelixChord(omega, u)));
    }
  }
}

}  // namespace

double Obstacle::SignedDistanceHessian(const Vec3& x, Vec3* gradient, Mat3* hessian) const {
  const double d = SignedDistance(x, gradient);
  if (!hessian) return d;
  // Central differences of the exact gradient, one column per axis (truncation O(h^2)).
  const double h = kDistanceHessianStep;
  for (int j = 0; j < 3; ++j) {
    Vec3 xp = x, xm = x, gp, gm;
    xp(j) += h;
    xm(j) -= h;
    SignedDistance(xp, &gp);
    SignedDistance(xm, &gm);
    hessian->col(j) = (gp - gm) / (2.0 * h);
  }
  *hessian = (0.5 * (*hessian + hessian->transpose())).eval();
  return d;
}

std::vector<ContactForce> ComputeContactForces(const StrandModel& model, const VecX& curvatures) {
  std::vector<ContactForce> forces;
  const Obstacle* obstacle = model.contact.obstacle.get();
  if (!obstacle) return forces;
  const double k = model.ContactStiffness();
  const StrandGeometry g = ComputeGeometry(model, curvatures);
  ForEachSample(model, curvatures, g, [&](int i, int j, double u, double w, const Vec3& x) {
    Vec3 normal;
    const double depth = model.contact.SampleClearance(i, j) - obstacle->SignedDistance(x, &normal);
    if (depth > 0.0) forces.push_back({i, u, x, (w * k * depth) * normal});
  });
  return forces;
}

ContactMeasure MeasureContact(const StrandModel& model, const VecX& curvatures) {
  ContactMeasure measure;
  const Obstacle* obstacle = model.contact.obstacle.get();
  if (!obstacle) return measure;
  const double clearance = model.contact.clearance;
  const StrandGeometry g = ComputeGeometry(model, curvatures);
  auto account = [&](const Vec3& x) {
    const double d = obstacle->SignedDistance(x, nullptr);
    measure.max_penetration = std::max(measure.max_penetration, -d);
    measure.max_clearance_violation = std::max(measure.max_clearance_violation, clearance - d);
    return d;
  };
  ForEachSample(model, curvatures, g, [&](int i, int j, double, double, const Vec3& x) {
    if (account(x) < model.contact.SampleClearance(i, j)) ++measure.samples_in_contact;
  });
  for (size_t i = 1; i < g.points.size(); ++i) account(g.points[i]);
  return measure;
}

}  // namespace ringlet
