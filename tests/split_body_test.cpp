// A head turning on a still torso (split_body.h, docs/body.md "Head and torso"): the parts by
// name, the placed body's distance, gradient and Hessian against independent formulas (spheres
// and boxes moved by hand), and the dynamics: a strand hanging over a torso sphere stays where
// the statics of the turned root over the unmoved sphere put it, hair resting on the head is
// still carried, the torso follows a walk's translation.
#include "ringlet/split_body.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "ringlet/body.h"
#include "ringlet/body_json.h"
#include "ringlet/contact.h"
#include "ringlet/dynamics.h"
#include "ringlet/energy.h"
#include "ringlet/motion.h"
#include "ringlet/simulate.h"
#include "ringlet/statics.h"
#include "ringlet/strand_geometry.h"
#include "ringlet/strand_model.h"
#include "test_util.h"

namespace ringlet {
namespace {

// Rodrigues: R = I + sin(a) [u]x + (1 - cos(a)) [u]x^2 for a unit axis u.
Mat3 Rodrigues(Vec3 axis, double angle) {
  axis.normalize();
  Mat3 k;
  k << 0, -axis.z(), axis.y(), axis.z(), 0, -axis.x(), -axis.y(), axis.x(), 0;
  return Mat3::Identity() + std::sin(angle) * k + (1.0 - std::cos(angle)) * k * k;
}

std::shared_ptr<const Body> MakeBody(std::vector<Sphere> spheres, double blend = 0.0) {
  auto body = std::make_shared<Body>();
  std::string error;
  EXPECT_TRUE(Body::Create(std::move(spheres), {}, body.get(), &error, blend)) << error;
  return body;
}

TEST(BodyParts, DefaultByName) {
  for (const char* name : {"head", "jaw", "skull", "Face", "ear_left", "left_ear", "Nose2",
                           "eyebrow", "lips", "chin", "cheek-right", "scalp", "cranium", "",
                           "Ears", "eyelashes", "leftEar", "EarLeft", "HEAD", "earrings", "hat",
                           "glasses"}) {
    EXPECT_EQ(DefaultBodyPart(name), BodyPart::kHead) << name;
  }
  for (const char* name : {"neck", "chest", "shoulder_left", "arm_right", "back", "torso",
                           "body", "hand", "belly",
                           // Words that begin like a head word but are not one (whole words).
                           "brown_coat", "earth", "headrest", "eyelet", "facet", "chinese",
                           "lipid", "capsule", "hatch", "early"}) {
    EXPECT_EQ(DefaultBodyPart(name), BodyPart::kTorso) << name;
  }
  // The mannequin: head and jaw turn, the rest is torso; an explicit field wins.
  Body mannequin;
  std::string error;
  ASSERT_TRUE(LoadBody(std::string(RINGLET_EXAMPLES_DIR) + "/bodies/mannequin.json", &mannequin,
                       &error)) << error;
  for (size_t i = 0; i < mannequin.spheres().size(); ++i) {
    const std::string& name = mannequin.spheres()[i].name;
    EXPECT_EQ(mannequin.sphere_part(i),
              name == "head" || name == "jaw" ? BodyPart::kHead : BodyPart::kTorso) << name;
  }
  EXPECT_TRUE(mannequin.HasTorsoPart());
  Sphere neck{Vec3::Zero(), 0.05, "neck"};
  neck.moves_with = BodyPart::kHead;
  const auto head_only = MakeBody({Sphere{Vec3(0, 0, 1), 0.1, "head"}, neck});
  EXPECT_FALSE(head_only->HasTorsoPart());
  EXPECT_EQ(SplitBody::Create(head_only), nullptr);  // moves rigidly, as before
  // Meshes: by name, or the list given to Create (one entry per mesh).
  TriangleMesh box;
  std::vector<Vec3> v;
  for (int i = 0; i < 8; ++i) v.emplace_back(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
  const std::vector<TriangleMesh::Triangle> t = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6},
                                                 {0, 1, 5}, {0, 5, 4}, {2, 6, 7}, {2, 7, 3},
                                                 {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  ASSERT_TRUE(TriangleMesh::Create(v, t, "torso", &box, &error)) << error;
  Body meshes;
  EXPECT_FALSE(Body::Create({}, {box}, &meshes, &error, 0.0, {}, {BodyPart::kHead, {}}));
  EXPECT_EQ(error, "mesh_moves_with: expected one entry per mesh (1) or none, got 2");
  ASSERT_TRUE(Body::Create({}, {box}, &meshes, &error));
  EXPECT_EQ(meshes.mesh_part(0), BodyPart::kTorso);
  ASSERT_TRUE(Body::Create({}, {box}, &meshes, &error, 0.0, {}, {BodyPart::kHead}));
  EXPECT_EQ(meshes.mesh_part(0), BodyPart::kHead);
}

// The mannequin's spheres, placed by hand: head and jaw by x -> R x + b, the rest by x + d.
struct HandPlaced {
  std::vector<Vec3> centres;
  std::vector<double> radii;
};
HandPlaced PlaceByHand(const Body& body, const Mat3& r, const Vec3& b, const Vec3& d) {
  HandPlaced out;
  for (const Sphere& s : body.spheres()) {
    const bool head = s.name == "head" || s.name == "jaw";
    out.centres.push_back(head ? Vec3(r * s.center + b) : Vec3(s.center + d));
    out.radii.push_back(s.radius);
  }
  return out;
}

// The placed mannequin (blend 0 and 5 mm) against the fold of the hand-placed spheres: the minimum,
// or the quadratic smooth minimum folded in file order; gradient and Hessian against central
// differences of that reference.
TEST(SplitBody, PlacedSpheresMatchTheHandPlacedFold) {
  Body loaded;
  std::string error;
  ASSERT_TRUE(LoadBody(std::string(RINGLET_EXAMPLES_DIR) + "/bodies/mannequin.json", &loaded,
                       &error)) << error;
  const Mat3 r = Rodrigues(Vec3(0.2, 0.1, 1.0), 0.9);
  const Vec3 b(0.01, -0.02, 0.015), d(-0.005, 0.01, 0.02);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> box(-0.3, 0.3);
  for (double blend : {0.0, 0.005}) {
    const auto body = MakeBody(loaded.spheres(), blend);
    const auto split = SplitBody::Create(body);
    ASSERT_NE(split, nullptr);
    const auto placed = split->Place(r, b, d);
    EXPECT_EQ(placed->LipschitzBound(), 1.0);
    const HandPlaced hand = PlaceByHand(*body, r, b, d);
    auto reference = [&](const Vec3& x) {
      double best = std::numeric_limits<double>::infinity();
      for (size_t i = 0; i < hand.centres.size(); ++i) {
        const double a = (x - hand.centres[i]).norm() - hand.radii[i];
        if (blend == 0.0) {
          best = std::min(best, a);
          continue;
        }
        // smin(best, a) = a + h (best - a) - k h (1 - h), h = clamp(1/2 + (a - best)/(2k), 0, 1).
        const double h = std::clamp(0.5 + (a - best) / (2.0 * blend), 0.0, 1.0);
        best = std::isinf(best) ? a : a + h * (best - a) - blend * h * (1.0 - h);
      }
      return best;
    };
    int checked = 0;
    for (int n = 0; n < 400; ++n) {
      const Vec3 x(box(random), box(random), box(random) - 0.2);
      Vec3 g;
      Mat3 hessian;
      const double value = placed->SignedDistanceHessian(x, &g, &hessian);
      EXPECT_NEAR(value, reference(x), 1e-14) << x.transpose();
      Vec3 g2;
      EXPECT_EQ(placed->SignedDistance(x, &g2), value);
      EXPECT_EQ(g2, g);
      // Central differences of the reference (step 1e-6 m) away from the kinks of the minimum.
      const double step = 1e-6;
      Vec3 fd;
      for (int a = 0; a < 3; ++a) {
        Vec3 e = Vec3::Zero();
        e(a) = step;
        fd(a) = (reference(x + e) - reference(x - e)) / (2.0 * step);
      }
      if ((fd - g).norm() > 1e-6) {
        EXPECT_EQ(blend, 0.0) << "the smooth union's gradient is continuous: " << x.transpose();
        continue;  // on a kink of the exact minimum
      }
      ++checked;
      Mat3 fh;
      for (int a = 0; a < 3; ++a) {
        Vec3 e = Vec3::Zero();
        e(a) = step;
        Vec3 gp, gm;
        placed->SignedDistance(x + e, &gp);
        placed->SignedDistance(x - e, &gm);
        fh.col(a) = (gp - gm) / (2.0 * step);
      }
      EXPECT_LT((fh - hessian).norm(), 1e-4 * std::max(1.0, hessian.norm())) << x.transpose();
    }
    EXPECT_GT(checked, 300);
  }
}

// A box [-1, 1]^3 scaled by s, as a closed mesh, and its exact signed distance.
TriangleMesh Box(double s, const Vec3& centre, const std::string& name) {
  std::vector<Vec3> v;
  for (int i = 0; i < 8; ++i) {
    v.push_back(centre + s * Vec3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1));
  }
  const std::vector<TriangleMesh::Triangle> t = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6},
                                                 {0, 1, 5}, {0, 5, 4}, {2, 6, 7}, {2, 7, 3},
                                                 {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  TriangleMesh mesh;
  std::string error;
  EXPECT_TRUE(TriangleMesh::Create(v, t, name, &mesh, &error)) << error;
  return mesh;
}
double BoxDistance(const Vec3& p, double s) {
  const Vec3 q = p.cwiseAbs() - Vec3::Constant(s);
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

// Two boxes, "head" and "torso": the placed body is the minimum of the exact box distances at
// the hand-moved points, exactly with exact meshes and within the grid spacing with a grid.
TEST(SplitBody, PlacedMeshesMatchTheMovedBoxes) {
  const double s = 0.05;
  const Vec3 head_centre(0, 0, 0.06), torso_centre(0, 0, -0.06);
  const Mat3 r = Rodrigues(Vec3(0.3, -0.2, 1.0), 0.6);
  const Vec3 b(0.004, 0.002, -0.003), d(0.0, 0.001, 0.002);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> box(-0.12, 0.12);
  for (auto mode : {MeshDistanceOptions::Mode::kExact, MeshDistanceOptions::Mode::kGrid}) {
    MeshDistanceOptions options;
    options.mode = mode;
    options.spacing = 0.004;
    options.threads = 1;
    auto body = std::make_shared<Body>();
    std::string error;
    ASSERT_TRUE(Body::Create({}, {Box(s, head_centre, "head"), Box(s, torso_centre, "torso")},
                             body.get(), &error, 0.0, options)) << error;
    const auto split = SplitBody::Create(body);
    ASSERT_NE(split, nullptr);
    const bool grid = mode == MeshDistanceOptions::Mode::kGrid;
    EXPECT_EQ(split->grid_build_seconds() > 0.0, grid);
    const auto placed = split->Place(r, b, d);
    EXPECT_EQ(placed->LipschitzBound(), grid ? 1.75 : 1.0);
    double worst = 0.0;
    for (int n = 0; n < 300; ++n) {
      const Vec3 x(box(random), box(random), box(random));
      const double reference =
          std::min(BoxDistance(r.transpose() * (x - b) - head_centre, s),
                   BoxDistance(x - d - torso_centre, s));
      if (std::abs(reference) > 0.01) continue;  // the grid's band is clamped farther out
      worst = std::max(worst, std::abs(placed->SignedDistance(x, nullptr) - reference));
    }
    // Exact: rounding; grid: within h (|F - d| <= h for a 1-Lipschitz d, docs/body.md).
    EXPECT_LT(worst, grid ? options.spacing : 1e-14);
    EXPECT_GT(worst, grid ? 1e-5 : -1.0);  // the grid really smooths (the test sees its error)
  }
}

TEST(SplitBody, MoveBodyPartsMovesEachPartRigidly) {
  auto body = std::make_shared<Body>();
  std::string error;
  ASSERT_TRUE(Body::Create({Sphere{Vec3(0, 0, 0.2), 0.05, "head"}, Sphere{Vec3::Zero(), 0.1, "chest"}},
                           {Box(0.05, Vec3(0, 0, 0.06), "head"), Box(0.05, Vec3(0, 0, -0.06), "torso")},
                           body.get(), &error)) << error;
  const Mat3 rh = Rodrigues(Vec3(0, 0, 1), 0.5), rt = Rodrigues(Vec3(1, 0, 0), -0.3);
  const Vec3 th(0.1, 0, 0), tt(0, 0.2, 0);
  Body moved;
  ASSERT_TRUE(MoveBodyParts(*body, rh, th, rt, tt, &moved, &error)) << error;
  EXPECT_LT((moved.spheres()[0].center - (rh * Vec3(0, 0, 0.2) + th)).norm(), 1e-15);
  EXPECT_LT((moved.spheres()[1].center - tt).norm(), 1e-15);
  EXPECT_EQ(moved.sphere_part(1), BodyPart::kTorso);
  for (size_t m = 0; m < 2; ++m) {
    const Mat3& rr = m == 0 ? rh : rt;
    const Vec3& tr = m == 0 ? th : tt;
    ASSERT_EQ(moved.meshes()[m].vertices().size(), body->meshes()[m].vertices().size());
    for (size_t i = 0; i < moved.meshes()[m].vertices().size(); ++i) {
      EXPECT_LT((moved.meshes()[m].vertices()[i] - (rr * body->meshes()[m].vertices()[i] + tr)).norm(),
                1e-15);
    }
    EXPECT_NEAR(moved.meshes()[m].volume(), body->meshes()[m].volume(), 1e-15);
  }
}

// A 30 cm strand hanging from the bottom of a head sphere, pushed sideways (-x) by a chest sphere
// below it; the head turns 60 degrees about the vertical through the root (the turn preset with
// its pivot at the root). The root only twists, so with the torso still the strand stays draped
// where it was: its tip ends where the statics of the turned root over the unmoved chest put it,
// not where they put it with the chest turned too (the old rigid body).
struct Drape {
  std::shared_ptr<const Body> body;
  StrandModel model;
};
Drape MakeDrape() {
  Drape drape;
  drape.body = MakeBody({Sphere{Vec3(0, 0, 0.1), 0.1, "head"},
                         Sphere{Vec3(0.1, 0, -0.15), 0.12, "chest"}});
  Mat3 down;  // (n1, n2, t) = (x, -y, -z)
  down << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  drape.model = testing::MakeStrand(0.3, 15, 0.0, Vec3::Zero(), down);
  drape.model.contact.obstacle = drape.body;
  drape.model.contact.clearance = 1e-3;
  return drape;
}
Vec3 Tip(const StrandModel& model, const VecX& q) { return SampleCentreline(model, q, 1).back(); }

TEST(SplitBody, StrandOverTheStillTorsoStaysWhenTheHeadTurns) {
  const Drape drape = MakeDrape();
  SolveOptions solve;
  solve.tolerance = 1e-10;
  const StrandSolution rest = SolveStrand(drape.model, solve);
  ASSERT_GT(MeasureContact(drape.model, rest.curvatures).samples_in_contact, 0);
  const Vec3 rest_tip = Tip(drape.model, rest.curvatures);
  ASSERT_LT(rest_tip.x(), -0.01);  // pushed aside by the chest
  // The statics of the turned root: over the chest where it is, and over the chest turned too.
  const Mat3 turn = Rodrigues(Vec3::UnitZ(), M_PI / 3);
  StrandModel still = drape.model;
  still.root_frame = turn * drape.model.root_frame;
  const Vec3 still_tip = Tip(still, SolveStrand(still, solve).curvatures);
  StrandModel carried = still;
  carried.contact.obstacle = MakeBody({Sphere{Vec3(0, 0, 0.1), 0.1, "head"},
                                       Sphere{turn * Vec3(0.1, 0, -0.15), 0.12, "chest"}});
  const Vec3 carried_tip = Tip(carried, SolveStrand(carried, solve).curvatures);
  EXPECT_LT((still_tip - rest_tip).norm(), 1e-5);  // a round strand: the twist changes nothing
  ASSERT_GT((carried_tip - still_tip).norm(), 0.02);

  SimulationOptions options;
  options.duration = 1.5;  // turned by 1 s, held since
  const HeadMotion head =
      HeadMotion::Preset(MotionPreset::kTurn, Vec3::Zero(), Vec3::UnitZ(), -Vec3::UnitX());
  Simulation simulation({drape.model}, {rest.curvatures}, head, options);
  double farthest = 0.0;
  while (!simulation.Done()) {
    ASSERT_TRUE(simulation.Advance(1));
    ASSERT_EQ(simulation.summary().failed_steps, 0);
    const StrandDynamics& strand = simulation.strand(0);
    farthest = std::max(farthest, (Tip(strand.model(), strand.state().curvatures) - still_tip).norm());
  }
  const StrandDynamics& strand = simulation.strand(0);
  EXPECT_LT((strand.model().root_frame - still.root_frame).norm(), 1e-12);
  const Vec3 tip = Tip(strand.model(), strand.state().curvatures);
  std::printf("rest tip (%.4f, %.4f, %.4f) m; turned: still chest %.4f m from the turned-root "
              "statics (at most %.4f m on the way), %.4f m from where the turned chest puts it\n",
              rest_tip.x(), rest_tip.y(), rest_tip.z(), (tip - still_tip).norm(), farthest,
              (tip - carried_tip).norm());
  EXPECT_LT((tip - still_tip).norm(), 2e-3) << tip.transpose() << " vs " << still_tip.transpose();
  EXPECT_LT(farthest, 5e-3);
}

// Hair resting on the head part keeps its contact exactly under a rigid head motion with the
// torso part far away; the torso part follows the motion's translation (a walk) and never its
// rotation.
TEST(SplitBody, HeadCarriesItsHairAndTheTorsoOnlyTranslates) {
  const auto body = MakeBody({Sphere{Vec3::Zero(), 0.1, "head"},
                              Sphere{Vec3(0, 0, -0.5), 0.1, "chest"}}, 0.005);
  const auto split = SplitBody::Create(body);
  ASSERT_NE(split, nullptr);
  // A strand lying on the head sphere (as in motion_test's CarriesTheObstacleRigidly).
  const double angle = 1.2;
  const Vec3 normal(std::cos(angle), 0.0, std::sin(angle));
  const Vec3 down_the_scalp(std::sin(angle), 0.0, -std::cos(angle));
  Mat3 frame;
  std::string error;
  ASSERT_TRUE(RootFrameFromTangentNormal(0.5 * normal + down_the_scalp, Vec3(0, 1, 0), &frame,
                                         &error)) << error;
  StrandModel model = testing::MakeStrand(0.3, 20, 0.0, Vec3::Zero(), frame);
  model.root_position = 0.1 * normal;
  model.contact.obstacle = body;
  model.contact.clearance = 1e-3;
  const StrandSolution rest = SolveStrand(model);
  EnergyTerms at_rest;
  StrandEnergy(model).Evaluate(rest.curvatures, nullptr, &at_rest);
  ASSERT_GT(at_rest.contact, 0.0);
  const Vec3 pivot(0, 0, -0.1);
  const Mat3 r = Rodrigues(Vec3(1, 2, 3), 0.7);
  const Vec3 shift(0.03, -0.02, 0.05);
  const HeadMotion moved = HeadMotion::Keyframes({{0.0, shift, Vec3(1, 2, 3), 0.7}}, pivot);
  StrandDynamics dynamics(model, DynamicsOptions{}, {rest.curvatures, VecX::Zero(60), 0.0});
  dynamics.SetClampMotion(moved.Clamp(model.root_position, model.root_frame, split));
  EXPECT_NEAR(dynamics.Potential().contact, at_rest.contact, 1e-9 * at_rest.contact);
  // The chest: translated by the pose's translation only, not turned about the pivot.
  const Obstacle& obstacle = *dynamics.model().contact.obstacle;
  for (const Vec3& offset : {Vec3(0.12, 0, 0), Vec3(0, -0.11, 0.02), Vec3(0, 0, -0.13)}) {
    const Vec3 x = Vec3(0, 0, -0.5) + shift + offset;
    EXPECT_NEAR(obstacle.SignedDistance(x, nullptr), offset.norm() - 0.1, 1e-14);
  }
  // The head: turned about the pivot and translated.
  const Vec3 head_centre = pivot + shift + r * (Vec3::Zero() - pivot);
  EXPECT_NEAR(obstacle.SignedDistance(head_centre + Vec3(0, 0.13, 0), nullptr), 0.03, 1e-14);

  // A walk: after 0.625 s both parts have moved by the walk's translation
  // r(t) [B sin(2 pi t / T) up + C sin(pi t / T) left] (docs/dynamics.md, "Presets").
  const HeadMotion walk = HeadMotion::Preset(MotionPreset::kWalk, pivot, Vec3::UnitZ(), -Vec3::UnitX());
  StrandDynamics walking(model, DynamicsOptions{}, {rest.curvatures, VecX::Zero(60), 0.0});
  walking.SetClampMotion(walk.Clamp(model.root_position, model.root_frame, split));
  for (int step = 0; step < 15; ++step) ASSERT_TRUE(walking.Step().converged);
  const double t = walking.state().time;
  ASSERT_NEAR(t, 15.0 / 24.0, 1e-12);
  const double x = t / 1.0, ramp = x * x * x * (10.0 - 15.0 * x + 6.0 * x * x);
  const Vec3 d = ramp * (0.02 * std::sin(2.0 * M_PI * t / 0.5) * Vec3::UnitZ() +
                         0.015 * std::sin(M_PI * t / 0.5) * -Vec3::UnitX());
  ASSERT_GT(d.norm(), 0.01);
  const Obstacle& walked = *walking.model().contact.obstacle;
  EXPECT_NEAR(walked.SignedDistance(Vec3(0, 0, -0.5) + d + Vec3(0, 0, -0.13), nullptr), 0.03, 1e-14);
  EXPECT_NEAR(walked.SignedDistance(d + Vec3(0, 0, 0.13), nullptr), 0.03, 1e-14);
}

}  // namespace
}  // namespace ringlet
