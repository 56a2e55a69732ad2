// Exact Hessian of E_e + E_g + E_c in block-semiseparable form and its O(n) factorization
// (strand_hessian.h).
//
// Derivation. Write T_i = (Q_i, r_i) for the frame and position at the start of segment i and
// E = sum_i e_i(T_i, Omega_i): the gravity of segment i (eq. 4, -f . (l_i r_i + Q_i c_i)) and its
// contact samples depend only on where the segment starts and on its own curvatures. A curvature
// change d of segment a moves T_k (k > a) by the rigid motion y -> y + omega x y + v with
// (omega, v) = S_a d (the same for every k > a: the product-of-exponentials form of a serial
// chain). Hence, for a < b, d^2E / dOmega_a dOmega_b collects
//   - the loads (gravity, contact forces) held fixed, moved by both changes: the rotation of a
//     acting on the displacement caused by b. It only needs the change of the downstream moment
//     at b's start, Vee(dQbar_b Q_b^T), with Qbar_b = dE/dQ_b the matrix adjoint of the gradient
//     sweep (energy.cpp): that is the top of B_b;
//   - the change of the contact forces, sum over samples s downstream of both of
//     (E_s S_a)^T Phi_s (E_s S_b), E_s = [-[y_s]x, I], Phi_s the penalty's Hessian in space:
//     S_a^T (Gamma_b S_b + own samples of b) with Gamma_b = sum_(s past b) E_s^T Phi_s E_s.
// The diagonal blocks add the segment's own second derivatives: the Jacobian of its closed-form
// gradient (HelixSegmentVjp and HelixChordVjp with the adjoints held fixed), in closed form from
// the G_m (helix.h) and their derivatives up to G_8 (OwnHessianSum, rod/helix_hessian.h).
#include "ringlet/strand_hessian.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <optional>

#include "ringlet/energy.h"
#include "ringlet/helix.h"
#include "ringlet/obstacle.h"
#include "rod/contact_broad_phase.h"
#include "rod/helix_hessian.h"

namespace ringlet {
namespace {

using Mat36 = Eigen::Matrix<double, 3, 6>;
using helix_hessian::ChordDerivative;
using helix_hessian::Coefficients;
using helix_hessian::CoefficientsOf;
using helix_hessian::CrossColumns;
using helix_hessian::HelixFunctions8;
using helix_hessian::OwnHessianSum;

// One segment of the forward sweep: start frame, closed forms and their first derivatives.
struct SegmentData {
  Mat3 frame;          // Q_i (world_from_material at the segment start)
  Mat3 rotation;       // R_i
  Vec3 chord;          // p_i (m)
  Vec3 moment;         // c_i (m^2)
  Mat3 jacobian;       // J_i: dR_i R_i^T = [J_i dOmega]x (local left Jacobian, m)
  Mat3 d_chord;        // column k: dp_i / dOmega_k
  Mat3 d_moment;       // column k: dc_i / dOmega_k
  Coefficients coefficients[4];  // of A_1, A_2, A_3 (index m)
};

// One contact sample carrying a force (the same samples as ContactEnergy).
struct SampleData {
  int segment;
  double u;     // arc length in the segment (m)
  Coefficients coefficients;  // of A_2 over length u (the partial chord)
  Vec3 h;       // partial chord in the segment's start frame (m)
  Mat3 d_h;     // column k: dh / dOmega_k
  Vec3 y;       // position relative to the root (m)
  Vec3 force;   // dE_c/dy (N)
  Mat3 phi;     // d^2 E_c / dy^2 (N/m)
};

Mat36 PointMotion(const Vec3& y) {
  Mat36 e;
  e.leftCols<3>() = -Hat(y);
  e.rightCols<3>().setIdentity();
  return e;
}

}  // namespace

void ComputeStrandHessian(const StrandModel& model, const VecX& curvatures,
                          StrandHessian* hessian) {
  ComputeStrandEnergyAndHessian(model, curvatures, hessian, nullptr, nullptr);
}

double ComputeStrandEnergyAndHessian(const StrandModel& model, const VecX& curvatures,
                                     StrandHessian* hessian, VecX* gradient, EnergyTerms* terms) {
  const int n = model.NumSegments();
  assert(curvatures.size() == 3 * n);
  hessian->diagonal.resize(n);
  hessian->twist.resize(n);
  hessian->load.resize(n);
  const Vec3 f = model.WeightPerLength();
  const Vec3 stiffness = model.Stiffness();
  const Obstacle* obstacle = model.contact.obstacle.get();
  const ContactModel& contact = model.contact;
  const int m = model.contact.samples_per_segment;
  const double k_contact = obstacle ? model.ContactStiffness() : 0.0;

  // Scratch reused across calls on this thread (no allocation per Hessian once warm).
  thread_local std::vector<SegmentData> segments;
  thread_local std::vector<SampleData> samples;
  segments.resize(static_cast<size_t>(n));
  samples.clear();

  // Forward sweep (as in the gradient, energy.cpp): frames, positions relative to the root, the
  // twists S_i and the contact samples.
  Mat3 q = model.root_frame;
  Vec3 r = Vec3::Zero();
  double gravity_energy = 0.0, contact_energy = 0.0;
  std::optional<internal::ContactBroadPhase> broad_phase;
  if (obstacle) {
    broad_phase.emplace(*obstacle, model.root_position,
                        model.root_position.cwiseAbs().maxCoeff() + model.Length());
  }
  for (int i = 0; i < n; ++i) {
    const double l = model.segment_lengths[static_cast<size_t>(i)];
    const Vec3 omega = curvatures.segment<3>(3 * i);
    SegmentData& s = segments[static_cast<size_t>(i)];
    s.frame = q;
    double g[9];
    HelixFunctions8(l * omega.norm(), g);
    for (int mm = 1; mm <= 3; ++mm) s.coefficients[mm] = CoefficientsOf(mm, l, g);
    // The closed forms of helix.h from the same G_m: R = A_1, p = A_2 e3, c = A_3 e3 with
    // A_m = l^(m-1)/(m-1)! I + a1 W + a2 W^2 (the gradient's values to rounding).
    const Mat3 w = Hat(omega);
    Mat3 w2 = omega * omega.transpose();  // W^2 = Omega Omega^T - |Omega|^2 I
    w2.diagonal().array() -= omega.squaredNorm();
    const Coefficients& c1 = s.coefficients[1];
    const Coefficients& c2 = s.coefficients[2];
    const Coefficients& c3 = s.coefficients[3];
    s.rotation = Mat3::Identity() + c1.a1 * w + c1.a2 * w2;
    s.chord = Vec3(0.0, 0.0, l) + c2.a1 * w.col(2) + c2.a2 * w2.col(2);
    s.moment = Vec3(0.0, 0.0, 0.5 * l * l) + c3.a1 * w.col(2) + c3.a2 * w2.col(2);
    // The rotation's left Jacobian: dR R^T = [J dOmega]x with J = l I + l^2 G2 W + l^3 G3 W^2
    // (A_2, the integral of exp(u W) over the segment).
    const Mat3 jacobian = l * Mat3::Identity() + c2.a1 * w + c2.a2 * w2;
    s.jacobian = jacobian;
    s.d_chord = ChordDerivative(omega, s.coefficients[2]);
    s.d_moment = ChordDerivative(omega, s.coefficients[3]);
    // S_i: dQ_(i+1) Q_(i+1)^T = [omega]x with omega = Q_i J dOmega, and the root-point velocity
    // v = Q_i dp + r_(i+1) x omega (the end of the segment moves by Q_i dp, the rest rotates
    // about it).
    Mat63 twist;
    twist.topRows<3>() = q * jacobian;
    const Vec3 r_next = r + q * s.chord;
    // Without an obstacle no load depends on position, so the bottom rows never meet a non-zero
    // load (B's bottom rows are the contact terms): skip them.
    if (obstacle) {
      twist.bottomRows<3>() = q * s.d_chord + Hat(r_next) * twist.topRows<3>();
    } else {
      twist.bottomRows<3>().setZero();
    }
    hessian->twist[static_cast<size_t>(i)] = twist;
    gravity_energy -= f.dot(l * r + q * s.moment);  // eq. 4, as GravityEnergy

    // The samples and the broad phase of ContactEnergy (energy.cpp); a sample's derivatives
    // only once it is known to carry a force.
    if (obstacle && broad_phase->Near(r, r_next, l, contact.SegmentClearance(i))) {
      const double weight = l / m;
      const double norm = omega.norm();
      for (int j = 0; j < m; ++j) {
        const double u = (j + 1) * weight;
        const Vec3 h = HelixChordFromFunctions(omega, u, EvaluateHelixFunctions(norm * u));
        const Vec3 y = r + q * h;
        Vec3 normal;
        Mat3 distance_hessian;
        const double d =
            obstacle->SignedDistanceHessian(model.root_position + y, &normal, &distance_hessian);
        const double x = contact.SampleClearance(i, j) - d;  // penetration of the layer
        if (!(x > 0.0)) continue;
        contact_energy += 0.5 * weight * k_contact * x * x;  // as ContactEnergy
        SampleData& p = samples.emplace_back();
        p.segment = i;
        p.u = u;
        p.h = h;
        p.y = y;
        double gu[9];
        HelixFunctions8(norm * u, gu);
        p.coefficients = CoefficientsOf(2, u, gu);
        p.d_h = ChordDerivative(omega, p.coefficients);
        // phi = 1/2 w k x^2: grad = -w k x n, Hessian = w k (n n^T - x d''(y)).
        p.force = -(weight * k_contact * x) * normal;
        p.phi = (weight * k_contact) * (normal * normal.transpose() - x * distance_hessian);
      }
    }
    r = r_next;
    q = q * s.rotation;
  }

  // Reverse sweep: the adjoints of the gradient (r_bar = dE/dr_(i+1), q_bar = dE/dQ_(i+1), loads
  // held fixed) and Gamma, the contact stiffness of the samples downstream, in twist space.
  hessian->translational = !samples.empty();
  if (gradient) gradient->resize(3 * n);
  Vec3 r_bar = Vec3::Zero();
  Mat3 q_bar = Mat3::Zero();
  Mat6 gamma = Mat6::Zero();
  int c = static_cast<int>(samples.size()) - 1;
  for (int i = n - 1; i >= 0; --i) {
    const SegmentData& s = segments[static_cast<size_t>(i)];
    const double l = model.segment_lengths[static_cast<size_t>(i)];
    const Mat3 qt = s.frame.transpose();
    const Mat63& twist = hessian->twist[static_cast<size_t>(i)];
    const Vec3 omega = curvatures.segment<3>(3 * i);

    // The Jacobian of the segment's own gradient (HelixSegmentVjp), adjoints fixed.
    OwnHessianSum own(omega);
    own.AddMatrix(s.coefficients[1], qt * q_bar);
    own.AddChord(s.coefficients[2], qt * r_bar);
    own.AddChord(s.coefficients[3], -(qt * f));
    // dQbar_i/dOmega_k with the loads fixed (the update of q_bar below, differentiated):
    // dR_k = [J e_k]x R, so q_bar dR_k^T = -(q_bar R^T) [J e_k]x, and
    //   dQbar_k = -(q_bar R^T) [J e_k]x + r_bar (dp_k)^T - f (dc_k)^T (+ each sample's F (dh_k)^T).
    // Its moment, column k of B's top rows, is Vee(dQbar_k Q_i^T). With B = q_bar R^T Q_i^T,
    // Vee(B [v]x) = (tr(B) I - B^T) v (v = Q_i J e_k) and Vee(a b^T) = b x a, all three columns
    // at once: -(tr(B) I - B^T) Q_i J - [r_bar]x Q_i dp + [f]x Q_i dc - sum [F]x Q_i dh.
    const Mat3 q_bar_rt = q_bar * s.rotation.transpose();  // also the adjoint's update below
    const Mat3 moved = q_bar_rt * qt;
    Mat3 load_top = -(moved.trace() * Mat3::Identity() - moved.transpose()) * twist.topRows<3>() -
                    CrossColumns(r_bar, s.frame * s.d_chord) +
                    CrossColumns(f, s.frame * s.d_moment);
    Mat63 b = Mat63::Zero();
    Mat3 d = Mat3::Zero();
    if (!samples.empty() && c + 1 < static_cast<int>(samples.size())) {  // Gamma != 0
      b.noalias() = gamma * twist;
      d.noalias() = twist.transpose() * b;
    }
    Mat6 gamma_own = Mat6::Zero();
    const int last = c;
    for (; c >= 0 && samples[static_cast<size_t>(c)].segment == i; --c) {
      const SampleData& p = samples[static_cast<size_t>(c)];
      own.AddChord(p.coefficients, qt * p.force);
      const Mat3 jacobian = s.frame * p.d_h;  // dy/dOmega_i
      const Mat36 e = PointMotion(p.y);
      const Mat63 e_phi = e.transpose() * p.phi;  // shared by b and gamma
      d += jacobian.transpose() * p.phi * jacobian;
      b += e_phi * jacobian;
      gamma_own += e_phi * e;
      load_top -= CrossColumns(p.force, jacobian);
    }
    d += own.Hessian();
    if (gradient) {
      // The gradient's chain rule with the same adjoints (LoadSweep's reverse sweep): the chord
      // and moment through their derivative matrices, the rotation through its left Jacobian
      // (dR = [J dOmega]x R: d tr(A^T R) = tr(R A^T [J dOmega]x) = -Vee(R A^T) . J dOmega with
      // A = Q_i^T q_bar, math.h's Vee), each sample's force through its partial chord's
      // derivative.
      const Mat3 ra = s.rotation * (qt * q_bar).transpose();
      Vec3 g = s.d_chord.transpose() * (qt * r_bar) - s.d_moment.transpose() * (qt * f) -
               s.jacobian.transpose() * Vee(ra);
      for (int j = last; j > c; --j) {
        const SampleData& p = samples[static_cast<size_t>(j)];
        g += p.d_h.transpose() * (qt * p.force);
      }
      gradient->segment<3>(3 * i) = g;
    }
    d.diagonal() += l * stiffness;  // elastic, eq. 3
    hessian->diagonal[static_cast<size_t>(i)] = 0.5 * (d + d.transpose());
    b.topRows<3>() += load_top;
    hessian->load[static_cast<size_t>(i)] = b;
    gamma += gamma_own;

    // Advance the adjoints exactly as the gradient sweep does.
    q_bar = q_bar_rt + r_bar * s.chord.transpose() - f * s.moment.transpose();
    r_bar -= l * f;
    for (int j = last; j > c; --j) {
      const SampleData& p = samples[static_cast<size_t>(j)];
      q_bar += p.force * p.h.transpose();
      r_bar += p.force;
    }
  }
  VecX elastic_gradient;
  const double elastic = ElasticEnergy(model, curvatures, gradient ? &elastic_gradient : nullptr);
  if (gradient) *gradient += elastic_gradient;
  if (terms) {
    terms->elastic = elastic;
    terms->gravity = gravity_energy;
    terms->contact = contact_energy;
    terms->total = elastic + gravity_energy + contact_energy;
  }
  return elastic + gravity_energy + contact_energy;
}

void StrandHessian::Multiply(const VecX& v, VecX* out) const {
  const int n = NumSegments();
  assert(v.size() == 3 * n);
  out->resize(3 * n);
  // Upper part: sum over b > a of S_a^T B_b v_b, accumulated from the tip.
  Vec6 suffix = Vec6::Zero();
  for (int a = n - 1; a >= 0; --a) {
    const Vec3 va = v.segment<3>(3 * a);
    out->segment<3>(3 * a) = diagonal[static_cast<size_t>(a)] * va +
                             twist[static_cast<size_t>(a)].transpose() * suffix;
    suffix += load[static_cast<size_t>(a)] * va;
  }
  // Lower part: sum over b < a of B_a^T S_b v_b, accumulated from the root.
  Vec6 prefix = Vec6::Zero();
  for (int a = 0; a < n; ++a) {
    out->segment<3>(3 * a) += load[static_cast<size_t>(a)].transpose() * prefix;
    prefix += twist[static_cast<size_t>(a)] * v.segment<3>(3 * a);
  }
}

MatX StrandHessian::Dense() const {
  const int n = NumSegments();
  MatX h(3 * n, 3 * n);
  for (int a = 0; a < n; ++a) {
    h.block<3, 3>(3 * a, 3 * a) = diagonal[static_cast<size_t>(a)];
    for (int b = a + 1; b < n; ++b) {
      const Mat3 block = twist[static_cast<size_t>(a)].transpose() * load[static_cast<size_t>(b)];
      h.block<3, 3>(3 * a, 3 * b) = block;
      h.block<3, 3>(3 * b, 3 * a) = block.transpose();
    }
  }
  return h;
}

void StrandHessian::Scale(const VecX& s) {
  const int n = NumSegments();
  assert(s.size() == 3 * n);
  for (int a = 0; a < n; ++a) {
    const Eigen::DiagonalMatrix<double, 3> sa(s.segment<3>(3 * a));
    Mat3& d = diagonal[static_cast<size_t>(a)];
    d = sa * d * sa;
    twist[static_cast<size_t>(a)] = twist[static_cast<size_t>(a)] * sa;
    load[static_cast<size_t>(a)] = load[static_cast<size_t>(a)] * sa;
  }
}

namespace {

// Cholesky of a symmetric 3x3 matrix and its inverse, by hand (Eigen's general triangular
// solves cost more than the factorization here). Returns false unless every pivot is > 0.
bool InvertPositiveDefinite3(const Mat3& a, Mat3* inverse) {
  const double l00 = a(0, 0);
  if (!(l00 > 0.0)) return false;
  const double s00 = std::sqrt(l00);
  const double l10 = a(1, 0) / s00, l20 = a(2, 0) / s00;
  const double p11 = a(1, 1) - l10 * l10;
  if (!(p11 > 0.0)) return false;
  const double s11 = std::sqrt(p11);
  const double l21 = (a(2, 1) - l20 * l10) / s11;
  const double p22 = a(2, 2) - l20 * l20 - l21 * l21;
  if (!(p22 > 0.0)) return false;
  const double s22 = std::sqrt(p22);
  // L^(-1) (lower triangular), then A^(-1) = L^(-T) L^(-1).
  Mat3 li = Mat3::Zero();
  li(0, 0) = 1.0 / s00;
  li(1, 1) = 1.0 / s11;
  li(2, 2) = 1.0 / s22;
  li(1, 0) = -l10 * li(0, 0) / s11;
  li(2, 1) = -l21 * li(1, 1) / s22;
  li(2, 0) = -(l20 * li(0, 0) + l21 * li(1, 0)) / s22;
  inverse->noalias() = li.transpose() * li;
  return true;
}

}  // namespace

bool StrandHessianFactor::Factor(const StrandHessian& hessian, double shift) {
  const int n = hessian.NumSegments();
  hessian_ = &hessian;
  inverses_.resize(static_cast<size_t>(n));
  reduced_load_.resize(static_cast<size_t>(n));
  failed_ = -1;
  // Eliminate from the tip: after eliminating the segments past k, the remaining blocks keep
  // the form S_a^T (B_b - C S_b) (a < b) and D_b - S_b^T C S_b, with
  // C = sum over eliminated k of B'_k D'_k^(-1) B'_k^T (6 x 6). Without contact the bottom
  // rows of every B are zero, so C lives in its top-left 3 x 3 block: 4x less work.
  if (!hessian.translational) {
    Mat3 c = Mat3::Zero();
    for (int k = n - 1; k >= 0; --k) {
      const auto s = hessian.twist[static_cast<size_t>(k)].topRows<3>();
      Mat63& b = reduced_load_[static_cast<size_t>(k)];
      b.bottomRows<3>().setZero();
      const Mat3 cs = c * s;
      b.topRows<3>() = hessian.load[static_cast<size_t>(k)].topRows<3>() - cs;
      Mat3 d = hessian.diagonal[static_cast<size_t>(k)] - s.transpose() * cs;
      d = 0.5 * (d + d.transpose());
      d.diagonal().array() -= shift;
      Mat3& inverse = inverses_[static_cast<size_t>(k)];
      if (!InvertPositiveDefinite3(d, &inverse)) {
        failed_ = k;
        return false;
      }
      const Mat3 bt = b.topRows<3>();
      c.noalias() += bt * (inverse * bt.transpose());
      c = (0.5 * (c + c.transpose())).eval();
    }
    return true;
  }
  Mat6 c = Mat6::Zero();
  for (int k = n - 1; k >= 0; --k) {
    const Mat63& s = hessian.twist[static_cast<size_t>(k)];
    Mat63& b = reduced_load_[static_cast<size_t>(k)];
    b.noalias() = hessian.load[static_cast<size_t>(k)] - c * s;
    Mat3 d = hessian.diagonal[static_cast<size_t>(k)] - s.transpose() * c * s;
    d = 0.5 * (d + d.transpose());
    d.diagonal().array() -= shift;
    Mat3& inverse = inverses_[static_cast<size_t>(k)];
    if (!InvertPositiveDefinite3(d, &inverse)) {
      failed_ = k;
      return false;
    }
    c.noalias() += b * (inverse * b.transpose());  // B' D'^(-1) B'^T
    c = (0.5 * (c + c.transpose())).eval();
  }
  return true;
}

void StrandHessianFactor::Solve(const VecX& rhs, VecX* x) const {
  assert(hessian_ && failed_ < 0);
  const int n = hessian_->NumSegments();
  assert(rhs.size() == 3 * n);
  x->resize(3 * n);
  // H - shift I = U D U^T with U_ak = S_a^T B'_k D'_k^(-1) (a < k). First U D t = rhs from the
  // tip (t = D^(-1) y, U y = rhs), accumulating w = sum over j > k of B'_j t_j.
  Vec6 w = Vec6::Zero();
  for (int k = n - 1; k >= 0; --k) {
    const Vec3 y = rhs.segment<3>(3 * k) - hessian_->twist[static_cast<size_t>(k)].transpose() * w;
    const Vec3 t = inverses_[static_cast<size_t>(k)] * y;
    x->segment<3>(3 * k) = t;
    w += reduced_load_[static_cast<size_t>(k)] * t;
  }
  // Then U^T z = t from the root: z_j = t_j - D'_j^(-1) B'_j^T sum over k < j of S_k z_k.
  Vec6 u = Vec6::Zero();
  for (int j = 0; j < n; ++j) {
    const Vec3 z = x->segment<3>(3 * j) - inverses_[static_cast<size_t>(j)] *
                                              (reduced_load_[static_cast<size_t>(j)].transpose() * u);
    x->segment<3>(3 * j) = z;
    u += hessian_->twist[static_cast<size_t>(j)] * z;
  }
}

}  // namespace ringlet
