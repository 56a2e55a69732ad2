// Kinematics of a strand for its dynamics (kinematics.h; docs/dynamics.md, "Mass matrix").
#include "dynamics/kinematics.h"

#include <cassert>
#include <cmath>

namespace ringlet::dynamics {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Left Jacobian of the rotation exp(u W) in the segment's start frame: dR R^T = [A dOmega]x with
// A = u I + u^2 G2 W + u^3 G3 W^2 (strand_hessian.cpp, "the rotation's left Jacobian").
Mat3 RotationJacobian(const Vec3& omega, double u, const HelixFunctions& g) {
  const Mat3 w = Hat(omega);
  Mat3 w2 = omega * omega.transpose();
  w2.diagonal().array() -= omega.squaredNorm();
  return u * Mat3::Identity() + (u * u * g.g[2]) * w + (u * u * u * g.g[3]) * w2;
}

}  // namespace

GaussRule GaussLegendre01(int points) {
  assert(points >= 1 && points <= 8);
  GaussRule rule;
  rule.nodes.resize(static_cast<size_t>(points));
  rule.weights.resize(static_cast<size_t>(points));
  // Newton's method on the Legendre polynomial P_n from Tricomi's initial guess, with P_n and
  // P_n' from the three-term recurrence (Abramowitz & Stegun 22.7.10, 22.8.5); weights
  // 2 / ((1 - x^2) P_n'(x)^2) (A&S 25.4.29). Mapped from [-1, 1] to [0, 1].
  const int n = points;
  for (int i = 0; i < n; ++i) {
    double x = std::cos(kPi * (i + 0.75) / (n + 0.5));
    double derivative = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      derivative = n * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / derivative;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    // Recompute the derivative at the final node.
    double p0 = 1.0, p1 = x;
    for (int k = 2; k <= n; ++k) {
      const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
      p0 = p1;
      p1 = p2;
    }
    derivative = n * (x * p1 - p0) / (x * x - 1.0);
    // Nodes in ascending order on [0, 1].
    const size_t j = static_cast<size_t>(n - 1 - i);
    rule.nodes[j] = 0.5 * (1.0 + x);
    rule.weights[j] = 1.0 / ((1.0 - x * x) * derivative * derivative);  // half of A&S's
  }
  return rule;
}

void ComputeKinematics(const StrandModel& model, const VecX& curvatures, const GaussRule& rule,
                       Kinematics* kin, bool jacobians) {
  const int n = model.NumSegments();
  assert(curvatures.size() == 3 * n);
  const size_t points = rule.nodes.size();
  kin->frames.resize(static_cast<size_t>(n));
  kin->starts.resize(static_cast<size_t>(n));
  kin->segments.resize(static_cast<size_t>(n));
  kin->samples.resize(static_cast<size_t>(n) * points);
  kin->first_sample.resize(static_cast<size_t>(n) + 1);
  Mat3 q = model.root_frame;
  Vec3 r = Vec3::Zero();
  for (int i = 0; i < n; ++i) {
    const size_t si = static_cast<size_t>(i);
    const double l = model.segment_lengths[si];
    const Vec3 omega = curvatures.segment<3>(3 * i);
    const double norm = omega.norm();
    kin->frames[si] = q;
    kin->starts[si] = r;
    const HelixSegment segment = EvaluateHelixSegment(omega, l);
    kin->segments[si] = segment;
    kin->first_sample[si] = static_cast<int>(si * points);
    // W and W^2 = Omega Omega^T - |Omega|^2 I, once per segment.
    const Mat3 w = Hat(omega);
    Mat3 w2 = omega * omega.transpose();
    w2.diagonal().array() -= omega.squaredNorm();
    for (size_t j = 0; j < points; ++j) {
      Sample& s = kin->samples[si * points + j];
      s.segment = i;
      s.u = rule.nodes[j] * l;
      s.weight = rule.weights[j] * l;
      s.functions = EvaluateHelixFunctions(norm * s.u);
      const Vec3 h = HelixChordFromFunctions(omega, s.u, s.functions);
      s.y = r + q * h;
      // R(u) = I + u G1 W + u^2 G2 W^2 (helix.h, Rodrigues).
      const Mat3 rotation = Mat3::Identity() + (s.u * s.functions.g[1]) * w +
                            (s.u * s.u * s.functions.g[2]) * w2;
      s.frame = q * rotation;
    }
    r += q * segment.chord;
    q = q * segment.rotation;
  }
  kin->first_sample[static_cast<size_t>(n)] = static_cast<int>(static_cast<size_t>(n) * points);
  kin->jacobians = false;
  if (jacobians) AddJacobians(model, curvatures, kin);
}

void AddJacobians(const StrandModel& model, const VecX& curvatures, Kinematics* kin) {
  if (kin->jacobians) return;
  using helix_hessian::CoefficientsOf;
  const int n = model.NumSegments();
  kin->twist.resize(static_cast<size_t>(n));
  kin->rotation_coefficients.resize(static_cast<size_t>(n));
  kin->chord_coefficients.resize(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const size_t si = static_cast<size_t>(i);
    const double l = model.segment_lengths[si];
    const Vec3 omega = curvatures.segment<3>(3 * i);
    const double norm = omega.norm();
    const Mat3& q = kin->frames[si];
    const HelixSegment& segment = kin->segments[si];
    // The coefficients of the second derivatives (helix_hessian.h): only the Newton matrix's
    // Jacobians and force curvature use them, so they are not part of ComputeKinematics.
    double g[9];
    helix_hessian::HelixFunctions8(l * norm, g);
    kin->rotation_coefficients[si] = CoefficientsOf(1, l, g);
    kin->chord_coefficients[si] = CoefficientsOf(2, l, g);
    // S_i: a change dOmega of segment i turns everything past its end by omega = Q_i A(l) dOmega
    // and moves its end by Q_i dp; a point y past it moves by omega x (y - r_(i+1)) + Q_i dp =
    // omega x y + v with v = Q_i dp + r_(i+1) x omega (strand_hessian.cpp, the same twist).
    // r_(i+1) is the segment's start (its first sample minus its partial chord) plus Q_i p.
    const Vec3 r_next = kin->starts[si] + q * segment.chord;
    Mat63 twist;
    twist.topRows<3>() = q * RotationJacobian(omega, l, segment.functions);
    twist.bottomRows<3>() = q * helix_hessian::ChordDerivative(omega, kin->chord_coefficients[si]) +
                            Hat(r_next) * twist.topRows<3>();
    kin->twist[si] = twist;
    for (int k = kin->first_sample[si]; k < kin->first_sample[si + 1]; ++k) {
      Sample& s = kin->samples[static_cast<size_t>(k)];
      double gu[9];
      helix_hessian::HelixFunctions8(norm * s.u, gu);
      s.chord = CoefficientsOf(2, s.u, gu);
      s.angular = q * RotationJacobian(omega, s.u, s.functions);
      s.linear = q * helix_hessian::ChordDerivative(omega, s.chord);  // dh(u)/dOmega
    }
  }
  kin->jacobians = true;
}

Mat3 SectionInertia(const StrandModel& model, const Sample& sample, bool rotational_inertia) {
  if (!rotational_inertia) return Mat3::Zero();
  const double i1 = model.section.I1(), i2 = model.section.I2();
  const Eigen::DiagonalMatrix<double, 3> local(i1, i2, i1 + i2);
  return (model.material.density * sample.weight) * (sample.frame * local * sample.frame.transpose());
}

void AssembleMetric(const StrandModel& model, const DynamicsOptions& options,
                    const Kinematics& kin, double mass_scale, double drag_scale,
                    StrandHessian* metric) {
  const int n = model.NumSegments();
  metric->diagonal.resize(static_cast<size_t>(n));
  metric->twist = kin.twist;
  metric->load.resize(static_cast<size_t>(n));
  metric->translational = true;
  const double line_density = model.material.density * model.section.Area();
  // Reverse sweep: I accumulates the spatial inertia sum_s P_s^T W_s P_s of the samples past the
  // current segment, P_s = [[I, 0], [-[y_s]x, I]] mapping a twist (omega, v) to the sample's
  // (angular, linear) velocity (omega, omega x y_s + v).
  Mat6 inertia = Mat6::Zero();
  for (int i = n - 1; i >= 0; --i) {
    const size_t si = static_cast<size_t>(i);
    const Mat63& twist = kin.twist[si];
    Mat63 load = inertia * twist;
    Mat3 diagonal = twist.transpose() * load;
    Mat6 own = Mat6::Zero();
    for (int k = kin.first_sample[si]; k < kin.first_sample[si + 1]; ++k) {
      const Sample& s = kin.samples[static_cast<size_t>(k)];
      const double a = mass_scale * line_density * s.weight + drag_scale * options.air_drag * s.weight;
      const Mat3 theta = mass_scale * SectionInertia(model, s, options.rotational_inertia);
      const Mat3 yx = Hat(s.y);
      // P^T W P = [[Theta - a [y]x^2, a [y]x], [-a [y]x, a I]].
      own.topLeftCorner<3, 3>() += theta - a * yx * yx;
      own.topRightCorner<3, 3>() += a * yx;
      own.bottomLeftCorner<3, 3>() -= a * yx;
      own.bottomRightCorner<3, 3>().diagonal().array() += a;
      // P^T W K with K = [angular; linear]: [Theta K_a + a [y]x K_l; a K_l].
      load.topRows<3>() += theta * s.angular + a * yx * s.linear;
      load.bottomRows<3>() += a * s.linear;
      // K^T W K.
      diagonal += s.angular.transpose() * theta * s.angular + a * s.linear.transpose() * s.linear;
    }
    metric->load[si] = load;
    metric->diagonal[si] = 0.5 * (diagonal + diagonal.transpose());
    inertia += own;
  }
}

void SampleVelocities(const Kinematics& kin, const VecX& rates, std::vector<Vec3>* angular,
                      std::vector<Vec3>* linear) {
  const int n = static_cast<int>(kin.twist.size());
  angular->resize(kin.samples.size());
  linear->resize(kin.samples.size());
  Vec6 upstream = Vec6::Zero();  // sum over segments before i of S_a qdot_a
  for (int i = 0; i < n; ++i) {
    const size_t si = static_cast<size_t>(i);
    const Vec3 rate = rates.segment<3>(3 * i);
    const Vec3 omega = upstream.head<3>();
    const Vec3 v = upstream.tail<3>();
    for (int k = kin.first_sample[si]; k < kin.first_sample[si + 1]; ++k) {
      const Sample& s = kin.samples[static_cast<size_t>(k)];
      (*angular)[static_cast<size_t>(k)] = omega + s.angular * rate;
      (*linear)[static_cast<size_t>(k)] = omega.cross(s.y) + v + s.linear * rate;
    }
    upstream += kin.twist[si] * rate;
  }
}

void ApplyJacobianTranspose(const StrandModel& model, const VecX& curvatures,
                            const Kinematics& kin, const std::vector<Vec3>& forces,
                            const std::vector<Mat3>& frame_adjoints, VecX* gradient) {
  assert(kin.jacobians);
  const int n = model.NumSegments();
  assert(curvatures.size() == 3 * n);
  (void)curvatures;
  gradient->resize(3 * n);
  // With the twists: a change dOmega_a turns and moves everything past segment a rigidly by the
  // twist (omega, v) = S_a dOmega_a, so a sample there moves by dy = omega x y + v and turns by
  // dQ = [omega]x Q; its own segment's samples move by their own Jacobians (linear, angular). A
  // force F_s = dPhi/dy_s and a frame adjoint G_s = dPhi/dQ_s are then the wrench
  // (tau_s + y_s x F_s, F_s) about the root, tau_s = sum_d Q_s,d x G_s,d (the columns: <G, [w]x Q>
  // = w . sum_d Q_d x G_d), and dPhi/dOmega_a = S_a^T W_(past a) + sum_(s in a) (angular_s^T tau_s
  // + linear_s^T F_s), W_(past a) the sum of the wrenches of the samples past segment a.
  Vec6 wrench = Vec6::Zero();
  for (int i = n - 1; i >= 0; --i) {
    const size_t si = static_cast<size_t>(i);
    Vec3 g = kin.twist[si].transpose() * wrench;
    for (int k = kin.first_sample[si]; k < kin.first_sample[si + 1]; ++k) {
      const Sample& s = kin.samples[static_cast<size_t>(k)];
      const Vec3& f = forces[static_cast<size_t>(k)];
      const Mat3& adjoint = frame_adjoints[static_cast<size_t>(k)];
      const Vec3 tau = s.frame.col(0).cross(adjoint.col(0)) + s.frame.col(1).cross(adjoint.col(1)) +
                       s.frame.col(2).cross(adjoint.col(2));
      g.noalias() += s.angular.transpose() * tau;
      g.noalias() += s.linear.transpose() * f;
      wrench.head<3>() += tau + s.y.cross(f);
      wrench.tail<3>() += f;
    }
    gradient->segment<3>(3 * i) = g;
  }
}

void AddForceCurvature(const StrandModel& model, const VecX& curvatures, const Kinematics& kin,
                       const std::vector<Vec3>& forces, StrandHessian* matrix) {
  const int n = model.NumSegments();
  // Reverse sweep. Past segment b (its end and everything downstream): f_sum = sum F_s,
  // a_f = sum [F_s]x [y_s]x, and the adjoints r_bar, q_bar of the gradient sweep
  // (ApplyJacobianTranspose), which do not depend on Omega_b.
  Vec3 f_sum = Vec3::Zero();
  Mat3 a_f = Mat3::Zero();
  Vec3 r_bar = Vec3::Zero();
  Mat3 q_bar = Mat3::Zero();
  for (int b = n - 1; b >= 0; --b) {
    const size_t sb = static_cast<size_t>(b);
    const Vec3 omega = curvatures.segment<3>(3 * b);
    const Mat3& q = kin.frames[sb];
    const Mat3 qt = q.transpose();
    const Mat63& twist = kin.twist[sb];
    // B_b (top rows; a point force has no stiffness in the translations): for a < b,
    // F . d^2 y / dq_a dq_b = omega_a . (dy/dq_b x F), with dy/dq_b = -[y]x S_top + S_bottom past
    // b and the own Jacobian inside b: B_top = sum [F]x [y]x S_top - [f_sum]x S_bottom
    // - sum_(s in b) [F_s]x dy_s/dOmega_b.
    Mat3 load_top = a_f * twist.topRows<3>() - Hat(f_sum) * twist.bottomRows<3>();
    const int first = kin.first_sample[sb], last = kin.first_sample[sb + 1];
    for (int k = first; k < last; ++k) {
      load_top -= Hat(forces[static_cast<size_t>(k)]) * kin.samples[static_cast<size_t>(k)].linear;
    }
    matrix->load[sb].topRows<3>() += load_top;
    // Diagonal: the Jacobian in Omega_b of segment b's step of the reverse sweep, adjoints fixed
    // (HelixSegmentVjp with dE/dR = Q_b^T q_bar, dE/dp = Q_b^T r_bar and HelixChordVjp of each
    // sample's force), in closed form as in the statics' exact Hessian (helix_hessian.h).
    helix_hessian::OwnHessianSum own(omega);
    own.AddMatrix(kin.rotation_coefficients[sb], qt * q_bar);
    own.AddChord(kin.chord_coefficients[sb], qt * r_bar);
    for (int k = first; k < last; ++k) {
      own.AddChord(kin.samples[static_cast<size_t>(k)].chord, qt * forces[static_cast<size_t>(k)]);
    }
    const Mat3 diagonal = own.Hessian();
    matrix->diagonal[sb] += 0.5 * (diagonal + diagonal.transpose());
    // Advance the sums and adjoints past segment b's start.
    const HelixSegment& segment = kin.segments[sb];
    Mat3 q_bar_b = q_bar * segment.rotation.transpose() + r_bar * segment.chord.transpose();
    for (int k = first; k < last; ++k) {
      const Sample& s = kin.samples[static_cast<size_t>(k)];
      const Vec3& f = forces[static_cast<size_t>(k)];
      q_bar_b += f * HelixChordFromFunctions(omega, s.u, s.functions).transpose();
      r_bar += f;
      f_sum += f;
      a_f += Hat(f) * Hat(s.y);
    }
    q_bar = q_bar_b;
  }
}

}  // namespace ringlet::dynamics
