// Elastic (eq. 3), gravity (eqs. 4-5) and contact (section 3.1) energies with exact O(n) gradients.
#include "ringlet/energy.h"

#include <algorithm>
#include <cassert>
#include <optional>

#include "rod/contact_broad_phase.h"

namespace ringlet {

double ElasticEnergy(const StrandModel& model, const VecX& curvatures, VecX* gradient) {
  const int n = model.NumSegments();
  assert(curvatures.size() == 3 * n);
  const Vec3 k = model.Stiffness();
  double energy = 0.0;
  if (gradient) gradient->resize(3 * n);
  for (int i = 0; i < n; ++i) {
    // 1/2 l_i (Omega_i - Omega^0)^T K (Omega_i - Omega^0), K diagonal (eq. 3, constant on the segment).
    const Vec3 d = curvatures.segment<3>(3 * i) - model.NaturalCurvature(i);
    const double l = model.segment_lengths[i];
    energy += 0.5 * l * d.dot(k.cwiseProduct(d));
    if (gradient) gradient->segment<3>(3 * i) = l * k.cwiseProduct(d);
  }
  return energy;
}

void LoadWorkspace::Resize(int segments) {
  frames_.resize(segments);
  starts_.resize(segments);
  segments_.resize(segments);
}

// One forward and one reverse sweep over the segments for the external loads: gravity (eqs. 4-5)
// and the contact penalty (section 3.1), either or both.
struct LoadSweep {
  static void Run(const StrandModel& model, const VecX& curvatures, bool with_gravity,
                  bool with_contact, VecX* gradient, LoadWorkspace* ws, double* gravity_energy,
                  double* contact_energy) {
    const int n = model.NumSegments();
    assert(curvatures.size() == 3 * n);
    if (static_cast<int>(ws->frames_.size()) != n) ws->Resize(n);
    ws->contacts_.clear();
    const Vec3 f = with_gravity ? model.WeightPerLength() : Vec3::Zero();
    const Obstacle* obstacle = with_contact ? model.contact.obstacle.get() : nullptr;
    const ContactModel& contact = model.contact;
    const int m = model.contact.samples_per_segment;
    const double k = obstacle ? model.ContactStiffness() : 0.0;

    // Forward sweep: Q_(i+1) = Q_i R_i, r_(i+1) = r_i + Q_i p_i with r_0 = 0 (the root is the
    // origin of heights, the paper's z(0) = 0); the segment contributes -f . (l_i r_i + Q_i c_i)
    // to E_g (DESIGN.md) and 1/2 k x^2 l_i / m per penetrating sample to E_c.
    Mat3 q = model.root_frame;
    Vec3 r = Vec3::Zero();
    double eg = 0.0, ec = 0.0;
    std::optional<internal::ContactBroadPhase> broad_phase;
    if (obstacle) {
      broad_phase.emplace(*obstacle, model.root_position,
                          model.root_position.cwiseAbs().maxCoeff() + model.Length());
    }
    for (int i = 0; i < n; ++i) {
      const double l = model.segment_lengths[i];
      const Vec3 omega = curvatures.segment<3>(3 * i);
      HelixSegment& s = ws->segments_[i];
      s = EvaluateHelixSegment(omega, l);
      ws->frames_[i] = q;
      ws->starts_[i] = r;
      eg -= f.dot(l * r + q * s.moment);
      const Vec3 r_next = r + q * s.chord;
      if (obstacle && broad_phase->Near(r, r_next, l, contact.SegmentClearance(i))) {
        const double weight = l / m;  // samples at (j + 1) l / m, weight l / m
        const double norm = omega.norm();
        for (int j = 0; j < m; ++j) {
          const double u = (j + 1) * weight;
          const HelixFunctions functions = EvaluateHelixFunctions(norm * u);
          const Vec3 h = HelixChordFromFunctions(omega, u, functions);
          Vec3 normal;
          const double d = obstacle->SignedDistance(model.root_position + r + q * h, &normal);
          const double x = contact.SampleClearance(i, j) - d;  // penetration of the layer
          if (x <= 0.0) continue;
          ec += 0.5 * weight * k * x * x;
          ws->contacts_.push_back({i, u, h, -(weight * k * x) * normal, functions});
        }
      }
      r = r_next;
      q = q * s.rotation;
    }
    if (gravity_energy) *gravity_energy = eg;
    if (contact_energy) *contact_energy = ec;
    if (!gradient) return;

    // Reverse sweep. r_bar and q_bar are dE/dr_(i+1) and dE/dQ_(i+1); for gravity r_bar =
    // -(L - s_(i+1)) f and q_bar carries the moment of the hanging part. Each segment's
    // sensitivities to R, p, c go through the exact derivative of the closed forms
    // (HelixSegmentVjp); a contact sample's through that of its partial chord h(u).
    gradient->resize(3 * n);
    Vec3 r_bar = Vec3::Zero();
    Mat3 q_bar = Mat3::Zero();
    int c = static_cast<int>(ws->contacts_.size()) - 1;
    for (int i = n - 1; i >= 0; --i) {
      const Mat3& qi = ws->frames_[i];
      const HelixSegment& s = ws->segments_[i];
      const Vec3 omega = curvatures.segment<3>(3 * i);
      const double l = model.segment_lengths[i];
      Vec3 g = HelixSegmentVjp(omega, l, s.functions, qi.transpose() * q_bar,
                               qi.transpose() * r_bar, -(qi.transpose() * f));
      q_bar = q_bar * s.rotation.transpose() + r_bar * s.chord.transpose() -
              f * s.moment.transpose();
      r_bar -= l * f;
      for (; c >= 0 && ws->contacts_[c].segment == i; --c) {
        const LoadWorkspace::ContactSample& p = ws->contacts_[c];
        g += HelixChordVjp(omega, p.u, p.functions, qi.transpose() * p.dE_dx);
        q_bar += p.dE_dx * p.h.transpose();
        r_bar += p.dE_dx;
      }
      gradient->segment<3>(3 * i) = g;
    }
  }
};

double GravityEnergy(const StrandModel& model, const VecX& curvatures, VecX* gradient,
                     LoadWorkspace* workspace) {
  double energy = 0.0;
  LoadSweep::Run(model, curvatures, true, false, gradient, workspace, &energy, nullptr);
  return energy;
}

double ContactEnergy(const StrandModel& model, const VecX& curvatures, VecX* gradient,
                     LoadWorkspace* workspace) {
  double energy = 0.0;
  LoadSweep::Run(model, curvatures, false, true, gradient, workspace, nullptr, &energy);
  return energy;
}

StrandEnergy::StrandEnergy(const StrandModel& model)
    : model_(model), workspace_(model.NumSegments()), scratch_(3 * model.NumSegments()) {}

double StrandEnergy::Evaluate(const VecX& curvatures, VecX* gradient, EnergyTerms* terms) {
  const double elastic = ElasticEnergy(model_, curvatures, gradient);
  double gravity = 0.0, contact = 0.0;
  LoadSweep::Run(model_, curvatures, true, model_.contact.obstacle != nullptr,
                 gradient ? &scratch_ : nullptr, &workspace_, &gravity, &contact);
  if (gradient) *gradient += scratch_;
  if (terms) {
    terms->elastic = elastic;
    terms->gravity = gravity;
    terms->contact = contact;
    terms->total = elastic + gravity + contact;
  }
  return elastic + gravity + contact;
}

}  // namespace ringlet
