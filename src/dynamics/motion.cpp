// Rigid head motions: presets and keyframes (motion.h; docs/dynamics.md, "Head motion").
#include "ringlet/motion.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "ringlet/split_body.h"

namespace ringlet {
namespace {

// Cubic Hermite basis on s in [0, 1] (h00, h10, h01, h11): p(s) = h00 p0 + h10 D m0 + h01 p1 +
// h11 D m1 for an interval of length D with end tangents m0, m1 (Catmull & Rom 1974 choose the
// tangents as central differences of the neighbouring keys).
struct Hermite {
  double h00, h10, h01, h11;
};
Hermite HermiteBasis(double s) {
  const double s2 = s * s, s3 = s2 * s;
  return {2.0 * s3 - 3.0 * s2 + 1.0, s3 - 2.0 * s2 + s, -2.0 * s3 + 3.0 * s2, s3 - s2};
}

// sin^2(pi x) on [0, 1], 0 outside: the envelope of the oscillating presets. It and its first
// derivative vanish at both ends, and so does the oscillation sin(2 pi t / T) at whole cycles,
// so the angle A env sin is C2 there.
double Envelope(double x) {
  if (x <= 0.0 || x >= 1.0) return 0.0;
  const double s = std::sin(M_PI * x);
  return s * s;
}

Mat3 AxisAngle(const Vec3& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

Eigen::Vector4d Quaternion(const MotionKeyframe& key) {
  const Vec3 u = key.axis.normalized();
  const double half = 0.5 * key.angle;
  return {std::cos(half), std::sin(half) * u.x(), std::sin(half) * u.y(), std::sin(half) * u.z()};
}

}  // namespace

const char* MotionPresetName(MotionPreset preset) {
  switch (preset) {
    case MotionPreset::kNone: return "none";
    case MotionPreset::kNod: return "nod";
    case MotionPreset::kShake: return "shake";
    case MotionPreset::kTurn: return "turn";
    case MotionPreset::kWalk: return "walk";
  }
  return "none";
}

bool MotionPresetFromName(const std::string& name, MotionPreset* preset) {
  for (MotionPreset p : {MotionPreset::kNone, MotionPreset::kNod, MotionPreset::kShake,
                         MotionPreset::kTurn, MotionPreset::kWalk}) {
    if (name == MotionPresetName(p)) {
      *preset = p;
      return true;
    }
  }
  return false;
}

double Smootherstep(double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  return x * x * x * (x * (6.0 * x - 15.0) + 10.0);
}

HeadMotion HeadMotion::Preset(MotionPreset preset, const Vec3& pivot, const Vec3& up,
                              const Vec3& left) {
  HeadMotion motion;
  motion.preset_ = preset;
  motion.pivot_ = pivot;
  motion.up_ = up.normalized();
  motion.left_ = left.normalized();
  return motion;
}

HeadMotion HeadMotion::Keyframes(std::vector<MotionKeyframe> keyframes, const Vec3& pivot) {
  if (keyframes.empty()) throw std::invalid_argument("keyframes: expected at least one keyframe");
  if (!pivot.allFinite()) throw std::invalid_argument("pivot: expected 3 finite numbers (m)");
  HeadMotion motion;
  motion.pivot_ = pivot;
  for (size_t k = 0; k < keyframes.size(); ++k) {
    const MotionKeyframe& key = keyframes[k];
    const std::string at = "keyframes[" + std::to_string(k) + "].";
    if (!(std::isfinite(key.time) && key.time >= 0.0)) {
      throw std::invalid_argument(at + "time: expected a finite number >= 0 (s)");
    }
    if (k > 0 && !(key.time > keyframes[k - 1].time)) {
      throw std::invalid_argument(at + "time: expected a time after the previous keyframe's");
    }
    if (!key.translation.allFinite() || key.translation.cwiseAbs().maxCoeff() > kMaxTranslation) {
      throw std::invalid_argument(at + "translation: expected 3 numbers of magnitude at most 1e6 (m)");
    }
    if (!key.axis.allFinite() || !(key.axis.norm() > 0.0) || !std::isfinite(key.axis.norm())) {
      throw std::invalid_argument(at + "axis: expected a non-zero direction [x, y, z]");
    }
    if (!std::isfinite(key.angle)) {
      throw std::invalid_argument(at + "angle: expected a finite number (degrees)");
    }
    Eigen::Vector4d q = Quaternion(key);
    if (k > 0) {
      // The shorter way between consecutive orientations; opposite ones (180 degrees apart)
      // have no shorter way and would leave the spline near the zero quaternion.
      const double dot = q.dot(motion.quaternions_.back());
      if (dot < 0.0) q = -q;
      if (std::abs(dot) < std::cos(0.5 * (179.0 * M_PI / 180.0))) {
        throw std::invalid_argument(
            at + "angle: the orientation turns 179 degrees or more from the previous keyframe's "
                 "(expected less; add a keyframe in between)");
      }
    }
    motion.quaternions_.push_back(q);
  }
  motion.keyframes_ = std::move(keyframes);
  return motion;
}

RigidPose HeadMotion::Pose(double t) const {
  RigidPose pose;
  if (!keyframes_.empty()) {
    const auto& keys = keyframes_;
    const size_t count = keys.size();
    if (t <= keys.front().time) {
      pose.translation = keys.front().translation;
      pose.rotation = Eigen::Quaterniond(quaternions_.front()(0), quaternions_.front()(1),
                                         quaternions_.front()(2), quaternions_.front()(3))
                          .normalized()
                          .toRotationMatrix();
      return pose;
    }
    if (t >= keys.back().time) {
      pose.translation = keys.back().translation;
      pose.rotation = Eigen::Quaterniond(quaternions_.back()(0), quaternions_.back()(1),
                                         quaternions_.back()(2), quaternions_.back()(3))
                          .normalized()
                          .toRotationMatrix();
      return pose;
    }
    // The interval [t_k, t_(k+1)) holding t, by bisection (files may hold many keyframes).
    const auto after = std::upper_bound(keys.begin(), keys.end(), t,
                                        [](double x, const MotionKeyframe& key) {
                                          return x < key.time;
                                        });
    const size_t k = std::min(static_cast<size_t>(after - keys.begin()) - 1, count - 2);
    // Catmull-Rom tangents (central differences over the neighbours), zero at both ends, times
    // the interval's span: span / (t_(i+1) - t_(i-1)) <= 1 is formed first, so that keyframes
    // however close in time give no overflow (found by fuzz_motion_json).
    const double span = keys[k + 1].time - keys[k].time;
    auto weight = [&](size_t i) {
      if (i == 0 || i + 1 == count) return 0.0;
      return span / (keys[i + 1].time - keys[i - 1].time);
    };
    auto tangent_p = [&](size_t i) -> Vec3 {
      const double w = weight(i);
      return w == 0.0 ? Vec3::Zero()
                      : Vec3(w * (keys[i + 1].translation - keys[i - 1].translation));
    };
    auto tangent_q = [&](size_t i) -> Eigen::Vector4d {
      const double w = weight(i);
      return w == 0.0 ? Eigen::Vector4d::Zero()
                      : Eigen::Vector4d(w * (quaternions_[i + 1] - quaternions_[i - 1]));
    };
    const Hermite h = HermiteBasis((t - keys[k].time) / span);
    pose.translation = h.h00 * keys[k].translation + h.h10 * tangent_p(k) +
                       h.h01 * keys[k + 1].translation + h.h11 * tangent_p(k + 1);
    const Eigen::Vector4d q = h.h00 * quaternions_[k] + h.h10 * tangent_q(k) +
                              h.h01 * quaternions_[k + 1] + h.h11 * tangent_q(k + 1);
    // |q| >= sqrt((1 + dot)/2) - 2 (4/27) 2 > 0.1 with dot >= cos(89.5 deg): never zero.
    pose.rotation = Eigen::Quaterniond(q(0), q(1), q(2), q(3)).normalized().toRotationMatrix();
    return pose;
  }
  switch (preset_) {
    case MotionPreset::kNone:
      break;
    case MotionPreset::kNod:
    case MotionPreset::kShake: {
      const bool nod = preset_ == MotionPreset::kNod;
      const double amplitude = nod ? kNodAmplitude : kShakeAmplitude;
      const double period = nod ? kNodPeriod : kShakePeriod;
      const double angle = amplitude * Envelope(t / (kOscillationCycles * period)) *
                           std::sin(2.0 * M_PI * t / period);
      pose.rotation = AxisAngle(nod ? left_ : up_, angle);
      break;
    }
    case MotionPreset::kTurn: {
      const double angle =
          kTurnAngle * (Smootherstep(t / kTurnTime) - Smootherstep((t - 2.0 * kTurnTime) / kTurnTime));
      pose.rotation = AxisAngle(up_, angle);
      break;
    }
    case MotionPreset::kWalk: {
      const double ramp = Smootherstep(t / kWalkRampTime);
      pose.translation = ramp * (kWalkBounce * std::sin(2.0 * M_PI * t / kWalkStepPeriod) * up_ +
                                 kWalkSway * std::sin(M_PI * t / kWalkStepPeriod) * left_);
      break;
    }
  }
  return pose;
}

Vec3 HeadMotion::Apply(double t, const Vec3& x) const {
  const RigidPose pose = Pose(t);
  return pivot_ + pose.translation + pose.rotation * (x - pivot_);
}

ClampMotion HeadMotion::Clamp(const Vec3& position, const Mat3& frame,
                              std::shared_ptr<const SplitBody> body) const {
  ClampMotion clamp;
  const HeadMotion motion = *this;
  clamp.position = [motion, position](double t) { return motion.Apply(t, position); };
  clamp.frame = [motion, frame](double t) -> Mat3 { return motion.Pose(t).rotation * frame; };
  clamp.carries_obstacle = true;
  if (body) {
    // x(t) = c + d + R (x - c) = R x + b with b = c + d - R c: the torso's d = b - c + R c.
    const Vec3 pivot = pivot_;
    clamp.move_obstacle = [body, pivot](const Mat3& rotation, const Vec3& translation) {
      return body->Place(rotation, translation, translation - pivot + rotation * pivot);
    };
  }
  return clamp;
}

}  // namespace ringlet
