// The equilibrium certificate: Kirchhoff's balance from the geometry, by quadrature.
#include "ringlet/kirchhoff.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <type_traits>

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
  std::vector<Vec3> segment_moments;
  const StrandGeometry g = ComputeGeometry(model, curvatures, &segment_moments);
  return KirchhoffImbalance(model, curvatures, g, segment_moments);
}

VecX KirchhoffImbalance(const StrandModel& model, const VecX& curvatures,
                        const StrandGeometry& g, const std::vector<Vec3>& whole_moment) {
  const int n = model.NumSegments();
  assert(static_cast<int>(g.points.size()) == n + 1 && static_cast<int>(whole_moment.size()) == n);
  const Vec3 f = model.WeightPerLength();
  const Vec3 k = model.Stiffness();
  const double length = model.Length();

  // t_end[i] = T(s_(i+1)) = int from the end of segment i to the tip of r ds (closed form per
  // segment: int_segment r = l r_i + Q_i c), accumulated from the tip.
  // whole_moment[i] = C(l_i), segment i's first moment in its start frame (helix.h).
  std::vector<Vec3> t_end(n);
  std::vector<double> s_start(n);
  Vec3 acc = Vec3::Zero();
  for (int i = n - 1; i >= 0; --i) {
    t_end[i] = acc;
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
    const Vec3 a1 = omega.cross(e3), a2 = omega.cross(a1);
    const double omega_norm = omega.norm();
    // The moment about r(u) of the load beyond it (weight w per length; F and N the sums of the
    // contact forces x_k and of their moments x_k x F_k over the samples beyond u):
    //   M(u) = (int_u^l r + T(s_(i+1)) - (L - s_i - u) r(u)) x w + N - r(u) x F
    //        = K - e3 x (s0 w + u F) - a1 x (s1 w + u^2 G2 F) - a2 x (s2 w + u^3 G3 F),
    // K = (T(s_(i+1)) + (l - L + s_i) r_i + C(l)) x w + N - r_i x F, and S(u) = C(u) +
    // (L - s_i - u) c(u) = s0 e3 + s1 a1 + s2 a2. So M(u) = sum_j s_j(u) V_j over seven fixed
    // vectors V_j (F and T change only at the contact samples, which are piece boundaries), and
    // its material components R(u)^T M = M - u G1 Omega x M + u^2 G2 Omega x (Omega x M)
    // integrate to I_A - Omega x I_B + Omega x (Omega x I_C), I_X = sum_j (int x_j s_j) V_j
    // with x = 1, u G1, u^2 G2: the quadrature sums scalars only.
    const Vec3 gravity_constant = (beyond + (l - remaining) * root + whole_moment[i]).cross(weight);
    const Vec3 e3_w = e3.cross(weight), a1_w = a1.cross(weight), a2_w = a2.cross(weight);
    const double turn_pieces = std::ceil(omega_norm * l / kMaxTurnPerInterval);
    int pieces = turn_pieces >= 1.0 ? static_cast<int>(std::min(turn_pieces, kMaxPiecesPerSegment))
                                    : 1;  // NaN and 0 also give one piece
    // With contact, the moment jumps at the samples (j + 1) l / m: make them piece boundaries.
    if (!contacts.empty()) pieces = m * ((pieces + m - 1) / m);
    const double h = l / pieces;
    Vec3 sum_a = Vec3::Zero(), sum_b = Vec3::Zero(), sum_c = Vec3::Zero();
    for (int p = 0; p < pieces; ++p) {
      const double mid = (p + 0.5) * h;
      // The samples beyond this piece (their u is a piece boundary, so comparing with the
      // midpoint decides for every node of the piece).
      Vec3 force = force_beyond, torque = torque_beyond;
      for (int c = c_begin; c < c_end; ++c) {
        if (contacts[c].u > mid) {
          force += to_local * contacts[c].force;
          torque += to_local * contacts[c].position.cross(contacts[c].force);
        }
      }
      // The seven vectors V_j; without contact forces on the strand the last three are zero and
      // only the first four are summed.
      const Vec3 terms[7] = {gravity_constant + torque - root.cross(force),
                             e3_w,
                             a1_w,
                             a2_w,
                             e3.cross(force),
                             a1.cross(force),
                             a2.cross(force)};
      // sa_j, sb_j, sc_j: the quadrature sums of s_j, u G1 s_j and u^2 G2 s_j (s_0 = 1), in
      // plain doubles (an Eigen array filled per node and read back as packed vectors stalled
      // on store forwarding).
      auto integrate = [&]<int kTerms>(std::integral_constant<int, kTerms>) {
        double sa[kTerms] = {}, sb[kTerms] = {}, sc[kTerms] = {};
        for (int q = 0; q < 6; ++q) {
          const double u = q < 3 ? mid - 0.5 * h * kNodes[q] : mid + 0.5 * h * kNodes[q - 3];
          const double wa = 0.5 * h * kWeights[q % 3];
          const HelixFunctions hf = EvaluateHelixFunctions(u * omega_norm);
          const double u2 = u * u, u3 = u2 * u;
          const double p2 = u2 * hf.g[2], p3 = u3 * hf.g[3], p4 = u3 * u * hf.g[4];
          const double rest = remaining - u;
          const double wb = wa * u * hf.g[1], wc = wa * p2;
          const double coefficient[7] = {1.0, -u * (remaining - 0.5 * u), -(p3 + rest * p2),
                                         -(p4 + rest * p3), -u, -p2, -p3};
          for (int j = 0; j < kTerms; ++j) {
            sa[j] += wa * coefficient[j];
            sb[j] += wb * coefficient[j];
            sc[j] += wc * coefficient[j];
          }
        }
        for (int j = 0; j < kTerms; ++j) {
          sum_a += sa[j] * terms[j];
          sum_b += sb[j] * terms[j];
          sum_c += sc[j] * terms[j];
        }
      };
      if (contacts.empty()) {
        integrate(std::integral_constant<int, 4>{});
      } else {
        integrate(std::integral_constant<int, 7>{});
      }
    }
    const Vec3 integral = sum_a - omega.cross(sum_b) + omega.cross(omega.cross(sum_c));
    const Vec3 internal = l * k.cwiseProduct(omega - model.NaturalCurvature(i));
    imbalance.segment<3>(3 * i) = internal - integral;
  }
  return imbalance;
}

double KirchhoffResidual(const StrandModel& model, const VecX& curvatures) {
  return EquilibriumResidual(model, curvatures, KirchhoffImbalance(model, curvatures));
}

double KirchhoffResidual(const StrandModel& model, const VecX& curvatures,
                         const StrandGeometry& geometry, const std::vector<Vec3>& segment_moments) {
  return EquilibriumResidual(model, curvatures,
                             KirchhoffImbalance(model, curvatures, geometry, segment_moments));
}

}  // namespace ringlet
