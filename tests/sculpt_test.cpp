// Brushes (styling.h, docs/styling.md "Brushes"): the falloff, the head's mirror plane, puff
// (roots lifted by the brush) and sculpt (a comb stroke held by inverse statics), and the file
// format of both operations (docs/hairstyle-format.md, "operations").
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ringlet/body.h"
#include "ringlet/hair_type.h"
#include "ringlet/hairstyle_json.h"
#include "ringlet/kirchhoff.h"
#include "ringlet/strand_geometry.h"
#include "ringlet/styling.h"
#include "test_util.h"

namespace ringlet {
namespace {

// The falloff curves at chosen points, by hand: smooth f(x) = 1 - 3x^2 + 2x^3 gives f(0.25) =
// 1 - 0.1875 + 0.03125 = 0.84375 and f(0.5) = 0.5; linear 1 - x; constant 1; 0 from x = 1 on.
TEST(Brush, FalloffCurvesAtChosenPoints) {
  Brush b;
  b.radius = 0.04;
  b.strength = 0.5;
  EXPECT_DOUBLE_EQ(b.Weight(0.0), 0.5);
  EXPECT_DOUBLE_EQ(b.Weight(0.01), 0.5 * 0.84375);
  EXPECT_DOUBLE_EQ(b.Weight(0.02), 0.5 * 0.5);
  EXPECT_EQ(b.Weight(0.04), 0.0);
  EXPECT_EQ(b.Weight(1.0), 0.0);
  EXPECT_EQ(b.Weight(std::nan("")), 0.0);
  b.falloff = Brush::Falloff::kLinear;
  EXPECT_DOUBLE_EQ(b.Weight(0.01), 0.5 * 0.75);
  EXPECT_DOUBLE_EQ(b.Weight(0.03), 0.5 * 0.25);
  b.falloff = Brush::Falloff::kConstant;
  EXPECT_DOUBLE_EQ(b.Weight(0.039), 0.5);
  EXPECT_EQ(b.Weight(0.04), 0.0);
}

// The mid-plane reflection by hand: up z, face +y gives left = up x front = -x, so the plane is
// x = c_x; a head facing +x has left = z x x = +y, so the plane is y = c_y.
TEST(Brush, MirrorAcrossTheHeadsMidPlane) {
  HeadFrame head;
  head.centre = Vec3(0.01, 0.02, 0.1);
  const Vec3 p(0.05, 0.3, 0.2);
  EXPECT_LT((MirrorAcrossHead(head, p) - Vec3(-0.03, 0.3, 0.2)).norm(), 1e-15);
  EXPECT_LT((MirrorVectorAcrossHead(head, Vec3(1, 2, 3)) - Vec3(-1, 2, 3)).norm(), 1e-15);
  head.front = Vec3(2, 0, 0);
  EXPECT_LT((MirrorAcrossHead(head, p) - Vec3(0.05, -0.26, 0.2)).norm(), 1e-15);
  EXPECT_LT((MirrorVectorAcrossHead(head, Vec3(1, 2, 3)) - Vec3(1, -2, 3)).norm(), 1e-15);
}

// A small groomed head (the styling tests' sphere head, radius 0.1 m at the origin).
StyledHair SmallHead(int count, double length) {
  Hairstyle style;
  auto body = std::make_shared<Body>();
  std::string error;
  EXPECT_TRUE(Body::Create({Sphere{Vec3::Zero(), 0.1, "head"}}, {}, body.get(), &error)) << error;
  style.body = body;
  style.scalp = SphereScalp{};
  style.roots.count = count;
  style.roots.seed = 5;
  EXPECT_TRUE(FindHairType("caucasian", "straight", &style.hair_type, &error)) << error;
  style.length = length;
  style.segments = 10;
  style.wisps.strands_per_wisp = 2;
  style.wisps.points_per_strand = 12;
  Groom groom;
  EXPECT_TRUE(GroomHairstyle(style, {}, &groom, &error)) << error;
  StyledHair state;
  EXPECT_TRUE(MakeStyledHair(style, groom, &state, &error)) << error;
  return state;
}

bool SameBits(const StrandModel& a, const StrandModel& b) {
  return a.root_frame == b.root_frame && a.rest_curvatures.size() == b.rest_curvatures.size() &&
         (a.rest_curvatures.size() == 0 || a.rest_curvatures == b.rest_curvatures) &&
         a.contact.support_offsets == b.contact.support_offsets;
}

double Tilt(const StyledHair& s, int i) {
  const Vec3 t = s.masters.models[i].root_frame.col(2);
  return std::acos(std::clamp(t.dot(s.masters.roots[i].normal.normalized()), -1.0, 1.0));
}

// A constant brush of strength 1 centred on a root turns its tangent toward the scalp normal by
// exactly the angle (the tilt is measured independently from the frame and the normal); roots
// outside the brush keep their models and equilibria bit for bit. The mirrored brush lifts the
// same root from the other side.
TEST(Brush, PuffLiftsTheRootsUnderTheBrushOnly) {
  const StyledHair start = SmallHead(24, 0.12);
  const int picked = 3;
  const Vec3 root = start.masters.roots[picked].position;
  const double angle = 0.15;
  ASSERT_GT(Tilt(start, picked), angle);  // the comb's tilt leaves room to lift by 0.15 rad
  for (bool mirrored : {false, true}) {
    SCOPED_TRACE(mirrored ? "mirrored brush" : "brush");
    StyleOperation op;
    op.kind = StyleOperation::Kind::kPuff;
    op.puff_angle = angle;
    op.puff_brush.centre = mirrored ? MirrorAcrossHead(HairstyleHead(start.style), root) : root;
    op.puff_brush.radius = 0.012;
    op.puff_brush.falloff = Brush::Falloff::kConstant;
    op.puff_brush.mirror = mirrored;
    StyledHair s = start;
    OperationReport report;
    std::string error;
    ASSERT_TRUE(ApplyOperation(&s, op, {}, nullptr, &report, &error)) << error;
    EXPECT_EQ(report.name, "puff");
    EXPECT_NEAR(Tilt(s, picked), Tilt(start, picked) - angle, 1e-12);
    EXPECT_TRUE(s.solutions[picked].summary.Converged());
    EXPECT_NE(s.solutions[picked].curvatures, start.solutions[picked].curvatures);
    int untouched = 0;
    for (int i = 0; i < static_cast<int>(s.masters.models.size()); ++i) {
      const Vec3 r = s.masters.roots[i].position;
      const bool outside = (r - root).norm() >= 0.012 &&
                           (!mirrored || (r - op.puff_brush.centre).norm() >= 0.012);
      if (!outside) continue;
      ++untouched;
      EXPECT_TRUE(SameBits(s.masters.models[i], start.masters.models[i])) << "master " << i;
      EXPECT_EQ(s.solutions[i].curvatures, start.solutions[i].curvatures) << "master " << i;
    }
    EXPECT_GT(untouched, 15);
  }
}

// Two straight strands hanging from roots mirrored across the mid-plane x = 0 (default head:
// up z, face +y), no contact: the styled state of the mirror test.
StyledHair MirroredPair(double length) {
  StyledHair state;
  Hairstyle style;
  auto body = std::make_shared<Body>();
  std::string error;
  EXPECT_TRUE(Body::Create({Sphere{Vec3(0, 0, 1), 0.01, "far away"}}, {}, body.get(), &error));
  style.body = body;
  style.scalp = SphereScalp{};
  state.style = style;
  // Right strand: t = -z, n1 = +x, n2 = t x n1 = -y. Its mirror image (x -> -x) has n1 = -x,
  // t = -z and n2 = t x n1 = +y: a proper frame whose n1 is the reflected n1.
  Mat3 right, left;
  right << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  left << -1, 0, 0, 0, 1, 0, 0, 0, -1;
  for (const auto& [x, frame] : {std::pair{0.02, right}, std::pair{-0.02, left}}) {
    StrandModel m = testing::MakeStrand(length, 12, 0.0, Vec3::Zero(), frame);
    m.root_position = Vec3(x, 0, 0);
    state.masters.models.push_back(m);
    Root root;
    root.position = m.root_position;
    root.normal = Vec3(0, 0, -1);
    root.frame = frame;
    state.masters.roots.push_back(root);
    state.masters.layers.push_back(0);
    state.masters.wisp_radii.push_back(0.0);
  }
  state.solutions = SolveStrands(state.masters.models, state.style.solver);
  return state;
}

// A sculpt stroke near the right strand's tip with mirror on: the right strand's tip moves
// toward the stroke (at least half the displacement its target point was given), its new shape
// balances by Kirchhoff's equations (an independent quadrature of the forces and moments,
// kirchhoff.h) with the rest shape inverse statics chose, and the left strand becomes the mirror
// image of the right one to within the inversion's 1e-6 L.
TEST(Brush, SculptHoldsTheStrokeAndMirrorsIt) {
  const double length = 0.2;
  const StyledHair start = MirroredPair(length);
  StyleOperation op;
  op.kind = StyleOperation::Kind::kSculpt;
  op.sculpt.brush.centre = Vec3(0.02, 0.0, -0.18);
  op.sculpt.brush.radius = 0.035;
  op.sculpt.brush.mirror = true;
  const Vec3 d(0.03, 0.02, 0.0);
  op.sculpt.to = op.sculpt.brush.centre + d;
  StyledHair s = start;
  OperationReport report;
  std::string error;
  ASSERT_TRUE(ApplyOperation(&s, op, {}, nullptr, &report, &error)) << error;
  EXPECT_EQ(report.strands, 2) << report.message;
  const auto tip = [](const StyledHair& h, int i) {
    return ComputeGeometry(h.masters.models[i], h.solutions[i].curvatures).points.back();
  };
  // The tip sits 0.02 m from the brush centre: its target moved by w d, w = f(0.02 / 0.035).
  const double x = 0.02 / 0.035;
  const double w = 1.0 - x * x * (3.0 - 2.0 * x);
  const Vec3 moved = tip(s, 0) - tip(start, 0);
  EXPECT_GT(moved.dot(d.normalized()), 0.5 * w * d.norm()) << moved.transpose();
  for (int i = 0; i < 2; ++i) {
    EXPECT_TRUE(s.masters.models[i].HasRestShape());
    EXPECT_TRUE(s.solutions[i].summary.Converged());
    EXPECT_LT(KirchhoffResidual(s.masters.models[i], s.solutions[i].curvatures), 1e-8);
  }
  const HeadFrame& head = HairstyleHead(s.style);
  const std::vector<Vec3> right =
      SampleCentreline(s.masters.models[0], s.solutions[0].curvatures, 4);
  const std::vector<Vec3> left = SampleCentreline(s.masters.models[1], s.solutions[1].curvatures, 4);
  ASSERT_EQ(right.size(), left.size());
  double worst = 0.0;
  for (size_t j = 0; j < right.size(); ++j) {
    worst = std::max(worst, (MirrorAcrossHead(head, right[j]) - left[j]).norm());
  }
  EXPECT_LT(worst, 1e-6 * length);
  EXPECT_GT((tip(s, 1) - tip(start, 1)).norm(), 0.5 * w * d.norm());  // it moved at all

  // Without mirror the left strand is not touched (bit for bit); the stroke replays exactly.
  op.sculpt.brush.mirror = false;
  StyledHair a = start, b = start;
  ASSERT_TRUE(ApplyOperation(&a, op, {}, nullptr, &report, &error)) << error;
  EXPECT_EQ(report.strands, 1);
  ASSERT_TRUE(ApplyOperation(&b, op, {}, nullptr, &report, &error)) << error;
  EXPECT_EQ(a.solutions[1].curvatures, start.solutions[1].curvatures);
  EXPECT_FALSE(a.masters.models[1].HasRestShape());
  EXPECT_EQ(a.solutions[0].curvatures, b.solutions[0].curvatures);
  EXPECT_EQ(a.masters.models[0].rest_curvatures, b.masters.models[0].rest_curvatures);
}

// The sculpted rest shape is physical: cutting the sculpted strand lets the shortened hair
// spring back (the rest shape stays with the kept segments), and a stroke on a head with
// contact keeps the masters outside the body's clearance layer.
TEST(Brush, SculptOnAHeadWithContact) {
  const StyledHair start = SmallHead(24, 0.15);
  const int picked = 7;
  const StrandModel& m0 = start.masters.models[picked];
  const std::vector<Vec3> before = SampleCentreline(m0, start.solutions[picked].curvatures, 4);
  StyleOperation op;
  op.kind = StyleOperation::Kind::kSculpt;
  op.sculpt.brush.centre = before.back();
  op.sculpt.brush.radius = 0.05;
  // Drag the tip 2 cm sideways along the head (the head's left axis is -x).
  op.sculpt.to = before.back() + Vec3(0.0, 0.02, 0.0);
  StyledHair s = start;
  OperationReport report;
  std::string error;
  ASSERT_TRUE(ApplyOperation(&s, op, {}, nullptr, &report, &error)) << error;
  EXPECT_GE(report.strands, 1);
  EXPECT_EQ(report.unconverged, 0) << report.message;
  const Vec3 moved = SampleCentreline(s.masters.models[picked], s.solutions[picked].curvatures, 4)
                         .back() -
                     before.back();
  EXPECT_GT(moved.y(), 0.01) << moved.transpose();
  // The deepest sample below the clearance surface (m, < 0 inside), over every master.
  const auto deepest = [](const StyledHair& h) {
    double depth = 0.0;
    for (size_t i = 0; i < h.masters.models.size(); ++i) {
      const StrandModel& m = h.masters.models[i];
      for (const Vec3& p : SampleCentreline(m, h.solutions[i].curvatures, 4)) {
        depth = std::min(depth, p.norm() - 0.1 - m.contact.clearance);
      }
    }
    return depth;
  };
  // The roots sit on the scalp, inside their clearance layer (hull layers: the layer offset
  // is part of the clearance), so the groom starts with samples below the clearance surface:
  // the stroke must not push any master deeper than the groom's deepest.
  EXPECT_GE(deepest(s), deepest(start) - 1e-3 * 0.15);
  // The stroked master: no sample pushed into the clearance layer beyond where it was (or, for
  // a sample that was outside, beyond the penalty's documented penetration kContactPenetration L
  // = 1e-3 L at 10 weights per length; 2e-3 L allowed). The depths are measured here from the
  // sphere (|p| - 0.1 m) and the clearance, not by the contact code.
  const StrandModel& m = s.masters.models[picked];
  const std::vector<Vec3> after = SampleCentreline(m, s.solutions[picked].curvatures, 4);
  ASSERT_EQ(after.size(), before.size());
  for (size_t j = 0; j < after.size(); ++j) {
    const double was = std::min(0.0, before[j].norm() - 0.1 - m0.contact.clearance);
    EXPECT_GT(after[j].norm() - 0.1 - m.contact.clearance, was - 2e-3 * m.Length())
        << "sample " << j;
  }
}

// The file format: both operations parse with their defaults, and bad fields are named.
TEST(Brush, OperationsParseAndNameBadFields) {
  const auto parse = [](const std::string& text, std::vector<StyleOperation>* ops) {
    std::string error;
    const bool ok = ParseStyleOperations(nlohmann::json::parse(text), ops, &error);
    return ok ? std::string() : error;
  };
  std::vector<StyleOperation> ops;
  ASSERT_EQ(parse(R"({"operations": [
      {"sculpt": {"from": [0, 0.1, 0], "to": [0, 0.12, 0.01], "radius": 0.03}},
      {"puff": {"angle": 0.2, "centre": [0, 0, 0.1], "radius": 0.05, "strength": 0.5,
                "falloff": "linear", "mirror": true, "select": {"polar_angle": [0, 1]}}}]})",
                  &ops),
            "");
  ASSERT_EQ(ops.size(), 2u);
  EXPECT_EQ(ops[0].kind, StyleOperation::Kind::kSculpt);
  EXPECT_EQ(ops[0].sculpt.brush.centre, Vec3(0, 0.1, 0));
  EXPECT_EQ(ops[0].sculpt.to, Vec3(0, 0.12, 0.01));
  EXPECT_EQ(ops[0].sculpt.brush.radius, 0.03);
  EXPECT_EQ(ops[0].sculpt.brush.strength, 1.0);
  EXPECT_EQ(ops[0].sculpt.brush.falloff, Brush::Falloff::kSmooth);
  EXPECT_FALSE(ops[0].sculpt.brush.mirror);
  EXPECT_EQ(ops[1].kind, StyleOperation::Kind::kPuff);
  EXPECT_EQ(ops[1].puff_angle, 0.2);
  EXPECT_EQ(ops[1].puff_brush.strength, 0.5);
  EXPECT_EQ(ops[1].puff_brush.falloff, Brush::Falloff::kLinear);
  EXPECT_TRUE(ops[1].puff_brush.mirror);
  EXPECT_EQ(ops[1].selection.max_polar_angle, 1.0);

  const std::vector<std::pair<std::string, std::string>> bad = {
      {R"({"sculpt": {"to": [0, 0, 0], "radius": 0.03}})", "operations[0].sculpt.from: missing"},
      {R"({"sculpt": {"from": [0, 0, 0], "radius": 0.03}})", "operations[0].sculpt.to: missing"},
      {R"({"sculpt": {"from": [0, 0, 0], "to": [0, 0, 0]}})",
       "operations[0].sculpt.radius: missing"},
      {R"({"sculpt": {"from": [0, 0, 0], "to": [0, 0, 0], "radius": 0}})",
       "operations[0].sculpt.radius: expected a finite number in (0, 10] (m)"},
      {R"({"sculpt": {"from": [0, 0, 0], "to": [20, 0, 0], "radius": 0.1}})",
       "operations[0].sculpt.to: expected a point within 10 m"},
      {R"({"sculpt": {"from": [0, 0, 0], "to": [0, 0, 0], "radius": 0.1, "strength": 2}})",
       "operations[0].sculpt.strength: expected a finite number in (0, 1]"},
      {R"({"sculpt": {"from": [0, 0, 0], "to": [0, 0, 0], "radius": 0.1, "falloff": "cubic"}})",
       "operations[0].sculpt.falloff: expected \"smooth\", \"linear\" or \"constant\""},
      {R"({"sculpt": {"from": [0, 0, 0], "to": [0, 0, 0], "radius": 0.1, "mirror": 1}})",
       "operations[0].sculpt.mirror: expected true or false"},
      {R"({"sculpt": {"from": [0, 0], "to": [0, 0, 0], "radius": 0.1}})",
       "operations[0].sculpt.from: expected an array of 3 finite numbers"},
      {R"({"puff": {"centre": [0, 0, 0], "radius": 0.1}})", "operations[0].puff.angle: missing"},
      {R"({"puff": {"angle": 2, "centre": [0, 0, 0], "radius": 0.1}})",
       "operations[0].puff.angle: expected a finite number in [-pi/2, pi/2]"},
      {R"({"puff": {"angle": 0.1, "radius": 0.1}})", "operations[0].puff.centre: missing"},
      {R"({"puff": {"angle": 0.1, "centre": [0, 0, 0], "radius": 0.1, "size": 1}})",
       "operations[0].puff.size: unknown field"},
  };
  for (const auto& [op, message] : bad) {
    const std::string error = parse("{\"operations\": [" + op + "]}", &ops);
    EXPECT_NE(error.find(message), std::string::npos) << op << "\n  gave: " << error;
  }

  // The library's own checks (ApplyOperation on operations made in code) name the fields too.
  StyleOperation op;
  op.kind = StyleOperation::Kind::kSculpt;
  op.sculpt.brush.radius = -1.0;
  std::string why;
  EXPECT_FALSE(op.IsValid(&why));
  EXPECT_NE(why.find("sculpt.radius"), std::string::npos) << why;
  op.sculpt.brush.radius = 0.1;
  op.sculpt.brush.centre = Vec3(std::nan(""), 0, 0);
  EXPECT_FALSE(op.IsValid(&why));
  EXPECT_NE(why.find("sculpt.from"), std::string::npos) << why;
  op.kind = StyleOperation::Kind::kPuff;
  op.puff_angle = 3.0;
  EXPECT_FALSE(op.IsValid(&why));
  EXPECT_NE(why.find("puff.angle"), std::string::npos) << why;
}

}  // namespace
}  // namespace ringlet
