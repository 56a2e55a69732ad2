// Kinematics of a strand for its dynamics (docs/dynamics.md): the twists S_i, the mass samples
// with their own-segment Jacobians, the semiseparable assembly of sum_s J_s^T W_s J_s and the
// reverse sweep that applies J^T to forces and moments at the samples. Internal to the library;
// tests include it to check the pieces one by one.
#pragma once

#include <vector>

#include "ringlet/dynamics.h"
#include "ringlet/helix.h"
#include "ringlet/math.h"
#include "ringlet/strand_hessian.h"
#include "ringlet/strand_model.h"
#include "rod/helix_hessian.h"

namespace ringlet::dynamics {

/// Gauss-Legendre rule on [0, 1] with `points` nodes (1..8): nodes and weights summing to 1.
struct GaussRule {
  std::vector<double> nodes;
  std::vector<double> weights;
};
GaussRule GaussLegendre01(int points);

/// One mass sample: a Gauss point of a segment.
struct Sample {
  // Not value-initialized: ComputeKinematics writes every field (the Jacobians with jacobians), so
  // a vector of samples is not zeroed when it grows.
  Sample() {}
  int segment = 0;
  double u = 0.0;       ///< arc length inside the segment (m)
  double weight = 0.0;  ///< quadrature weight w (m): l_i times the rule's weight
  Vec3 y;               ///< position relative to the root, r(s) - r(0) (m)
  Vec3 partial_chord;   ///< h(u), the chord from the segment's start in its start frame (m)
  Mat3 frame;           ///< material frame Q(s) = Q_i R(u)
  Mat3 angular;         ///< d omega / d Omega_i of the sample's frame (world, m); with jacobians
  Mat3 linear;          ///< d y / d Omega_i (world, m^2); with jacobians
  HelixFunctions functions;  ///< G_m(u |Omega_i|)
  /// The partial chord's coefficients (A_2 over length u, helix_hessian.h): its Jacobian and
  /// second derivatives in Omega_i; with jacobians.
  helix_hessian::Coefficients chord;
};

/// Everything the dynamics needs at one configuration, in one forward sweep (O(n)).
struct Kinematics {
  std::vector<Mat63> twist;         ///< S_i, full (rows 0-2 rotation, 3-5 root-point velocity)
  std::vector<Mat3> frames;         ///< Q_i at segment starts
  std::vector<Vec3> starts;         ///< r_i - r(0) at segment starts (m)
  /// The segments' closed forms (HelixSegment, not value-initialized either: all written).
  struct Segment : HelixSegment {
    Segment() {}
  };
  std::vector<Segment> segments;
  std::vector<Sample> samples;      ///< segment by segment, root to tip
  std::vector<int> first_sample;    ///< index of segment i's first sample; size n + 1
  /// Coefficients of A_1 (rotation) and A_2 (chord) of each whole segment (helix_hessian.h);
  /// with jacobians.
  std::vector<helix_hessian::Coefficients> rotation_coefficients, chord_coefficients;
  bool jacobians = false;           ///< twist and the samples' angular, linear are filled
};
/// Positions, frames and helix functions of the segments and samples; with `jacobians` also the
/// twists S_i and the samples' own Jacobians (angular, linear), which the Newton matrix needs and
/// the energy and its gradient do not.
void ComputeKinematics(const StrandModel& model, const VecX& curvatures, const GaussRule& rule,
                       Kinematics* kinematics, bool jacobians = true);
/// Fills the twists, the samples' Jacobians and the coefficients (segments' and samples') of
/// kinematics computed without them (no-op when present).
void AddJacobians(const StrandModel& model, const VecX& curvatures, Kinematics* kinematics);

/// Per-sample inertia of the section: Theta = rho w Q diag(I1, I2, I1 + I2) Q^T (kg m^2), or
/// zero when the options drop the rotational inertia.
Mat3 SectionInertia(const StrandModel& model, const Sample& sample, bool rotational_inertia);

/// sum_s J_s^T diag(rotational_scale Theta_s, (mass_scale m_s + drag_scale nu w_s) I) J_s in the
/// block-semiseparable form of strand_hessian.h (twists S_i, translational = true).
void AssembleMetric(const StrandModel& model, const DynamicsOptions& options,
                    const Kinematics& kinematics, double mass_scale, double drag_scale,
                    StrandHessian* metric);

/// Sample velocities (angular omega_s, linear v_s) for curvature rates qdot, O(n).
void SampleVelocities(const Kinematics& kinematics, const VecX& rates, std::vector<Vec3>* angular,
                      std::vector<Vec3>* linear);

/// J^T of forces F_s (N, dPhi/dy_s) and frame adjoints G_s (dPhi/dQ_s, 3x3) at the samples:
/// dPhi/dq (size 3n), by one reverse sweep of the samples' wrenches about the root through the
/// twists and the samples' own Jacobians (O(n)). Needs kinematics with jacobians.
void ApplyJacobianTranspose(const StrandModel& model, const VecX& curvatures,
                            const Kinematics& kinematics, const std::vector<Vec3>& forces,
                            const std::vector<Mat3>& frame_adjoints, VecX* gradient);

/// Adds to `matrix` (block-semiseparable with the twists of kinematics) the curvature term of
/// point forces held fixed, d^2/dq^2 sum_s F_s . y_s(q): the part of the exact Hessian of
/// sum_s 1/2 m_s |y_s - y~_s|^2 / a that the Gauss-Newton metric leaves out (docs/dynamics.md,
/// "Newton matrix"). Off-diagonal blocks in closed form (H_ab = S_a^T B_b, a < b, with
/// d^2 y_s / dq_a dq_b = omega_a x dy_s/dq_b), diagonal blocks in closed form: the Jacobian of
/// the segment's own reverse-sweep step, adjoints fixed (helix_hessian.h, OwnHessianSum, as the
/// statics' exact Hessian), O(n) in all. Needs kinematics with jacobians.
void AddForceCurvature(const StrandModel& model, const VecX& curvatures,
                       const Kinematics& kinematics, const std::vector<Vec3>& forces,
                       StrandHessian* matrix);

}  // namespace ringlet::dynamics
