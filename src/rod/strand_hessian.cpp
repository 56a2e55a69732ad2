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
// gradient (HelixSegmentVjp and HelixChordVjp with the adjoints held fixed), computed exactly by
// forward-mode jets of Omega_a through the same closed forms (rod/helix_formulas.h).
#include "ringlet/strand_hessian.h"

#include <unsupported/Eigen/AutoDiff>

#include <algorithm>
#include <cassert>
#include <cmath>

#include "ringlet/obstacle.h"
#include "rod/helix_formulas.h"

namespace ringlet {
namespace {

using Jet = Eigen::AutoDiffScalar<Vec3>;
using JVec3 = internal::Vec3T<Jet>;
using JMat3 = internal::Mat3T<Jet>;
using Mat36 = Eigen::Matrix<double, 3, 6>;

constexpr double kInverseFactorial[9] = {1.0,         1.0,          0.5,           1.0 / 6.0,
                                         1.0 / 24.0,  1.0 / 120.0,  1.0 / 720.0,   1.0 / 5040.0,
                                         1.0 / 40320.0};

// G_m(x), m = 1..8 (helix.h). Below |x| = 2 the Taylor series of G7 and G8 (16 terms: the next
// one is below 1e-20 relative at x = 2) and the downward recurrence G_m = 1/m! - x^2 G_(m+2),
// which only adds; above, the closed forms of G1, G2 and G_(m+2) = (1/m! - G_m) / x^2.
void HelixFunctions8(double x, double g[9]) {
  const double y = x * x;
  g[0] = 0.0;
  if (std::abs(x) < 2.0) {
    constexpr int kTerms = 16;
    for (int m = 7; m <= 8; ++m) {
      double sum = 0.0;
      for (int k = kTerms - 1; k >= 0; --k) {
        double factorial = 1.0;
        for (int j = 2; j <= 2 * k + m; ++j) factorial *= j;
        sum = sum * y + (k % 2 == 0 ? 1.0 : -1.0) / factorial;
      }
      g[m] = sum;
    }
    for (int m = 6; m >= 1; --m) g[m] = kInverseFactorial[m] - y * g[m + 2];
    return;
  }
  g[1] = std::sin(x) / x;
  g[2] = (1.0 - std::cos(x)) / y;
  for (int m = 1; m <= 6; ++m) g[m + 2] = (kInverseFactorial[m] - g[m]) / y;
}

// Jets of G_m(l |Omega|), m = 1..6, as functions of Omega: with x = l |Omega|,
// dG_m/dOmega = (G_m'(x)/x) x dx/dOmega = (m G_(m+2) - G_(m+1)) l^2 Omega (helix.h).
void FunctionJets(const Vec3& omega, double l, Jet g[7]) {
  double v[9];
  HelixFunctions8(l * omega.norm(), v);
  g[0] = Jet(0.0, Vec3::Zero());
  for (int m = 1; m <= 6; ++m) g[m] = Jet(v[m], ((m * v[m + 2] - v[m + 1]) * l * l) * omega);
}

// Omega as a jet of itself.
JVec3 OmegaJet(const Vec3& omega) {
  JVec3 o;
  for (int k = 0; k < 3; ++k) o(k) = Jet(omega(k), Vec3::Unit(k));
  return o;
}

// Rows are the derivatives of the components.
Mat3 Jacobian(const JVec3& v) {
  Mat3 j;
  for (int k = 0; k < 3; ++k) j.row(k) = v(k).derivatives().transpose();
  return j;
}

// One segment of the forward sweep: start frame, closed forms and their first derivatives.
struct SegmentData {
  Mat3 frame;          // Q_i (world_from_material at the segment start)
  Mat3 rotation;       // R_i
  Vec3 chord;          // p_i (m)
  Vec3 moment;         // c_i (m^2)
  Mat3 d_rotation[3];  // dR_i / dOmega_k
  Mat3 d_chord;        // column k: dp_i / dOmega_k
  Mat3 d_moment;       // column k: dc_i / dOmega_k
  Jet g[7];            // jets of G_m(l_i |Omega_i|)
};

// One contact sample carrying a force (the same samples as ContactEnergy).
struct SampleData {
  int segment;
  double u;     // arc length in the segment (m)
  Jet g[7];     // jets of G_m(u |Omega_i|)
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
  const int n = model.NumSegments();
  assert(curvatures.size() == 3 * n);
  hessian->diagonal.resize(n);
  hessian->twist.resize(n);
  hessian->load.resize(n);
  const Vec3 f = model.WeightPerLength();
  const Vec3 stiffness = model.Stiffness();
  const Obstacle* obstacle = model.contact.obstacle.get();
  const double clearance = model.contact.clearance;
  const int m = model.contact.samples_per_segment;
  const double k_contact = obstacle ? model.ContactStiffness() : 0.0;

  std::vector<SegmentData> segments(static_cast<size_t>(n));
  std::vector<SampleData> samples;

  // Forward sweep (as in the gradient, energy.cpp): frames, positions relative to the root, the
  // twists S_i and the contact samples.
  Mat3 q = model.root_frame;
  Vec3 r = Vec3::Zero();
  double d_start = obstacle ? obstacle->SignedDistance(model.root_position, nullptr) : 0.0;
  for (int i = 0; i < n; ++i) {
    const double l = model.segment_lengths[static_cast<size_t>(i)];
    const Vec3 omega = curvatures.segment<3>(3 * i);
    SegmentData& s = segments[static_cast<size_t>(i)];
    s.frame = q;
    FunctionJets(omega, l, s.g);
    const JVec3 omega_jet = OmegaJet(omega);
    JMat3 rotation;
    JVec3 chord, moment;
    internal::HelixSegmentFromFunctions<Jet>(omega_jet, l, s.g, &rotation, &chord, &moment);
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        s.rotation(a, b) = rotation(a, b).value();
        for (int k = 0; k < 3; ++k) s.d_rotation[k](a, b) = rotation(a, b).derivatives()(k);
      }
      s.chord(a) = chord(a).value();
      s.moment(a) = moment(a).value();
      s.d_chord.row(a) = chord(a).derivatives().transpose();
      s.d_moment.row(a) = moment(a).derivatives().transpose();
    }
    // S_i: dQ_(i+1) Q_(i+1)^T = [omega]x with omega = Q_i Vee(dR R^T)/2 (dR R^T is skew), and
    // the root-point velocity v = Q_i dp + r_(i+1) x omega (the end of the segment moves by
    // Q_i dp, the rest rotates about it).
    Mat63 twist;
    for (int k = 0; k < 3; ++k) {
      twist.block<3, 1>(0, k) = q * (0.5 * Vee(s.d_rotation[k] * s.rotation.transpose()));
    }
    const Vec3 r_next = r + q * s.chord;
    twist.bottomRows<3>() = q * s.d_chord + Hat(r_next) * twist.topRows<3>();
    hessian->twist[static_cast<size_t>(i)] = twist;

    if (obstacle) {
      // The samples and the broad phase of ContactEnergy (energy.cpp).
      const double d_end = obstacle->SignedDistance(model.root_position + r_next, nullptr);
      if (std::min(d_start, d_end) - 0.5 * l < clearance) {
        const double weight = l / m;
        for (int j = 0; j < m; ++j) {
          SampleData p;
          p.segment = i;
          p.u = (j + 1) * weight;
          FunctionJets(omega, p.u, p.g);
          const JVec3 h = internal::HelixChordT<Jet>(omega_jet, p.u, p.g);
          for (int a = 0; a < 3; ++a) {
            p.h(a) = h(a).value();
            p.d_h.row(a) = h(a).derivatives().transpose();
          }
          p.y = r + q * p.h;
          Vec3 normal;
          Mat3 distance_hessian;
          const double d =
              obstacle->SignedDistanceHessian(model.root_position + p.y, &normal, &distance_hessian);
          const double x = clearance - d;  // penetration of the clearance layer
          if (!(x > 0.0)) continue;
          // phi = 1/2 w k x^2: grad = -w k x n, Hessian = w k (n n^T - x d''(y)).
          p.force = -(weight * k_contact * x) * normal;
          p.phi = (weight * k_contact) * (normal * normal.transpose() - x * distance_hessian);
          samples.push_back(p);
        }
      }
      d_start = d_end;
    }
    r = r_next;
    q = q * s.rotation;
  }

  // Reverse sweep: the adjoints of the gradient (r_bar = dE/dr_(i+1), q_bar = dE/dQ_(i+1), loads
  // held fixed) and Gamma, the contact stiffness of the samples downstream, in twist space.
  Vec3 r_bar = Vec3::Zero();
  Mat3 q_bar = Mat3::Zero();
  Mat6 gamma = Mat6::Zero();
  int c = static_cast<int>(samples.size()) - 1;
  for (int i = n - 1; i >= 0; --i) {
    const SegmentData& s = segments[static_cast<size_t>(i)];
    const double l = model.segment_lengths[static_cast<size_t>(i)];
    const Mat3 qt = s.frame.transpose();
    const Mat63& twist = hessian->twist[static_cast<size_t>(i)];
    const JVec3 omega_jet = OmegaJet(curvatures.segment<3>(3 * i));

    // The segment's own gradient as a jet of Omega_i, adjoints fixed (forward over reverse).
    JVec3 own = internal::HelixSegmentVjpT<Jet>(omega_jet, l, s.g, qt * q_bar, qt * r_bar,
                                                -(qt * f));
    // dQbar_i/dOmega_k with the loads fixed (the update of q_bar below, differentiated).
    Mat3 dq_bar[3];
    for (int k = 0; k < 3; ++k) {
      dq_bar[k] = q_bar * s.d_rotation[k].transpose() + r_bar * s.d_chord.col(k).transpose() -
                  f * s.d_moment.col(k).transpose();
    }
    Mat3 d = twist.transpose() * gamma * twist;
    Mat63 b = gamma * twist;
    Mat6 gamma_own = Mat6::Zero();
    const int last = c;
    for (; c >= 0 && samples[static_cast<size_t>(c)].segment == i; --c) {
      const SampleData& p = samples[static_cast<size_t>(c)];
      own += internal::HelixChordVjpT<Jet>(omega_jet, p.u, p.g, qt * p.force);
      const Mat3 jacobian = s.frame * p.d_h;  // dy/dOmega_i
      const Mat36 e = PointMotion(p.y);
      d += jacobian.transpose() * p.phi * jacobian;
      b += e.transpose() * p.phi * jacobian;
      gamma_own += e.transpose() * p.phi * e;
      for (int k = 0; k < 3; ++k) dq_bar[k] += p.force * p.d_h.col(k).transpose();
    }
    d += Jacobian(own);
    d.diagonal() += l * stiffness;  // elastic, eq. 3
    hessian->diagonal[static_cast<size_t>(i)] = 0.5 * (d + d.transpose());
    for (int k = 0; k < 3; ++k) b.block<3, 1>(0, k) += Vee(dq_bar[k] * s.frame.transpose());
    hessian->load[static_cast<size_t>(i)] = b;
    gamma += gamma_own;

    // Advance the adjoints exactly as the gradient sweep does.
    q_bar = q_bar * s.rotation.transpose() + r_bar * s.chord.transpose() -
            f * s.moment.transpose();
    r_bar -= l * f;
    for (int j = last; j > c; --j) {
      const SampleData& p = samples[static_cast<size_t>(j)];
      q_bar += p.force * p.h.transpose();
      r_bar += p.force;
    }
  }
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

bool StrandHessianFactor::Factor(const StrandHessian& hessian, double shift) {
  const int n = hessian.NumSegments();
  hessian_ = &hessian;
  pivots_.resize(static_cast<size_t>(n));
  reduced_load_.resize(static_cast<size_t>(n));
  failed_ = -1;
  // Eliminate from the tip: after eliminating the segments past k, the remaining blocks keep
  // the form S_a^T (B_b - C S_b) (a < b) and D_b - S_b^T C S_b, with
  // C = sum over eliminated k of B'_k D'_k^(-1) B'_k^T (6 x 6).
  Mat6 c = Mat6::Zero();
  for (int k = n - 1; k >= 0; --k) {
    const Mat63& s = hessian.twist[static_cast<size_t>(k)];
    const Mat63 b = hessian.load[static_cast<size_t>(k)] - c * s;
    Mat3 d = hessian.diagonal[static_cast<size_t>(k)] - s.transpose() * c * s;
    d = 0.5 * (d + d.transpose());
    d.diagonal().array() -= shift;
    Eigen::LLT<Mat3>& llt = pivots_[static_cast<size_t>(k)];
    llt.compute(d);
    if (llt.info() != Eigen::Success || !(llt.matrixLLT().diagonal().minCoeff() > 0.0)) {
      failed_ = k;
      return false;
    }
    reduced_load_[static_cast<size_t>(k)] = b;
    const Eigen::Matrix<double, 3, 6> w = llt.solve(b.transpose());  // D'^(-1) B'^T
    c += b * w;
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
    const Vec3 t = pivots_[static_cast<size_t>(k)].solve(y);
    x->segment<3>(3 * k) = t;
    w += reduced_load_[static_cast<size_t>(k)] * t;
  }
  // Then U^T z = t from the root: z_j = t_j - D'_j^(-1) B'_j^T sum over k < j of S_k z_k.
  Vec6 u = Vec6::Zero();
  for (int j = 0; j < n; ++j) {
    const Vec3 z = x->segment<3>(3 * j) - pivots_[static_cast<size_t>(j)].solve(
                                              reduced_load_[static_cast<size_t>(j)].transpose() * u);
    x->segment<3>(3 * j) = z;
    u += hessian_->twist[static_cast<size_t>(j)] * z;
  }
}

}  // namespace ringlet
