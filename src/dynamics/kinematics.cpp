// Kinematics of a strand for its dynamics (kinematics.h; docs/dynamics.md, "Mass matrix").
#include "dynamics/kinematics.h"

#include <cassert>
#include <cmath>

namespace ringlet::dynamics {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The small loops over 3 rows or columns carry `#pragma GCC unroll 3` (GCC and Clang): at -O2 GCC
// leaves them rolled, which cost the metric's assembly a fifth more instructions.
// The 3x3 products below are written out (Eigen's small fixed-size products cost about twice as
// many instructions here) with the sums in the order of the Eigen 3.4 SSE2 products they replace
// (rows 0 and 1 by packets, (a0 b0 + a1 b1) + a2 b2; row 2 by the scalar reduction,
// a0 b0 + (a1 b1 + a2 b2)), so the results are the same to the last bit as before on x86-64 (the
// written-out order is the same on every target; Eigen's varies with the SIMD width). Any order is
// as accurate. c is __restrict__: the factors are not reloaded after each store.
inline void MulColumn(const Mat3& a, const double* b, double* __restrict__ c) {
  const double b0 = b[0], b1 = b[1], b2 = b[2];
  c[0] = (a(0, 0) * b0 + a(0, 1) * b1) + a(0, 2) * b2;
  c[1] = (a(1, 0) * b0 + a(1, 1) * b1) + a(1, 2) * b2;
  c[2] = a(2, 0) * b0 + (a(2, 1) * b1 + a(2, 2) * b2);
}
inline Mat3 Mul(const Mat3& a, const Mat3& b) {
  Mat3 c;
  MulColumn(a, b.data(), c.data());
  MulColumn(a, b.data() + 3, c.data() + 3);
  MulColumn(a, b.data() + 6, c.data() + 6);
  return c;
}

// (CrossColumns and TransposeMul read their factors into locals before storing anything: the
// result may be the caller's memory, which the compiler must otherwise assume to alias them.)
// [a]x M = a x (each column of M): two products an entry, the zero terms of Hat(a) * M dropped.
inline Mat3 CrossColumns(const Vec3& a, const Mat3& m) {
  const double ax = a.x(), ay = a.y(), az = a.z();
  double c[9];
  #pragma GCC unroll 3
  for (int j = 0; j < 3; ++j) {
    const double m0 = m(0, j), m1 = m(1, j), m2 = m(2, j);
    c[3 * j] = ay * m2 - az * m1;
    c[3 * j + 1] = az * m0 - ax * m2;
    c[3 * j + 2] = ax * m1 - ay * m0;
  }
  return Eigen::Map<const Mat3>(c);
}

// [b]x [y]x = y b^T - (b . y) I: two products on the diagonal, one off it (Hat(b) * Hat(y)'s
// non-zero terms).
inline Mat3 HatProduct(const Vec3& b, const Vec3& y) {
  Mat3 m;
  m(0, 0) = -(b.z() * y.z()) - b.y() * y.y();
  m(1, 1) = -(b.z() * y.z()) - b.x() * y.x();
  m(2, 2) = -(b.y() * y.y()) - b.x() * y.x();
  m(0, 1) = b.y() * y.x();
  m(0, 2) = b.z() * y.x();
  m(1, 0) = b.x() * y.y();
  m(1, 2) = b.z() * y.y();
  m(2, 0) = b.x() * y.z();
  m(2, 1) = b.y() * y.z();
  return m;
}

// a^T b (3x3), the sums left to right (as Eigen's product with a transposed left factor).
inline Mat3 TransposeMul(const Mat3& a, const Mat3& b) {
  const double a00 = a(0, 0), a10 = a(1, 0), a20 = a(2, 0);
  const double a01 = a(0, 1), a11 = a(1, 1), a21 = a(2, 1);
  const double a02 = a(0, 2), a12 = a(1, 2), a22 = a(2, 2);
  double c[9];
  #pragma GCC unroll 3
  for (int j = 0; j < 3; ++j) {
    const double b0 = b(0, j), b1 = b(1, j), b2 = b(2, j);
    c[3 * j] = (a00 * b0 + a10 * b1) + a20 * b2;
    c[3 * j + 1] = (a01 * b0 + a11 * b1) + a21 * b2;
    c[3 * j + 2] = (a02 * b0 + a12 * b1) + a22 * b2;
  }
  return Eigen::Map<const Mat3>(c);
}

// scale Q diag(i1, i2, i1 + i2) Q^T (SectionInertia).
inline Mat3 FrameInertia(const Mat3& frame, double scale, double i1, double i2) {
  Mat3 weighted = frame;
  weighted.col(0) *= i1;
  weighted.col(1) *= i2;
  weighted.col(2) *= i1 + i2;
  Mat3 theta = Mul(weighted, frame.transpose());
  theta *= scale;
  return theta;
}

// EvaluateHelixSegment (helix.h) with the same sums, W^2 by HatProduct (the non-zero terms of
// W W) instead of a general 3x3 product.
inline void HelixSegmentOf(const Vec3& o, double l, HelixSegment* s) {
  const HelixFunctions& h = s->functions;
  s->functions = EvaluateHelixFunctions(l * o.norm());
  const Mat3 w2 = HatProduct(o, o);
  const double l2 = l * l, l3 = l2 * l, l4 = l3 * l;
  // R = I + l G1 W + l^2 G2 W^2 (Rodrigues).
  const double a1 = l * h.g[1], a2 = l * l * h.g[2];
  Mat3& r = s->rotation;
  r(0, 0) = 1.0 + a2 * w2(0, 0);
  r(1, 1) = 1.0 + a2 * w2(1, 1);
  r(2, 2) = 1.0 + a2 * w2(2, 2);
  r(0, 1) = a1 * -o.z() + a2 * w2(0, 1);
  r(1, 0) = a1 * o.z() + a2 * w2(1, 0);
  r(0, 2) = a1 * o.y() + a2 * w2(0, 2);
  r(2, 0) = a1 * -o.y() + a2 * w2(2, 0);
  r(1, 2) = a1 * -o.x() + a2 * w2(1, 2);
  r(2, 1) = a1 * o.x() + a2 * w2(2, 1);
  // p = (l I + l^2 G2 W + l^3 G3 W^2) e3, c = (l^2/2 I + l^3 G3 W + l^4 G4 W^2) e3, W e3 =
  // (Omega_y, -Omega_x, 0).
  const double p1 = l2 * h.g[2], p2 = l3 * h.g[3];
  s->chord = Vec3(p1 * o.y() + p2 * w2(0, 2), p1 * -o.x() + p2 * w2(1, 2), l + p2 * w2(2, 2));
  const double c1 = l3 * h.g[3], c2 = l4 * h.g[4];
  s->moment = Vec3(c1 * o.y() + c2 * w2(0, 2), c1 * -o.x() + c2 * w2(1, 2),
                   0.5 * l2 + c2 * w2(2, 2));
}

// Left Jacobian of the rotation exp(u W) in the segment's start frame: dR R^T = [A dOmega]x with
// A = u I + u^2 G2 W + u^3 G3 W^2 (strand_hessian.cpp, "the rotation's left Jacobian"), with
// W^2 = Omega Omega^T - |Omega|^2 I; entry by entry (squared_norm = |Omega|^2).
inline Mat3 RotationJacobian(const Vec3& o, double squared_norm, double u,
                             const HelixFunctions& g) {
  const double c2 = u * u * g.g[2], c3 = u * u * u * g.g[3];
  Mat3 a;
  a(0, 0) = u + c3 * (o.x() * o.x() - squared_norm);
  a(1, 1) = u + c3 * (o.y() * o.y() - squared_norm);
  a(2, 2) = u + c3 * (o.z() * o.z() - squared_norm);
  a(0, 1) = c2 * -o.z() + c3 * (o.x() * o.y());
  a(1, 0) = c2 * o.z() + c3 * (o.y() * o.x());
  a(0, 2) = c2 * o.y() + c3 * (o.x() * o.z());
  a(2, 0) = c2 * -o.y() + c3 * (o.z() * o.x());
  a(1, 2) = c2 * -o.x() + c3 * (o.y() * o.z());
  a(2, 1) = c2 * o.x() + c3 * (o.z() * o.y());
  return a;
}

// helix_hessian::ChordDerivative entry by entry: u Omega^T + a2 Omega_z I - [a1 e3 + a2 W e3]x,
// u = b1 W e3 + b2 W^2 e3 - a2 e3, W e3 = (Omega_y, -Omega_x, 0),
// W^2 e3 = (Omega_z Omega_x, Omega_z Omega_y, -Omega_x^2 - Omega_y^2).
inline Mat3 ChordJacobian(const Vec3& o, const helix_hessian::Coefficients& c) {
  const double w2x = o.z() * o.x(), w2y = o.z() * o.y(), w2z = -(o.x() * o.x()) - o.y() * o.y();
  const double ux = c.b1 * o.y() + c.b2 * w2x;
  const double uy = c.b1 * -o.x() + c.b2 * w2y;
  const double uz = c.b2 * w2z - c.a2;
  const double vx = c.a2 * o.y(), vy = c.a2 * -o.x(), vz = c.a1;  // a1 e3 + a2 W e3
  const double diagonal = c.a2 * o.z();
  Mat3 d;
  d(0, 0) = ux * o.x() + diagonal;
  d(1, 0) = uy * o.x() - vz;
  d(2, 0) = uz * o.x() + vy;
  d(0, 1) = ux * o.y() + vz;
  d(1, 1) = uy * o.y() + diagonal;
  d(2, 1) = uz * o.y() - vx;
  d(0, 2) = ux * o.z() - vy;
  d(1, 2) = uy * o.z() + vx;
  d(2, 2) = uz * o.z() + diagonal;
  return d;
}

// helix_hessian::CoefficientsOf for a fixed m, inlined (the same products in the same order).
template <int m>
inline helix_hessian::Coefficients CoefficientsOf(double l, const double g[9]) {
  auto d = [&](int k) { return k * g[k + 2] - g[k + 1]; };
  double lp[m + 6];
  lp[0] = 1.0;
  #pragma GCC unroll 8
  for (int k = 1; k < m + 6; ++k) lp[k] = lp[k - 1] * l;
  helix_hessian::Coefficients c;
  c.a1 = lp[m] * g[m];
  c.a2 = lp[m + 1] * g[m + 1];
  c.b1 = lp[m + 2] * d(m);
  c.b2 = lp[m + 3] * d(m + 1);
  c.c1 = lp[m + 4] * (m * d(m + 2) - d(m + 1));
  c.c2 = lp[m + 5] * ((m + 1) * d(m + 3) - d(m + 2));
  return c;
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
    const Vec3 o = curvatures.segment<3>(3 * i);
    const double norm = o.norm();
    kin->frames[si] = q;
    kin->starts[si] = r;
    HelixSegment& segment = kin->segments[si];
    HelixSegmentOf(o, l, &segment);
    kin->first_sample[si] = static_cast<int>(si * points);
    // W^2 = Omega Omega^T - |Omega|^2 I and W^2 e3 (helix.h), once per segment.
    const double squared_norm = o.squaredNorm();
    const double w2x = o.z() * o.x(), w2y = o.z() * o.y(), w2z = -(o.x() * o.x()) - o.y() * o.y();
    for (size_t j = 0; j < points; ++j) {
      Sample& s = kin->samples[si * points + j];
      s.segment = i;
      s.u = rule.nodes[j] * l;
      s.weight = rule.weights[j] * l;
      s.functions = EvaluateHelixFunctions(norm * s.u);
      const double u = s.u, g1 = s.functions.g[1], g2 = s.functions.g[2], g3 = s.functions.g[3];
      // The partial chord h(u) = u e3 + u^2 G2 W e3 + u^3 G3 W^2 e3 (HelixChordFromFunctions).
      const double c2 = u * u * g2, c3 = u * u * u * g3;
      const Vec3 h(c2 * o.y() + c3 * w2x, c2 * -o.x() + c3 * w2y, u + c3 * w2z);
      s.partial_chord = h;
      s.y = r + q * h;
      // R(u) = I + u G1 W + u^2 G2 W^2 (helix.h, Rodrigues), entry by entry.
      const double b1 = u * g1;
      Mat3 rotation;
      rotation(0, 0) = 1.0 + c2 * (o.x() * o.x() - squared_norm);
      rotation(1, 1) = 1.0 + c2 * (o.y() * o.y() - squared_norm);
      rotation(2, 2) = 1.0 + c2 * (o.z() * o.z() - squared_norm);
      rotation(0, 1) = b1 * -o.z() + c2 * (o.x() * o.y());
      rotation(1, 0) = b1 * o.z() + c2 * (o.y() * o.x());
      rotation(0, 2) = b1 * o.y() + c2 * (o.x() * o.z());
      rotation(2, 0) = b1 * -o.y() + c2 * (o.z() * o.x());
      rotation(1, 2) = b1 * -o.x() + c2 * (o.y() * o.z());
      rotation(2, 1) = b1 * o.x() + c2 * (o.z() * o.y());
      s.frame = Mul(q, rotation);
    }
    r += q * segment.chord;
    q = Mul(q, segment.rotation);
  }
  kin->first_sample[static_cast<size_t>(n)] = static_cast<int>(static_cast<size_t>(n) * points);
  kin->jacobians = false;
  if (jacobians) AddJacobians(model, curvatures, kin);
}

void AddJacobians(const StrandModel& model, const VecX& curvatures, Kinematics* kin) {
  if (kin->jacobians) return;
  const int n = model.NumSegments();
  kin->twist.resize(static_cast<size_t>(n));
  kin->rotation_coefficients.resize(static_cast<size_t>(n));
  kin->chord_coefficients.resize(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    const size_t si = static_cast<size_t>(i);
    const double l = model.segment_lengths[si];
    const Vec3 o = curvatures.segment<3>(3 * i);
    const double norm = o.norm();
    const double squared_norm = o.squaredNorm();
    const Mat3& q = kin->frames[si];
    const HelixSegment& segment = kin->segments[si];
    // The coefficients of the second derivatives (helix_hessian.h): only the Newton matrix's
    // Jacobians and force curvature use them, so they are not part of ComputeKinematics.
    double g[9];
    helix_hessian::HelixFunctions8(l * norm, g);
    kin->rotation_coefficients[si] = CoefficientsOf<1>(l, g);
    kin->chord_coefficients[si] = CoefficientsOf<2>(l, g);
    // S_i: a change dOmega of segment i turns everything past its end by omega = Q_i A(l) dOmega
    // and moves its end by Q_i dp; a point y past it moves by omega x (y - r_(i+1)) + Q_i dp =
    // omega x y + v with v = Q_i dp + r_(i+1) x omega (strand_hessian.cpp, the same twist).
    // r_(i+1) is the segment's start (its first sample minus its partial chord) plus Q_i p.
    const Vec3 r_next = kin->starts[si] + q * segment.chord;
    const Mat3 top = Mul(q, RotationJacobian(o, squared_norm, l, segment.functions));
    const Mat3 bottom = Mul(q, ChordJacobian(o, kin->chord_coefficients[si]));
    const Mat3 turn = CrossColumns(r_next, top);
    Mat63& twist = kin->twist[si];
    twist.topRows<3>() = top;
    #pragma GCC unroll 3
    for (int c = 0; c < 3; ++c) {
      #pragma GCC unroll 3
      for (int rr = 0; rr < 3; ++rr) twist(3 + rr, c) = bottom(rr, c) + turn(rr, c);
    }
    for (int k = kin->first_sample[si]; k < kin->first_sample[si + 1]; ++k) {
      Sample& s = kin->samples[static_cast<size_t>(k)];
      double gu[9];
      helix_hessian::HelixFunctions8(norm * s.u, gu);
      s.chord = CoefficientsOf<2>(s.u, gu);
      s.angular = Mul(q, RotationJacobian(o, squared_norm, s.u, s.functions));
      s.linear = Mul(q, ChordJacobian(o, s.chord));  // dh(u)/dOmega
    }
  }
  kin->jacobians = true;
}

Mat3 SectionInertia(const StrandModel& model, const Sample& sample, bool rotational_inertia) {
  if (!rotational_inertia) return Mat3::Zero();
  return FrameInertia(sample.frame, model.material.density * sample.weight, model.section.I1(),
                      model.section.I2());
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
  const double i1 = model.section.I1(), i2 = model.section.I2();
  // Reverse sweep: I accumulates the spatial inertia sum_s P_s^T W_s P_s of the samples past the
  // current segment, P_s = [[I, 0], [-[y_s]x, I]] mapping a twist (omega, v) to the sample's
  // (angular, linear) velocity (omega, omega x y_s + v). With the sample's
  // P^T W P = [[Theta - a [y]x^2, a [y]x], [-a [y]x, a I]], I = [[J, [c]x], [-[c]x, m I]] with
  // J = sum (Theta - a [y]x^2), c = sum a y and m = sum a: those are all that is kept, and
  // I S = [J S_top + c x S_bottom; -c x S_top + m S_bottom] is formed without the zeros.
  Mat3 inertia_j = Mat3::Zero();
  Vec3 inertia_c = Vec3::Zero();
  double inertia_m = 0.0;
  for (int i = n - 1; i >= 0; --i) {
    const size_t si = static_cast<size_t>(i);
    const Mat63& twist = kin.twist[si];
    // load = I S, each sum in the order of the 6x6 by 6x3 product (left to right, zeros dropped).
    Mat63& load = metric->load[si];
    const double cx = inertia_c.x(), cy = inertia_c.y(), cz = inertia_c.z();
    #pragma GCC unroll 3
    for (int j = 0; j < 3; ++j) {
      const double t0 = twist(0, j), t1 = twist(1, j), t2 = twist(2, j);
      const double v0 = twist(3, j), v1 = twist(4, j), v2 = twist(5, j);
      load(0, j) = (((inertia_j(0, 0) * t0 + inertia_j(0, 1) * t1) + inertia_j(0, 2) * t2) +
                    -cz * v1) + cy * v2;
      load(1, j) = (((inertia_j(1, 0) * t0 + inertia_j(1, 1) * t1) + inertia_j(1, 2) * t2) +
                    cz * v0) + -cx * v2;
      load(2, j) = (((inertia_j(2, 0) * t0 + inertia_j(2, 1) * t1) + inertia_j(2, 2) * t2) +
                    -cy * v0) + cx * v1;
      load(3, j) = (cz * t1 + -cy * t2) + inertia_m * v0;
      load(4, j) = (-cz * t0 + cx * t2) + inertia_m * v1;
      load(5, j) = (cy * t0 + -cx * t1) + inertia_m * v2;
    }
    // S^T I S, the sums as Eigen's 3x6 by 6x3 product: (p0 + (p2 + p4)) + (p1 + (p3 + p5)).
    Mat3 diagonal;
    #pragma GCC unroll 3
    for (int j = 0; j < 3; ++j) {
      #pragma GCC unroll 3
      for (int r = 0; r < 3; ++r) {
        const double p0 = twist(0, r) * load(0, j), p1 = twist(1, r) * load(1, j);
        const double p2 = twist(2, r) * load(2, j), p3 = twist(3, r) * load(3, j);
        const double p4 = twist(4, r) * load(4, j), p5 = twist(5, r) * load(5, j);
        diagonal(r, j) = (p0 + (p2 + p4)) + (p1 + (p3 + p5));
      }
    }
    Mat3 own_j = Mat3::Zero();
    Vec3 own_c = Vec3::Zero();
    double own_m = 0.0;
    for (int k = kin.first_sample[si]; k < kin.first_sample[si + 1]; ++k) {
      const Sample& s = kin.samples[static_cast<size_t>(k)];
      const double a = mass_scale * line_density * s.weight + drag_scale * options.air_drag * s.weight;
      Mat3 theta = Mat3::Zero();
      if (options.rotational_inertia) {
        theta = FrameInertia(s.frame, model.material.density * s.weight, i1, i2);
        theta = mass_scale * theta;
      }
      const Vec3 ay = a * s.y;  // a [y]x = [a y]x
      own_j += theta - HatProduct(ay, s.y);
      own_c += ay;
      own_m += a;
      // P^T W K with K = [angular; linear]: [Theta K_a + a [y]x K_l; a K_l].
      const Mat3 theta_angular = Mul(theta, s.angular);
      const Mat3 y_linear = CrossColumns(ay, s.linear);
      const Mat3 a_linear = a * s.linear;
      #pragma GCC unroll 3
      for (int j = 0; j < 3; ++j) {
        #pragma GCC unroll 3
        for (int r = 0; r < 3; ++r) {
          load(r, j) += theta_angular(r, j) + y_linear(r, j);
          load(3 + r, j) += a_linear(r, j);
        }
      }
      // K^T W K.
      diagonal += Mul(TransposeMul(s.angular, theta), s.angular) + TransposeMul(a_linear, s.linear);
    }
    Mat3& symmetric = metric->diagonal[si];
    #pragma GCC unroll 3
    for (int j = 0; j < 3; ++j) {
      #pragma GCC unroll 3
      for (int r = 0; r < 3; ++r) symmetric(r, j) = 0.5 * (diagonal(r, j) + diagonal(j, r));
    }
    inertia_j += own_j;
    inertia_c += own_c;
    inertia_m += own_m;
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
    const Mat3 top = twist.topRows<3>(), bottom = twist.bottomRows<3>();
    Mat3 load_top = Mul(a_f, top) - CrossColumns(f_sum, bottom);
    const int first = kin.first_sample[sb], last = kin.first_sample[sb + 1];
    for (int k = first; k < last; ++k) {
      load_top -= CrossColumns(forces[static_cast<size_t>(k)],
                               kin.samples[static_cast<size_t>(k)].linear);
    }
    matrix->load[sb].topRows<3>() += load_top;
    // Diagonal: the Jacobian in Omega_b of segment b's step of the reverse sweep, adjoints fixed
    // (HelixSegmentVjp with dE/dR = Q_b^T q_bar, dE/dp = Q_b^T r_bar and HelixChordVjp of each
    // sample's force), in closed form as in the statics' exact Hessian (helix_hessian.h).
    helix_hessian::OwnHessianSum own(omega);
    own.AddMatrix(kin.rotation_coefficients[sb], Mul(qt, q_bar));
    own.AddChord(kin.chord_coefficients[sb], qt * r_bar);
    for (int k = first; k < last; ++k) {
      own.AddChord(kin.samples[static_cast<size_t>(k)].chord, qt * forces[static_cast<size_t>(k)]);
    }
    const Mat3 diagonal = own.Hessian();
    matrix->diagonal[sb] += 0.5 * (diagonal + diagonal.transpose());
    // Advance the sums and adjoints past segment b's start.
    const HelixSegment& segment = kin.segments[sb];
    Mat3 q_bar_b = Mul(q_bar, segment.rotation.transpose()) + r_bar * segment.chord.transpose();
    for (int k = first; k < last; ++k) {
      const Sample& s = kin.samples[static_cast<size_t>(k)];
      const Vec3& f = forces[static_cast<size_t>(k)];
      q_bar_b += f * s.partial_chord.transpose();
      r_bar += f;
      f_sum += f;
      a_f += HatProduct(f, s.y);
    }
    q_bar = q_bar_b;
  }
}

}  // namespace ringlet::dynamics
