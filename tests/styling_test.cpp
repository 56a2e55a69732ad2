// Virtual hairdressing (styling.h): wet, dry, cut, curl and grow on small hairstyles on a sphere
// head and on single strands.
#include "ringlet/styling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>

#include "ringlet/body.h"
#include "ringlet/hair_type.h"
#include "ringlet/strand_geometry.h"
#include "test_util.h"

namespace ringlet {
namespace {

// A small hairstyle: `count` masters of `length` on the default sphere scalp (radius 0.1 m,
// centre at the origin), colliding with the head sphere.
Hairstyle SmallStyle(const std::string& origin, const std::string& curl, int count,
                     double length) {
  Hairstyle style;
  auto body = std::make_shared<Body>();
  std::string error;
  EXPECT_TRUE(Body::Create({Sphere{Vec3::Zero(), 0.1, "head"}}, {}, body.get(), &error)) << error;
  style.body = body;
  style.scalp = SphereScalp{};
  style.roots.count = count;
  style.roots.seed = 3;
  EXPECT_TRUE(FindHairType(origin, curl, &style.hair_type, &error)) << error;
  style.length = length;
  style.segments = 12;
  style.wisps.strands_per_wisp = 4;
  style.wisps.points_per_strand = 16;
  return style;
}

StyledHair Groomed(const Hairstyle& style) {
  Groom groom;
  std::string error;
  EXPECT_TRUE(GroomHairstyle(style, {}, &groom, &error)) << error;
  StyledHair state;
  EXPECT_TRUE(MakeStyledHair(style, groom, &state, &error)) << error;
  return state;
}

// One strand hanging from the origin, root tangent -z, without contact: a StyledHair of one
// master (styling needs roots, layers and wisp radii besides the model).
StyledHair SingleStrand(const Vec3& natural, double length, int segments, const Vec3& gravity) {
  StyledHair state;
  state.style = SmallStyle("caucasian", "curly", 1, length);
  state.style.solver.tolerance = 1e-9;
  Mat3 frame;
  frame << 1, 0, 0,  //
      0, -1, 0,      //
      0, 0, -1;      // columns n1 = x, n2 = -y, t = -z: proper (det +1)
  StrandModel m = testing::MakeStrand(length, segments, 0.0, natural, frame);
  m.gravity = gravity;
  state.masters.models = {m};
  state.masters.roots = {Root{}};
  state.masters.layers = {0};
  state.masters.wisp_radii = {0.0};
  state.solutions = SolveStrands(state.masters.models, state.style.solver);
  return state;
}

double MeanTipZ(const StyledHair& s) {
  double z = 0.0;
  for (size_t i = 0; i < s.solutions.size(); ++i) {
    z += ComputeGeometry(s.masters.models[i], s.solutions[i].curvatures).points.back().z();
  }
  return z / s.solutions.size();
}

double MeanPointZ(const StyledHair& s) {
  double z = 0.0;
  int n = 0;
  for (size_t i = 0; i < s.solutions.size(); ++i) {
    for (const Vec3& p : SampleCentreline(s.masters.models[i], s.solutions[i].curvatures, 4)) {
      z += p.z();
      ++n;
    }
  }
  return z / n;
}

Vec3 Tip(const StyledHair& s, int i) {
  return ComputeGeometry(s.masters.models[i], s.solutions[i].curvatures).points.back();
}

TEST(StylingTest, WetHairSagsLower) {
  StyledHair state = Groomed(SmallStyle("caucasian", "wavy", 20, 0.25));
  const double tip0 = MeanTipZ(state), mean0 = MeanPointZ(state);
  OperationReport report;
  std::string error;
  ASSERT_TRUE(Wet(&state, {}, {}, &report, &error)) << error;
  EXPECT_EQ(report.unconverged, 0) << report.message;
  const double tip1 = MeanTipZ(state), mean1 = MeanPointZ(state);
  // Wet hair: E I drops to 0.1 * 1.13^4 = 0.163 of dry while the weight per length grows by
  // (1300 + 998.2 (1.13^2 - 1)) / 1300 = 1.213, so it hangs lower.
  EXPECT_LT(tip1, tip0 - 1e-3);
  EXPECT_LT(mean1, mean0 - 1e-3);
  RecordProperty("mean_tip_z_dry", std::to_string(tip0));
  RecordProperty("mean_tip_z_wet", std::to_string(tip1));
  std::printf("wet: mean tip z %.4f -> %.4f m, mean z %.4f -> %.4f m\n", tip0, tip1, mean0,
              mean1);
}

TEST(StylingTest, WetMaterialFollowsTheDocumentedModel) {
  StyledHair state = SingleStrand(Vec3(-60.0, 0.0, 20.0), 0.2, 20, Vec3(0, 0, -9.81));
  const StrandModel dry = state.masters.models[0];
  std::string error;
  ASSERT_TRUE(Wet(&state, {}, {}, nullptr, &error)) << error;
  const StrandModel& wet = state.masters.models[0];
  // Robbins (2002): E / 10, radius x 1.13; water fills the swelling at 998.2 kg/m^3.
  EXPECT_DOUBLE_EQ(wet.material.young_modulus, dry.material.young_modulus / 10.0);
  EXPECT_DOUBLE_EQ(wet.section.a, 1.13 * dry.section.a);
  EXPECT_DOUBLE_EQ(wet.section.MeanRadius(), 1.13 * dry.section.MeanRadius());
  const double mass_dry = dry.material.density * dry.section.Area();
  const double water = 998.2 * (1.13 * 1.13 - 1.0) * dry.section.Area();
  EXPECT_NEAR(wet.material.density * wet.section.Area(), mass_dry + water, 1e-12 * mass_dry);
}

// End-to-end distance over length of a strand: 1 for a straight hanging strand, smaller for curls.
double Extension(const StyledHair& s) {
  const StrandGeometry g = ComputeGeometry(s.masters.models[0], s.solutions[0].curvatures);
  return (g.points.back() - g.points.front()).norm() / s.masters.models[0].Length();
}

TEST(StylingTest, WetCurlsStretch) {
  // A ringlet of the "curly" preset's scale: R = 1 cm, p = 2 cm, hanging 30 cm under gravity.
  const HelixCurvature h = CurvatureFromHelix(0.01, 0.02);
  StyledHair state = SingleStrand(Vec3(-h.curvature, 0.0, h.torsion), 0.3, 40, Vec3(0, 0, -9.81));
  ASSERT_TRUE(state.solutions[0].summary.Converged());
  const double dry = Extension(state);
  std::string error;
  ASSERT_TRUE(Wet(&state, {}, {}, nullptr, &error)) << error;
  ASSERT_TRUE(state.solutions[0].summary.Converged());
  const double wet = Extension(state);
  std::printf("curl extension (end-to-end / length): dry %.4f, wet %.4f\n", dry, wet);
  // Zero gravity would give the helix's own c / sqrt(R^2 + c^2) = 0.303 (c = p / 2 pi); the
  // load stretches it, and wet hair ~6x softer and 21% heavier much more.
  EXPECT_GT(dry, 0.303);
  EXPECT_GT(wet, dry + 0.05);
}

TEST(StylingTest, DryUndoesWet) {
  StyledHair state = Groomed(SmallStyle("caucasian", "curly", 20, 0.2));
  const StyledHair before = state;
  std::string error;
  OperationReport wet_report, dry_report;
  ASSERT_TRUE(Wet(&state, {}, {}, &wet_report, &error)) << error;
  ASSERT_TRUE(Dry(&state, {}, &dry_report, &error)) << error;
  EXPECT_FALSE(state.wet);
  double worst = 0.0;
  for (size_t i = 0; i < state.masters.models.size(); ++i) {
    const StrandModel& a = before.masters.models[i];
    const StrandModel& b = state.masters.models[i];
    // Bit for bit: restored, not recomputed.
    EXPECT_EQ(a.section.a, b.section.a);
    EXPECT_EQ(a.section.b, b.section.b);
    EXPECT_EQ(a.material.young_modulus, b.material.young_modulus);
    EXPECT_EQ(a.material.density, b.material.density);
    EXPECT_EQ(a.material.poisson_ratio, b.material.poisson_ratio);
    EXPECT_EQ(a.contact.clearance, b.contact.clearance);
    EXPECT_EQ(a.segment_lengths, b.segment_lengths);
    EXPECT_EQ(a.natural_curvature, b.natural_curvature);
    worst = std::max(worst, (Tip(before, i) - Tip(state, i)).norm());
  }
  std::printf("dry(wet(x)): largest tip distance to x %.3g m\n", worst);
  // Same equilibrium to the groom's solver tolerance (residual 1e-6): tips within 0.1 mm.
  EXPECT_LT(worst, 1e-4);
}

TEST(StylingTest, CutShortensByTheCutLengthAndTipsRise) {
  StyledHair state = Groomed(SmallStyle("asian", "straight", 20, 0.3));
  const StyledHair before = state;
  const double z = -0.12;
  std::string error;
  OperationReport report;
  ASSERT_TRUE(CutBelow(&state, z, {}, {}, &report, &error)) << error;
  std::printf("%s\n", report.message.c_str());
  ASSERT_GT(report.strands, 3);  // not vacuous: several strands hung below z
  CutRegion plane;
  plane.offset = z;
  int cut = 0;
  double lowest_tip = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < state.masters.models.size(); ++i) {
    const StrandModel& old_model = before.masters.models[i];
    const VecX& old_q = before.solutions[i].curvatures;
    const double l_prev = old_model.Length();
    const double l_new = state.masters.models[i].Length();
    if (l_new == l_prev) continue;
    ++cut;
    // l_new = l_prev - l_cut with l_cut the arc length below the crossing.
    const double s = CutArcLength(old_model, old_q, plane);
    const double l_cut = l_prev - s;
    EXPECT_NEAR(l_new, l_prev - l_cut, 1e-12);
    // The crossing lies on the plane (bisection on the exact helix)...
    const FramedCentreline dense = SampleFramedCentreline(old_model, old_q, 400);
    // ... and agrees with an independent search: the first sample below z on a dense polyline,
    // linearly interpolated (error ~ spacing^2 curvature, below 1e-5 m here).
    double s_dense = -1.0;
    for (int j = 1; j < dense.NumPoints(); ++j) {
      if (dense.points[j].z() < z) {
        const double z0 = dense.points[j - 1].z(), z1 = dense.points[j].z();
        const double t = (z0 - z) / (z0 - z1);
        s_dense = dense.arc_lengths[j - 1] + t * (dense.arc_lengths[j] - dense.arc_lengths[j - 1]);
        break;
      }
    }
    EXPECT_NEAR(s, s_dense, 1e-5);
    const Vec3 old_at_cut = ComputeGeometry(TruncateModel(old_model, s), VecX(old_q.head(
        3 * TruncateModel(old_model, s).NumSegments()))).points.back();
    EXPECT_NEAR(old_at_cut.z(), z, 1e-12);
    // The lighter strand rises: its tip ends above the cut plane (the paper's point).
    const double tip_z = Tip(state, static_cast<int>(i)).z();
    EXPECT_GT(tip_z, z);
    lowest_tip = std::min(lowest_tip, tip_z);
  }
  EXPECT_EQ(cut, report.strands);
  std::printf("cut at z = %.3f: %d strands, lowest tip after re-solve %.4f m\n", z, cut,
              lowest_tip);
}

TEST(StylingTest, SettledCutPutsTipsOnThePlane) {
  StyledHair state = Groomed(SmallStyle("asian", "straight", 20, 0.3));
  const StyledHair before = state;
  const double z = -0.12;
  CutOptions options;
  options.settle = true;
  options.tolerance = 5e-4;
  std::string error;
  OperationReport report;
  ASSERT_TRUE(CutBelow(&state, z, options, {}, &report, &error)) << error;
  std::printf("%s\n", report.message.c_str());
  EXPECT_GT(report.rounds, 1);
  int cut = 0;
  for (size_t i = 0; i < state.masters.models.size(); ++i) {
    if (state.masters.models[i].Length() == before.masters.models[i].Length()) continue;
    ++cut;
    EXPECT_NEAR(Tip(state, static_cast<int>(i)).z(), z, options.tolerance) << "master " << i;
  }
  EXPECT_EQ(cut, report.strands);
  EXPECT_GT(cut, 3);
}

TEST(StylingTest, SphereAndLengthCuts) {
  StyledHair state = Groomed(SmallStyle("asian", "straight", 12, 0.3));
  StyledHair by_length = state;
  std::string error;
  CutRegion length;
  length.kind = CutRegion::Kind::kMaxLength;
  length.length = 0.2;
  ASSERT_TRUE(Cut(&by_length, length, {}, {}, nullptr, &error)) << error;
  for (const StrandModel& m : by_length.masters.models) EXPECT_LE(m.Length(), 0.2 + 1e-15);

  CutRegion bob;
  bob.kind = CutRegion::Kind::kInsideSphere;
  bob.centre = Vec3::Zero();
  bob.radius = 0.18;
  const StyledHair before = state;
  OperationReport report;
  ASSERT_TRUE(Cut(&state, bob, {}, {}, &report, &error)) << error;
  EXPECT_GT(report.strands, 3);
  // Every cut master ends where its previous equilibrium first left the sphere: that point lies
  // on the sphere to rounding. (Unlike a plane below, a sphere does not say where the lighter
  // strand goes: it lifts, which can carry its tip outward.)
  for (size_t i = 0; i < state.masters.models.size(); ++i) {
    const double l_new = state.masters.models[i].Length();
    if (l_new == before.masters.models[i].Length()) continue;
    const StrandModel kept = TruncateModel(before.masters.models[i], l_new);
    const VecX q = before.solutions[i].curvatures.head(3 * kept.NumSegments());
    EXPECT_NEAR(ComputeGeometry(kept, q).points.back().norm(), 0.18, 1e-12);
  }
}

// Radius and pitch of a helix measured from four equally spaced centreline points: second
// differences point to the axis, so their cross product gives the axis a; the chord of the
// projection on the plane normal to a is 2 R sin(dt/2) and the second difference 4 R sin^2(dt/2).
HelixShape MeasureHelix(const std::vector<Vec3>& p, double h) {
  const Vec3 d1 = p[2] - 2.0 * p[1] + p[0];
  const Vec3 d2 = p[3] - 2.0 * p[2] + p[1];
  const Vec3 a = d1.cross(d2).normalized();
  const Vec3 chord = p[1] - p[0];
  const double chord_h = (chord - chord.dot(a) * a).norm();
  const double d = d1.norm();
  const double radius = chord_h * chord_h / d;
  const double dt = 2.0 * std::asin(d / (2.0 * chord_h));
  const double lambda = h / dt;  // sqrt(R^2 + c^2)
  const double c = lambda * std::abs((p[3] - p[0]).dot(a)) / (3.0 * h);
  return {radius, 2.0 * std::numbers::pi * c};
}

TEST(StylingTest, CurlRoundTripsRadiusAndPitch) {
  StyledHair state = SingleStrand(Vec3::Zero(), 0.1, 10, Vec3::Zero());
  std::string error;
  OperationReport report;
  const double radius = 0.012, pitch = 0.03;
  ASSERT_TRUE(Curl(&state, radius, pitch, {}, {}, &report, &error)) << error;
  // kappa = R / (R^2 + c^2), tau = c / (R^2 + c^2), c = p / 2 pi (do Carmo 1-5).
  const double c = pitch / (2.0 * std::numbers::pi);
  EXPECT_NEAR(state.masters.models[0].natural_curvature.x(), -radius / (radius * radius + c * c),
              1e-9);
  EXPECT_NEAR(state.masters.models[0].natural_curvature.z(), c / (radius * radius + c * c), 1e-9);
  ASSERT_TRUE(state.solutions[0].summary.Converged());
  // Four points 1 cm apart (10 samples per 1-cm segment, every 10th).
  const std::vector<Vec3> all = SampleCentreline(state.masters.models[0],
                                                 state.solutions[0].curvatures, 10);
  const HelixShape measured = MeasureHelix({all[20], all[30], all[40], all[50]}, 0.01);
  EXPECT_NEAR(measured.radius, radius, 1e-9);
  EXPECT_NEAR(measured.pitch, pitch, 1e-9);
  std::printf("curl R = %.4f, p = %.4f -> measured %.9f, %.9f\n", radius, pitch, measured.radius,
              measured.pitch);
}

// With comb.curl_inward the curl operation starts its curl into the head, as the groom does:
// the same helix (radius and pitch) with kappa1^0 > 0, the mirror of the default's.
TEST(StylingTest, CurlFollowsTheCombsCurlSense) {
  StyledHair state = SingleStrand(Vec3::Zero(), 0.1, 10, Vec3::Zero());
  state.style.comb.curl_inward = true;
  std::string error;
  OperationReport report;
  const double radius = 0.012, pitch = 0.03;
  ASSERT_TRUE(Curl(&state, radius, pitch, {}, {}, &report, &error)) << error;
  const double c = pitch / (2.0 * std::numbers::pi);
  EXPECT_NEAR(state.masters.models[0].natural_curvature.x(), radius / (radius * radius + c * c),
              1e-9);
  EXPECT_NEAR(state.masters.models[0].natural_curvature.z(), c / (radius * radius + c * c), 1e-9);
  ASSERT_TRUE(state.solutions[0].summary.Converged());
}

TEST(StylingTest, CurlActsOnTheSelectionOnly) {
  StyledHair state = Groomed(SmallStyle("caucasian", "wavy", 20, 0.2));
  const StyledHair before = state;
  StrandSelection crown;
  crown.max_polar_angle = 0.8;
  std::string error;
  OperationReport report;
  ASSERT_TRUE(Curl(&state, 0.01, 0.02, crown, {}, &report, &error)) << error;
  int selected = 0;
  for (size_t i = 0; i < state.masters.models.size(); ++i) {
    const bool in = state.masters.roots[i].head.polar_angle <= 0.8;
    selected += in;
    if (in) {
      EXPECT_NE(state.masters.models[i].natural_curvature, before.masters.models[i].natural_curvature);
    } else {
      EXPECT_EQ(state.masters.models[i].natural_curvature, before.masters.models[i].natural_curvature);
      EXPECT_EQ(state.solutions[i].curvatures, before.solutions[i].curvatures);
    }
  }
  EXPECT_EQ(report.strands, selected);
  EXPECT_GT(selected, 0);
  EXPECT_LT(selected, 20);
}

TEST(StylingTest, GrowAddsStepTimesSteps) {
  StyledHair state = Groomed(SmallStyle("caucasian", "wavy", 10, 0.1));
  const StyledHair before = state;
  std::vector<StyledHair> sequence;
  OperationReport report;
  std::string error;
  const double step = 0.02;
  const int steps = 5;
  ASSERT_TRUE(Grow(&state, step, steps, {}, &sequence, &report, &error)) << error;
  ASSERT_EQ(sequence.size(), 5u);
  std::printf("%s\n", report.message.c_str());
  for (size_t i = 0; i < state.masters.models.size(); ++i) {
    const double l0 = before.masters.models[i].Length();
    for (int t = 0; t < steps; ++t) {
      EXPECT_NEAR(sequence[t].masters.models[i].Length(), l0 + (t + 1) * step, 1e-12);
    }
    EXPECT_NEAR(state.masters.models[i].Length() - l0, step * steps, 1e-12);
    // The grid stays as fine as the groom's.
    const auto& l0s = before.masters.models[i].segment_lengths;
    const double max0 = *std::max_element(l0s.begin(), l0s.end());
    for (double l : state.masters.models[i].segment_lengths) EXPECT_LE(l, max0);
    EXPECT_GT(state.masters.models[i].NumSegments(), before.masters.models[i].NumSegments());
  }
  EXPECT_EQ(report.unconverged, 0);
}

// Issue 16: a grow within the step bounds that would exceed kMaxSegments is refused before any
// re-solve, and leaves the state as it was.
TEST(StylingTest, GrowBeyondTheSegmentLimitIsRefused) {
  StyledHair state = Groomed(SmallStyle("caucasian", "wavy", 3, 0.1));
  // A fine grid (1000 segments of 0.1 mm on master 1): 10 m of growth would append 100,000
  // segments. The check comes before any re-solve, so the solutions need not match the grid.
  state.masters.models[1].segment_lengths.assign(1000, 1e-4);
  const StyledHair before = state;
  OperationReport report;
  std::string error;
  EXPECT_FALSE(Grow(&state, kMaxGrowStep, 10, {}, nullptr, &report, &error));
  EXPECT_EQ(error.rfind("grow.step: growing master 1 by 10 m in 10 steps would give it", 0), 0u)
      << error;
  EXPECT_NE(error.find("more than the limit of 100000"), std::string::npos) << error;
  for (size_t i = 0; i < state.masters.models.size(); ++i) {
    EXPECT_EQ(state.masters.models[i].segment_lengths, before.masters.models[i].segment_lengths);
  }
  // More than kMaxGrowLength in all is refused whatever the grid.
  EXPECT_FALSE(Grow(&state, kMaxGrowStep, kMaxGrowSteps, {}, nullptr, &report, &error));
  EXPECT_EQ(error.rfind("grow.step, grow.steps: expected at most 10 m of growth in all", 0), 0u)
      << error;
}

TEST(StylingTest, BadParametersAreRejectedByName) {
  StyledHair state = Groomed(SmallStyle("caucasian", "wavy", 6, 0.15));
  const StyledHair before = state;
  std::string error;
  const auto rejects = [&](bool ok, const std::string& field) {
    EXPECT_FALSE(ok);
    EXPECT_NE(error.find(field), std::string::npos) << error;
    error.clear();
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  rejects(Curl(&state, -0.01, 0.02, {}, {}, nullptr, &error), "curl.radius");
  rejects(Curl(&state, nan, 0.02, {}, {}, nullptr, &error), "curl.radius");
  rejects(Curl(&state, 0.01, std::numeric_limits<double>::infinity(), {}, {}, nullptr, &error),
          "curl.pitch");
  rejects(Curl(&state, 0.0, 0.0, {}, {}, nullptr, &error), "curl.radius, curl.pitch");
  StrandSelection bad;
  bad.indices = {0, 99};
  rejects(Curl(&state, 0.01, 0.02, bad, {}, nullptr, &error), "selection.indices");
  StrandSelection reversed;
  reversed.min_polar_angle = 1.0;
  reversed.max_polar_angle = 0.5;
  rejects(Curl(&state, 0.01, 0.02, reversed, {}, nullptr, &error), "selection.polar_angle");
  WetOptions wet;
  wet.stiffness_factor = 0.0;
  rejects(Wet(&state, wet, {}, nullptr, &error), "wet.stiffness_factor");
  wet = {};
  wet.swelling = 0.9;
  rejects(Wet(&state, wet, {}, nullptr, &error), "wet.swelling");
  rejects(Dry(&state, {}, nullptr, &error), "not wet");
  rejects(CutBelow(&state, nan, {}, {}, nullptr, &error), "cut.z");
  CutRegion sphere;
  sphere.kind = CutRegion::Kind::kInsideSphere;
  rejects(Cut(&state, sphere, {}, {}, nullptr, &error), "cut.radius");
  CutRegion length;
  length.kind = CutRegion::Kind::kMaxLength;
  length.length = -1.0;
  rejects(Cut(&state, length, {}, {}, nullptr, &error), "cut.length");
  length.length = 0.1;
  CutOptions settle;
  settle.settle = true;
  rejects(Cut(&state, length, settle, {}, nullptr, &error), "cut.settle");
  CutOptions tolerance;
  tolerance.tolerance = 0.0;
  rejects(CutBelow(&state, -0.1, tolerance, {}, nullptr, &error), "cut.tolerance");
  rejects(Grow(&state, 0.0, 3, {}, nullptr, nullptr, &error), "grow.step");
  rejects(Grow(&state, 0.01, 0, {}, nullptr, nullptr, &error), "grow.steps");
  // Nothing changed.
  for (size_t i = 0; i < state.masters.models.size(); ++i) {
    EXPECT_EQ(state.masters.models[i].segment_lengths, before.masters.models[i].segment_lengths);
    EXPECT_EQ(state.masters.models[i].natural_curvature, before.masters.models[i].natural_curvature);
    EXPECT_EQ(state.solutions[i].curvatures, before.solutions[i].curvatures);
  }
  // Wet twice.
  ASSERT_TRUE(Wet(&state, {}, {}, nullptr, &error)) << error;
  rejects(Wet(&state, {}, {}, nullptr, &error), "already wet");
}

// ---------------------------------------------------------------------------------------------
// Operations on wet hair.

// The first arc length where a strand's centreline goes below z, found independently of
// CutArcLength: the first sample below z on a dense polyline (n samples per segment), linearly
// interpolated (error ~ spacing^2 curvature / 8, below 1e-5 m for 400 samples of 2.5 cm).
double DenseCrossing(const StrandModel& model, const VecX& q, double z, int n = 400) {
  const FramedCentreline dense = SampleFramedCentreline(model, q, n);
  for (int j = 1; j < dense.NumPoints(); ++j) {
    if (dense.points[j].z() < z) {
      const double z0 = dense.points[j - 1].z(), z1 = dense.points[j].z();
      const double t = (z0 - z) / (z0 - z1);
      return dense.arc_lengths[j - 1] + t * (dense.arc_lengths[j] - dense.arc_lengths[j - 1]);
    }
  }
  return model.Length();
}

// The parameters Dry must restore, compared bit for bit (restored, not recomputed).
void ExpectSameDryParameters(const StrandModel& a, const StrandModel& b) {
  EXPECT_EQ(a.section.a, b.section.a);
  EXPECT_EQ(a.section.b, b.section.b);
  EXPECT_EQ(a.material.young_modulus, b.material.young_modulus);
  EXPECT_EQ(a.material.poisson_ratio, b.material.poisson_ratio);
  EXPECT_EQ(a.material.density, b.material.density);
  EXPECT_EQ(a.contact.clearance, b.contact.clearance);
}

TEST(StylingTest, CuttingWetHairShortensByTheCutAndTipsRise) {
  StyledHair state = Groomed(SmallStyle("asian", "straight", 20, 0.3));
  const StyledHair dry = state;
  std::string error;
  ASSERT_TRUE(Wet(&state, {}, {}, nullptr, &error)) << error;
  const StyledHair wet = state;
  const double z = -0.12;
  OperationReport report;
  ASSERT_TRUE(CutBelow(&state, z, {}, {}, &report, &error)) << error;
  std::printf("wet %s\n", report.message.c_str());
  ASSERT_GT(report.strands, 3);  // not vacuous: several wet strands hung below z
  EXPECT_TRUE(state.wet);
  int cut = 0;
  double lowest = std::numeric_limits<double>::infinity(), worst_length = 0.0;
  for (size_t i = 0; i < state.masters.models.size(); ++i) {
    const StrandModel& before = wet.masters.models[i];
    const StrandModel& after = state.masters.models[i];
    // Still wet: E = E_dry / 10 exactly as before the cut (Robbins' factor, applied by Wet).
    EXPECT_EQ(after.material.young_modulus, before.material.young_modulus);
    EXPECT_EQ(after.section.a, before.section.a);
    if (after.Length() == before.Length()) continue;
    ++cut;
    // l_new = l_prev - l_cut, l_cut = what hung below z at the *wet* equilibrium: the new length
    // is the independent dense-polyline crossing of the wet centreline.
    const double s_dense = DenseCrossing(before, wet.solutions[i].curvatures, z);
    worst_length = std::max(worst_length, std::abs(after.Length() - s_dense));
    EXPECT_NEAR(after.Length(), s_dense, 1e-5) << "master " << i;
    // The lighter strand rises: its tip ends above the plane.
    const double tip_z = Tip(state, static_cast<int>(i)).z();
    EXPECT_GT(tip_z, z) << "master " << i;
    lowest = std::min(lowest, tip_z);
  }
  EXPECT_EQ(cut, report.strands);
  // Wet hair hangs lower than dry, so the wet cut removes more: at least as many strands cross.
  int dry_crossing = 0;
  for (size_t i = 0; i < dry.masters.models.size(); ++i) {
    dry_crossing += DenseCrossing(dry.masters.models[i], dry.solutions[i].curvatures, z) <
                    dry.masters.models[i].Length();
  }
  EXPECT_GE(cut, dry_crossing);
  std::printf(
      "wet cut at z = %.3f: %d strands (dry would cut %d), length vs dense crossing "
      "%.2g m, lowest tip %.4f m\n",
      z, cut, dry_crossing, worst_length, lowest);
  // Drying the cut hair restores the dry parameters bit for bit; the lengths stay cut, and the
  // stiffer, lighter hair rises further (load parameter w L^3 / (E I) / 7.4).
  const double wet_mean_tip = MeanTipZ(state);
  const std::vector<double> cut_lengths = [&] {
    std::vector<double> l;
    for (const StrandModel& m : state.masters.models) l.push_back(m.Length());
    return l;
  }();
  ASSERT_TRUE(Dry(&state, {}, nullptr, &error)) << error;
  for (size_t i = 0; i < state.masters.models.size(); ++i) {
    ExpectSameDryParameters(state.masters.models[i], dry.masters.models[i]);
    EXPECT_EQ(state.masters.models[i].Length(), cut_lengths[i]);
  }
  EXPECT_GT(MeanTipZ(state), wet_mean_tip);
}

TEST(StylingTest, GrowingWetHairAddsLengthAndStaysWet) {
  StyledHair state = Groomed(SmallStyle("caucasian", "wavy", 10, 0.1));
  const StyledHair dry = state;
  std::string error;
  ASSERT_TRUE(Wet(&state, {}, {}, nullptr, &error)) << error;
  const StyledHair wet = state;
  const double step = 0.02;
  const int steps = 3;
  std::vector<StyledHair> sequence;
  OperationReport report;
  ASSERT_TRUE(Grow(&state, step, steps, {}, &sequence, &report, &error)) << error;
  EXPECT_EQ(report.unconverged, 0) << report.message;
  ASSERT_EQ(sequence.size(), 3u);
  for (size_t i = 0; i < state.masters.models.size(); ++i) {
    const double l0 = dry.masters.models[i].Length();
    // L0 + k step exactly (to rounding): growth is a length edit.
    for (int t = 0; t < steps; ++t) {
      EXPECT_NEAR(sequence[t].masters.models[i].Length(), l0 + (t + 1) * step, 1e-12);
      EXPECT_TRUE(sequence[t].wet);
    }
    // The new hair is wet hair: one material per strand, the wet one.
    EXPECT_EQ(state.masters.models[i].material.young_modulus,
              wet.masters.models[i].material.young_modulus);
    EXPECT_EQ(state.masters.models[i].section.a, wet.masters.models[i].section.a);
  }
  // Dry restores every dry parameter bit for bit and keeps the grown length.
  ASSERT_TRUE(Dry(&state, {}, nullptr, &error)) << error;
  for (size_t i = 0; i < state.masters.models.size(); ++i) {
    ExpectSameDryParameters(state.masters.models[i], dry.masters.models[i]);
    EXPECT_NEAR(state.masters.models[i].Length(), dry.masters.models[i].Length() + steps * step,
                1e-12);
  }
}

TEST(StylingTest, WetHelixInZeroGravityStaysTheNaturalHelixWhenCurledAndGrown) {
  // Without gravity or contact the equilibrium is the natural helix whatever E, a, b and rho
  // (the elastic energy (EI/2) |kappa - kappa0|^2 has its minimum 0 there): wet hair curled to
  // R, p and grown must measure R, p (do Carmo 1-5, MeasureHelix), including the new segments.
  StyledHair state = SingleStrand(Vec3::Zero(), 0.1, 10, Vec3::Zero());
  std::string error;
  ASSERT_TRUE(Wet(&state, {}, {}, nullptr, &error)) << error;
  const double radius = 0.012, pitch = 0.03;
  ASSERT_TRUE(Curl(&state, radius, pitch, {}, {}, nullptr, &error)) << error;
  ASSERT_TRUE(Grow(&state, 0.025, 2, {}, nullptr, nullptr, &error)) << error;
  ASSERT_TRUE(state.solutions[0].summary.Converged());
  ASSERT_GT(state.masters.models[0].NumSegments(), 10);  // the grown part has its own segments
  // 1-cm segments, 10 samples each: four points 1 cm apart in the grown part (s = 11..14 cm).
  const std::vector<Vec3> all =
      SampleCentreline(state.masters.models[0], state.solutions[0].curvatures, 10);
  const HelixShape grown = MeasureHelix({all[110], all[120], all[130], all[140]}, 0.01);
  EXPECT_NEAR(grown.radius, radius, 1e-9);
  EXPECT_NEAR(grown.pitch, pitch, 1e-9);
  // Drying changes nothing of the shape (still zero gravity) and keeps the curl.
  ASSERT_TRUE(Dry(&state, {}, nullptr, &error)) << error;
  const std::vector<Vec3> dried =
      SampleCentreline(state.masters.models[0], state.solutions[0].curvatures, 10);
  const HelixShape measured = MeasureHelix({dried[20], dried[30], dried[40], dried[50]}, 0.01);
  EXPECT_NEAR(measured.radius, radius, 1e-9);
  EXPECT_NEAR(measured.pitch, pitch, 1e-9);
  std::printf("wet curl + grow, zero gravity: grown part R %.9f p %.9f; dried R %.9f p %.9f\n",
              grown.radius, grown.pitch, measured.radius, measured.pitch);
}

TEST(StylingTest, CurlingWetHairThenDryingEqualsCurlingDryHair) {
  const StyledHair groomed = Groomed(SmallStyle("caucasian", "wavy", 20, 0.2));
  const double radius = 0.01, pitch = 0.03;
  std::string error;
  // Path A: curl the dry hair.
  StyledHair a = groomed;
  ASSERT_TRUE(Curl(&a, radius, pitch, {}, {}, nullptr, &error)) << error;
  // Path B: wet, curl, dry.
  StyledHair b = groomed;
  ASSERT_TRUE(Wet(&b, {}, {}, nullptr, &error)) << error;
  ASSERT_TRUE(Curl(&b, radius, pitch, {}, {}, nullptr, &error)) << error;
  ASSERT_TRUE(Dry(&b, {}, nullptr, &error)) << error;
  double worst = 0.0;
  for (size_t i = 0; i < a.masters.models.size(); ++i) {
    // The curled dry model is the same bit for bit: natural curvature from CurvatureFromHelix,
    // wisp radius from the *dry* fibre radius (Curl reads the remembered dry section while
    // wet), hence the same clearance; the dry section and material restored.
    EXPECT_EQ(a.masters.models[i].natural_curvature, b.masters.models[i].natural_curvature);
    EXPECT_EQ(a.masters.wisp_radii[i], b.masters.wisp_radii[i]);
    ExpectSameDryParameters(a.masters.models[i], b.masters.models[i]);
    EXPECT_TRUE(b.solutions[i].summary.Converged());
    worst = std::max(worst, (Tip(a, static_cast<int>(i)) - Tip(b, static_cast<int>(i))).norm());
  }
  std::printf("curl(dry) vs dry(curl(wet)): largest tip distance %.3g m\n", worst);
  // Same model, same equilibrium reached by two paths: tips agree to the solver tolerance
  // (residual 1e-6, as DryUndoesWet).
  EXPECT_LT(worst, 1e-4);
}

// ---------------------------------------------------------------------------------------------
// Operations as data (StyleOperation, ApplyOperation).

TEST(StylingTest, ApplyOperationIsTheDirectCall) {
  const StyledHair groomed = Groomed(SmallStyle("asian", "straight", 12, 0.3));
  std::string error;
  std::vector<StyleOperation> ops(4);
  ops[0].kind = StyleOperation::Kind::kWet;
  ops[1].kind = StyleOperation::Kind::kCut;
  ops[1].cut_region.offset = -0.12;  // kAbovePlane, n = +z: CutBelow(-0.12)
  ops[1].cut.settle = true;
  ops[2].kind = StyleOperation::Kind::kDry;
  ops[3].kind = StyleOperation::Kind::kGrow;
  ops[3].grow_step = 0.01;
  ops[3].grow_steps = 2;
  StyledHair a = groomed;
  std::vector<std::string> names;
  for (const StyleOperation& op : ops) {
    ASSERT_TRUE(op.IsValid(&error)) << error;
    OperationReport report;
    ASSERT_TRUE(ApplyOperation(&a, op, {}, nullptr, &report, &error)) << error;
    names.push_back(report.name);
    EXPECT_EQ(report.name, OperationName(op.kind));
  }
  EXPECT_EQ(names, (std::vector<std::string>{"wet", "cut", "dry", "grow"}));
  StyledHair b = groomed;
  CutOptions settle;
  settle.settle = true;
  ASSERT_TRUE(Wet(&b, {}, {}, nullptr, &error)) << error;
  ASSERT_TRUE(CutBelow(&b, -0.12, settle, {}, nullptr, &error)) << error;
  ASSERT_TRUE(Dry(&b, {}, nullptr, &error)) << error;
  ASSERT_TRUE(Grow(&b, 0.01, 2, {}, nullptr, nullptr, &error)) << error;
  // Bit-identical: one code path, deterministic solver.
  for (size_t i = 0; i < a.masters.models.size(); ++i) {
    EXPECT_EQ(a.masters.models[i].segment_lengths, b.masters.models[i].segment_lengths);
    EXPECT_EQ(a.solutions[i].curvatures, b.solutions[i].curvatures);
  }
}

TEST(StylingTest, StyleOperationRejectsBadParametersByName) {
  const auto rejects = [](const StyleOperation& op, const std::string& field) {
    std::string why;
    EXPECT_FALSE(op.IsValid(&why)) << field;
    EXPECT_NE(why.find(field), std::string::npos) << why;
  };
  StyleOperation curl;
  curl.kind = StyleOperation::Kind::kCurl;
  curl.curl_radius = -1.0;
  rejects(curl, "curl.radius");
  curl.curl_radius = 0.01;
  curl.curl_pitch = std::numeric_limits<double>::quiet_NaN();
  rejects(curl, "curl.pitch");
  curl.curl_pitch = 0.02;
  curl.selection.indices = {3, -2};
  rejects(curl, "selection.indices");
  curl.selection.indices.clear();
  curl.selection.min_height = 1.0;
  curl.selection.max_height = 0.0;
  rejects(curl, "selection.height");
  StyleOperation wet;
  wet.wet.layer_factor = -0.5;
  rejects(wet, "wet.layer_factor");
  StyleOperation cut;
  cut.kind = StyleOperation::Kind::kCut;
  cut.cut_region.kind = CutRegion::Kind::kInsideSphere;
  cut.cut_region.radius = 0.0;
  rejects(cut, "cut.radius");
  cut.cut_region.kind = CutRegion::Kind::kMaxLength;
  cut.cut_region.length = 0.1;
  cut.cut.settle = true;
  rejects(cut, "cut.settle");
  cut.cut_region.kind = CutRegion::Kind::kAbovePlane;
  cut.cut_region.normal = Vec3::Zero();
  rejects(cut, "cut.normal");
  StyleOperation grow;
  grow.kind = StyleOperation::Kind::kGrow;
  grow.grow_step = 0.01;
  grow.grow_steps = 0;
  rejects(grow, "grow.steps");
  grow.grow_steps = 1;
  grow.grow_step = std::numeric_limits<double>::infinity();
  rejects(grow, "grow.step");
  // Issue 16: values that used to reach an assert or loop forever.
  curl.selection = {};
  curl.curl_radius = 1e-300;  // R^2 + c^2 underflows: curvature inf (WispRadius asserted)
  curl.curl_pitch = 0.0;
  rejects(curl, "curl.radius: expected a helix with curvature and torsion at most 100000 1/m");
  curl.curl_radius = 1e-7;  // finite, but a radius of curvature of 0.1 um
  rejects(curl, "curl.radius");
  curl.curl_radius = 0.0;
  curl.curl_pitch = 1e-9;  // a twist of 6e9 1/m
  rejects(curl, "curl.pitch: expected a helix");
  curl.curl_radius = 1e300;  // huge radii are straight, not an error
  curl.curl_pitch = 1e300;
  std::string huge_why;
  EXPECT_TRUE(curl.IsValid(&huge_why)) << huge_why;
  curl.curl_pitch = 0.02;
  cut.cut_region.normal = Vec3::Constant(1e300);  // finite entries, infinite norm
  rejects(cut, "cut.normal");
  grow.grow_step = 1e300;  // looped forever
  rejects(grow, "grow.step: expected a length in (0, 1] (m)");
  grow.grow_step = kMaxGrowStep;
  grow.grow_steps = kMaxGrowSteps + 1;
  rejects(grow, "grow.steps: expected an integer from 1 to 1000");
  grow.grow_steps = kMaxGrowSteps;  // 1000 m
  rejects(grow, "grow.step, grow.steps: expected at most 10 m of growth in all");
  grow.grow_steps = 10;
  EXPECT_TRUE(grow.IsValid(&huge_why)) << huge_why;
  // Valid ones pass (anti-vacuity), including a selection whose bound needs the hair.
  std::string why;
  curl.selection = {};
  curl.selection.indices = {1000};
  EXPECT_TRUE(curl.IsValid(&why)) << why;
  StyleOperation dry;
  dry.kind = StyleOperation::Kind::kDry;
  EXPECT_TRUE(dry.IsValid(&why)) << why;
}

// ---------------------------------------------------------------------------------------------
// Brushed operations: every operation takes a selection. Masters are solved independently (each
// touches only the body), so the reference for a selected master is the same master after the
// whole-head operation, bit for bit; an unselected master must keep its model and equilibrium
// bit for bit.

bool SameModelBits(const StrandModel& a, const StrandModel& b) {
  return a.segment_lengths == b.segment_lengths && a.section.a == b.section.a &&
         a.section.b == b.section.b && a.material.young_modulus == b.material.young_modulus &&
         a.material.density == b.material.density && a.natural_curvature == b.natural_curvature &&
         a.contact.clearance == b.contact.clearance;
}

// Checks `brushed` against `before` (unselected) and `whole` (selected), master by master.
void ExpectBrushed(const StyledHair& before, const StyledHair& whole, const StyledHair& brushed,
                   const std::vector<int>& selected, const char* what) {
  ASSERT_EQ(brushed.solutions.size(), before.solutions.size());
  int changed = 0;
  for (size_t i = 0; i < before.solutions.size(); ++i) {
    const bool in = std::find(selected.begin(), selected.end(), static_cast<int>(i)) !=
                    selected.end();
    const StyledHair& reference = in ? whole : before;
    EXPECT_TRUE(SameModelBits(brushed.masters.models[i], reference.masters.models[i]))
        << what << ": master " << i << (in ? " (selected)" : " (unselected)");
    EXPECT_TRUE(brushed.solutions[i].curvatures == reference.solutions[i].curvatures)
        << what << ": master " << i << (in ? " (selected)" : " (unselected)");
    EXPECT_EQ(brushed.masters.wisp_radii[i], reference.masters.wisp_radii[i]) << what << " " << i;
    changed += brushed.solutions[i].curvatures != before.solutions[i].curvatures ||
               !SameModelBits(brushed.masters.models[i], before.masters.models[i]);
  }
  // Anti-vacuity: the operation did change some master.
  EXPECT_GT(changed, 0) << what;
}

TEST(StylingTest, BrushedWetDryCutGrowActOnTheSelectedMastersOnly) {
  const StyledHair start = Groomed(SmallStyle("caucasian", "wavy", 12, 0.25));
  StrandSelection brush;
  brush.indices = {1, 4, 5, 9};
  std::string error;
  // Wet.
  StyledHair whole_wet = start, wet = start;
  ASSERT_TRUE(Wet(&whole_wet, {}, {}, nullptr, &error)) << error;
  OperationReport report;
  ASSERT_TRUE(Wet(&wet, {}, {}, &report, &error, brush)) << error;
  EXPECT_EQ(report.strands, 4);
  ExpectBrushed(start, whole_wet, wet, brush.indices, "wet");
  EXPECT_TRUE(wet.wet);
  for (int i = 0; i < 12; ++i) EXPECT_EQ(IsWet(wet, i), i == 1 || i == 4 || i == 5 || i == 9);
  // A second brushed wet of the same masters is refused; of others with other options too.
  StyledHair again = wet;
  EXPECT_FALSE(Wet(&again, {}, {}, nullptr, &error, brush));
  EXPECT_NE(error.find("already wet"), std::string::npos) << error;
  WetOptions other;
  other.stiffness_factor = 0.3;
  StrandSelection rest;
  rest.indices = {0, 2};
  EXPECT_FALSE(Wet(&again, other, {}, nullptr, &error, rest));
  EXPECT_NE(error.find("options differ"), std::string::npos) << error;

  // Dry of two of the four wet masters: the reference for them is drying every wet master
  // (independent masters); their models are the start's again, bit for bit.
  StrandSelection half;
  half.indices = {4, 9};
  StyledHair dry_half = wet, dry_all = wet;
  ASSERT_TRUE(Dry(&dry_half, {}, &report, &error, half)) << error;
  EXPECT_EQ(report.strands, 2);
  ASSERT_TRUE(Dry(&dry_all, {}, nullptr, &error)) << error;
  ExpectBrushed(wet, dry_all, dry_half, half.indices, "dry");
  EXPECT_TRUE(dry_half.wet);  // 1 and 5 are still wet
  EXPECT_TRUE(IsWet(dry_half, 1) && !IsWet(dry_half, 4));
  for (int i : half.indices) {
    EXPECT_TRUE(SameModelBits(dry_half.masters.models[i], start.masters.models[i])) << i;
  }
  EXPECT_FALSE(dry_all.wet);
  EXPECT_TRUE(dry_all.wet_masters.empty());
  StrandSelection dry_ones;
  dry_ones.indices = {0, 4};
  EXPECT_FALSE(Dry(&dry_half, {}, nullptr, &error, dry_ones));
  EXPECT_NE(error.find("not wet"), std::string::npos) << error;

  // Cut below z = -0.12 (the wavy 25-cm masters reach below it).
  CutRegion plane;
  plane.offset = -0.12;
  StyledHair whole_cut = start, cut = start;
  ASSERT_TRUE(Cut(&whole_cut, plane, {}, {}, nullptr, &error)) << error;
  ASSERT_TRUE(Cut(&cut, plane, {}, {}, nullptr, &error, brush)) << error;
  std::vector<int> really_cut;  // the selected masters the whole-head cut shortened
  for (int i : brush.indices) {
    if (whole_cut.masters.models[i].Length() < start.masters.models[i].Length()) {
      really_cut.push_back(i);
    }
  }
  ASSERT_FALSE(really_cut.empty());
  ExpectBrushed(start, whole_cut, cut, brush.indices, "cut");

  // Grow by 2 x 1 cm.
  StyledHair whole_grow = start, grow = start;
  ASSERT_TRUE(Grow(&whole_grow, 0.01, 2, {}, nullptr, nullptr, &error)) << error;
  ASSERT_TRUE(Grow(&grow, 0.01, 2, {}, nullptr, &report, &error, brush)) << error;
  EXPECT_EQ(report.strands, 4);
  ExpectBrushed(start, whole_grow, grow, brush.indices, "grow");
  for (int i : brush.indices) {
    EXPECT_NEAR(grow.masters.models[i].Length(), start.masters.models[i].Length() + 0.02, 1e-12);
  }

  // A selection by range (the crown: polar angle <= 0.9 rad) through ApplyOperation, the path
  // of the file's list: the same as the index list of the masters it selects.
  StyleOperation op;
  op.kind = StyleOperation::Kind::kCut;
  op.cut_region = plane;
  op.selection.max_polar_angle = 0.9;
  StrandSelection crown;
  for (int i = 0; i < 12; ++i) {
    if (op.selection.Selects(i, start.masters.roots[i])) crown.indices.push_back(i);
  }
  ASSERT_FALSE(crown.indices.empty());
  ASSERT_LT(crown.indices.size(), 12u);
  StyledHair by_range = start, by_index = start;
  ASSERT_TRUE(ApplyOperation(&by_range, op, {}, nullptr, nullptr, &error)) << error;
  ASSERT_TRUE(Cut(&by_index, plane, {}, {}, nullptr, &error, crown)) << error;
  for (int i = 0; i < 12; ++i) {
    EXPECT_TRUE(by_range.solutions[i].curvatures == by_index.solutions[i].curvatures) << i;
  }
  // Indices beyond the masters are refused by every operation, naming the field.
  StrandSelection bad;
  bad.indices = {12};
  StyledHair copy = start;
  EXPECT_FALSE(Grow(&copy, 0.01, 1, {}, nullptr, nullptr, &error, bad));
  EXPECT_NE(error.find("selection.indices: 12"), std::string::npos) << error;
  EXPECT_FALSE(Wet(&copy, {}, {}, nullptr, &error, bad));
  EXPECT_FALSE(Cut(&copy, plane, {}, {}, nullptr, &error, bad));
}


// The renderer learns which strands are wet (HairCurves::wetness): a brushed Wet of masters 0, 3
// and 7 wets exactly the strands of their wisps (GrowWisps writes strands_per_wisp = 4 strands
// per master, master by master); dry hair carries no wetness, nor hair after Dry.
TEST(StylingTest, StyledStrandsCarryTheWetnessOfTheirMasters) {
  StyledHair state = Groomed(SmallStyle("caucasian", "straight", 10, 0.15));
  std::string error;
  HairCurves strands;
  ASSERT_TRUE(StyledStrands(state, &strands, &error)) << error;
  EXPECT_TRUE(strands.wetness.empty());
  StrandSelection brush;
  brush.indices = {0, 3, 7};
  ASSERT_TRUE(Wet(&state, {}, {}, nullptr, &error, brush)) << error;
  ASSERT_TRUE(StyledStrands(state, &strands, &error)) << error;
  ASSERT_EQ(strands.NumStrands(), 40);
  ASSERT_EQ(strands.wetness.size(), 40u);
  for (int k = 0; k < 40; ++k) {
    const int master = k / 4;
    const float expected = master == 0 || master == 3 || master == 7 ? 1.0f : 0.0f;
    EXPECT_EQ(strands.wetness[static_cast<size_t>(k)], expected) << "strand " << k;
  }
  EXPECT_TRUE(CheckHairCurves(strands, "strands", &error)) << error;
  ASSERT_TRUE(Dry(&state, {}, nullptr, &error)) << error;
  ASSERT_TRUE(StyledStrands(state, &strands, &error)) << error;
  EXPECT_TRUE(strands.wetness.empty());
}

}  // namespace
}  // namespace ringlet
