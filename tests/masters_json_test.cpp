// Explicit masters (include/ringlet/masters_json.h, Hairstyle::explicit_masters, issue 13 item
// 7): a groom's own masters written to a masters file give a bit-identical groom through the
// explicit path; a hand-written master with a closed-form rest shape is solved to that shape;
// the reader's one-line errors; styling operations on explicit masters.
#include "ringlet/masters_json.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "ringlet/body_json.h"
#include "ringlet/hairstyle_json.h"
#include "ringlet/strand_geometry.h"
#include "ringlet/styling.h"

namespace ringlet {
namespace {

using nlohmann::json;

std::string Examples() { return RINGLET_EXAMPLES_DIR; }

class TempDirectory {
 public:
  TempDirectory() {
    std::string pattern = ::testing::TempDir() + "ringlet_masters_XXXXXX";
    path_ = ::mkdtemp(pattern.data()) ? pattern : std::string();
  }
  ~TempDirectory() {
    std::error_code ec;
    if (!path_.empty()) std::filesystem::remove_all(path_, ec);
  }
  const std::string& path() const { return path_; }
  std::string Write(const std::string& name, const std::string& text) const {
    const std::string file = path_ + "/" + name;
    std::ofstream(file) << text;
    return file;
  }

 private:
  std::string path_;
};

// A small sampled hairstyle on the sphere mannequin (absolute body path): 12 wavy masters of
// 20 cm, 8 segments graded "auto", 4 strands per wisp, 4 hull layers, a parting.
json SmallSampled() {
  return json::parse(R"({
    "body": ")" + Examples() + R"(/bodies/mannequin.json",
    "masters": {"count": 12, "seed": 3, "segments": 8, "grading": "auto", "points_per_segment": 3},
    "comb": {"tilt": 1.2, "direction": [0, 0, -1], "parting": {"normal": [1, 0, 0], "offset": 0.03}},
    "hair": {"origin": "caucasian", "curl": "wavy", "length": 0.2, "seed": 5},
    "wisps": {"strands_per_wisp": 4, "points_per_strand": 12, "tip_scale": 0.5, "jitter": 0.001},
    "layers": {"count": 4, "thickness": 0.003}
  })");
}

// The sampled document with its masters given by `file` instead (sampling keys removed).
json ExplicitOf(json document, const std::string& file) {
  document["masters"] = {{"file", file}, {"points_per_segment", 3}};
  document.erase("comb");
  document["hair"].erase("length");
  return document;
}

Groom MustGroom(const json& document, const std::string& base) {
  Hairstyle style;
  std::string error;
  EXPECT_TRUE(ParseHairstyle(document, base, &style, &error)) << error;
  Groom groom;
  EXPECT_TRUE(GroomHairstyle(style, BatchOptions{}, &groom, &error)) << error;
  return groom;
}

void ExpectBitIdentical(const Groom& a, const Groom& b) {
  ASSERT_EQ(a.masters.models.size(), b.masters.models.size());
  for (size_t i = 0; i < a.masters.models.size(); ++i) {
    const StrandModel& x = a.masters.models[i];
    const StrandModel& y = b.masters.models[i];
    EXPECT_EQ(x.segment_lengths, y.segment_lengths) << i;
    EXPECT_EQ(x.root_position, y.root_position) << i;
    EXPECT_EQ(x.root_frame, y.root_frame) << i;
    EXPECT_EQ(x.natural_curvature, y.natural_curvature) << i;
    EXPECT_EQ(x.section.a, y.section.a) << i;
    EXPECT_EQ(x.material.young_modulus, y.material.young_modulus) << i;
    EXPECT_EQ(x.contact.clearance, y.contact.clearance) << i;
    EXPECT_EQ(a.masters.layers[i], b.masters.layers[i]) << i;
    EXPECT_EQ(a.masters.wisp_radii[i], b.masters.wisp_radii[i]) << i;
    EXPECT_EQ(a.masters.roots[i].head.polar_angle, b.masters.roots[i].head.polar_angle) << i;
    ASSERT_EQ(a.solutions[i].curvatures.size(), b.solutions[i].curvatures.size());
    EXPECT_TRUE(a.solutions[i].curvatures == b.solutions[i].curvatures) << i;
  }
  EXPECT_EQ(a.masters.wisp_options.root_scale, b.masters.wisp_options.root_scale);
  EXPECT_EQ(a.strands.point_counts, b.strands.point_counts);
  ASSERT_EQ(a.strands.points.size(), b.strands.points.size());
  EXPECT_TRUE(a.strands.points == b.strands.points);
  EXPECT_TRUE(a.strands.widths == b.strands.widths);
  EXPECT_TRUE(a.strands.major_axes == b.strands.major_axes);
}

// A groom's own masters, written with every field (ExplicitMastersOf) and read back through
// "masters": {"file": ...}, give the same groom bit for bit: models, solutions and every strand.
// Then the same file without the optional fields (section, material, natural curvature, layer,
// wisp radius, clearance): what BuildMasters derives for an explicit master i is what it derives
// for sampled master i, so the groom is still bit-identical.
TEST(ExplicitMasters, SampledMastersRoundTripBitIdentical) {
  TempDirectory dir;
  const json sampled = SmallSampled();
  const Groom reference = MustGroom(sampled, dir.path());
  ASSERT_EQ(reference.masters.models.size(), 12u);
  ASSERT_EQ(reference.masters.root_summary.achieved, 12);  // spacing sqrt(packing A / N) holds
  // Anti-vacuity: the masters differ from each other and carry hull layers above 0.
  EXPECT_NE(reference.masters.models[0].root_position, reference.masters.models[1].root_position);
  int layered = 0;
  for (int l : reference.masters.layers) layered += l > 0 ? 1 : 0;
  EXPECT_GT(layered, 0);

  const std::vector<ExplicitMaster> full = ExplicitMastersOf(reference.masters);
  const std::string text = MastersToString(full);
  dir.Write("full.json", text);
  ExpectBitIdentical(reference, MustGroom(ExplicitOf(sampled, "full.json"), dir.path()));

  json minimal = json::parse(text);
  for (json& m : minimal["masters"]) {
    for (const char* key :
         {"section", "material", "natural_curvature", "layer", "wisp_radius", "clearance"}) {
      ASSERT_TRUE(m.contains(key)) << key;
      m.erase(key);
    }
  }
  dir.Write("minimal.json", minimal.dump());
  ExpectBitIdentical(reference, MustGroom(ExplicitOf(sampled, "minimal.json"), dir.path()));

  // A rest shape equal to the constant natural curvature is bit-identical too (StrandModel:
  // NaturalCurvature(i) gives the same triple either way).
  std::vector<ExplicitMaster> constant = full;
  for (ExplicitMaster& m : constant) {
    const int n = static_cast<int>(m.segment_lengths.size());
    m.rest_curvatures.resize(3 * n);
    for (int i = 0; i < n; ++i) m.rest_curvatures.segment<3>(3 * i) = *m.natural_curvature;
  }
  dir.Write("constant.json", MastersToString(constant));
  const Groom again = MustGroom(ExplicitOf(sampled, "constant.json"), dir.path());
  for (size_t i = 0; i < again.solutions.size(); ++i) {
    EXPECT_TRUE(again.solutions[i].curvatures == reference.solutions[i].curvatures) << i;
  }
  EXPECT_TRUE(again.strands.points == reference.strands.points);
}

// The writer and reader round-trip every number exactly.
TEST(ExplicitMasters, WriteReadRoundTrip) {
  ExplicitMaster m;
  m.root_position = Vec3(0.1, -1.0 / 3.0, 2e-7);
  const double c = std::cos(0.3), s = std::sin(0.3);
  m.root_frame << c, -s, 0, s, c, 0, 0, 0, 1;
  m.segment_lengths = {0.1 / 3.0, 0.07};
  m.section = CrossSection{6e-5, 4e-5};
  m.material = Material{3e9, 0.25, 1250.0};
  m.natural_curvature = Vec3(-20.0, 0.0, 1.0 / 7.0);
  m.rest_curvatures = VecX::LinSpaced(6, -1.0 / 3.0, 10.0);
  m.start_curvatures = VecX::LinSpaced(6, 0.1, 0.7);
  m.layer = 2;
  m.wisp_radius = 0.004;
  m.clearance = 0.0061;
  ExplicitMaster bare;
  bare.root_position = m.root_position;
  bare.root_frame = m.root_frame;
  bare.segment_lengths = {0.2};
  std::vector<ExplicitMaster> read;
  std::string error;
  ASSERT_TRUE(ParseMastersText(MastersToString({m, bare}), &read, &error)) << error;
  ASSERT_EQ(read.size(), 2u);
  const ExplicitMaster& r = read[0];
  EXPECT_EQ(r.root_position, m.root_position);
  EXPECT_EQ(r.root_frame, m.root_frame);
  EXPECT_EQ(r.segment_lengths, m.segment_lengths);
  EXPECT_EQ(r.section->a, m.section->a);
  EXPECT_EQ(r.section->b, m.section->b);
  EXPECT_EQ(r.material->poisson_ratio, m.material->poisson_ratio);
  EXPECT_EQ(*r.natural_curvature, *m.natural_curvature);
  EXPECT_TRUE(r.rest_curvatures == m.rest_curvatures);
  EXPECT_TRUE(r.start_curvatures == m.start_curvatures);
  EXPECT_EQ(*r.layer, 2);
  EXPECT_EQ(*r.wisp_radius, 0.004);
  EXPECT_EQ(*r.clearance, 0.0061);
  // The second master gave only what is required.
  EXPECT_FALSE(read[1].section || read[1].material || read[1].natural_curvature ||
               read[1].layer || read[1].wisp_radius || read[1].clearance);
  EXPECT_EQ(read[1].rest_curvatures.size(), 0);
}

// A hand-written master without gravity, far from the body: its equilibrium is its rest shape.
// Segment 0 (length l1) bends with kappa1^0 = k about n1 = x from the root frame (x, y, z) at
// the origin, segment 1 (length l2) is straight. dt/ds = Omega x t = k x x z = -k y, so the arc
// ends at (0, -(1 - cos(k l1)) / k, sin(k l1) / k) with tangent (0, -sin(k l1), cos(k l1)), and
// the tip lies l2 further along that tangent (closed form, no code of ringlet involved).
TEST(ExplicitMasters, HandWrittenRestShapeIsTheGravityFreeEquilibrium) {
  TempDirectory dir;
  const double k = 25.0, l1 = 0.06, l2 = 0.04;
  dir.Write("masters.json", R"({"masters": [{
      "root": {"position": [0, 0, 1], "frame": {"n1": [1, 0, 0], "n2": [0, 1, 0], "t": [0, 0, 1]}},
      "segment_lengths": [0.06, 0.04],
      "rest_curvatures": [[25, 0, 0], [0, 0, 0]]}]})");
  // The mannequin's head (radius 0.1 m at the origin) is 0.9 m below the root: no contact.
  const json document = json::parse(R"({
    "body": ")" + Examples() + R"(/bodies/mannequin.json",
    "masters": {"file": "masters.json"},
    "gravity": [0, 0, 0],
    "solver": {"tolerance": 1e-12},
    "wisps": {"strands_per_wisp": 2, "points_per_strand": 5}
  })");
  const Groom groom = MustGroom(document, dir.path());
  ASSERT_EQ(groom.solutions.size(), 1u);
  const std::vector<Vec3> points =
      ComputeGeometry(groom.masters.models[0], groom.solutions[0].curvatures).points;
  const Vec3 arc_end(0.0, -(1.0 - std::cos(k * l1)) / k, 1.0 + std::sin(k * l1) / k);
  const Vec3 tangent(0.0, -std::sin(k * l1), std::cos(k * l1));
  const Vec3 tip = arc_end + l2 * tangent;
  const double length = l1 + l2;
  EXPECT_LT((points[1] - arc_end).norm(), 1e-12 * length);
  EXPECT_LT((points[2] - tip).norm(), 1e-12 * length);
  // Anti-vacuity: the tip is far from the straight strand's (0, 0, 1.1).
  EXPECT_GT((tip - Vec3(0, 0, 1.1)).norm(), 0.01);
  // The hair type's section and material (caucasian/wavy, master 0) were used.
  EXPECT_GT(groom.masters.models[0].section.a, 0.0);
}

// One-line errors naming the file, the master and the field; nothing accepted half.
TEST(ExplicitMasters, BadFilesGiveOneLineErrors) {
  TempDirectory dir;
  const std::string root =
      R"("root": {"position": [0, 0, 0.1], "frame": {"n1": [1, 0, 0], "n2": [0, 1, 0], "t": [0, 0, 1]}})";
  struct Case {
    std::string text;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {R"({"masters": []})", "masters: has 0 entries, expected 1 to 1000000"},
      {R"({"masters": [{)" + root + R"(}]})", "masters[0].segment_lengths: missing required field"},
      {R"({"masters": [{)" + root + R"(, "segment_lengths": [0.1, -1]}]})",
       "masters[0].segment_lengths[1]: expected a finite number > 0 (m), got -1"},
      {R"({"masters": [{)" + root +
           R"(, "segment_lengths": [0.1, 0.1], "rest_curvatures": [[1, 2, 3]]}]})",
       "masters[0].rest_curvatures: has 1 entries, expected 2 (one triple per segment_lengths "
       "entry)"},
      {R"({"masters": [{)" + root +
           R"(, "segment_lengths": [0.1], "curvatures": [[1, 2]]}]})",
       "masters[0].curvatures[0]: expected an array of 3 finite numbers"},
      {R"({"masters": [{"root": {"position": [0, 0, 0], "frame": {"n1": [1, 0, 0], "n2": [0, 0, 1], "t": [0, 0, 1]}}, "segment_lengths": [0.1]}]})",
       "masters[0].root.frame: expected n1, n2, t orthonormal and right-handed"},
      {R"({"masters": [{)" + root + R"(, "segment_lengths": [0.1], "section": {"a": 1e-5, "b": 2e-5}}]})",
       "masters[0].section: expected a >= b"},
      {R"({"masters": [{)" + root + R"(, "segment_lengths": [0.1], "lenght": 2}]})",
       "masters[0].lenght: unknown field"},
  };
  for (const Case& c : cases) {
    std::vector<ExplicitMaster> masters;
    std::string error;
    EXPECT_FALSE(ParseMastersText(c.text, &masters, &error)) << c.text;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    EXPECT_EQ(error.rfind(c.expected, 0), 0u) << "got: " << error << "\nexpected: " << c.expected;
    EXPECT_TRUE(masters.empty());
  }
  // Through a hairstyle: the hairstyle's field, then the masters file's path and field.
  dir.Write("bad.json", cases[3].text);
  const std::string body = "\"body\": \"" + Examples() + "/bodies/mannequin.json\"";
  const std::string style = dir.Write("style.json", "{" + body + R"(, "masters": {"file": "bad.json"}})");
  Hairstyle parsed;
  std::string error;
  EXPECT_FALSE(LoadHairstyle(style, &parsed, &error));
  EXPECT_EQ(error, style + ": masters.file: " + dir.path() +
                       "/bad.json: masters[0].rest_curvatures: has 1 entries, expected 2 (one "
                       "triple per segment_lengths entry)");
  // The keys that would sample the masters are refused with a file.
  dir.Write("good.json", R"({"masters": [{)" + root + R"(, "segment_lengths": [0.1]}]})");
  for (const auto& [extra, field] :
       std::vector<std::pair<std::string, std::string>>{
           {R"("masters": {"file": "good.json", "count": 10})", "masters.count"},
           {R"("masters": {"file": "good.json", "segments": 10})", "masters.segments"},
           {R"("masters": {"file": "good.json"}, "hair": {"length": 0.3})", "hair.length"},
           {R"("masters": {"file": "good.json"}, "comb": {"tilt": 1})", "comb"}}) {
    EXPECT_FALSE(ParseHairstyle(json::parse("{" + body + ", " + extra + "}"), dir.path(), &parsed,
                                &error));
    EXPECT_EQ(error.rfind(field + ": not with masters.file", 0), 0u) << error;
  }
  EXPECT_TRUE(ParseHairstyle(json::parse("{" + body + R"(, "masters": {"file": "good.json"}})"),
                             dir.path(), &parsed, &error))
      << error;
  ASSERT_TRUE(parsed.explicit_masters);
  EXPECT_EQ(parsed.explicit_masters->masters.size(), 1u);
  // A layer beyond layers.count is refused when the masters are built.
  dir.Write("layer.json", R"({"masters": [{)" + root + R"(, "segment_lengths": [0.1], "layer": 5}]})");
  ASSERT_TRUE(ParseHairstyle(json::parse("{" + body + R"(, "masters": {"file": "layer.json"}})"),
                             dir.path(), &parsed, &error))
      << error;
  HairstyleMasters built;
  EXPECT_FALSE(BuildMasters(parsed, &built, &error));
  EXPECT_EQ(error, "masters.file: master 0: layer: expected 0 to layers.count - 1 = 3, got 5");
}

// Styling explicit masters with a rest shape: a wet master keeps its rest shape and its explicit
// clearance (plus the wet layer offset), sags more, and drying restores it bit for bit; a cut
// keeps the rest curvatures of the kept segments; a curl replaces the rest shape and the
// explicit clearance by the sampled rule.
TEST(ExplicitMasters, StylingKeepsOrReplacesTheRestShape) {
  TempDirectory dir;
  // One master leaving the crown horizontally (t = +y), 8 segments of 2.5 cm with a rest shape
  // bending it up against gravity, clearance 1 mm, layer 1 of 4 (3 mm).
  std::string rest = "[";
  for (int i = 0; i < 8; ++i) rest += std::string(i ? ", " : "") + "[" + std::to_string(-10 + i) + ", 0, 0]";
  rest += "]";
  dir.Write("masters.json", R"({"masters": [{
      "root": {"position": [0, 0, 0.1], "frame": {"n1": [1, 0, 0], "n2": [0, 0, 1], "t": [0, -1, 0]}},
      "segment_lengths": [0.025, 0.025, 0.025, 0.025, 0.025, 0.025, 0.025, 0.025],
      "rest_curvatures": )" + rest + R"(, "layer": 1, "clearance": 0.001}]})");
  const json document = json::parse(R"({
    "body": ")" + Examples() + R"(/bodies/mannequin.json",
    "masters": {"file": "masters.json"},
    "layers": {"count": 4, "thickness": 0.003},
    "wisps": {"strands_per_wisp": 2, "points_per_strand": 6}
  })");
  Hairstyle style;
  std::string error;
  ASSERT_TRUE(ParseHairstyle(document, dir.path(), &style, &error)) << error;
  Groom groom;
  ASSERT_TRUE(GroomHairstyle(style, BatchOptions{}, &groom, &error)) << error;
  StyledHair hair;
  ASSERT_TRUE(MakeStyledHair(style, groom, &hair, &error)) << error;
  const StrandModel dry_model = hair.masters.models[0];
  EXPECT_EQ(dry_model.contact.clearance, 0.001 + 1 * 0.003);
  const VecX dry_solution = hair.solutions[0].curvatures;
  const double dry_tip_z = ComputeGeometry(dry_model, dry_solution).points.back().z();

  ASSERT_TRUE(Wet(&hair, WetOptions{}, BatchOptions{}, nullptr, &error)) << error;
  const StrandModel& wet = hair.masters.models[0];
  EXPECT_TRUE(wet.rest_curvatures == dry_model.rest_curvatures);
  EXPECT_EQ(wet.contact.clearance, 0.001 + 1 * (0.003 * 0.5));
  EXPECT_LT(ComputeGeometry(wet, hair.solutions[0].curvatures).points.back().z(),
            dry_tip_z - 1e-3);  // 10x softer and heavier: sags by far more than a millimetre
  ASSERT_TRUE(Dry(&hair, BatchOptions{}, nullptr, &error)) << error;
  EXPECT_EQ(hair.masters.models[0].contact.clearance, dry_model.contact.clearance);

  StyledHair cut = hair;
  CutRegion region;
  region.kind = CutRegion::Kind::kMaxLength;
  region.length = 0.11;  // 4 whole segments and 1 cm of the fifth
  ASSERT_TRUE(Cut(&cut, region, CutOptions{}, BatchOptions{}, nullptr, &error)) << error;
  const StrandModel& short_model = cut.masters.models[0];
  ASSERT_EQ(short_model.NumSegments(), 5);
  EXPECT_NEAR(short_model.Length(), 0.11, 1e-15);
  EXPECT_TRUE(short_model.rest_curvatures == dry_model.rest_curvatures.head(15));

  ASSERT_TRUE(Curl(&hair, 0.01, 0.02, StrandSelection{}, BatchOptions{}, nullptr, &error)) << error;
  EXPECT_EQ(hair.masters.models[0].rest_curvatures.size(), 0);
  EXPECT_EQ(hair.masters.models[0].contact.clearance,
            hair.masters.wisp_radii[0] * std::max(1.0, style.wisps.tip_scale) + 1 * 0.003);
}

}  // namespace
}  // namespace ringlet
