// Rigid head motions for the dynamics (docs/dynamics.md, "Head motion"): keyframed translation
// and rotation with smooth interpolation, and the presets nod, shake, turn and walk. A motion
// gives the pose P(t) = (R(t), d(t)) that maps a point x of the head at rest to
//   x(t) = c + d(t) + R(t) (x - c),
// c the pivot (the neck), so that the roots of the hair and the body move together.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "ringlet/dynamics.h"
#include "ringlet/math.h"

namespace ringlet {

class SplitBody;

/// The rigid placement of the head at one time: x -> pivot + translation + rotation (x - pivot).
struct RigidPose {
  Mat3 rotation = Mat3::Identity();     ///< a proper rotation
  Vec3 translation = Vec3::Zero();      ///< (m)
};

/// One keyframe of a motion file (docs/dynamics.md, "Motion files").
struct MotionKeyframe {
  double time = 0.0;                   ///< (s), >= 0; strictly increasing along the keyframes
  Vec3 translation = Vec3::Zero();     ///< d (m)
  Vec3 axis = Vec3::UnitZ();           ///< rotation axis (any non-zero length; world frame)
  double angle = 0.0;                  ///< rotation angle about axis (rad, right-handed)
};

/// Largest translation a keyframe may hold, per component (m): far beyond any head motion, and
/// small enough that the spline's sums cannot overflow.
inline constexpr double kMaxTranslation = 1e6;

/// The presets of `ringlet simulate --motion` (docs/dynamics.md, "Presets").
enum class MotionPreset {
  kNone,   ///< the head stays still
  kNod,    ///< about the head's left axis: 20 deg, period 1 s, 2 cycles in a sin^2 envelope
  kShake,  ///< about the head's up axis: 30 deg, period 0.5 s, 2 cycles in a sin^2 envelope
  kTurn,   ///< about the up axis: to 60 deg in 1 s, held 1 s, back in 1 s (C2 smootherstep)
  kWalk,   ///< a walk's bounce: 2 cm up and down at 2 steps/s, 1.5 cm sway at 1 stride/s
};

/// Preset amplitudes and timings (docs/dynamics.md, "Presets").
inline constexpr double kNodAmplitude = 20.0 * M_PI / 180.0;    ///< (rad)
inline constexpr double kNodPeriod = 1.0;                        ///< (s)
inline constexpr double kShakeAmplitude = 30.0 * M_PI / 180.0;  ///< (rad)
inline constexpr double kShakePeriod = 0.5;                      ///< (s)
inline constexpr int kOscillationCycles = 2;                     ///< cycles of nod and shake
inline constexpr double kTurnAngle = 60.0 * M_PI / 180.0;       ///< (rad)
inline constexpr double kTurnTime = 1.0;                         ///< each way, and the hold (s)
inline constexpr double kWalkBounce = 0.02;                      ///< vertical amplitude (m)
inline constexpr double kWalkSway = 0.015;                       ///< sideways amplitude (m)
inline constexpr double kWalkStepPeriod = 0.5;                   ///< one step (s)
inline constexpr double kWalkRampTime = 1.0;                     ///< smootherstep ramp-in (s)

/// The preset's name ("nod", ...), and the preset of a name (false for an unknown name).
const char* MotionPresetName(MotionPreset preset);
bool MotionPresetFromName(const std::string& name, MotionPreset* preset);

/// The smootherstep 6x^5 - 15x^4 + 10x^3 on [0, 1] (0 before, 1 after): C2, with zero first
/// and second derivatives at both ends (Perlin 2002, "Improving noise").
double Smootherstep(double x);

/// A rigid head motion: a preset or keyframes, about a pivot in a head frame.
class HeadMotion {
 public:
  /// Still: the identity pose at every time.
  HeadMotion() = default;
  /// A preset about pivot with the head's up and left axes (unit vectors, orthogonal).
  static HeadMotion Preset(MotionPreset preset, const Vec3& pivot, const Vec3& up,
                           const Vec3& left);
  /// Keyframes (at least one, times >= 0 and strictly increasing, translations of at most
  /// kMaxTranslation per component, axes finite and non-zero, consecutive orientations less
  /// than 180 degrees apart) about pivot. Throws
  /// std::invalid_argument naming keyframes[k] and the field otherwise.
  static HeadMotion Keyframes(std::vector<MotionKeyframe> keyframes, const Vec3& pivot);

  /// The pose at time t (s). Keyframes: translation by a cubic Hermite spline with Catmull-Rom
  /// tangents (p_(k+1) - p_(k-1)) / (t_(k+1) - t_(k-1)) and zero tangents at the first and last
  /// keyframe; orientation by the same spline on unit quaternions (signs chosen so that
  /// consecutive ones have a non-negative dot product), normalized. It passes through every
  /// keyframe exactly (up to rounding), is C1, and holds the first pose before the first
  /// keyframe and the last after the last.
  RigidPose Pose(double t) const;
  /// A point x of the head at rest, at time t: pivot + d(t) + R(t) (x - pivot).
  Vec3 Apply(double t, const Vec3& x) const;

  const Vec3& pivot() const { return pivot_; }
  MotionPreset preset() const { return preset_; }
  const std::vector<MotionKeyframe>& keyframes() const { return keyframes_; }

  /// The clamp of a root at rest (position, frame) under this motion: position(t) =
  /// Apply(t, position), frame(t) = R(t) frame; it carries the obstacle (the head). With a split
  /// body (a body with a torso part, SplitBody) the obstacle at t is that body placed with its
  /// head part carried like the root and its torso part translated by the pose's d(t) alone
  /// (never turned), recovered from the clamp's rigid motion x -> R x + b as d = b - c + R c
  /// (c the pivot), so that head and torso move together exactly when R = I.
  ClampMotion Clamp(const Vec3& position, const Mat3& frame,
                    std::shared_ptr<const SplitBody> body = nullptr) const;

 private:
  MotionPreset preset_ = MotionPreset::kNone;
  Vec3 pivot_ = Vec3::Zero();
  Vec3 up_ = Vec3::UnitZ();
  Vec3 left_ = -Vec3::UnitX();
  std::vector<MotionKeyframe> keyframes_;
  std::vector<Eigen::Vector4d> quaternions_;  // (w, x, y, z) per keyframe, signs aligned
};

}  // namespace ringlet
