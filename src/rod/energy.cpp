// Elastic (eq. 3) and gravity (eqs. 4-5) energies with exact O(n) gradients.
#include "ringlet/energy.h"

#include <cassert>

namespace ringlet {

double ElasticEnergy(const StrandModel& model, const VecX& curvatures, VecX* gradient) {
  const int n = model.NumSegments();
  assert(curvatures.size() == 3 * n);
  const Vec3 k = model.Stiffness();
  double energy = 0.0;
  if (gradient) gradient->resize(3 * n);
  for (int i = 0; i < n; ++i) {
    // 1/2 l_i (Omega_i - Omega^0)^T K (Omega_i - Omega^0), K diagonal (eq. 3, constant on the segment).
    const Vec3 d = curvatures.segment<3>(3 * i) - model.natural_curvature;
    const double l = model.segment_lengths[i];
    energy += 0.5 * l * d.dot(k.cwiseProduct(d));
    if (gradient) gradient->segment<3>(3 * i) = l * k.cwiseProduct(d);
  }
  return energy;
}

void GravityWorkspace::Resize(int segments) {
  frames_.resize(segments);
  segments_.resize(segments);
}

double GravityEnergy(const StrandModel& model, const VecX& curvatures, VecX* gradient,
                     GravityWorkspace* workspace) {
  const int n = model.NumSegments();
  assert(curvatures.size() == 3 * n);
  if (static_cast<int>(workspace->frames_.size()) != n) workspace->Resize(n);
  const Vec3 f = model.WeightPerLength();

  // Forward sweep: Q_(i+1) = Q_i R_i, r_(i+1) = r_i + Q_i p_i with r_0 = 0 (the root is the origin
  // of heights, the paper's z(0) = 0); the segment contributes -f . (l_i r_i + Q_i c_i) (DESIGN.md).
  Mat3 q = model.root_frame;
  Vec3 r = Vec3::Zero();
  double energy = 0.0;
  for (int i = 0; i < n; ++i) {
    const double l = model.segment_lengths[i];
    HelixSegment& s = workspace->segments_[i];
    s = EvaluateHelixSegment(curvatures.segment<3>(3 * i), l);
    workspace->frames_[i] = q;
    energy -= f.dot(l * r + q * s.moment);
    r += q * s.chord;
    q = q * s.rotation;
  }
  if (!gradient) return energy;

  // Reverse sweep. r_bar and q_bar are dE/dr_(i+1) and dE/dQ_(i+1); r_bar = -(L - s_(i+1)) f and
  // q_bar carries the moment of the hanging part. Each segment's sensitivities to R, p, c go
  // through the exact derivative of the closed forms (HelixSegmentVjp).
  gradient->resize(3 * n);
  Vec3 r_bar = Vec3::Zero();
  Mat3 q_bar = Mat3::Zero();
  for (int i = n - 1; i >= 0; --i) {
    const Mat3& qi = workspace->frames_[i];
    const HelixSegment& s = workspace->segments_[i];
    const Mat3 d_rotation = qi.transpose() * q_bar;
    const Vec3 d_chord = qi.transpose() * r_bar;
    const Vec3 d_moment = -(qi.transpose() * f);
    gradient->segment<3>(3 * i) = HelixSegmentVjp(
        curvatures.segment<3>(3 * i), model.segment_lengths[i], s.functions, d_rotation, d_chord,
        d_moment);
    q_bar = q_bar * s.rotation.transpose() + r_bar * s.chord.transpose() - f * s.moment.transpose();
    r_bar -= model.segment_lengths[i] * f;
  }
  return energy;
}

StrandEnergy::StrandEnergy(const StrandModel& model)
    : model_(model), workspace_(model.NumSegments()), scratch_(3 * model.NumSegments()) {}

double StrandEnergy::Evaluate(const VecX& curvatures, VecX* gradient, EnergyTerms* terms) {
  const double elastic = ElasticEnergy(model_, curvatures, gradient);
  const double gravity = GravityEnergy(model_, curvatures, gradient ? &scratch_ : nullptr,
                                       &workspace_);
  if (gradient) *gradient += scratch_;
  if (terms) {
    terms->elastic = elastic;
    terms->gravity = gravity;
    terms->total = elastic + gravity;
  }
  return elastic + gravity;
}

}  // namespace ringlet
