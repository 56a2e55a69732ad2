// Head motions (motion.h), motion files (motion_json.h), the obstacle carried by a moving clamp
// (dynamics.h) and the frame-by-frame simulation (simulate.h). The references are written out
// here: Rodrigues' rotation formula, the presets' closed forms at chosen times.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "ringlet/body.h"
#include "ringlet/body_json.h"
#include "ringlet/hair_type.h"
#include "ringlet/hairstyle.h"
#include "ringlet/contact.h"
#include "ringlet/dynamics.h"
#include "ringlet/motion.h"
#include "ringlet/motion_json.h"
#include "ringlet/simulate.h"
#include "ringlet/statics.h"
#include "ringlet/strand_model.h"
#include "test_util.h"

namespace ringlet {
namespace {

constexpr double kDeg = M_PI / 180.0;

// Rodrigues: R = I + sin(a) [u]x + (1 - cos(a)) [u]x^2 for a unit axis u.
Mat3 Rodrigues(Vec3 axis, double angle) {
  axis.normalize();
  Mat3 k;
  k << 0, -axis.z(), axis.y(), axis.z(), 0, -axis.x(), -axis.y(), axis.x(), 0;
  return Mat3::Identity() + std::sin(angle) * k + (1.0 - std::cos(angle)) * k * k;
}

void ExpectProperRotation(const Mat3& r) {
  EXPECT_LT((r.transpose() * r - Mat3::Identity()).norm(), 1e-14);
  EXPECT_NEAR(r.determinant(), 1.0, 1e-14);
}

std::vector<MotionKeyframe> SomeKeyframes() {
  std::vector<MotionKeyframe> keys(4);
  keys[0] = {0.0, Vec3::Zero(), Vec3::UnitZ(), 0.0};
  keys[1] = {0.4, Vec3(0.01, -0.02, 0.03), Vec3(1, 1, 0), 35.0 * kDeg};
  keys[2] = {1.0, Vec3(-0.02, 0.0, 0.01), Vec3(0, 0, 1), -50.0 * kDeg};
  keys[3] = {1.3, Vec3(0.0, 0.05, 0.0), Vec3(0, 1, 2), 120.0 * kDeg};
  return keys;
}

TEST(HeadMotion, KeyframesAreHitExactly) {
  const auto keys = SomeKeyframes();
  const HeadMotion motion = HeadMotion::Keyframes(keys, Vec3(0, 0, -0.1));
  for (const MotionKeyframe& key : keys) {
    const RigidPose pose = motion.Pose(key.time);
    EXPECT_LT((pose.translation - key.translation).norm(), 1e-15) << key.time;
    EXPECT_LT((pose.rotation - Rodrigues(key.axis, key.angle)).norm(), 1e-14) << key.time;
  }
  // Before the first keyframe and after the last: held.
  EXPECT_LT((motion.Pose(5.0).rotation - Rodrigues(keys[3].axis, keys[3].angle)).norm(), 1e-14);
  EXPECT_LT((motion.Pose(5.0).translation - keys[3].translation).norm(), 1e-15);
}

TEST(HeadMotion, InterpolatedPosesAreProperRotationsAndC1) {
  const HeadMotion motion = HeadMotion::Keyframes(SomeKeyframes(), Vec3::Zero());
  for (double t = 0.0; t <= 1.4; t += 0.01) ExpectProperRotation(motion.Pose(t).rotation);
  // C1 at the interior keyframes: one-sided difference quotients agree to O(dt).
  const double dt = 1e-6;
  for (double t : {0.4, 1.0}) {
    const RigidPose left = motion.Pose(t - dt), mid = motion.Pose(t), right = motion.Pose(t + dt);
    const Vec3 v_left = (mid.translation - left.translation) / dt;
    const Vec3 v_right = (right.translation - mid.translation) / dt;
    EXPECT_LT((v_left - v_right).norm(), 1e-4 * (1.0 + v_left.norm())) << t;
    const Mat3 w_left = (mid.rotation - left.rotation) / dt;
    const Mat3 w_right = (right.rotation - mid.rotation) / dt;
    EXPECT_LT((w_left - w_right).norm(), 1e-4 * (1.0 + w_left.norm())) << t;
  }
  // At rest at both ends (zero end tangents).
  const RigidPose a = motion.Pose(1e-6), b = motion.Pose(1.3 - 1e-6);
  EXPECT_LT((a.translation - motion.Pose(0.0).translation).norm(), 1e-10);
  EXPECT_LT((b.translation - motion.Pose(1.3).translation).norm(), 1e-10);
}

TEST(HeadMotion, ApplyIsARigidMotionAboutThePivot) {
  const Vec3 pivot(0.01, 0.02, -0.1);
  const HeadMotion motion = HeadMotion::Keyframes(SomeKeyframes(), pivot);
  const double t = 0.7;
  const RigidPose pose = motion.Pose(t);
  const Vec3 x(0.05, -0.03, 0.08), y(-0.04, 0.06, 0.02);
  EXPECT_NEAR((motion.Apply(t, x) - motion.Apply(t, y)).norm(), (x - y).norm(), 1e-15);
  EXPECT_LT((motion.Apply(t, pivot) - (pivot + pose.translation)).norm(), 1e-16);
}

TEST(HeadMotion, PresetsFollowTheirFormulas) {
  const Vec3 pivot(0, 0, -0.1), up = Vec3::UnitZ(), left = -Vec3::UnitX();
  // shake: 30 deg sin^2(pi t / 1 s) sin(2 pi t / 0.5 s) about up; at t = 0.125 s that is
  // 30 deg sin^2(pi / 8).
  const HeadMotion shake = HeadMotion::Preset(MotionPreset::kShake, pivot, up, left);
  const double s = std::sin(M_PI / 8.0);
  EXPECT_LT((shake.Pose(0.125).rotation - Rodrigues(up, 30.0 * kDeg * s * s)).norm(), 1e-14);
  EXPECT_LT((shake.Pose(0.0).rotation - Mat3::Identity()).norm(), 1e-15);
  EXPECT_LT((shake.Pose(1.0).rotation - Mat3::Identity()).norm(), 1e-14);
  EXPECT_LT((shake.Pose(3.0).rotation - Mat3::Identity()).norm(), 1e-15);
  // nod: 20 deg sin^2(pi t / 2 s) sin(2 pi t / 1 s) about left; at t = 0.75 s:
  // 20 deg sin^2(3 pi / 8) (-1).
  const HeadMotion nod = HeadMotion::Preset(MotionPreset::kNod, pivot, up, left);
  const double n = std::sin(3.0 * M_PI / 8.0);
  EXPECT_LT((nod.Pose(0.75).rotation - Rodrigues(left, -20.0 * kDeg * n * n)).norm(), 1e-14);
  // turn: 60 deg from 1 s to 2 s, half way (smootherstep(1/2) = 1/2) at 0.5 s, back at 3 s.
  const HeadMotion turn = HeadMotion::Preset(MotionPreset::kTurn, pivot, up, left);
  EXPECT_LT((turn.Pose(1.5).rotation - Rodrigues(up, 60.0 * kDeg)).norm(), 1e-14);
  EXPECT_LT((turn.Pose(0.5).rotation - Rodrigues(up, 30.0 * kDeg)).norm(), 1e-14);
  EXPECT_LT((turn.Pose(3.0).rotation - Mat3::Identity()).norm(), 1e-14);
  // walk: at t = 1.125 s (ramp done) bounce 2 cm sin(4.5 pi) = 2 cm, sway 1.5 cm sin(2.25 pi).
  const HeadMotion walk = HeadMotion::Preset(MotionPreset::kWalk, pivot, up, left);
  const Vec3 expected = 0.02 * up + 0.015 * std::sin(2.25 * M_PI) * left;
  EXPECT_LT((walk.Pose(1.125).translation - expected).norm(), 1e-15);
  EXPECT_LT((walk.Pose(1.125).rotation - Mat3::Identity()).norm(), 0.0 + 1e-300);
  for (MotionPreset p : {MotionPreset::kNod, MotionPreset::kShake, MotionPreset::kTurn}) {
    const HeadMotion m = HeadMotion::Preset(p, pivot, up, left);
    for (double t = 0.0; t < 3.5; t += 0.05) ExpectProperRotation(m.Pose(t).rotation);
  }
  MotionPreset parsed;
  EXPECT_TRUE(MotionPresetFromName("shake", &parsed));
  EXPECT_EQ(parsed, MotionPreset::kShake);
  EXPECT_FALSE(MotionPresetFromName("shiver", &parsed));
}

TEST(HeadMotion, SmootherstepIsC2) {
  EXPECT_EQ(Smootherstep(0.0), 0.0);
  EXPECT_EQ(Smootherstep(1.0), 1.0);
  EXPECT_DOUBLE_EQ(Smootherstep(0.5), 0.5);
  // f'(x) = 30 x^2 (1 - x)^2: at 0.25, 30 / 16 * 9 / 16.
  const double d = 1e-6;
  EXPECT_NEAR((Smootherstep(0.25 + d) - Smootherstep(0.25 - d)) / (2 * d), 30.0 * 9.0 / 256.0,
              1e-8);
}

TEST(MotionJson, ReadsKeyframesInDegrees) {
  HeadMotion motion;
  std::string error;
  ASSERT_TRUE(ParseMotionText(
      R"({"description": "look left", "pivot": [0, 0, -0.12],
          "keyframes": [{"time": 0}, {"time": 0.5, "axis": [0, 0, 2], "angle": 45,
                         "translation": [0, 0.01, 0]}]})",
      Vec3::Zero(), &motion, &error))
      << error;
  EXPECT_EQ(motion.pivot(), Vec3(0, 0, -0.12));
  ASSERT_EQ(motion.keyframes().size(), 2u);
  EXPECT_LT((motion.Pose(0.5).rotation - Rodrigues(Vec3::UnitZ(), M_PI / 4)).norm(), 1e-15);
  EXPECT_LT((motion.Pose(0.5).translation - Vec3(0, 0.01, 0)).norm(), 1e-17);
  // Without a pivot: the default.
  ASSERT_TRUE(ParseMotionText(R"({"keyframes": [{"time": 0}]})", Vec3(1, 2, 3), &motion, &error));
  EXPECT_EQ(motion.pivot(), Vec3(1, 2, 3));
}

// The example motion files (examples/motions, also the fuzz seeds of tests/fuzz): they load and
// pass through their keyframes (Rodrigues' rotation of the file's axis and angle).
TEST(MotionJson, ExampleFilesLoadAndHitTheirKeyframes) {
  const std::string dir = std::string(RINGLET_EXAMPLES_DIR) + "/motions/";
  HeadMotion motion;
  std::string error;
  ASSERT_TRUE(LoadMotion(dir + "look_left.json", Vec3::Zero(), &motion, &error)) << error;
  EXPECT_EQ(motion.pivot(), Vec3(0, 0, -0.1));
  ASSERT_EQ(motion.keyframes().size(), 3u);
  EXPECT_LT((motion.Pose(0.4).rotation - Rodrigues(Vec3::UnitZ(), 40.0 * kDeg)).norm(), 1e-14);
  EXPECT_LT((motion.Pose(0.4).translation - Vec3(0, 0, 0.01)).norm(), 1e-16);
  EXPECT_LT((motion.Pose(1.0).rotation - Mat3::Identity()).norm(), 1e-14);
  ASSERT_TRUE(LoadMotion(dir + "nod_and_step.json", Vec3(0, 0, -0.2), &motion, &error)) << error;
  EXPECT_EQ(motion.pivot(), Vec3(0, 0, -0.2));  // the default pivot: the file gives none
  ASSERT_EQ(motion.keyframes().size(), 6u);
  EXPECT_LT((motion.Pose(0.5).rotation - Rodrigues(Vec3::UnitX(), -5.0 * kDeg)).norm(), 1e-14);
  EXPECT_LT((motion.Pose(0.75).translation - Vec3(0, 0.08, 0.01)).norm(), 1e-16);
  ExpectProperRotation(motion.Pose(0.6).rotation);
}

// Found by fuzz_motion_json: a translation of 1e308 m was accepted and the spline overflowed to a
// non-finite pose. Translations are bounded (1e6 m), and keyframes however close in time give
// finite poses and proper rotations between them.
TEST(MotionJson, HugeTranslationsAreRefusedAndCloseKeyframesStayFinite) {
  HeadMotion motion;
  std::string error;
  EXPECT_FALSE(ParseMotionText(
      R"({"keyframes": [{"time": 0}, {"time": 0.25, "translation": [0, 1e+308, 0.01]}, {"time": 0.5}]})",
      Vec3::Zero(), &motion, &error));
  EXPECT_NE(error.find("keyframes[1].translation: expected 3 numbers of magnitude at most 1e6"),
            std::string::npos)
      << error;
  ASSERT_TRUE(ParseMotionText(
      R"({"keyframes": [{"time": 0, "translation": [1e6, -1e6, 1e6]},
                        {"time": 1e-300, "translation": [-1e6, 1e6, -1e6], "axis": [1, 0, 0], "angle": 170},
                        {"time": 2e-300, "angle": 10},
                        {"time": 1, "translation": [1e6, 1e6, 1e6]}]})",
      Vec3::Zero(), &motion, &error))
      << error;
  for (const double t : {0.5e-300, 1.5e-300, 0.5}) {
    const RigidPose pose = motion.Pose(t);
    EXPECT_TRUE(pose.translation.allFinite()) << t;
    EXPECT_LE(pose.translation.cwiseAbs().maxCoeff(), 3e6) << t;
    ExpectProperRotation(pose.rotation);
  }
}

TEST(MotionJson, BadFilesNameTheField) {
  const std::pair<const char*, const char*> cases[] = {
      {R"({"keyframes": [{"time": 0}, {"time": 0}]})", "keyframes[1].time: expected a time after"},
      {R"({"keyframes": [{"time": -1}]})", "keyframes[0].time: expected a finite number >= 0"},
      {R"({"keyframes": [{"tim": 0}]})", "keyframes[0].tim: unknown field (did you mean \"time\"?)"},
      {R"({"keyframes": [{"time": 0, "angle": "45"}]})", "keyframes[0].angle: expected a finite"},
      {R"({"keyframes": [{"time": 0, "axis": [0, 0, 0]}]})", "keyframes[0].axis: expected a non-zero"},
      {R"({"keyframes": [{"time": 0, "translation": [0, 0]}]})",
       "keyframes[0].translation: expected an array of 3"},
      {R"({"keyframes": []})", "keyframes: expected an array of 1 to"},
      {R"({"pivot": [0, 0, null], "keyframes": [{"time": 0}]})", "pivot: expected an array of 3"},
      {R"({})", "keyframes: missing required field"},
      {R"([])", "expected a JSON object"},
      {R"({"keyframes": [{"time": 0}, {"time": 1, "angle": 180}]})",
       "keyframes[1].angle: the orientation turns 179 degrees or more"},
      {R"({"keyframes": [{"time": 0}] )", "line 1"},
  };
  for (const auto& [text, expected] : cases) {
    HeadMotion motion;
    std::string error;
    EXPECT_FALSE(ParseMotionText(text, Vec3::Zero(), &motion, &error)) << text;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    EXPECT_NE(error.find(expected), std::string::npos) << text << " -> " << error;
  }
}

// A 30 cm strand of 20 segments on a head sphere of radius 10 cm: rooted 70 degrees up, growing
// 27 degrees off the scalp toward the side, so that gravity lays it on the sphere (as in
// dynamics_test's film-frame test).
std::shared_ptr<const Body> Head() {
  Body head;
  std::string error;
  EXPECT_TRUE(Body::Create({Sphere{Vec3::Zero(), 0.1, "head"}}, {}, &head, &error)) << error;
  return std::make_shared<const Body>(std::move(head));
}
StrandModel StrandOnSphere(const std::shared_ptr<const Body>& body) {
  const double angle = 1.2;
  const Vec3 normal(std::cos(angle), 0.0, std::sin(angle));
  const Vec3 down_the_scalp(std::sin(angle), 0.0, -std::cos(angle));
  Mat3 frame;
  std::string error;
  EXPECT_TRUE(RootFrameFromTangentNormal(0.5 * normal + down_the_scalp, Vec3(0, 1, 0), &frame,
                                         &error)) << error;
  StrandModel model = testing::MakeStrand(0.3, 20, 0.0, Vec3::Zero(), frame);
  model.root_position = 0.1 * normal;
  model.contact.obstacle = body;
  model.contact.clearance = 1e-3;
  return model;
}

TEST(MovingClamp, CarriesTheObstacleRigidly) {
  const auto shared = Head();
  const StrandModel model = StrandOnSphere(shared);
  const StrandSolution rest = SolveStrand(model);
  const ContactMeasure measure = MeasureContact(model, rest.curvatures);
  ASSERT_GT(measure.samples_in_contact, 0);
  // The whole head moved by a fixed rigid motion: contact exactly as at rest when the obstacle
  // moves with the clamp, none when it stays behind.
  const HeadMotion moved = HeadMotion::Keyframes({{0.0, Vec3(0.3, -0.2, 0.5), Vec3(1, 2, 3), 0.7}},
                                                 Vec3(0, 0, -0.1));
  for (bool carries : {true, false}) {
    StrandDynamics dynamics(model, DynamicsOptions{}, {rest.curvatures, VecX::Zero(60), 0.0});
    ClampMotion clamp = moved.Clamp(model.root_position, model.root_frame);
    clamp.carries_obstacle = carries;
    dynamics.SetClampMotion(clamp);
    const EnergyTerms terms = dynamics.Potential();
    EnergyTerms at_rest;
    StrandEnergy(model).Evaluate(rest.curvatures, nullptr, &at_rest);
    ASSERT_GT(at_rest.contact, 0.0);
    if (carries) {
      EXPECT_NEAR(terms.contact, at_rest.contact, 1e-9 * at_rest.contact);
      EXPECT_NEAR(MeasureContact(dynamics.model(), rest.curvatures).max_clearance_violation,
                  measure.max_clearance_violation, 1e-12);
    } else {
      EXPECT_EQ(terms.contact, 0.0);
    }
  }
}

TEST(Simulation, StillHeadKeepsTheEquilibriumAndIsDeterministic) {
  const auto shared = Head();
  const StrandModel model = StrandOnSphere(shared);
  SolveOptions solve;
  solve.tolerance = 1e-10;
  const StrandSolution rest = SolveStrand(model, solve);
  SimulationOptions options;
  options.duration = 0.25;
  const std::vector<StrandModel> models(3, model);
  const std::vector<VecX> start(3, rest.curvatures);
  Simulation still(models, start, HeadMotion(), options);
  EXPECT_EQ(still.NumFrames(), 7);  // floor(0.25 * 24) + 1
  while (!still.Done()) ASSERT_TRUE(still.Advance(1));
  EXPECT_EQ(still.frame(), 6);
  EXPECT_DOUBLE_EQ(still.summary().time, 0.25);
  EXPECT_EQ(still.summary().halved_steps, 0);
  const double drift = (still.strand(0).state().curvatures - rest.curvatures).norm() /
                       rest.curvatures.norm();
  EXPECT_LT(drift, 1e-6);
  // A shake: the strands move, and with 1 or 2 threads the bits are the same.
  const Vec3 pivot(0, 0, -0.1);
  const HeadMotion shake =
      HeadMotion::Preset(MotionPreset::kShake, pivot, Vec3::UnitZ(), -Vec3::UnitX());
  Simulation one(models, start, shake, options), two(models, start, shake, options);
  while (!one.Done()) {
    ASSERT_TRUE(one.Advance(1));
    ASSERT_TRUE(two.Advance(2));
    EXPECT_EQ(one.summary().kinetic, two.summary().kinetic);
  }
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(one.strand(i).state().curvatures, two.strand(i).state().curvatures);
  }
  EXPECT_GT((one.strand(0).state().curvatures - rest.curvatures).norm(), 1e-3 * rest.curvatures.norm());
  // Options are checked with the field's name.
  SimulationOptions bad = options;
  bad.fps = 0.0;
  std::string why;
  EXPECT_FALSE(bad.IsValid(&why));
  EXPECT_NE(why.find("fps: "), std::string::npos) << why;
}

// The children of a simulated groom: at the rest pose the groom's own strands, bit for bit; under a
// rigid pose the same strands carried rigidly (points and major axes), to float rounding.
TEST(GroomFrameStrands, ChildrenFollowTheMastersAndTheHead) {
  Hairstyle style;
  auto body = std::make_shared<Body>();
  std::string error;
  ASSERT_TRUE(LoadBody(std::string(RINGLET_EXAMPLES_DIR) + "/bodies/mannequin.json", body.get(),
                       &error)) << error;
  style.body = body;
  style.scalp = SphereScalp{};
  style.roots.count = 5;
  ASSERT_TRUE(FindHairType("caucasian", "wavy", &style.hair_type, &error)) << error;
  style.length = 0.15;
  style.segments = 6;
  style.wisps.strands_per_wisp = 3;
  style.wisps.points_per_strand = 8;
  Groom groom;
  ASSERT_TRUE(GroomHairstyle(style, BatchOptions{}, &groom, &error)) << error;
  std::vector<VecX> q;
  for (const StrandSolution& s : groom.solutions) q.push_back(s.curvatures);
  HairCurves still;
  ASSERT_TRUE(GroomFrameStrands(style, groom.masters, q, HeadMotion(), 0.0, &still, &error));
  EXPECT_EQ(still.points, groom.strands.points);
  EXPECT_EQ(still.major_axes, groom.strands.major_axes);
  const Vec3 pivot(0, 0, -0.1);
  const HeadMotion tilted =
      HeadMotion::Keyframes({{0.0, Vec3(0.01, 0.02, 0.03), Vec3(1, 1, 1), 0.5}}, pivot);
  HairCurves moved;
  ASSERT_TRUE(GroomFrameStrands(style, groom.masters, q, tilted, 0.3, &moved, &error));
  const Mat3 r = Rodrigues(Vec3(1, 1, 1), 0.5);
  ASSERT_EQ(moved.points.size(), still.points.size());
  for (size_t i = 0; i < moved.points.size(); ++i) {
    const Vec3 expected = pivot + Vec3(0.01, 0.02, 0.03) + r * (still.points[i].cast<double>() - pivot);
    EXPECT_LT((moved.points[i].cast<double>() - expected).norm(), 1e-7) << i;
    EXPECT_LT((moved.major_axes[i].cast<double>() - r * still.major_axes[i].cast<double>()).norm(), 1e-6);
  }
  // A wrong number of curvature vectors is refused.
  q.pop_back();
  EXPECT_FALSE(GroomFrameStrands(style, groom.masters, q, HeadMotion(), 0.0, &moved, &error));
  EXPECT_NE(error.find("curvatures"), std::string::npos) << error;
}

}  // namespace
}  // namespace ringlet
