// Strand dynamics: mass matrix, backward Euler as an incremental potential, modal analysis
// (dynamics.h; docs/dynamics.md).
#include "ringlet/dynamics.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <utility>
#include <stdexcept>

#include "dynamics/kinematics.h"
#include "ringlet/strand_hessian.h"

namespace ringlet {

using dynamics::ComputeKinematics;
using dynamics::GaussLegendre01;
using dynamics::GaussRule;
using dynamics::Kinematics;

bool DynamicsOptions::IsValid(std::string* why) const {
  auto fail = [&](const std::string& message) {
    if (why) *why = message;
    return false;
  };
  if (!(std::isfinite(time_step) && time_step > 0.0)) {
    return fail("dynamics time_step must be a finite number > 0 (s)");
  }
  if (!(std::isfinite(internal_friction) && internal_friction >= 0.0)) {
    return fail("dynamics internal_friction must be a finite number >= 0 (N m^2 s)");
  }
  if (!(std::isfinite(air_drag) && air_drag >= 0.0)) {
    return fail("dynamics air_drag must be a finite number >= 0 (N s/m^2)");
  }
  if (mass_points < 1 || mass_points > 8) return fail("dynamics mass_points must be in 1..8");
  if (max_newton_iterations < 1) return fail("dynamics max_newton_iterations must be >= 1");
  if (!(std::isfinite(model_tolerance) && model_tolerance >= 0.0 && model_tolerance < 1.0)) {
    return fail("dynamics model_tolerance must be a number in [0, 1) (0 = Newton to the "
                "tolerance)");
  }
  if (!(std::isfinite(tolerance) && tolerance > 0.0)) {
    return fail("dynamics tolerance must be a finite number > 0 (rad)");
  }
  if (max_halvings < 0 || max_halvings > 30) return fail("dynamics max_halvings must be in 0..30");
  if (integrator != Integrator::kBackwardEuler && integrator != Integrator::kBdf2) {
    return fail("dynamics integrator must be backward_euler or bdf2");
  }
  return true;
}

namespace {

// An obstacle carried by a rigid motion x -> translation + rotation x (ClampMotion::
// carries_obstacle): d'(x) = d(R^T (x - t)), grad d' = R grad d, Hess d' = R Hess d R^T.
class MovedObstacle final : public Obstacle {
 public:
  MovedObstacle(std::shared_ptr<const Obstacle> base, const Mat3& rotation, const Vec3& translation)
      : base_(std::move(base)), rotation_(rotation), translation_(translation) {}
  double SignedDistance(const Vec3& x, Vec3* gradient) const override {
    Vec3 g;
    const double d = base_->SignedDistance(rotation_.transpose() * (x - translation_),
                                           gradient ? &g : nullptr);
    if (gradient) *gradient = rotation_ * g;
    return d;
  }
  double SignedDistanceHessian(const Vec3& x, Vec3* gradient, Mat3* hessian) const override {
    Vec3 g;
    Mat3 h;
    const double d = base_->SignedDistanceHessian(rotation_.transpose() * (x - translation_),
                                                  gradient ? &g : nullptr,
                                                  hessian ? &h : nullptr);
    if (gradient) *gradient = rotation_ * g;
    if (hessian) *hessian = rotation_ * h * rotation_.transpose();
    return d;
  }
  // A rigid motion keeps distances: the carried body's Lipschitz bound is the body's (the
  // statics' contact broad phase culls with it, contact_broad_phase.h).
  double LipschitzBound() const override { return base_->LipschitzBound(); }

 private:
  std::shared_ptr<const Obstacle> base_;
  Mat3 rotation_;
  Vec3 translation_;
};

void CheckInputs(const StrandModel& model, const DynamicsOptions& options, const VecX& curvatures,
                 const VecX* rates) {
  std::string why;
  if (!IsValid(model, &why)) throw std::invalid_argument(why);
  if (!options.IsValid(&why)) throw std::invalid_argument(why);
  const Eigen::Index size = 3 * model.NumSegments();
  if (curvatures.size() != size || !curvatures.allFinite()) {
    throw std::invalid_argument("curvatures must be " + std::to_string(size) +
                                " finite numbers (3 per segment)");
  }
  if (rates && (rates->size() != size || !rates->allFinite())) {
    throw std::invalid_argument("rates must be " + std::to_string(size) +
                                " finite numbers (3 per segment)");
  }
}

// Sum of two block-semiseparable matrices: `metric` (full twists) plus the Hessian of E (whose
// loads have zero bottom rows when its twists do, strand_hessian.h) plus diag(extra_i I).
void AddHessian(const StrandHessian& hessian, const std::vector<double>& extra,
                StrandHessian* metric) {
  for (size_t i = 0; i < metric->diagonal.size(); ++i) {
    metric->diagonal[i] += hessian.diagonal[i];
    metric->diagonal[i].diagonal().array() += extra[i];
    metric->load[i] += hessian.load[i];
  }
}

}  // namespace

StrandHessian ComputeMassMatrix(const StrandModel& model, const VecX& curvatures,
                                const DynamicsOptions& options) {
  CheckInputs(model, options, curvatures, nullptr);
  Kinematics kin;
  ComputeKinematics(model, curvatures, GaussLegendre01(options.mass_points), &kin);
  StrandHessian mass;
  dynamics::AssembleMetric(model, options, kin, 1.0, 0.0, &mass);
  return mass;
}

double KineticEnergy(const StrandModel& model, const StrandState& state,
                     const DynamicsOptions& options) {
  CheckInputs(model, options, state.curvatures, &state.rates);
  Kinematics kin;
  ComputeKinematics(model, state.curvatures, GaussLegendre01(options.mass_points), &kin);
  std::vector<Vec3> angular, linear;
  dynamics::SampleVelocities(kin, state.rates, &angular, &linear);
  const double line_density = model.material.density * model.section.Area();
  double kinetic = 0.0;
  for (size_t k = 0; k < kin.samples.size(); ++k) {
    const dynamics::Sample& s = kin.samples[k];
    const Mat3 theta = dynamics::SectionInertia(model, s, options.rotational_inertia);
    kinetic += 0.5 * (line_density * s.weight * linear[k].squaredNorm() +
                      angular[k].dot(theta * angular[k]));
  }
  return kinetic;
}

Modes ComputeModes(const StrandModel& model, const VecX& curvatures, int count,
                   const DynamicsOptions& options) {
  CheckInputs(model, options, curvatures, nullptr);
  const int n = model.NumSegments();
  if (n > kMaxModalSegments) {
    throw std::invalid_argument("modal analysis is dense: at most " +
                                std::to_string(kMaxModalSegments) + " segments, not " +
                                std::to_string(n));
  }
  StrandHessian hessian;
  ComputeStrandHessian(model, curvatures, &hessian);
  MatX h = hessian.Dense();
  h = (0.5 * (h + h.transpose())).eval();
  MatX m = ComputeMassMatrix(model, curvatures, options).Dense();
  m = (0.5 * (m + m.transpose())).eval();
  // Solved as M v = mu (H + sigma M) v, mu = 1 / (omega^2 + sigma): the wanted low modes are
  // then the largest mu, accurate relative to themselves. Directly (H v = omega^2 M v) their
  // rounding would be relative to the largest omega^2, the twist waves of the section (omega^2 ~
  // (n pi / L)^2 mu / rho ~ 1e12 / s^2 at 40 segments of 10 cm), 1e-4 / s^2 and more. sigma = 0
  // when H is positive definite; otherwise twice the most negative omega^2 of the direct
  // problem plus 1e-6 of its largest, which makes H + sigma M positive definite.
  double sigma = 0.0;
  if (Eigen::LLT<MatX>(h).info() != Eigen::Success) {
    Eigen::GeneralizedSelfAdjointEigenSolver<MatX> direct(h, m, Eigen::EigenvaluesOnly);
    if (direct.info() != Eigen::Success) {
      throw std::runtime_error("modal analysis: the generalized eigensolver failed");
    }
    const VecX& values = direct.eigenvalues();
    sigma = 2.0 * std::max(0.0, -values(0)) + 1e-6 * std::abs(values(values.size() - 1));
  }
  const MatX shifted = h + sigma * m;
  Eigen::GeneralizedSelfAdjointEigenSolver<MatX> solver(m, shifted);
  if (solver.info() != Eigen::Success) {
    throw std::runtime_error("modal analysis: the generalized eigensolver failed");
  }
  const int size = 3 * n;
  const int k = count <= 0 ? size : std::min(count, size);
  Modes modes;
  modes.omega_squared.resize(k);
  modes.shapes.resize(size, k);
  for (int j = 0; j < k; ++j) {
    // Largest mu first; v^T (H + sigma M) v = 1 gives v^T M v = mu.
    const int index = size - 1 - j;
    const double mu = solver.eigenvalues()(index);
    modes.omega_squared(j) = 1.0 / mu - sigma;
    modes.shapes.col(j) = solver.eigenvectors().col(index) / std::sqrt(mu);
  }
  return modes;
}

// World positions and directors (n1, n2; third column zero) of the mass samples at a
// configuration, with the root where the model puts it.
void SamplePlaces(const StrandModel& model, const VecX& curvatures, const GaussRule& rule,
                  StrandDynamics::SampleMotion* motion) {
  Kinematics kin;
  ComputeKinematics(model, curvatures, rule, &kin, /*jacobians=*/false);
  motion->positions.resize(kin.samples.size());
  motion->directors.resize(kin.samples.size());
  for (size_t k = 0; k < kin.samples.size(); ++k) {
    motion->positions[k] = model.root_position + kin.samples[k].y;  // world
    motion->directors[k] = kin.samples[k].frame;
    motion->directors[k].col(2).setZero();
  }
}

// The motion of a state from its rates: velocities J qdot, director velocities omega x n, plus
// the clamp's rigid motion when it moves (velocity v0 and angular velocity w0 by central
// differences of its functions: y' += v0 + w0 x (y - r(0)), n' += w0 x n).
StrandDynamics::SampleMotion MotionFromRates(const StrandModel& model, const StrandState& state,
                                             const GaussRule& rule, const ClampMotion* clamp) {
  Kinematics kin;
  ComputeKinematics(model, state.curvatures, rule, &kin);
  std::vector<Vec3> angular;
  StrandDynamics::SampleMotion motion;
  dynamics::SampleVelocities(kin, state.rates, &angular, &motion.velocities);
  SamplePlaces(model, state.curvatures, rule, &motion);
  Vec3 v0 = Vec3::Zero(), w0 = Vec3::Zero();
  if (clamp) {
    const double dt = 1e-6;
    v0 = (clamp->position(state.time + dt) - clamp->position(state.time - dt)) / (2.0 * dt);
    const Mat3 dq = (clamp->frame(state.time + dt) - clamp->frame(state.time - dt)) / (2.0 * dt);
    w0 = 0.5 * Vee(dq * clamp->frame(state.time).transpose());
  }
  motion.director_velocities.resize(kin.samples.size());
  for (size_t k = 0; k < kin.samples.size(); ++k) {
    motion.velocities[k] += v0 + w0.cross(kin.samples[k].y);
    Mat3& dv = motion.director_velocities[k];
    dv.setZero();
    for (int d = 0; d < 2; ++d) dv.col(d) = (angular[k] + w0).cross(motion.directors[k].col(d));
  }
  return motion;
}

// The incremental potential of one implicit step (dynamics.h, docs/dynamics.md "Time step"): its
// value, gradient and Newton matrix at a configuration. Both schemes have the form
//   Phi(q) = sum_s [ m_s/(2a) |y_s - y~_s|^2 + c nu w_s/2 |y_s - y^_s|^2 ] + E(q)
//            + c gamma/2 sum_i l_i |Omega_i - Omega^_i|^2  (+ the section's rotational inertia),
// backward Euler: a = h^2, c = 1/h, y^ = y_n, y~ = y_n + h v_n;
// BDF2: a = 4h^2/9, c = 3/(2h), y^ = (4 y_n - y_(n-1))/3, y~ = y^ + (2h/3)(4 v_n - v_(n-1))/3,
// so that stationarity is M a_(n+1) = F(q_(n+1)) - dissipation(v_(n+1)) with each scheme's
// acceleration and velocity (Hairer & Wanner, Solving ODEs II, section V.1: BDF2 is
// x_(n+1) - 4/3 x_n + 1/3 x_(n-1) = 2h/3 x'_(n+1)).
class IncrementalPotential {
 public:
  // Bound to the model at the end of the step (its root and obstacle are updated between steps;
  // the segment count never changes), the options and the mass samples' rule.
  IncrementalPotential(const StrandModel& model, const DynamicsOptions& options,
                       const GaussRule& rule)
      : model_(model), options_(options), rule_(rule), energy_(model) {}

  // Sets up the step of length h from `start` (sample motion `now`; BDF2 with `previous` and
  // `before` when given). The buffers are kept from step to step.
  void Begin(const StrandState& start, const StrandDynamics::SampleMotion& now,
             const StrandState* previous, const StrandDynamics::SampleMotion* before, double h) {
    root_ = model_.root_position;
    evaluated_ = false;
    const bool bdf2 = previous != nullptr;
    a_ = bdf2 ? 4.0 * h * h / 9.0 : h * h;
    c_ = bdf2 ? 1.5 / h : 1.0 / h;
    const size_t count = now.positions.size();
    anchor_positions_.resize(count);
    predicted_positions_.resize(count);
    predicted_directors_.resize(count);
    for (size_t k = 0; k < count; ++k) {
      if (!bdf2) {
        anchor_positions_[k] = now.positions[k];
        predicted_positions_[k] = now.positions[k] + h * now.velocities[k];
        predicted_directors_[k] = now.directors[k] + h * now.director_velocities[k];
        continue;
      }
      anchor_positions_[k] = (4.0 * now.positions[k] - before->positions[k]) / 3.0;
      predicted_positions_[k] =
          anchor_positions_[k] +
          (2.0 * h / 3.0) * (4.0 * now.velocities[k] - before->velocities[k]) / 3.0;
      predicted_directors_[k] =
          (4.0 * now.directors[k] - before->directors[k]) / 3.0 +
          (2.0 * h / 3.0) * (4.0 * now.director_velocities[k] - before->director_velocities[k]) / 3.0;
    }
    if (bdf2) {
      anchor_curvatures_ = (4.0 * start.curvatures - previous->curvatures) / 3.0;
    } else {
      anchor_curvatures_ = start.curvatures;
    }
    extra_.resize(static_cast<size_t>(model_.NumSegments()));
    for (int i = 0; i < model_.NumSegments(); ++i) {
      extra_[static_cast<size_t>(i)] =
          c_ * options_.internal_friction * model_.segment_lengths[static_cast<size_t>(i)];
    }
  }

  // The potential energy terms at q (J), with the model's root and obstacle.
  EnergyTerms Potential(const VecX& q) {
    EnergyTerms terms;
    energy_.Evaluate(q, nullptr, &terms);
    return terms;
  }

  // Whether the last Evaluate since Begin was at exactly q: its kinematics and energy terms are
  // then those of q with the model at the end of the step (the same operations on the same
  // numbers, so the same bits as computing them again).
  bool EvaluatedAt(const VecX& q) const {
    return evaluated_ && evaluated_q_.size() == q.size() && evaluated_q_ == q;
  }
  // The potential energy terms of the last Evaluate (EvaluatedAt).
  const EnergyTerms& LastTerms() const { return terms_; }
  // World positions and directors (n1, n2; third column zero) of the mass samples of the last
  // Evaluate (EvaluatedAt): SamplePlaces without computing the kinematics again.
  void LastPlaces(StrandDynamics::SampleMotion* motion) const {
    const size_t count = kin_.samples.size();
    motion->positions.resize(count);
    motion->directors.resize(count);
    for (size_t k = 0; k < count; ++k) {
      motion->positions[k] = model_.root_position + kin_.samples[k].y;
      motion->directors[k] = kin_.samples[k].frame;
      motion->directors[k].col(2).setZero();
    }
  }

  // Phi(q) and, when gradient is not null, dPhi/dq; kinematics at q are kept for the Newton
  // matrix. With `matrix` (and gradient) also the Newton matrix at q (NewtonMatrix), E's value,
  // gradient and Hessian then from one sweep (ComputeStrandEnergyAndHessian: one helix closed
  // form and one body query per sample instead of two of each).
  double Evaluate(const VecX& q, VecX* gradient, StrandHessian* matrix = nullptr) {
    // The gradient goes through the twists and the samples' own Jacobians (kinematics.h), which
    // the Newton matrix at this q then reuses; the value alone needs positions and frames only.
    ComputeKinematics(model_, q, rule_, &kin_, /*jacobians=*/gradient != nullptr);
    const double line_density = model_.material.density * model_.section.Area();
    const double inv_a = 1.0 / a_;
    const size_t count = kin_.samples.size();
    forces_.resize(count);
    adjoints_.resize(count);
    double inertia = 0.0;
    const double i1 = model_.section.I1(), i2 = model_.section.I2();
    for (size_t k = 0; k < count; ++k) {
      const dynamics::Sample& s = kin_.samples[k];
      const double mass = line_density * s.weight;
      const Vec3 miss = root_ + s.y - predicted_positions_[k];  // world positions
      const Vec3 moved = root_ + s.y - anchor_positions_[k];
      const double drag = c_ * options_.air_drag * s.weight;
      inertia += 0.5 * mass * inv_a * miss.squaredNorm() + 0.5 * drag * moved.squaredNorm();
      forces_[k] = (mass * inv_a) * miss + drag * moved;
      adjoints_[k].setZero();
      if (options_.rotational_inertia) {
        // 1/2 rho w (I2 |n1 - n1~|^2 + I1 |n2 - n2~|^2) / a: the kinetic energy
        // 1/2 rho (I2 |dn1/dt|^2 + I1 |dn2/dt|^2) of the section (docs/dynamics.md).
        const double c[2] = {model_.material.density * s.weight * i2 * inv_a,
                             model_.material.density * s.weight * i1 * inv_a};
        for (int d = 0; d < 2; ++d) {
          const Vec3 miss_d = s.frame.col(d) - predicted_directors_[k].col(d);
          inertia += 0.5 * c[d] * miss_d.squaredNorm();
          adjoints_[k].col(d) = c[d] * miss_d;
        }
      }
    }
    double dissipation = 0.0;
    for (int i = 0; i < model_.NumSegments(); ++i) {
      const Vec3 change = q.segment<3>(3 * i) - anchor_curvatures_.segment<3>(3 * i);
      dissipation += 0.5 * extra_[static_cast<size_t>(i)] * change.squaredNorm();
    }
    const double potential =
        matrix && gradient
            ? ComputeStrandEnergyAndHessian(model_, q, &hessian_, &energy_gradient_, &terms_)
            : energy_.Evaluate(q, gradient ? &energy_gradient_ : nullptr, &terms_);
    evaluated_q_ = q;
    evaluated_ = true;
    if (gradient) {
      dynamics::ApplyJacobianTranspose(model_, q, kin_, forces_, adjoints_, gradient);
      *gradient += energy_gradient_;
      for (int i = 0; i < model_.NumSegments(); ++i) {
        gradient->segment<3>(3 * i) +=
            extra_[static_cast<size_t>(i)] *
            (q.segment<3>(3 * i) - anchor_curvatures_.segment<3>(3 * i));
      }
    }
    if (matrix && gradient) AssembleNewtonMatrix(q, matrix);
    return inertia + dissipation + potential;
  }

  // The Newton matrix at the q of the last Evaluate (its forces): M/a + c nu-drag (Gauss-Newton)
  // + the curvature of those forces + the exact Hessian of E + c gamma l_i.
  void NewtonMatrix(const VecX& q, StrandHessian* matrix) {
    ComputeStrandHessian(model_, q, &hessian_);
    AssembleNewtonMatrix(q, matrix);
  }

 private:
  // The Newton matrix from the kinematics and forces of the last Evaluate and hessian_ (E's
  // Hessian), both at q.
  void AssembleNewtonMatrix(const VecX& q, StrandHessian* matrix) {
    dynamics::AddJacobians(model_, q, &kin_);
    dynamics::AssembleMetric(model_, options_, kin_, 1.0 / a_, c_, matrix);
    AddHessian(hessian_, extra_, matrix);
    // The curvature of the inertial and drag forces (the rest of the inertia's exact Hessian;
    // the section's rotational part, of order rho I / (rho S L^2) ~ 1e-7, is left out).
    dynamics::AddForceCurvature(model_, q, kin_, forces_, matrix);
  }

  const StrandModel& model_;
  const DynamicsOptions& options_;
  const GaussRule& rule_;
  double a_ = 0.0, c_ = 0.0;
  StrandEnergy energy_;
  Vec3 root_ = Vec3::Zero();  // r(0) at the end of the step (m, world)
  std::vector<Vec3> anchor_positions_, predicted_positions_;
  std::vector<Mat3> predicted_directors_;
  VecX anchor_curvatures_;
  std::vector<double> extra_;
  Kinematics kin_;
  std::vector<Vec3> forces_;
  std::vector<Mat3> adjoints_;
  VecX energy_gradient_;
  StrandHessian hessian_;
  // The point of the last Evaluate since Begin and its potential energy terms.
  bool evaluated_ = false;
  VecX evaluated_q_;
  EnergyTerms terms_;
};

StrandDynamics::StrandDynamics(const StrandModel& model, const DynamicsOptions& options,
                               const StrandState& initial)
    : model_(model), options_(options), state_(initial) {
  CheckInputs(model_, options_, state_.curvatures, &state_.rates);
  if (!std::isfinite(state_.time)) throw std::invalid_argument("state time must be finite (s)");
  motion_ = MotionFromRates(model_, state_, GaussLegendre01(options_.mass_points), nullptr);
}

void StrandDynamics::SetClampMotion(ClampMotion clamp) {
  if (has_history_) throw std::logic_error("SetClampMotion: only before the first step");
  if (!clamp.position || !clamp.frame) {
    throw std::invalid_argument("clamp motion needs both a position and a frame function");
  }
  clamp_ = std::move(clamp);
  reference_root_ = model_.root_position;
  reference_frame_ = model_.root_frame;
  reference_obstacle_ = model_.contact.obstacle;
  std::string why;
  if (!PlaceClamp(state_.time, &model_)) {
    throw std::invalid_argument("clamp motion at t = 0: non-finite position or frame");
  }
  if (!IsValid(model_, &why)) throw std::invalid_argument("clamp motion at t = 0: " + why);
  motion_ = MotionFromRates(model_, state_, GaussLegendre01(options_.mass_points), &clamp_);
}

bool StrandDynamics::PlaceClamp(double t, StrandModel* model) const {
  model->root_position = clamp_.position(t);
  model->root_frame = clamp_.frame(t);
  if (!model->root_position.allFinite() || !model->root_frame.allFinite()) return false;
  if (clamp_.carries_obstacle && reference_obstacle_) {
    // x -> p(t) + F(t) F0^T (x - p0) = R x + (p(t) - R p0).
    const Mat3 rotation = model->root_frame * reference_frame_.transpose();
    const Vec3 translation = model->root_position - rotation * reference_root_;
    model->contact.obstacle =
        clamp_.move_obstacle
            ? clamp_.move_obstacle(rotation, translation)
            : std::make_shared<MovedObstacle>(reference_obstacle_, rotation, translation);
  }
  return true;
}

double StrandDynamics::Kinetic() const {
  // 1/2 sum_s (m_s |v_s|^2 + rho w_s (I2 |dn1/dt|^2 + I1 |dn2/dt|^2)): with v = J qdot and
  // dn/dt = omega x n this is KineticEnergy's 1/2 qdot^T M qdot.
  const GaussRule rule = GaussLegendre01(options_.mass_points);
  const double line_density = model_.material.density * model_.section.Area();
  const double i1 = model_.section.I1(), i2 = model_.section.I2();
  double kinetic = 0.0;
  const int n = model_.NumSegments();
  for (int i = 0; i < n; ++i) {
    const double l = model_.segment_lengths[static_cast<size_t>(i)];
    for (size_t j = 0; j < rule.nodes.size(); ++j) {
      const size_t k = static_cast<size_t>(i) * rule.nodes.size() + j;
      const double w = rule.weights[j] * l;
      kinetic += 0.5 * line_density * w * motion_.velocities[k].squaredNorm();
      if (options_.rotational_inertia) {
        kinetic += 0.5 * model_.material.density * w *
                   (i2 * motion_.director_velocities[k].col(0).squaredNorm() +
                    i1 * motion_.director_velocities[k].col(1).squaredNorm());
      }
    }
  }
  return kinetic;
}

EnergyTerms StrandDynamics::Potential() const {
  StrandEnergy energy(model_);
  EnergyTerms terms;
  energy.Evaluate(state_.curvatures, nullptr, &terms);
  return terms;
}

// The buffers of the time step (dynamics.h, StrandDynamics::Scratch), one per thread. The model
// at the end of the step, the options and the rule live here, so that the incremental
// potential's references stay valid; BindScratch copies the stepping strand's model and options
// in before each use (the copies reuse their storage), so that nothing of another strand is
// left. Everything else is overwritten before it is read in each step.
struct StrandDynamics::Scratch {
  DynamicsOptions options;
  StrandModel stepped;  // the model at the end of the step: root and obstacle where the clamp is
  GaussRule rule;
  int points = 0;    // options.mass_points of rule
  int segments = -1;  // the segment count phi was made for (its energy's workspace)
  std::optional<IncrementalPotential> phi;
  StrandHessian matrix;
  StrandHessianFactor factor;
  VecX q, gradient, rhs, step, trial, trial_gradient;
};

StrandDynamics::Scratch& StrandDynamics::BindScratch() const {
  thread_local std::unique_ptr<Scratch> scratch;
  if (!scratch) scratch = std::make_unique<Scratch>();
  Scratch& w = *scratch;
  w.options = options_;
  w.stepped = model_;
  if (w.points != options_.mass_points) {
    w.rule = GaussLegendre01(options_.mass_points);
    w.points = options_.mass_points;
  }
  if (w.segments != model_.NumSegments() || !w.phi) {
    w.phi.emplace(w.stepped, w.options, w.rule);
    w.segments = model_.NumSegments();
  }
  return w;
}

namespace {

// Chord (modified) Newton (docs/dynamics.md, "Newton"): after a full step, the next update is
// first solved with the factor of the last Newton matrix. It is kept when the iteration
// contracts (ratio r = |update| / |previous update| <= kChordContraction) fast enough to reach
// the tolerance within kChordPower more such updates, or the iterations left if fewer
// (|update| r^power <= tolerance); otherwise the Newton matrix is built at the current point
// and the update solved again (the rejected chord solve costs one back-substitution). Near the
// solution a chord update differs from Newton's by O(|q - q_factor| |update|). Measured on
// shaken heads (benchmarks.md): powers 2..4 build about half the matrices for 7-12 % more
// updates; 3 is the middle.
constexpr double kChordContraction = 0.5;
constexpr int kChordPower = 3;

}  // namespace

bool StrandDynamics::TryStep(double h, int* iterations, int* factorizations, std::string* why) {
  Scratch& w = BindScratch();
  // BDF2 needs the previous state one step of the same length back; otherwise (the first step,
  // after a halving) backward Euler starts it again.
  const bool bdf2 = options_.integrator == Integrator::kBdf2 && has_history_ && previous_h_ == h;
  // The model at the end of the step: the clamp where its motion puts it then (the rest of the
  // model never changes).
  StrandModel& stepped = w.stepped;
  if (clamp_.position && !PlaceClamp(state_.time + h, &stepped)) {
    *why = "the clamp motion gave a non-finite position or frame";
    return false;
  }
  IncrementalPotential& phi = *w.phi;
  phi.Begin(state_, motion_, bdf2 ? &previous_ : nullptr, bdf2 ? &previous_motion_ : nullptr, h);
  const int n = model_.NumSegments();
  VecX& q = w.q;
  VecX& gradient = w.gradient;
  VecX& step = w.step;
  if (has_history_ && previous_h_ == h) {
    // Newton's starting point: the rates extrapolated linearly over the step,
    // q_n + h (qdot_n + h qddot_n) with qddot_n = (qdot_n - qdot_(n-1)) / h (docs/dynamics.md,
    // "Newton"); it only changes where Newton starts, not what it converges to.
    q = state_.curvatures + h * (2.0 * state_.rates - previous_.rates);
  } else {
    q = state_.curvatures + h * state_.rates;  // the explicit predictor
  }
  // The first update always needs the Newton matrix at the starting point: built with Phi and
  // its gradient there.
  double value = phi.Evaluate(q, &gradient, &w.matrix);
  if (!std::isfinite(value) || !gradient.allFinite()) {
    // The predictor went somewhere unreasonable: start from where the step starts.
    q = state_.curvatures;
    value = phi.Evaluate(q, &gradient, &w.matrix);
  }
  bool matrix_at_q = true;  // w.matrix is the Newton matrix at q, not factored yet
  // Builds and factors the Newton matrix at q.
  auto refactor = [&]() {
    ++*factorizations;
    if (!matrix_at_q) phi.NewtonMatrix(q, &w.matrix);
    matrix_at_q = false;
    // Positive definite unless the potential's Hessian is too negative for the inertia: then a
    // growing multiple of the identity (Levenberg) until the factorization succeeds.
    double mean_diagonal = 0.0;
    for (const Mat3& d : w.matrix.diagonal) mean_diagonal += d.trace();
    mean_diagonal /= 3.0 * n;
    double shift = 0.0;
    bool factored = w.factor.Factor(w.matrix, 0.0);
    for (int tries = 0; !factored && tries < 20; ++tries) {
      shift = (shift == 0.0 ? 1e-8 : 10.0 * shift);
      factored = w.factor.Factor(w.matrix, -shift * std::abs(mean_diagonal));
    }
    return factored;
  };
  auto solve = [&]() {
    w.rhs = -gradient;
    w.factor.Solve(w.rhs, &step);
    double change = 0.0;
    for (int i = 0; i < n; ++i) {
      change += model_.segment_lengths[static_cast<size_t>(i)] * step.segment<3>(3 * i).norm();
    }
    return change;
  };
  bool chord = false;  // whether the factor at hand is of an earlier point (a chord update)
  double previous_change = 0.0;
  for (int iteration = 0; iteration < options_.max_newton_iterations; ++iteration) {
    ++*iterations;
    if (!std::isfinite(value) || !gradient.allFinite()) {
      *why = "non-finite energy or gradient";
      return false;
    }
    if (!chord && !refactor()) {
      *why = "the Newton matrix could not be made positive definite";
      return false;
    }
    double change = solve();
    // The chord may count on no more updates than the iterations left allow.
    const int power = std::min(kChordPower, options_.max_newton_iterations - iteration - 1);
    const double ratio = previous_change > 0.0 ? change / previous_change : 1.0;
    if (chord && !(ratio <= kChordContraction &&
                   change * std::pow(ratio, power) <= options_.tolerance)) {
      // The chord update contracts too slowly: Newton's own at q.
      if (!refactor()) {
        *why = "the Newton matrix could not be made positive definite";
        return false;
      }
      change = solve();
    }
    const double slope = gradient.dot(step);  // < 0
    if (change <= options_.tolerance) {
      q += step;
      last_update_ = change;
      Accept(w, q, h, bdf2);
      return true;
    }
    // Backtracking line search on Phi (Armijo, c = 1e-4). The inexact step (options.
    // model_tolerance > 0) tries points by Phi's value alone: it may end at the point found.
    const bool inexact = options_.model_tolerance > 0.0;
    double alpha = 1.0;
    bool accepted = false;
    double trial_value = value;
    for (int k = 0; k < 40; ++k) {
      w.trial = q + alpha * step;
      trial_value = phi.Evaluate(w.trial, inexact ? nullptr : &w.trial_gradient);
      if (inexact) w.trial_gradient = gradient;  // computed below if the step goes on
      if (std::isfinite(trial_value) && w.trial_gradient.allFinite() &&
          trial_value <= value + 1e-4 * alpha * slope) {
        accepted = true;
        break;
      }
      // A decrease below the rounding of Phi: the full step is as good as converged.
      if (std::isfinite(trial_value) && -slope <= 1e-14 * std::abs(value)) {
        accepted = true;
        break;
      }
      alpha *= 0.5;
    }
    if (!accepted) {
      *why = "the line search found no decrease";
      return false;
    }
    // The inexact step's test: a unit step whose actual decrease of Phi is the decrease of
    // Phi's quadratic model with the matrix it was solved with (-g.d - d^T A d / 2 = -g.d / 2,
    // since A d = -g) within the fraction model_tolerance; the cubic remainder is then that
    // fraction of the model, and the update's error about that fraction of its size
    // (docs/dynamics.md, "Inexact steps").
    const double predicted = -0.5 * slope;
    // A model decrease below the rounding of Phi (1e-14 of it, as the line search's) ends it too:
    // Phi cannot tell the point from the minimizer.
    const bool model_agrees =
        inexact && alpha == 1.0 &&
        (predicted <= 1e-14 * std::abs(value) ||
         std::abs((value - trial_value) / predicted - 1.0) <= options_.model_tolerance);
    q.swap(w.trial);
    gradient.swap(w.trial_gradient);
    value = trial_value;
    if (alpha * change <= options_.tolerance || model_agrees) {
      last_update_ = alpha * change;
      Accept(w, q, h, bdf2);
      return true;
    }
    if (inexact) {
      // The inexact step goes on with Newton's own update at the new point (a chord update
      // would have to shrink its predecessor below the tolerance, 1e-11 rad, to be kept: the
      // inexact step's updates are far larger), its matrix built with Phi's gradient.
      value = phi.Evaluate(q, &gradient, &w.matrix);
      matrix_at_q = true;
      chord = false;
    } else {
      // The next update reuses this factor only after a full step (close enough to the solution
      // for the chord to converge); a shortened step asks for a fresh Newton matrix.
      chord = alpha == 1.0;
    }
    previous_change = change;
  }
  std::ostringstream out;
  out << "Newton did not converge in " << options_.max_newton_iterations << " iterations";
  *why = out.str();
  return false;
}

void StrandDynamics::Accept(const Scratch& w, const VecX& q, double h, bool bdf2) {
  const StrandModel& stepped = w.stepped;
  // Rates: backward Euler (q1 - q0) / h; BDF2 (3 q1 - 4 q0 + q_(-1)) / (2h). The samples'
  // velocities by the same formulas on their positions and directors: the scheme's velocities,
  // which the next step predicts from (J qdot would differ by O(h) and, over large rotations in
  // one step, feed energy in; docs/dynamics.md).
  VecX rates = bdf2 ? VecX((3.0 * q - 4.0 * state_.curvatures + previous_.curvatures) / (2.0 * h))
                    : VecX((q - state_.curvatures) / h);
  SampleMotion next;
  if (w.phi->EvaluatedAt(q)) {
    w.phi->LastPlaces(&next);  // the line search's last evaluation was at q
  } else {
    SamplePlaces(stepped, q, w.rule, &next);
  }
  const size_t count = next.positions.size();
  next.velocities.resize(count);
  next.director_velocities.resize(count);
  for (size_t k = 0; k < count; ++k) {
    if (bdf2) {
      next.velocities[k] = (3.0 * next.positions[k] - 4.0 * motion_.positions[k] +
                            previous_motion_.positions[k]) / (2.0 * h);
      next.director_velocities[k] = (3.0 * next.directors[k] - 4.0 * motion_.directors[k] +
                                     previous_motion_.directors[k]) / (2.0 * h);
    } else {
      next.velocities[k] = (next.positions[k] - motion_.positions[k]) / h;
      next.director_velocities[k] = (next.directors[k] - motion_.directors[k]) / h;
    }
  }
  previous_ = state_;
  previous_motion_ = std::move(motion_);
  motion_ = std::move(next);
  previous_h_ = h;
  has_history_ = true;
  state_.curvatures = q;
  state_.rates = std::move(rates);
  state_.time += h;
  model_.root_position = stepped.root_position;
  model_.root_frame = stepped.root_frame;
  model_.contact.obstacle = stepped.contact.obstacle;
}

StepReport StrandDynamics::Step() { return Step(options_.time_step); }

StepReport StrandDynamics::Step(double h) {
  if (!(std::isfinite(h) && h > 0.0)) {
    throw std::invalid_argument("time step must be a finite number > 0 (s)");
  }
  StepReport report;
  std::string why, first_why;
  bool ok = true;
  const double start_time = state_.time;
  if (TryStep(h, &report.newton_iterations, &report.factorizations, &why)) {
    report.substeps = 1;
  } else {
    // A failed try leaves the state as it was: saved now, for a halving that fails part way.
    const StrandState saved = state_, saved_previous = previous_;
    const SampleMotion saved_motion = motion_, saved_previous_motion = previous_motion_;
    const Vec3 saved_root = model_.root_position;
    const Mat3 saved_frame = model_.root_frame;
    const std::shared_ptr<const Obstacle> saved_obstacle = model_.contact.obstacle;
    const double saved_previous_h = previous_h_;
    const bool saved_history = has_history_;
    first_why = why;
    // Depth-first halving: a sub-step of h / 2^depth that fails is replaced by two of half its
    // length, down to max_halvings.
    struct Pending {
      double h;
      int depth;
    };
    std::vector<Pending> stack;
    if (options_.max_halvings > 0) {
      stack = {{0.5 * h, 1}, {0.5 * h, 1}};
    } else {
      ok = false;
    }
    while (!stack.empty()) {
      const Pending p = stack.back();
      stack.pop_back();
      if (TryStep(p.h, &report.newton_iterations, &report.factorizations, &why)) {
        ++report.substeps;
        report.halvings = std::max(report.halvings, p.depth);
        continue;
      }
      if (p.depth >= options_.max_halvings) {
        ok = false;
        break;
      }
      stack.push_back({0.5 * p.h, p.depth + 1});
      stack.push_back({0.5 * p.h, p.depth + 1});
    }
    if (!ok) {
      state_ = saved;
      previous_ = saved_previous;
      motion_ = saved_motion;
      previous_motion_ = saved_previous_motion;
      model_.root_position = saved_root;
      model_.root_frame = saved_frame;
      model_.contact.obstacle = saved_obstacle;
      previous_h_ = saved_previous_h;
      has_history_ = saved_history;
    }
  }
  if (!ok) {
    std::ostringstream out;
    out << "step of " << h << " s at t = " << start_time << " s failed after "
        << options_.max_halvings << " halvings: " << why;
    report.message = out.str();
    report.converged = false;
  } else {
    report.converged = true;
    report.residual = last_update_;
    if (report.halvings > 0) {
      std::ostringstream out;
      out << "step of " << h << " s at t = " << start_time << " s halved " << report.halvings
          << " time(s) (" << report.substeps << " sub-steps): " << first_why;
      report.message = out.str();
    }
  }
  report.time = state_.time;
  // The potential with the model as it is now.
  Scratch& w = BindScratch();
  // The terms of the accepted point when its last evaluation was there (the same numbers).
  report.potential = ok && w.phi->EvaluatedAt(state_.curvatures)
                         ? w.phi->LastTerms()
                         : w.phi->Potential(state_.curvatures);
  // The thread's buffers keep no body alive past the step (a body may be large: a distance grid).
  w.stepped.contact.obstacle.reset();
  report.kinetic = Kinetic();
  return report;
}

}  // namespace ringlet
