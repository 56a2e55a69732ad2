// The length, clump and frizz brushes (styling.h, docs/styling.md "Brushes"): weights against
// hand values, exactly the reached masters changed by exactly the brush's amount, mirror images,
// the clips of earlier cuts rescaled, and the file format (docs/hairstyle-format.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ringlet/body.h"
#include "ringlet/hair_type.h"
#include "ringlet/hairstyle_json.h"
#include "ringlet/strand_geometry.h"
#include "ringlet/styling.h"
#include "ringlet/wisp.h"
#include "test_util.h"

namespace ringlet {
namespace {

// Two straight strands of length L hanging (t = -z) from roots at x = +-0.02 m, mirror images
// across the default head's mid-plane x = 0, far from the body: the straight line is their exact
// equilibrium (gravity along the strand: no moment), so every sample lies on x = +-0.02, y = 0.
StyledHair HangingPair(double length) {
  StyledHair state;
  Hairstyle style;
  auto body = std::make_shared<Body>();
  std::string error;
  EXPECT_TRUE(Body::Create({Sphere{Vec3(0, 0, 1), 0.01, "far away"}}, {}, body.get(), &error));
  style.body = body;
  style.scalp = SphereScalp{};
  state.style = style;
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

Vec3 Tip(const StyledHair& h, int i) {
  return ComputeGeometry(h.masters.models[i], h.solutions[i].curvatures).points.back();
}

StyleOperation BrushOp(StyleOperation::Kind kind, const Vec3& centre, double radius,
                       Brush::Falloff falloff, double strength, bool mirror) {
  StyleOperation op;
  op.kind = kind;
  op.brush.centre = centre;
  op.brush.radius = radius;
  op.brush.falloff = falloff;
  op.brush.strength = strength;
  op.brush.mirror = mirror;
  return op;
}

// The weight by hand: the brush centre (0.03, 0, -0.1) lies 0.01 m beside the right strand's
// sample at arc length 0.1 (L = 0.2: 12 segments, 4 samples each, so s = 0.1 is sample 24 of
// 48), and 0.05 m from the left strand; its mirror image (-0.03, 0, -0.1) likewise. A linear
// brush of radius 0.04 and strength 0.5 weighs 0.5 (1 - 0.01 / 0.04) = 0.375 there and 0 at
// 0.05 m, so a factor 0.6 scales L by 1 + 0.375 (0.6 - 1) = 0.85: 0.17 m. Without mirror the left
// strand keeps its model and equilibrium bit for bit; with mirror both are shortened to 0.17 m
// and hang straight to z = -0.17 (mirror images).
TEST(LengthBrush, WeightsAndMirrorByHand) {
  const StyledHair start = HangingPair(0.2);
  for (bool mirror : {false, true}) {
    SCOPED_TRACE(mirror ? "mirror" : "no mirror");
    StyleOperation op = BrushOp(StyleOperation::Kind::kLength, Vec3(0.03, 0, -0.1), 0.04,
                                Brush::Falloff::kLinear, 0.5, mirror);
    op.factor = 0.6;
    EXPECT_DOUBLE_EQ(MasterBrushWeight(start, 0, op.brush), 0.375);
    EXPECT_EQ(MasterBrushWeight(start, 1, op.brush), mirror ? MasterBrushWeight(start, 0, op.brush)
                                                            : 0.0);
    StyledHair s = start;
    OperationReport report;
    std::string error;
    ASSERT_TRUE(ApplyOperation(&s, op, {}, nullptr, &report, &error)) << error;
    EXPECT_EQ(report.name, "length");
    EXPECT_EQ(report.strands, mirror ? 2 : 1) << report.message;
    EXPECT_NEAR(s.masters.models[0].Length(), 0.17, 1e-15);
    EXPECT_TRUE(s.solutions[0].summary.Converged());
    EXPECT_LT((Tip(s, 0) - Vec3(0.02, 0, -0.17)).norm(), 1e-9) << Tip(s, 0).transpose();
    if (mirror) {
      EXPECT_NEAR(s.masters.models[1].Length(), 0.17, 1e-15);
      EXPECT_LT((Tip(s, 1) - Vec3(-0.02, 0, -0.17)).norm(), 1e-9) << Tip(s, 1).transpose();
    } else {
      EXPECT_EQ(s.masters.models[1].segment_lengths, start.masters.models[1].segment_lengths);
      EXPECT_EQ(s.solutions[1].curvatures, start.solutions[1].curvatures);
    }
  }
}

// Lengthening by a constant brush at strength 1: factor 2 doubles the strand (0.4 m), grown at
// the tip in segments no longer than the original 0.2 / 12 m (as Grow), still hanging straight.
TEST(LengthBrush, LengthensAsGrowDoes) {
  const StyledHair start = HangingPair(0.2);
  StyleOperation op = BrushOp(StyleOperation::Kind::kLength, Vec3(0.02, 0, -0.2), 0.01,
                              Brush::Falloff::kConstant, 1.0, false);
  op.factor = 2.0;
  StyledHair s = start;
  std::string error;
  ASSERT_TRUE(ApplyOperation(&s, op, {}, nullptr, nullptr, &error)) << error;
  const StrandModel& m = s.masters.models[0];
  EXPECT_NEAR(m.Length(), 0.4, 1e-14);
  EXPECT_GE(m.NumSegments(), 24);
  EXPECT_LE(m.NumSegments(), 25);
  for (double l : m.segment_lengths) EXPECT_LE(l, 0.2 / 12 * (1 + 1e-12));
  EXPECT_LT((Tip(s, 0) - Vec3(0.02, 0, -0.4)).norm(), 1e-9);
  EXPECT_EQ(s.masters.models[1].segment_lengths, start.masters.models[1].segment_lengths);
}

// A small groomed head (sphere of radius 0.1 m at the origin), wisps of 4 strands of 12 points.
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
  style.wisps.strands_per_wisp = 4;
  style.wisps.points_per_strand = 12;
  Groom groom;
  EXPECT_TRUE(GroomHairstyle(style, {}, &groom, &error)) << error;
  StyledHair state;
  EXPECT_TRUE(MakeStyledHair(style, groom, &state, &error)) << error;
  return state;
}

// The smallest distance from p to master i's equilibrium samples (root and 4 per segment),
// measured here with SampleCentreline.
double Distance(const StyledHair& h, int i, const Vec3& p) {
  double d = 1e300;
  for (const Vec3& x : SampleCentreline(h.masters.models[i], h.solutions[i].curvatures, 4)) {
    d = std::min(d, (x - p).norm());
  }
  return d;
}

// Each strand's drawn arc length (m), summed in double from its float points.
std::vector<double> DrawnLengths(const HairCurves& c) {
  std::vector<double> out;
  size_t first = 0;
  for (std::uint32_t count : c.point_counts) {
    double s = 0.0;
    for (size_t j = first + 1; j < first + count; ++j) {
      s += (c.points[j] - c.points[j - 1]).cast<double>().norm();
    }
    out.push_back(s);
    first += count;
  }
  return out;
}

// A constant brush of strength 1 and factor 0.7 at a master's root shortens exactly the masters
// with a sample within the radius (measured here) to 0.7 of their length; the others keep model
// and solution bit for bit. Every clipped strand of a shortened wisp is drawn at 0.7
// of its clipped length (or whole, when its new strand is shorter), and the wisps of the other
// masters keep their clip records and points bit for bit.
TEST(LengthBrush, ShortensExactlyTheReachedMastersAndRescalesTheirClips) {
  StyledHair start = SmallHead(24, 0.12);
  const int n = static_cast<int>(start.masters.models.size());
  // Clip records as a cut leaves them (ClipStrands' form: the strand ends in segment j at t),
  // on every third strand: points 0 .. j kept and the end at t of segment j.
  const size_t per_wisp = 4;
  start.strand_cuts.assign(static_cast<size_t>(n) * per_wisp, StrandCut{});
  for (size_t j = 0; j < start.strand_cuts.size(); j += 3) {
    start.strand_cuts[j] = StrandCut{5 + static_cast<int>(j % 5), 0.25};
  }
  std::string error;
  OperationReport report;
  const int picked = 3;
  const double radius = 0.015;
  StyleOperation op = BrushOp(StyleOperation::Kind::kLength, start.masters.roots[picked].position,
                              radius, Brush::Falloff::kConstant, 1.0, false);
  op.factor = 0.7;
  HairCurves before;
  ASSERT_TRUE(StyledStrands(start, &before, &error)) << error;
  StyledHair s = start;
  ASSERT_TRUE(ApplyOperation(&s, op, {}, nullptr, &report, &error)) << error;
  HairCurves after;
  ASSERT_TRUE(StyledStrands(s, &after, &error)) << error;
  const std::vector<double> was = DrawnLengths(before);
  const std::vector<double> now = DrawnLengths(after);
  int reached = 0, outside = 0, rescaled = 0;
  size_t first_before = 0, first_after = 0;
  for (int i = 0; i < n; ++i) {
    const double d = Distance(start, i, op.brush.centre);
    ASSERT_GT(std::abs(d - radius), 1e-9) << "master " << i << " on the brush's edge";
    const bool inside = d < radius;
    if (inside) {
      ++reached;
      EXPECT_NEAR(s.masters.models[i].Length(), 0.7 * start.masters.models[i].Length(), 1e-15);
      EXPECT_TRUE(s.solutions[i].summary.Converged());
    } else {
      ++outside;
      EXPECT_EQ(s.masters.models[i].segment_lengths, start.masters.models[i].segment_lengths);
      EXPECT_EQ(s.solutions[i].curvatures, start.solutions[i].curvatures);
    }
    for (size_t k = 0; k < per_wisp; ++k) {
      const size_t j = i * per_wisp + k;
      const StrandCut old_cut = start.strand_cuts[j];
      const StrandCut new_cut = s.strand_cuts.empty() ? StrandCut{} : s.strand_cuts[j];
      const size_t nb = before.point_counts[j], na = after.point_counts[j];
      if (!inside) {
        EXPECT_EQ(new_cut.segment, old_cut.segment);
        EXPECT_EQ(new_cut.t, old_cut.t);
        ASSERT_EQ(na, nb);
        EXPECT_TRUE(std::equal(after.points.begin() + first_after,
                               after.points.begin() + first_after + na,
                               before.points.begin() + first_before))
            << "strand " << j;
      } else if (old_cut.segment >= 0) {
        ++rescaled;
        EXPECT_LE(now[j], 0.7 * was[j] + 1e-6) << "strand " << j;
        if (new_cut.segment >= 0) {
          EXPECT_GE(now[j], 0.7 * was[j] - 1e-6) << "strand " << j;
        }
      }
      first_before += nb;
      first_after += na;
    }
  }
  EXPECT_GE(reached, 1);
  EXPECT_GE(outside, 10);
  EXPECT_GE(rescaled, 1);
}

// The wisp of master i drawn with the given options (the wisp generator itself).
HairCurves WispWith(const StyledHair& h, int i, const WispOptions& options) {
  HairCurves c;
  AppendWisp(SampleFramedCentreline(h.masters.models[i], h.solutions[i].curvatures,
                                    h.style.master_points_per_segment),
             h.masters.models[i].section, h.masters.wisp_radii[i], options,
             WispSeed(h.style.seed, i), h.style.body.get(), &c);
  return c;
}

// The strands of wisp i of all strands (N strands of m points each).
std::vector<Vec3f> WispPoints(const HairCurves& all, int i, size_t per_wisp, size_t points) {
  const auto begin = all.points.begin() + static_cast<std::ptrdiff_t>(i * per_wisp * points);
  return std::vector<Vec3f>(begin, begin + static_cast<std::ptrdiff_t>(per_wisp * points));
}

// Clump and frizz: a constant brush at strength 0.5 gives the reached masters' wisps the clump
// factor 1 + 0.5 (0.4 - 1) = 0.7 (tip_scale x 0.7) and the frizz amplitude 0 + 0.5 (0.004 - 0) =
// 0.002 m: each such wisp equals the wisp generator's with those options, bit for bit; the other
// wisps are unchanged bit for bit, as are every master's model and solution. A frizz brush
// toward 0 at strength 1 then restores the unfrizzed strands bit for bit.
TEST(ClumpAndFrizzBrushes, SetTheReachedWispsOptions) {
  const StyledHair start = SmallHead(24, 0.12);
  const int n = static_cast<int>(start.masters.models.size());
  const int picked = 3;
  const Vec3 centre = start.masters.roots[picked].position;
  const double radius = 0.015;
  StyleOperation clump = BrushOp(StyleOperation::Kind::kClump, centre, radius,
                                 Brush::Falloff::kConstant, 0.5, false);
  clump.factor = 0.4;
  StyleOperation frizz = BrushOp(StyleOperation::Kind::kFrizz, centre, radius,
                                 Brush::Falloff::kConstant, 0.5, false);
  frizz.frizz_amplitude = 0.004;
  StyledHair s = start;
  std::string error;
  OperationReport report;
  ASSERT_TRUE(ApplyOperation(&s, clump, {}, nullptr, &report, &error)) << error;
  EXPECT_EQ(report.name, "clump");
  ASSERT_TRUE(ApplyOperation(&s, frizz, {}, nullptr, &report, &error)) << error;
  EXPECT_EQ(report.name, "frizz");
  HairCurves before, after;
  ASSERT_TRUE(StyledStrands(start, &before, &error)) << error;
  ASSERT_TRUE(StyledStrands(s, &after, &error)) << error;
  ASSERT_EQ(s.masters.clump_factors.size(), static_cast<size_t>(n));
  ASSERT_EQ(s.masters.frizz_amplitudes.size(), static_cast<size_t>(n));
  int reached = 0;
  for (int i = 0; i < n; ++i) {
    const bool inside = Distance(start, i, centre) < radius;
    EXPECT_EQ(s.masters.clump_factors[i], inside ? 0.7 : 1.0) << "master " << i;
    EXPECT_EQ(s.masters.frizz_amplitudes[i], inside ? 0.002 : 0.0) << "master " << i;
    EXPECT_EQ(s.solutions[i].curvatures, start.solutions[i].curvatures);
    EXPECT_EQ(s.masters.models[i].segment_lengths, start.masters.models[i].segment_lengths);
    const std::vector<Vec3f> got = WispPoints(after, i, 4, 12);
    if (inside) {
      ++reached;
      WispOptions o = start.masters.wisp_options;
      o.tip_scale *= 0.7;
      o.frizz_amplitude = 0.002;
      EXPECT_EQ(got, WispWith(start, i, o).points) << "master " << i;
      EXPECT_NE(got, WispPoints(before, i, 4, 12)) << "master " << i;
    } else {
      EXPECT_EQ(got, WispPoints(before, i, 4, 12)) << "master " << i;
    }
  }
  EXPECT_GE(reached, 1);
  // Smooth the frizz away and undo the clump (factor 1 / 0.7 at full strength: 0.7 / 0.7 = 1).
  frizz.frizz_amplitude = 0.0;
  frizz.brush.strength = 1.0;
  clump.factor = 1.0 / 0.7;
  clump.brush.strength = 1.0;
  ASSERT_TRUE(ApplyOperation(&s, frizz, {}, nullptr, &report, &error)) << error;
  ASSERT_TRUE(ApplyOperation(&s, clump, {}, nullptr, &report, &error)) << error;
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(s.masters.frizz_amplitudes[i], 0.0);
    EXPECT_NEAR(s.masters.clump_factors[i], 1.0, 1e-15);
  }
}

// With mirror, the clump brush at the right strand reaches its mirror image too: both factors
// 1 + 0.375 (0.5 - 1) = 0.8125 (the linear weight of the length test).
TEST(ClumpAndFrizzBrushes, MirrorReachesTheImage) {
  const StyledHair start = HangingPair(0.2);
  StyleOperation op = BrushOp(StyleOperation::Kind::kClump, Vec3(0.03, 0, -0.1), 0.04,
                              Brush::Falloff::kLinear, 0.5, true);
  op.factor = 0.5;
  StyledHair s = start;
  std::string error;
  ASSERT_TRUE(ApplyOperation(&s, op, {}, nullptr, nullptr, &error)) << error;
  ASSERT_EQ(s.masters.clump_factors.size(), 2u);
  EXPECT_DOUBLE_EQ(s.masters.clump_factors[0], 0.8125);
  EXPECT_DOUBLE_EQ(s.masters.clump_factors[1], 0.8125);
}

// The curl brush: a constant brush at strength 1 is Curl on the masters it reaches (selected by
// index, as measured here), bit for bit: natural curvature, wisp radius, clearance and
// equilibrium; the others keep their models and solutions.
TEST(CurlBrush, AtFullStrengthIsCurlOnTheReachedMasters) {
  const StyledHair start = SmallHead(24, 0.12);
  const int n = static_cast<int>(start.masters.models.size());
  StyleOperation op = BrushOp(StyleOperation::Kind::kCurl, start.masters.roots[3].position,
                              0.015, Brush::Falloff::kConstant, 1.0, false);
  op.curl_brushed = true;
  op.curl_brush = op.brush;
  op.curl_radius = 0.01;
  op.curl_pitch = 0.03;
  StyleOperation curl;
  curl.kind = StyleOperation::Kind::kCurl;
  curl.curl_radius = 0.01;
  curl.curl_pitch = 0.03;
  for (int i = 0; i < n; ++i) {
    if (Distance(start, i, op.curl_brush.centre) < 0.015) curl.selection.indices.push_back(i);
  }
  ASSERT_FALSE(curl.selection.indices.empty());
  StyledHair a = start, b = start;
  std::string error;
  OperationReport report;
  ASSERT_TRUE(ApplyOperation(&a, op, {}, nullptr, &report, &error)) << error;
  EXPECT_EQ(report.strands, static_cast<int>(curl.selection.indices.size())) << report.message;
  ASSERT_TRUE(ApplyOperation(&b, curl, {}, nullptr, nullptr, &error)) << error;
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(a.masters.models[i].natural_curvature, b.masters.models[i].natural_curvature) << i;
    EXPECT_EQ(a.masters.wisp_radii[i], b.masters.wisp_radii[i]) << i;
    EXPECT_EQ(a.masters.models[i].contact.clearance, b.masters.models[i].contact.clearance) << i;
    EXPECT_EQ(a.solutions[i].curvatures, b.solutions[i].curvatures) << i;
  }
}

// Part strength, by hand: the linear brush of the length test weighs 0.375 on the right strand
// and, mirrored, on the left one; their natural curvature goes from 0 to 0.375 of the helix's
// (-kappa, 0, tau), kappa = R / (R^2 + c^2), tau = c / (R^2 + c^2), c = p / (2 pi) (R = 0.01 m,
// p = 0.03 m).
TEST(CurlBrush, PartStrengthMovesTheCurvatureByTheWeight) {
  const StyledHair start = HangingPair(0.2);
  StyleOperation op;
  op.kind = StyleOperation::Kind::kCurl;
  op.curl_brushed = true;
  op.curl_brush = BrushOp(StyleOperation::Kind::kCurl, Vec3(0.03, 0, -0.1), 0.04,
                          Brush::Falloff::kLinear, 0.5, true).brush;
  op.curl_radius = 0.01;
  op.curl_pitch = 0.03;
  StyledHair s = start;
  std::string error;
  ASSERT_TRUE(ApplyOperation(&s, op, {}, nullptr, nullptr, &error)) << error;
  const double c = 0.03 / (2 * std::numbers::pi), d = 0.01 * 0.01 + c * c;
  const Vec3 expected = 0.375 * Vec3(-0.01 / d, 0.0, c / d);
  for (int i = 0; i < 2; ++i) {
    EXPECT_LT((s.masters.models[i].natural_curvature - expected).norm(), 1e-12 * expected.norm())
        << s.masters.models[i].natural_curvature.transpose();
    EXPECT_TRUE(s.solutions[i].summary.Converged());
  }
}

TEST(LengthBrush, OperationsParseAndNameBadFields) {
  const auto parse = [](const std::string& text, std::vector<StyleOperation>* ops) {
    std::string error;
    const bool ok = ParseStyleOperations(nlohmann::json::parse(text), ops, &error);
    return ok ? std::string() : error;
  };
  std::vector<StyleOperation> ops;
  ASSERT_EQ(parse(R"({"operations": [
      {"length": {"factor": 0.8, "centre": [0, 0.1, 0], "radius": 0.03}},
      {"clump": {"factor": 2, "centre": [0, 0, 0.1], "radius": 0.05, "strength": 0.5,
                 "falloff": "linear", "mirror": true, "select": {"indices": [1, 2]}}},
      {"frizz": {"amplitude": 0.003, "centre": [0, 0, 0.1], "radius": 0.05,
                 "falloff": "constant"}}]})",
                  &ops),
            "");
  ASSERT_EQ(ops.size(), 3u);
  std::vector<StyleOperation> curls;
  ASSERT_EQ(parse(R"({"operations": [{"curl": {"radius": 0.01, "pitch": 0.02,
      "brush": {"centre": [0, 0, 0.1], "radius": 0.05, "mirror": true}}}]})",
                  &curls),
            "");
  ASSERT_EQ(curls.size(), 1u);
  EXPECT_TRUE(curls[0].curl_brushed);
  EXPECT_EQ(curls[0].curl_brush.centre, Vec3(0, 0, 0.1));
  EXPECT_EQ(curls[0].curl_brush.radius, 0.05);
  EXPECT_TRUE(curls[0].curl_brush.mirror);
  EXPECT_EQ(curls[0].curl_radius, 0.01);
  EXPECT_EQ(ops[0].kind, StyleOperation::Kind::kLength);
  EXPECT_EQ(ops[0].factor, 0.8);
  EXPECT_EQ(ops[0].brush.centre, Vec3(0, 0.1, 0));
  EXPECT_EQ(ops[0].brush.radius, 0.03);
  EXPECT_EQ(ops[0].brush.strength, 1.0);
  EXPECT_EQ(ops[0].brush.falloff, Brush::Falloff::kSmooth);
  EXPECT_FALSE(ops[0].brush.mirror);
  EXPECT_EQ(ops[1].kind, StyleOperation::Kind::kClump);
  EXPECT_EQ(ops[1].factor, 2.0);
  EXPECT_EQ(ops[1].brush.strength, 0.5);
  EXPECT_EQ(ops[1].brush.falloff, Brush::Falloff::kLinear);
  EXPECT_TRUE(ops[1].brush.mirror);
  EXPECT_EQ(ops[1].selection.indices, (std::vector<int>{1, 2}));
  EXPECT_EQ(ops[2].kind, StyleOperation::Kind::kFrizz);
  EXPECT_EQ(ops[2].frizz_amplitude, 0.003);
  EXPECT_EQ(ops[2].brush.falloff, Brush::Falloff::kConstant);

  const std::vector<std::pair<std::string, std::string>> bad = {
      {R"({"length": {"centre": [0, 0, 0], "radius": 0.03}})",
       "operations[0].length.factor: missing"},
      {R"({"length": {"factor": 0, "centre": [0, 0, 0], "radius": 0.03}})",
       "operations[0].length.factor: expected a finite number in (0, 10]"},
      {R"({"clump": {"factor": 11, "centre": [0, 0, 0], "radius": 0.03}})",
       "operations[0].clump.factor: expected a finite number in (0, 10]"},
      {R"({"length": {"factor": 0.5, "radius": 0.03}})", "operations[0].length.centre: missing"},
      {R"({"clump": {"factor": 0.5, "centre": [0, 0, 0]}})", "operations[0].clump.radius: missing"},
      {R"({"clump": {"factor": 0.5, "centre": [0, 0, 0], "radius": 20}})",
       "operations[0].clump.radius: expected a finite number in (0, 10] (m)"},
      {R"({"length": {"factor": 0.5, "centre": [0, 0, 0], "radius": 0.1, "strength": 0}})",
       "operations[0].length.strength: expected a finite number in (0, 1]"},
      {R"({"frizz": {"centre": [0, 0, 0], "radius": 0.1}})",
       "operations[0].frizz.amplitude: missing"},
      {R"({"frizz": {"amplitude": 0.1, "centre": [0, 0, 0], "radius": 0.1}})",
       "operations[0].frizz.amplitude: expected a finite number in [0, 0.05] (m)"},
      {R"({"frizz": {"amplitude": -0.001, "centre": [0, 0, 0], "radius": 0.1}})",
       "operations[0].frizz.amplitude: expected a finite number in [0, 0.05] (m)"},
      {R"({"frizz": {"factor": 2, "amplitude": 0.001, "centre": [0, 0, 0], "radius": 0.1}})",
       "operations[0].frizz.factor: unknown field"},
      {R"({"length": {"amplitude": 2, "factor": 0.5, "centre": [0, 0, 0], "radius": 0.1}})",
       "operations[0].length.amplitude: unknown field"},
      {R"({"clump": {"factor": 0.5, "centre": [0, 0, 0], "radius": 0.1, "falloff": "cubic"}})",
       "operations[0].clump.falloff: expected \"smooth\", \"linear\" or \"constant\""},
      {R"({"curl": {"radius": 0.01, "pitch": 0.02, "brush": {"centre": [0, 0, 0]}}})",
       "operations[0].curl.brush.radius: missing"},
      {R"({"curl": {"radius": 0.01, "pitch": 0.02, "brush": 0.05}})",
       "operations[0].curl.brush: expected an object"},
      {R"({"curl": {"radius": 0.01, "pitch": 0.02, "brush": {"centre": [0, 0, 0],
                    "radius": 0.05, "size": 1}}})",
       "operations[0].curl.brush.size: unknown field"},
  };
  for (const auto& [op, message] : bad) {
    const std::string error = parse("{\"operations\": [" + op + "]}", &ops);
    EXPECT_NE(error.find(message), std::string::npos) << op << "\n  gave: " << error;
  }

  // The library's own checks name the fields too.
  StyleOperation op;
  op.kind = StyleOperation::Kind::kLength;
  op.factor = -1.0;
  std::string why;
  EXPECT_FALSE(op.IsValid(&why));
  EXPECT_NE(why.find("length.factor"), std::string::npos) << why;
  op.factor = 0.5;
  op.brush.radius = 0.0;
  EXPECT_FALSE(op.IsValid(&why));
  EXPECT_NE(why.find("length.radius"), std::string::npos) << why;
  op.kind = StyleOperation::Kind::kFrizz;
  op.brush.radius = 0.1;
  op.frizz_amplitude = 1.0;
  EXPECT_FALSE(op.IsValid(&why));
  EXPECT_NE(why.find("frizz.amplitude"), std::string::npos) << why;
  // A lengthening past kMaxSegments is refused, the state unchanged.
  StyledHair s = HangingPair(0.2);
  s.masters.models[0].segment_lengths.assign(kMaxSegments - 2, 0.2 / (kMaxSegments - 2));
  s.solutions[0].curvatures = VecX::Zero(3 * (kMaxSegments - 2));
  StyleOperation grow = BrushOp(StyleOperation::Kind::kLength, Vec3(0.02, 0, 0), 0.01,
                                Brush::Falloff::kConstant, 1.0, false);
  grow.factor = 2.0;
  const StyledHair copy = s;
  EXPECT_FALSE(ApplyOperation(&s, grow, {}, nullptr, nullptr, &why));
  EXPECT_NE(why.find("length.factor: lengthening master 0"), std::string::npos) << why;
  EXPECT_EQ(s.masters.models[0].segment_lengths, copy.masters.models[0].segment_lengths);
}

}  // namespace
}  // namespace ringlet
