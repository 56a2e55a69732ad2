// Dynamics of one strand in its curvature coordinates (Super-Helices, Bertails et al. 2006; the
// linear-time form of Bertails 2009): mass matrix, implicit time steps, modal analysis.
// docs/dynamics.md derives every formula cited here.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "ringlet/energy.h"
#include "ringlet/math.h"
#include "ringlet/obstacle.h"
#include "ringlet/strand_hessian.h"
#include "ringlet/strand_model.h"

namespace ringlet {

/// Internal friction gamma of hair (N m^2 s = kg m^3/s): the viscous moment -gamma dOmega/dt per
/// unit length (docs/dynamics.md, "Dissipation"). Super-Helices (Bertails et al. 2006, table 1)
/// use gamma in [5e-11, 5e-10]; this is the geometric middle of that range.
inline constexpr double kHairInternalFriction = 1.6e-10;
/// Air drag nu of hair (N s/m^2 = kg/(m s)): the force -nu dr/dt per unit length of a strand
/// moving through still air. Super-Helices (table 1) use nu in [5e-6, 5e-5]; geometric middle.
inline constexpr double kHairAirDrag = 1.6e-5;

/// The implicit scheme of StrandDynamics (docs/dynamics.md, "Time step").
enum class Integrator {
  /// Backward Euler: first order, L-stable, energy-decreasing; its numerical damping takes a
  /// fraction ~(omega h)^2 of a mode's energy per step (strong at h = 1/24 s).
  kBackwardEuler,
  /// BDF2: second order, L-stable, numerical damping ~(omega h)^4 per step; the first step and
  /// the one after a halving are backward Euler (it needs the previous step of the same length).
  kBdf2,
};

/// Options of the dynamics: dissipation, quadrature of the kinetic energy and the implicit step.
struct DynamicsOptions {
  /// Time step h (s): one film frame by default.
  double time_step = 1.0 / 24.0;
  /// The implicit scheme.
  Integrator integrator = Integrator::kBackwardEuler;
  /// Internal friction gamma >= 0 (N m^2 s); 0 = none (docs/dynamics.md, "Dissipation").
  double internal_friction = kHairInternalFriction;
  /// Air drag nu >= 0 (N s/m^2); 0 = none.
  double air_drag = kHairAirDrag;
  /// Whether the kinetic energy keeps the rotational inertia of the section,
  /// 1/2 rho omega^T Q diag(I1, I2, I1 + I2) Q^T omega per unit length. Without it the mass
  /// matrix of a straight strand is singular in the twist (twisting a straight line moves none
  /// of its points); with it the twist waves are fast (c = sqrt(mu J / (rho (I1 + I2))) ~ 1.7
  /// km/s for hair) and the implicit step damps them.
  bool rotational_inertia = true;
  /// Gauss-Legendre points per segment in the kinetic energy (1..8); each is a mass sample.
  int mass_points = 6;
  /// Newton iterations allowed for one (sub)step before it is halved.
  int max_newton_iterations = 25;
  /// Inexact steps: 0 (default) solves the implicit scheme, Newton until an update is below
  /// `tolerance`. eta in (0, 1): a unit-length update also ends the step when the decrease of
  /// Phi it achieved is the decrease of Phi's quadratic model within the fraction eta,
  /// |dPhi / dPhi_model - 1| <= eta. The first Newton update from the starting point is then
  /// often the last: the linearly implicit form of the scheme (one Newton iteration on the
  /// exact Hessian, Baraff & Witkin 1998; Hairer & Wanner, Solving ODEs II, IV.7), with more
  /// updates exactly where the step is nonlinear (large rotations in one step). First order
  /// like backward Euler; the same stability function on linear problems (docs/dynamics.md,
  /// "Inexact steps").
  double model_tolerance = 0.0;
  /// Convergence: a Newton update with sum_i l_i |dOmega_i| below this (rad) ends the step.
  double tolerance = 1e-11;
  /// How many times a step may be halved (2^max_halvings sub-steps at most).
  int max_halvings = 10;

  /// True when every field is in range; otherwise says which and why.
  bool IsValid(std::string* why) const;
};

/// The state of a strand: curvatures and their rates.
struct StrandState {
  VecX curvatures;  ///< q, size 3n (1/m), as in StrandSolution::curvatures
  VecX rates;       ///< dq/dt, size 3n (1/(m s))
  double time = 0.0;  ///< t (s)
};

/// What one call of StrandDynamics::Step did. A step that needed halving says so; a step that
/// failed even after max_halvings halvings leaves the state unchanged and says why.
struct StepReport {
  bool converged = false;
  std::string message;         ///< empty when converged without halving
  double time = 0.0;           ///< time after the step (s)
  int substeps = 0;            ///< implicit sub-steps taken (1 without halving)
  int halvings = 0;            ///< deepest halving used (0 = the full step)
  int newton_iterations = 0;   ///< over all sub-steps, failed tries included
  /// Newton matrices built and factored over all sub-steps (at most newton_iterations: a chord
  /// iteration reuses the last factor, docs/dynamics.md "Time step").
  int factorizations = 0;
  /// The size of the last Newton update of the last sub-step, sum_i l_i |dOmega_i| (rad): below
  /// options.tolerance when converged (0 when the step failed).
  double residual = 0.0;
  EnergyTerms potential;       ///< potential energy terms after the step (J)
  double kinetic = 0.0;        ///< kinetic energy after the step (J)
};

/// The block-semiseparable mass matrix M(q) of the kinetic energy T = 1/2 qdot^T M qdot
/// (J s^2 per (1/m)^2: kg m^4), in the form of StrandHessian (strand_hessian.h):
///   M_ab = S_a^T L_b (a < b),  M_aa = diagonal_a,  L_b = I_b S_b + P_b,
/// with S_a the twists (full 6x3, translation rows included), I_b the 6x6 spatial inertia of the
/// strand past segment b and P_b the coupling of segment b's own deformation (docs/dynamics.md,
/// "Mass matrix"). StrandHessianFactor factors it in O(n); Dense() gives the matrix.
StrandHessian ComputeMassMatrix(const StrandModel& model, const VecX& curvatures,
                                const DynamicsOptions& options = {});

/// Kinetic energy 1/2 qdot^T M(q) qdot (J) of a state with the root at rest, in O(n).
double KineticEnergy(const StrandModel& model, const StrandState& state,
                     const DynamicsOptions& options = {});

/// Small oscillations about a configuration: the generalized eigenproblem H v = omega^2 M v
/// with H the exact Hessian of the potential energy and M the mass matrix, dense (O(n^3); up to
/// kMaxModalSegments segments).
struct Modes {
  VecX omega_squared;  ///< omega^2 (1/s^2), ascending; negative at an unstable configuration
  MatX shapes;         ///< columns: the modes v (M-orthonormal), size 3n x count
};
inline constexpr int kMaxModalSegments = 2000;
/// The `count` lowest modes (all 3n when count <= 0). Throws std::invalid_argument for a model
/// with more than kMaxModalSegments segments or curvatures of the wrong size.
Modes ComputeModes(const StrandModel& model, const VecX& curvatures, int count = 0,
                   const DynamicsOptions& options = {});

/// A prescribed rigid motion of the root (the head moving): where the clamp is at time t. Both
/// functions must be smooth in t; the initial velocity of the clamp is taken from them by central
/// differences over 1e-6 s.
struct ClampMotion {
  std::function<Vec3(double)> position;  ///< r(0) at time t (m, world)
  std::function<Mat3(double)> frame;     ///< root frame (n1, n2, t) at time t, a proper rotation
  /// Whether the model's obstacle (contact.obstacle: the head) moves rigidly with the clamp: at
  /// time t it is the obstacle of the model given to StrandDynamics carried by the rigid motion
  /// that takes that model's root (root_position, root_frame) to (position(t), frame(t)),
  ///   x -> position(t) + frame(t) frame0^T (x - position0).
  /// False: the obstacle stays where it is (a strand brushing past a fixed body).
  bool carries_obstacle = false;
  /// With carries_obstacle, when set: the obstacle at time t is move_obstacle(R, c) for the rigid
  /// motion x -> R x + c above (R = frame(t) frame0^T, c = position(t) - R position0) instead of
  /// the model's obstacle carried by it. HeadMotion::Clamp sets it for a body whose torso does
  /// not turn with the head (SplitBody::Place). Called from the threads that step the strands.
  std::function<std::shared_ptr<const Obstacle>(const Mat3& rotation, const Vec3& translation)>
      move_obstacle = nullptr;
};

/// Time integration of one strand by an implicit scheme (Integrator) in the form of an
/// incremental potential (docs/dynamics.md, "Time step"). For backward Euler q1 minimizes
///   Phi(q) = sum_s [ m_s/(2h^2) |y_s(q) - y_s0 - h v_s0|^2 + nu w_s/(2h) |y_s(q) - y_s0|^2
///                    + rotational inertia of the section, same form ]
///            + E(q) + gamma/(2h) sum_i l_i |Omega_i - Omega_i0|^2,
/// over the mass samples s (position y_s, velocity v_s, weight w_s, mass m_s = rho S w_s), with E
/// the potential energy of the statics (elastic, gravity, contact penalty); BDF2 has the same form
/// with other coefficients and predictions. Stationarity of Phi is the scheme applied to
/// Lagrange's equations, Coriolis and centrifugal terms included. Newton on the exact Hessian of E
/// plus the Gauss-Newton Hessian of the inertia (the mass matrix over h^2), factored in O(n)
/// (StrandHessianFactor), with a backtracking line search on Phi; then the rates follow from the
/// scheme (backward Euler: qdot1 = (q1 - q0)/h). The positions y_s are world positions, so a
/// moving clamp (SetClampMotion) brings its inertial terms along. Deterministic.
class StrandDynamics {
 public:
  /// Throws std::invalid_argument on an invalid model, options or state (sizes, non-finite).
  StrandDynamics(const StrandModel& model, const DynamicsOptions& options,
                 const StrandState& initial);

  /// Moves the root with `clamp` from now on (before the first step only; throws
  /// std::logic_error after it, std::invalid_argument when a function is empty). The inertial
  /// terms of the moving frame need no extra code: the time step's inertia is written in world
  /// positions (docs/dynamics.md, "Moving clamp"). The state's rates stay relative to the clamp.
  void SetClampMotion(ClampMotion clamp);

  /// Advances by options.time_step (halving on non-convergence, reported).
  StepReport Step();
  /// Advances by h (s) > 0.
  StepReport Step(double h);

  const StrandState& state() const { return state_; }
  const StrandModel& model() const { return model_; }
  const DynamicsOptions& options() const { return options_; }
  /// Kinetic energy of the current state (J), from the scheme's sample velocities (differences of
  /// sample positions and directors, world frame: a moving clamp's motion included); at the
  /// initial state with the root at rest, KineticEnergy(model, state).
  double Kinetic() const;
  /// Potential energy terms of the current state (J), with the root where the clamp is now.
  EnergyTerms Potential() const;

  /// The mass samples' motion: world positions y_s (m), directors (n1, n2, 0) and their
  /// velocities (m/s, 1/s). Internal to the time step; public for its implementation.
  struct SampleMotion {
    std::vector<Vec3> positions, velocities;
    std::vector<Mat3> directors, director_velocities;
  };

 private:
  bool TryStep(double h, int* iterations, int* factorizations, std::string* why);
  // Puts the root (and with carries_obstacle the obstacle) of *model where the clamp is at t.
  bool PlaceClamp(double t, StrandModel* model) const;
  struct Scratch;
  // Takes the step to `curvatures` with the model at its end (scratch.stepped).
  void Accept(const Scratch& scratch, const VecX& curvatures, double h, bool bdf2);

  StrandModel model_;
  DynamicsOptions options_;
  StrandState state_;
  StrandState previous_;     // the state one step back (BDF2)
  double previous_h_ = 0.0;  // the length of that step (s)
  bool has_history_ = false;
  SampleMotion motion_;           // of state_
  SampleMotion previous_motion_;  // of previous_
  ClampMotion clamp_;             // empty: the root stays where model_ puts it
  // The root and obstacle of the model as given (ClampMotion::carries_obstacle's reference).
  Vec3 reference_root_ = Vec3::Zero();
  Mat3 reference_frame_ = Mat3::Identity();
  std::shared_ptr<const Obstacle> reference_obstacle_;
  double last_update_ = 0.0;  // the last Newton update of TryStep (rad)

  // Buffers of the time step (the incremental potential, its kinematics, the Newton matrix and
  // its factor): one set per thread, reused by every strand stepped on that thread, so that a
  // step allocates nothing once warm and the buffers stay in cache however many strands there
  // are (dynamics.cpp). They hold nothing from one step to the next.
  Scratch& BindScratch() const;
};

}  // namespace ringlet
