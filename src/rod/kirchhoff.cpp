// The equilibrium certificate: Kirchhoff's balance from the geometry, by quadrature.
#include "ringlet/kirchhoff.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ringlet/contact.h"
#include "ringlet/helix.h"
#include "ringlet/strand_geometry.h"

namespace ringlet {
namespace {

// 6-point Gauss-Legendre nodes and weights on [-1, 1] (Abramowitz & Stegun, table 25.4). The
// rule's error on a piece of length h is h^13 (6!)^4 / (13 (12!)^3) |M^(12)| (A&S 25.4.30); the
// integrand M(u) in material coordinates is a degree-1 polynomial in u times sines and cosines of
// frequency up to 2 |Omega| (the rotation R(u)^T applied to a moment that turns with r(u)), so on
// a piece turning by theta = |Omega| h its relative error is about
//   (2 theta)^12 (6!)^4 / (13 (12!)^3) = 7.7e-13 at theta = 1 rad, 4e-15 at 0.64 rad,
// and far below at the turns of real hair segments: 1,000 times below the smallest tolerance the
// solver takes (1e-9). The 8-point rule it replaces (1e-18 at 1 rad, below rounding) took a third
// more evaluations (docs/benchmarks.md, "CLI overhead").
constexpr double kNodes[3] = {0.238619186083196909, 0.661209386466264514, 0.932469514203152028};
constexpr double kWeights[3] = {0.467913934572691047, 0.360761573048138608, 0.171324492379170345};
// Quadrature pieces turn by at most this angle (the error bound above).
constexpr double kMaxTurnPerInterval = 1.0;  // rad
// At most this many pieces per segment (a segment turning by more than 4096 rad is not a hair;
// the cap keeps the count an int whatever the curvature).
constexpr double kMaxPiecesPerSegment = 4096.0;

}  // namespace

double EquilibriumResidual(const StrandModel& model, const VecX& curvatures,
                           const VecX& gradient) {
  const int n = model.NumSegments();
  const Vec3 k = model.Stiffness();
  const double length = model.Length();
  double max_internal = 0.0;
  for (int i = 0; i < n; ++i) {
    const Vec3 d = curvatures.segment<3>(3 * i) - model.NaturalCurvature(i);
    max_internal = std::max(max_internal, k.cwiseProduct(d).norm());
  }
  // Moment scale: heaviest gravity moment, largest internal moment, and the moment E I1 / L that
  // bends the whole strand by one radian (so that an unloaded strand has a finite scale).
  const double m_ref =
      0.5 * model.WeightPerLength().norm() * length * length + max_internal + k(0) / length;
  double residual = 0.0;
  for (int i = 0; i < n; ++i) {
    const double r = gradient.segment<3>(3 * i).norm() / (model.segment_lengths[i] * m_ref);
    if (!std::isfinite(r)) return std::numeric_limits<double>::infinity();
    residual = std::max(residual, r);
  }
  return residual;
}

VecX KirchhoffImbalance(const StrandModel& model, const VecX& curvatures) {
  const int n = model.NumSegments();
  const StrandGeometry g = ComputeGeometry(model, curvatures);
  const Vec3 f = model.WeightPerLength();
  const Vec3 k = model.Stiffness();
  const double length = model.Length();

  // t_end[i] = T(s_(i+1)) = int from the end of segment i to the tip of r ds (closed form per
  // segment: int_segment r = l r_i + Q_i c), accumulated from the tip.
  // whole_moment[i] = C(l_i), segment i's first moment in its start frame (helix.h).
  std::vector<Vec3> t_end(n), whole_moment(n);
  std::vector<double> s_start(n);
  Vec3 acc = Vec3::Zero();
  for (int i = n - 1; i >= 0; --i) {
    t_end[i] = acc;
    whole_moment[i] =
        EvaluateHelixSegment(curvatures.segment<3>(3 * i), model.segment_lengths[i]).moment;
    acc += model.segment_lengths[i] * g.points[i] + g.frames[i] * whole_moment[i];
  }
  double s = 0.0;
  for (int i = 0; i < n; ++i) {
    s_start[i] = s;
    s += model.segment_lengths[i];
  }

  // Contact penalty forces are point loads at the samples (section 3.1). The moment
  // about r(u) of those beyond u is sum (x_k - r(u)) x F_k = sum x_k x F_k - r(u) x sum F_k:
  // suffix sums over the segments after i plus the samples of segment i beyond u.
  const std::vector<ContactForce> contacts = ComputeContactForces(model, curvatures);
  std::vector<Vec3> force_after(n + 1, Vec3::Zero()), torque_after(n + 1, Vec3::Zero());
  for (const ContactForce& c : contacts) {
    force_after[c.segment] += c.force;
    torque_after[c.segment] += c.position.cross(c.force);
  }
  for (int i = n - 1; i >= 0; --i) {  // turn per-segment sums into sums over segments >= i
    force_after[i] += force_after[i + 1];
    torque_after[i] += torque_after[i + 1];
  }
  std::vector<int> first_contact(n + 1, static_cast<int>(contacts.size()));
  for (int c = static_cast<int>(contacts.size()) - 1; c >= 0; --c) {
    first_contact[contacts[c].segment] = c;
  }
  for (int i = n - 1; i >= 0; --i) first_contact[i] = std::min(first_contact[i], first_contact[i + 1]);
  const int m = model.contact.samples_per_segment;

  VecX imbalance(3 * n);
  const Vec3 e3(0.0, 0.0, 1.0);
  std::vector<Vec3> local_force, local_torque;  // the contacts of segment i, in its start frame
  for (int i = 0; i < n; ++i) {
    const Vec3 omega = curvatures.segment<3>(3 * i);
    const double l = model.segment_lengths[i];
    const double remaining = length - s_start[i];  // L - s_i: the strand from here to the tip
    // Everything in segment i's start material frame F_i (rotations keep cross products):
    // r(u) = r_i + F_i c(u), int_u^l r(v) dv = (l - u) r_i + F_i (C(l) - C(u)), with the chord
    // c(u) = u e3 + u^2 G2 a1 + u^3 G3 a2 and its first moment C(u) = u^2/2 e3 + u^3 G3 a1 +
    // u^4 G4 a2 (helix.h, a1 = Omega x e3, a2 = Omega x a1, G_m = G_m(u |Omega|)).
    const Mat3 to_local = g.frames[i].transpose();
    const Vec3 root = to_local * g.points[i];
    const Vec3 beyond = to_local * t_end[i];
    const Vec3 weight = to_local * f;
    const Vec3 force_beyond = to_local * force_after[i + 1];
    const Vec3 torque_beyond = to_local * torque_after[i + 1];
    const int c_begin = first_contact[i], c_end = first_contact[i + 1];
    local_force.clear();
    local_torque.clear();
    for (int c = c_begin; c < c_end; ++c) {
      local_force.push_back(to_local * contacts[c].force);
      local_torque.push_back(to_local * contacts[c].position.cross(contacts[c].force));
    }
    const Vec3 a1 = omega.cross(e3), a2 = omega.cross(a1);
    const double omega_norm = omega.norm();
    // The material components of the moment of the load beyond r(u) about r(u):
    // R(u)^T F_i^T M(u), R(u)^T v = v - u G1 Omega x v + u^2 G2 Omega x (Omega x v).
    auto moment_below = [&](double u) {
      const HelixFunctions h = EvaluateHelixFunctions(u * omega_norm);
      const double u2 = u * u, u3 = u2 * u;
      const Vec3 chord = u * e3 + (u2 * h.g[2]) * a1 + (u3 * h.g[3]) * a2;
      const Vec3 first_moment = (0.5 * u2) * e3 + (u3 * h.g[3]) * a1 + (u3 * u * h.g[4]) * a2;
      const Vec3 r = root + chord;
      const Vec3 t = beyond + (l - u) * root + (whole_moment[i] - first_moment);
      Vec3 force = force_beyond, torque = torque_beyond;
      for (int c = c_begin; c < c_end; ++c) {
        if (contacts[c].u > u) {
          force += local_force[static_cast<size_t>(c - c_begin)];
          torque += local_torque[static_cast<size_t>(c - c_begin)];
        }
      }
      const Vec3 moment = (t - (remaining - u) * r).cross(weight) + torque - r.cross(force);
      const Vec3 w_moment = omega.cross(moment);
      return Vec3(moment - (u * h.g[1]) * w_moment + (u2 * h.g[2]) * omega.cross(w_moment));
    };
    const double turn_pieces = std::ceil(omega_norm * l / kMaxTurnPerInterval);
    int pieces = turn_pieces >= 1.0 ? static_cast<int>(std::min(turn_pieces, kMaxPiecesPerSegment))
                                    : 1;  // NaN and 0 also give one piece
    // With contact, the moment jumps at the samples (j + 1) l / m: make them piece boundaries.
    if (!contacts.empty()) pieces = m * ((pieces + m - 1) / m);
    const double h = l / pieces;
    Vec3 integral = Vec3::Zero();
    for (int p = 0; p < pieces; ++p) {
      const double mid = (p + 0.5) * h;
      for (int q = 0; q < 3; ++q) {
        const double d = 0.5 * h * kNodes[q];
        integral += (0.5 * h * kWeights[q]) * (moment_below(mid - d) + moment_below(mid + d));
      }
    }
    const Vec3 internal = l * k.cwiseProduct(omega - model.NaturalCurvature(i));
    imbalance.segment<3>(3 * i) = internal - integral;
  }
  return imbalance;
}

double KirchhoffResidual(const StrandModel& model, const VecX& curvatures) {
  return EquilibriumResidual(model, curvatures, KirchhoffImbalance(model, curvatures));
}

}  // namespace ringlet
