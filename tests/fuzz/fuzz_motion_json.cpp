// Fuzz harness: motion files of `ringlet simulate --motion FILE.json` (motion_json.h,
// docs/dynamics.md, "Motion files"). On success the motion's own invariants are checked: the
// keyframes' times strictly increase, and the pose at the keyframes, between them and outside
// them is finite with a proper rotation (R^T R = I, det R = 1), as HeadMotion::Pose promises.
#include <cmath>

#include "fuzz_input.h"
#include "ringlet/motion_json.h"

namespace {

void CheckPose(const ringlet::HeadMotion& motion, double t) {
  const ringlet::RigidPose pose = motion.Pose(t);
  ringlet::fuzz::Require(pose.rotation.allFinite() && pose.translation.allFinite(),
                         "a pose that is not finite");
  const double orthogonality =
      (pose.rotation.transpose() * pose.rotation - ringlet::Mat3::Identity()).norm();
  ringlet::fuzz::Require(orthogonality < 1e-9 && std::abs(pose.rotation.determinant() - 1.0) < 1e-9,
                         "a pose whose rotation is not proper");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  ringlet::HeadMotion motion;
  std::string error;
  const bool ok = ringlet::ParseMotionText(ringlet::fuzz::Text(data, size),
                                           ringlet::Vec3(0.0, 0.0, -0.1), &motion, &error);
  ringlet::fuzz::CheckAnswer(ok, error);
  if (!ok) return 0;
  const auto& keys = motion.keyframes();
  ringlet::fuzz::Require(!keys.empty(), "a motion without keyframes");
  for (size_t k = 0; k < keys.size(); ++k) {
    ringlet::fuzz::Require(std::isfinite(keys[k].time) && keys[k].time >= 0.0 &&
                               (k == 0 || keys[k].time > keys[k - 1].time),
                           "keyframe times not finite, negative or not increasing");
  }
  // The pose before, at and after the keyframes, and halfway between the first few.
  CheckPose(motion, keys.front().time - 1.0);
  CheckPose(motion, keys.back().time + 1.0);
  for (size_t k = 0; k < keys.size() && k < 64; ++k) {
    CheckPose(motion, keys[k].time);
    if (k + 1 < keys.size()) CheckPose(motion, 0.5 * (keys[k].time + keys[k + 1].time));
  }
  return 0;
}
