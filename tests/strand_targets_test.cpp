// Strand targets read from .hair, .data, .usda and .obj files (issue 13, item 2), and the
// USC-HairSalon .data writer.
//
// Independent references: the .data layout as USC-HairSalon's public readers use it (int32
// strand count, then per strand an int32 vertex count and float32 xyz triples, little-endian;
// built here byte by byte); hand-written files in tests/data/strand_targets/ whose expected
// coordinates are worked out by hand in the comments (cm -> m: divide by 100; y up -> z up:
// (x, y, z) -> (x, -z, y)); and the library's own exporters for the round trips, which write the
// shortest decimal text of each float (std::to_chars), so text round trips are exact.
#include <gtest/gtest.h>
#include <unistd.h>

#include <bit>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "ringlet/atomic_file.h"
#include "ringlet/hair_file.h"
#include "ringlet/obj_export.h"
#include "ringlet/strand_targets.h"
#include "ringlet/usc_data.h"
#include "ringlet/usd_export.h"

#ifndef RINGLET_TEST_DATA_DIR
#error "RINGLET_TEST_DATA_DIR must name tests/data"
#endif

namespace ringlet {
namespace {

using UpAxis = StrandTargetOptions::UpAxis;

std::string Data(const std::string& name) {
  return std::string(RINGLET_TEST_DATA_DIR) + "/strand_targets/" + name;
}

// Strands with the given point counts: a random walk of 1..2 cm steps from random roots within
// 10 cm (so no two consecutive points coincide), widths 40..120 um, optional colours. Seeded.
HairCurves MakeCurves(const std::vector<uint32_t>& counts, bool colors, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> root(-0.1f, 0.1f), step(0.01f, 0.02f),
      width(40e-6f, 120e-6f), rgb(0.0f, 1.0f);
  std::uniform_int_distribution<int> axis(0, 2);
  HairCurves c;
  c.point_counts = counts;
  for (uint32_t n : counts) {
    Vec3f x(root(rng), root(rng), root(rng));
    for (uint32_t i = 0; i < n; ++i) {
      if (i > 0) x[axis(rng)] -= step(rng);
      c.points.push_back(x);
      c.widths.push_back(width(rng));
    }
    if (colors) c.colors.emplace_back(rgb(rng), rgb(rng), rgb(rng));
  }
  return c;
}

bool SameBits(float a, float b) { return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b); }

void ExpectSamePoints(const HairCurves& expected, const HairCurves& got) {
  ASSERT_EQ(got.point_counts, expected.point_counts);
  ASSERT_EQ(got.points.size(), expected.points.size());
  for (size_t i = 0; i < expected.points.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      ASSERT_TRUE(SameBits(got.points[i][c], expected.points[i][c]))
          << "point " << i << "," << c << ": " << got.points[i][c] << " vs "
          << expected.points[i][c];
    }
  }
}

void ExpectSameWidthsAndColors(const HairCurves& expected, const HairCurves& got) {
  ASSERT_EQ(got.widths.size(), expected.widths.size());
  for (size_t i = 0; i < expected.widths.size(); ++i) {
    ASSERT_TRUE(SameBits(got.widths[i], expected.widths[i])) << "width " << i;
  }
  ASSERT_EQ(got.colors.size(), expected.colors.size());
  for (size_t k = 0; k < expected.colors.size(); ++k) {
    for (int c = 0; c < 3; ++c) ASSERT_TRUE(SameBits(got.colors[k][c], expected.colors[k][c]));
  }
}

// Converted values: the file's decimal, divided by 100 in double and rounded to float, against
// the float of the hand-computed decimal: equal to within 1 ulp (EXPECT_FLOAT_EQ allows 4).
void ExpectPoint(const HairCurves& c, size_t i, float x, float y, float z) {
  ASSERT_LT(i, c.points.size());
  EXPECT_FLOAT_EQ(c.points[i].x(), x) << "point " << i;
  EXPECT_FLOAT_EQ(c.points[i].y(), y) << "point " << i;
  EXPECT_FLOAT_EQ(c.points[i].z(), z) << "point " << i;
}

void Put32(std::string* b, uint32_t v) {
  for (int i = 0; i < 4; ++i) b->push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
void PutF(std::string* b, float v) { Put32(b, std::bit_cast<uint32_t>(v)); }

// A .data file built from the layout: strands of (x, y, z) lists.
std::string DataBytes(const std::vector<std::vector<Vec3f>>& strands) {
  std::string b;
  Put32(&b, static_cast<uint32_t>(strands.size()));
  for (const auto& s : strands) {
    Put32(&b, static_cast<uint32_t>(s.size()));
    for (const Vec3f& x : s) {
      for (int c = 0; c < 3; ++c) PutF(&b, x[c]);
    }
  }
  return b;
}

class TempDir {
 public:
  TempDir() {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "ringlet_targets_XXXXXX").string();
    path_ = ::mkdtemp(pattern.data()) ? pattern : std::string();
  }
  ~TempDir() {
    std::error_code ignored;
    if (!path_.empty()) std::filesystem::remove_all(path_, ignored);
  }
  std::string File(const std::string& name) const { return path_ + "/" + name; }
  // Writes text to a file of the directory and returns its path.
  std::string Write(const std::string& name, const std::string& text) const {
    std::string error;
    EXPECT_TRUE(WriteFileAtomically(File(name), text, true, &error)) << error;
    return File(name);
  }

 private:
  std::string path_;
};

// The error of reading path (with options), expected to fail and leave the curves unchanged.
std::string ReadError(const std::string& path, const StrandTargetOptions& options = {}) {
  HairCurves curves = MakeCurves({2}, false, 1);
  const HairCurves before = curves;
  std::string why;
  EXPECT_FALSE(ReadStrandTargets(path, options, &curves, &why)) << path;
  EXPECT_EQ(curves.points, before.points) << "curves changed on failure";
  return why;
}

// ---------------------------------------------------------------------------------------------
// .data: layout, round trips, HairSalon's empty strands

TEST(UscData, EncodeWritesTheLayoutByteForByte) {
  HairCurves c;
  c.point_counts = {2, 3};
  c.points = {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}, {10, 11, 12}, {13, 14, 15}};
  c.widths.assign(5, 1e-4f);
  std::string bytes, error;
  ASSERT_TRUE(EncodeUscData(c, StrandTargetOptions(), &bytes, &error)) << error;
  EXPECT_EQ(bytes, DataBytes({{{1, 2, 3}, {4, 5, 6}}, {{7, 8, 9}, {10, 11, 12}, {13, 14, 15}}}));
  // Y up and centimetres: (x, y, z) m -> (x, z, -y) * 100.
  StrandTargetOptions yup_cm;
  yup_cm.up_axis = UpAxis::kY;
  yup_cm.units_per_metre = 100.0;
  ASSERT_TRUE(EncodeUscData(c, yup_cm, &bytes, &error)) << error;
  EXPECT_EQ(bytes, DataBytes({{{100, 300, -200}, {400, 600, -500}},
                              {{700, 900, -800}, {1000, 1200, -1100}, {1300, 1500, -1400}}}));
}

TEST(UscData, RoundTripIsBitExact) {
  const HairCurves curves = MakeCurves({100, 2, 37, 100}, false, 7);
  for (const UpAxis up : {UpAxis::kZ, UpAxis::kY}) {
    StrandTargetOptions options;
    options.up_axis = up;
    std::string bytes, error;
    ASSERT_TRUE(EncodeUscData(curves, options, &bytes, &error)) << error;
    EXPECT_EQ(bytes.size(), 4u + 4 * 4 + 12 * curves.points.size());
    HairCurves back;
    StrandTargetSummary summary;
    ASSERT_TRUE(DecodeUscData(bytes, options, &back, &summary, &error)) << error;
    ExpectSamePoints(curves, back);
    ASSERT_EQ(back.widths.size(), back.points.size());
    EXPECT_EQ(back.widths[0], static_cast<float>(70e-6));  // the default width
    EXPECT_EQ(summary.skipped_empty_strands, 0u);
    EXPECT_EQ(summary.file_strand_index, (std::vector<uint64_t>{0, 1, 2, 3}));
  }
  // Through files, with ReadStrandTargets.
  TempDir dir;
  std::string error;
  ASSERT_TRUE(WriteUscData(dir.File("a.data"), curves, {}, false, &error)) << error;
  HairCurves back;
  ASSERT_TRUE(ReadStrandTargets(dir.File("a.data"), {}, &back, &error)) << error;
  ExpectSamePoints(curves, back);
  EXPECT_FALSE(WriteUscData(dir.File("a.data"), curves, {}, false, &error));
  EXPECT_EQ(error, dir.File("a.data") + ": already exists");
}

TEST(UscData, HandWrittenYUpFileSkipsEmptyStrands) {
  // hairsalon_yup.data: 4 strands of 1, 3, 0 and 2 vertices, metres, y up (made with Python's
  // struct.pack('<i') and ('<3f')). Strands 0 and 2 hold no hair and are skipped; y up -> z up:
  // (x, y, z) -> (x, -z, y), exact in float.
  StrandTargetOptions options;
  options.up_axis = UpAxis::kY;
  HairCurves c;
  StrandTargetSummary summary;
  std::string error;
  ASSERT_TRUE(ReadStrandTargets(Data("hairsalon_yup.data"), options, &c, &summary, &error))
      << error;
  EXPECT_EQ(c.point_counts, (std::vector<uint32_t>{3, 2}));
  EXPECT_EQ(summary.skipped_empty_strands, 2u);
  EXPECT_EQ(summary.file_strand_index, (std::vector<uint64_t>{1, 3}));
  const std::vector<Vec3f> expected = {{0.0f, -0.05f, 1.7f},   {0.0f, -0.06f, 1.6f},
                                       {0.01f, -0.065f, 1.5f}, {-0.02f, 0.04f, 1.68f},
                                       {-0.02f, 0.05f, 1.58f}};
  ASSERT_EQ(c.points.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(SameBits(c.points[i][k], expected[i][k])) << i;
  }
  EXPECT_TRUE(c.colors.empty());
  EXPECT_TRUE(c.major_axes.empty());
}

TEST(UscData, MalformedFilesGiveOneLineNamingStrandAndPoint) {
  const StrandTargetOptions z;
  std::string error;
  HairCurves c;
  const auto decode = [&](const std::string& bytes) {
    error.clear();
    EXPECT_FALSE(DecodeUscData(bytes, z, &c, nullptr, &error));
    return error;
  };
  EXPECT_EQ(decode(""), "header: truncated, expected a 4-byte strand count, got 0 bytes");
  // 2^32 - 1 strands announced in a 100-byte file: as the int32 the format uses, that is -1.
  std::string huge;
  Put32(&huge, 0xffffffffu);
  huge.resize(100, '\0');
  EXPECT_EQ(decode(huge), "header: negative strand count -1 (bytes 0-3 read as a little-endian "
                          "int32)");
  // 2^31 - 1 strands in 100 bytes: each strand needs its 4-byte count, so at most 24 fit.
  std::string big;
  Put32(&big, 0x7fffffffu);
  big.resize(100, '\0');
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(decode(big), "header: 2147483647 strands announced, but a 100-byte file holds at "
                         "most 24 (4 bytes per strand at least)");
  // Not a timing assertion: the refusal comes from the header, before any allocation.
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
  // A vertex count of 2^31 - 1 in a small file.
  std::string many;
  Put32(&many, 1);
  Put32(&many, 0x7fffffffu);
  EXPECT_EQ(decode(many), "strand 0: truncated, 2147483647 vertices need 25769803764 bytes "
                          "from byte 8, the file has 0 left");
  std::string negative;
  Put32(&negative, 1);
  Put32(&negative, 0xfffffffeu);
  EXPECT_EQ(decode(negative), "strand 0: negative vertex count -2");
  std::string two = DataBytes({{{0, 0, 0}, {0, 0, 1}}});
  Put32(&two, 0);  // announce 1 strand, store 2: the second count is trailing data
  EXPECT_EQ(decode(two), "trailing data: 4 bytes after the last strand (which ends at byte 32)");
  std::string missing = DataBytes({{{0, 0, 0}, {0, 0, 1}}});
  missing[0] = 2;  // 2 strands announced, 1 stored
  EXPECT_EQ(decode(missing), "strand 1: truncated, the vertex count at byte 32 is missing (file "
                             "of 32 bytes)");
  std::string cut = DataBytes({{{0, 0, 0}, {0, 0, 1}}});
  cut.pop_back();
  EXPECT_EQ(decode(cut), "strand 0: truncated, 2 vertices need 24 bytes from byte 8, the file "
                         "has 23 left");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(decode(DataBytes({{{0, 0, 0}}, {{0, 0, 0}, {0, 0, 1}, {nan, 0, 2}}})),
            "strand 1, point 2: expected finite coordinates");
  EXPECT_EQ(decode(DataBytes({{{0, 0, 0}}, {{0, 0, 0}, {0, 0, 1}, {0, 0, 1}}})),
            "strand 1, point 2: repeated point (the same as point 1, (0, 0, 1) m): a zero-length "
            "segment has no tangent");
  EXPECT_EQ(decode(DataBytes({{{0, 0, 0}, {0, 0, 2e4f}}})),
            "strand 0, point 1: coordinates (0, 0, 20000) m beyond the limit of 1e4 m (check the "
            "length unit)");
  // The options are checked first.
  StrandTargetOptions bad;
  bad.units_per_metre = 0.0;
  EXPECT_FALSE(DecodeUscData(DataBytes({}), bad, &c, nullptr, &error));
  EXPECT_EQ(error, "strand target options: units_per_metre: expected a finite number > 0");
  // A file of empty roots only reads as no strands.
  ASSERT_TRUE(DecodeUscData(DataBytes({{{0, 0, 0}}, {}}), z, &c, nullptr, &error)) << error;
  EXPECT_EQ(c.NumStrands(), 0);
}

TEST(UscData, EncodeRejectsWhatTheFormatCannotHold) {
  HairCurves c = MakeCurves({3}, false, 2);
  std::string bytes, error;
  StrandTargetOptions huge_unit;
  huge_unit.units_per_metre = 1e300;
  EXPECT_FALSE(EncodeUscData(c, huge_unit, &bytes, &error));
  EXPECT_EQ(error.rfind("curves.points[0]: not finite in file units", 0), 0u) << error;
  c.point_counts = {2};
  EXPECT_FALSE(EncodeUscData(c, {}, &bytes, &error));
  EXPECT_EQ(error, "curves.points: expected 2 points (the sum of point_counts), got 3");
  TempDir dir;
  EXPECT_FALSE(WriteUscData(dir.File("bad.data"), c, {}, false, &error));
  EXPECT_FALSE(std::filesystem::exists(dir.File("bad.data")));
}

// ---------------------------------------------------------------------------------------------
// Round trips through ringlet's own exporters

TEST(StrandTargets, RingletOwnUsdaObjAndHairReadBackExactly) {
  const HairCurves curves = MakeCurves({5, 2, 9}, true, 3);
  TempDir dir;
  std::string error;
  HairCurves back;
  // .usda: points, widths and colours, bit for bit (shortest float text, parsed back).
  ASSERT_TRUE(WriteUsda(dir.File("a.usda"), curves, {}, false, &error)) << error;
  StrandTargetSummary summary;
  ASSERT_TRUE(ReadStrandTargets(dir.File("a.usda"), {}, &back, &summary, &error)) << error;
  ExpectSamePoints(curves, back);
  ExpectSameWidthsAndColors(curves, back);
  EXPECT_EQ(summary.metres_per_unit, 1.0);
  EXPECT_EQ(summary.up_axis, UpAxis::kZ);
  // A y-up option does not apply to .usda, whose stage says z up ...
  StrandTargetOptions yup;
  yup.up_axis = UpAxis::kY;
  ASSERT_TRUE(ReadStrandTargets(dir.File("a.usda"), yup, &back, &error)) << error;
  ExpectSamePoints(curves, back);
  // ... unless the options override the stage's metadata: then (x, y, z) -> (x, -z, y).
  yup.ignore_file_metadata = true;
  ASSERT_TRUE(ReadStrandTargets(dir.File("a.usda"), yup, &back, &error)) << error;
  ASSERT_EQ(back.points.size(), curves.points.size());
  EXPECT_TRUE(SameBits(back.points[4].y(), -curves.points[4].z()));
  EXPECT_TRUE(SameBits(back.points[4].z(), curves.points[4].y()));

  // .obj: points and colours exactly; widths are not in OBJ (the default).
  ASSERT_TRUE(WriteObj(dir.File("a.obj"), curves, false, &error)) << error;
  ASSERT_TRUE(ReadStrandTargets(dir.File("a.obj"), {}, &back, &error)) << error;
  ExpectSamePoints(curves, back);
  HairCurves expected = curves;
  expected.widths.assign(curves.points.size(), static_cast<float>(70e-6));
  ExpectSameWidthsAndColors(expected, back);

  // .hair (the existing reader, with the strand checks added).
  ASSERT_TRUE(WriteHairFile(dir.File("a.hair"), curves, {}, false, &error)) << error;
  ASSERT_TRUE(ReadStrandTargets(dir.File("a.hair"), {}, &back, &error)) << error;
  ExpectSamePoints(curves, back);
  ExpectSameWidthsAndColors(curves, back);
  // In centimetres: written x100, read /100: within 1 ulp of float (double arithmetic,
  // rounded twice).
  HairFileOptions cm;
  cm.units_per_metre = 100.0;
  ASSERT_TRUE(WriteHairFile(dir.File("cm.hair"), curves, cm, false, &error)) << error;
  StrandTargetOptions read_cm;
  read_cm.units_per_metre = 100.0;
  ASSERT_TRUE(ReadStrandTargets(dir.File("cm.hair"), read_cm, &back, &error)) << error;
  ASSERT_EQ(back.points.size(), curves.points.size());
  for (size_t i = 0; i < curves.points.size(); ++i) {
    for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(back.points[i][c], curves.points[i][c]);
  }
}

TEST(StrandTargets, UsdaSequenceReadsItsEarliestFrame) {
  // A grow-like sequence: frame 0 has 2 strands, frame 1 three (topology time-sampled).
  std::vector<HairCurves> frames = {MakeCurves({4, 3}, false, 5), MakeCurves({4, 3, 6}, false, 6)};
  TempDir dir;
  std::string error;
  ASSERT_TRUE(WriteUsdaSequence(dir.File("seq.usda"), frames, {}, false, &error)) << error;
  HairCurves back;
  ASSERT_TRUE(ReadStrandTargets(dir.File("seq.usda"), {}, &back, &error)) << error;
  ExpectSamePoints(frames[0], back);
}

// ---------------------------------------------------------------------------------------------
// Hand-written files: y up, centimetres, other writers' conventions

TEST(StrandTargets, HandWrittenYUpCentimetreUsda) {
  // yup_cm.usda: metersPerUnit 0.01, upAxis "Y" (the stage decides, whatever the options say).
  // (x, y, z) cm -> (x, -z, y) / 100 m.
  HairCurves c;
  StrandTargetSummary summary;
  std::string error;
  ASSERT_TRUE(ReadStrandTargets(Data("yup_cm.usda"), {}, &c, &summary, &error)) << error;
  EXPECT_EQ(summary.metres_per_unit, 0.01);
  EXPECT_EQ(summary.up_axis, UpAxis::kY);
  EXPECT_EQ(c.point_counts, (std::vector<uint32_t>{3, 2}));
  ExpectPoint(c, 0, 0.0f, -0.05f, 1.7f);    // (0, 170, 5)
  ExpectPoint(c, 1, 0.0f, -0.06f, 1.6f);    // (0, 160, 6)
  ExpectPoint(c, 2, 0.01f, -0.065f, 1.5f);  // (1, 150, 6.5)
  ExpectPoint(c, 3, -0.02f, 0.04f, 1.68f);  // (-2, 168, -4)
  ExpectPoint(c, 4, -0.02f, 0.05f, 1.58f);  // (-2, 158, -5)
  // primvars:widths, uniform: 0.008 cm and 0.01 cm per curve.
  ASSERT_EQ(c.widths.size(), 5u);
  for (int i = 0; i < 3; ++i) EXPECT_FLOAT_EQ(c.widths[i], 8e-5f);
  for (int i = 3; i < 5; ++i) EXPECT_FLOAT_EQ(c.widths[i], 1e-4f);
  // displayColor, constant: the same colour on both strands.
  ASSERT_EQ(c.colors.size(), 2u);
  EXPECT_EQ(c.colors[1], Vec3f(0.2f, 0.1f, 0.05f));
}

TEST(StrandTargets, HandWrittenUsdaWithTwoPrimsClassesAndTimeSamples) {
  // zup_m_two_prims.usda: "front" (1 curve, vertex widths), a class (abstract, skipped) and
  // "back" whose counts and points are time-sampled (times 2 then 1: the earliest, 1, is read)
  // with a constant width. Metres, z up: the numbers as written.
  HairCurves c;
  std::string error;
  ASSERT_TRUE(ReadStrandTargets(Data("zup_m_two_prims.usda"), {}, &c, &error)) << error;
  EXPECT_EQ(c.point_counts, (std::vector<uint32_t>{2, 3}));
  ExpectPoint(c, 0, 0.01f, 0.02f, 0.03f);
  ExpectPoint(c, 1, 0.01f, 0.02f, -0.07f);
  ExpectPoint(c, 2, 0.0f, -0.1f, 0.02f);
  ExpectPoint(c, 4, 0.01f, -0.11f, -0.18f);
  EXPECT_EQ(c.widths, (std::vector<float>{5e-05f, 6e-05f, 7e-05f, 7e-05f, 7e-05f}));
  EXPECT_TRUE(c.colors.empty());
}

TEST(StrandTargets, HandWrittenObjSegmentChainsYUpCentimetres) {
  // segments_yup_cm.obj: strand 0 = "l 1 2", "l 2 3" joined (they share vertex 2); strand 1 =
  // "l -4 -3", "l -3 -2", "l -2/7 -1/8" with 7 vertices defined: vertices 4-5, 5-6, 6-7.
  StrandTargetOptions options;
  options.up_axis = UpAxis::kY;
  options.units_per_metre = 100.0;
  HairCurves c;
  std::string error;
  ASSERT_TRUE(ReadStrandTargets(Data("segments_yup_cm.obj"), options, &c, &error)) << error;
  EXPECT_EQ(c.point_counts, (std::vector<uint32_t>{3, 4}));
  ExpectPoint(c, 0, 0.0f, -0.05f, 1.7f);
  ExpectPoint(c, 2, 0.01f, -0.065f, 1.5f);
  ExpectPoint(c, 3, -0.02f, 0.04f, 1.68f);
  ExpectPoint(c, 5, -0.02f, 0.055f, 1.48f);
  ExpectPoint(c, 6, -0.03f, 0.055f, 1.38f);
  EXPECT_EQ(c.widths, std::vector<float>(7, static_cast<float>(70e-6)));
  options.default_width = 1e-4;
  ASSERT_TRUE(ReadStrandTargets(Data("segments_yup_cm.obj"), options, &c, &error)) << error;
  EXPECT_EQ(c.widths[6], 1e-4f);
}

TEST(StrandTargets, HandWrittenObjPolylines) {
  // polylines.obj: "l 1/1 2/1 3/1" and "l 4 5" (not joined: 3 != 4); the face is skipped.
  HairCurves c;
  std::string error;
  ASSERT_TRUE(ReadStrandTargets(Data("polylines.obj"), {}, &c, &error)) << error;
  EXPECT_EQ(c.point_counts, (std::vector<uint32_t>{3, 2}));
  ExpectPoint(c, 2, 0.0f, 0.01f, -0.1f);
  ExpectPoint(c, 3, 0.05f, 0.0f, 0.1f);
}

// ---------------------------------------------------------------------------------------------
// Errors: one line naming the file, the strand (or line) and the point

TEST(StrandTargets, UsdaErrors) {
  TempDir dir;
  const std::string head = "#usda 1.0\n(\n    upAxis = \"Z\"\n    metersPerUnit = 1\n)\n";
  const auto curves = [](const std::string& body) {
    return "def BasisCurves \"hair\"\n{\n" + body + "}\n";
  };
  const std::string linear = "    uniform token type = \"linear\"\n";
  const std::string good = linear + "    int[] curveVertexCounts = [2]\n" +
                           "    point3f[] points = [(0, 0, 0), (0, 0, -1)]\n";
  struct Case {
    std::string name, text, message;
  };
  const std::vector<Case> cases = {
      {"no_header.usda", curves(good), "line 1: expected the header \"#usda 1.0\" (a text USD layer)"},
      {"cubic.usda", head + curves("    uniform token type = \"cubic\"\n    int[] curveVertexCounts = [4]\n"
                                   "    point3f[] points = [(0,0,0),(0,0,1),(0,0,2),(0,0,3)]\n"),
       "</hair>.type: only \"linear\" curves are read, got \"cubic\""},
      {"no_type.usda", head + curves("    int[] curveVertexCounts = [2]\n    point3f[] points = [(0,0,0),(0,0,1)]\n"),
       "</hair>.type: not authored, and the schema's fallback is \"cubic\": only linear curves "
       "are read (uniform token type = \"linear\")"},
      {"periodic.usda", head + curves(good + "    uniform token wrap = \"periodic\"\n"),
       "</hair>.wrap: only open curves are read (\"nonperiodic\"), got \"periodic\""},
      {"nurbs.usda", head + "def NurbsCurves \"hair\"\n{\n}\n",
       "line 6: </hair> is a NurbsCurves prim: only linear BasisCurves are read"},
      {"none.usda", head + "def Xform \"root\"\n{\n}\n",
       "no BasisCurves prim (def BasisCurves \"name\" { ... }) in the file"},
      {"count_sum.usda", head + curves(linear + "    int[] curveVertexCounts = [3]\n"
                                                "    point3f[] points = [(0,0,0),(0,0,1)]\n"),
       "</hair>.points: 2 points, but curveVertexCounts add up to 3"},
      {"count_one.usda", head + curves(linear + "    int[] curveVertexCounts = [1, 1]\n"
                                                "    point3f[] points = [(0,0,0),(0,0,1)]\n"),
       "</hair>.curveVertexCounts[0]: expected an integer >= 2 (a linear curve needs 2 points), "
       "got 1"},
      {"nan.usda", head + curves(linear + "    int[] curveVertexCounts = [2]\n"
                                          "    point3f[] points = [(0,0,0),(0,nan,1)]\n"),
       "</hair>.points[1]: expected finite coordinates (as float)"},
      {"repeated.usda", head + curves(linear + "    int[] curveVertexCounts = [2, 3]\n"
                                               "    point3f[] points = [(0,0,0),(0,0,1),(1,0,0),(1,0,1),(1,0,1)]\n"),
       "strand 1 (</hair> curve 1), point 2: repeated point (the same as point 1, (1, 0, 1) m): a "
       "zero-length segment has no tangent"},
      {"widths.usda", head + curves(good + "    float[] widths = [1, 2, 3]\n"),
       "</hair>.widths: 3 values, but vertex interpolation needs 2"},
      {"xform.usda", head + "def Xform \"root\"\n{\n    double3 xformOp:translate = (0, 0, 1)\n"
                            "    uniform token[] xformOpOrder = [\"xformOp:translate\"]\n" +
                            curves(good) + "}\n",
       "</root/hair>: transforms (xformOpOrder on </root>) are not supported: bake them into the "
       "points first"},
      {"references.usda", head + "def Xform \"root\" (\n    references = @other.usda@\n)\n{\n}\n",
       "line 7: references: composition (sublayers, references, payloads, inherits, "
       "specializes, variants) is not supported; flatten the stage first (e.g. usdcat --flatten)"},
      {"unterminated.usda", head + "def BasisCurves \"hair\n{\n}\n",
       "line 6: unterminated string (a newline inside a quoted string)"},
      {"unclosed.usda", head + "def BasisCurves \"hair\"\n{\n" + good,
       "line 10: expected '}' closing prim </hair>, got the end of the file"},
      {"bad_number.usda", head + curves(linear + "    int[] curveVertexCounts = [2]\n"
                                                 "    point3f[] points = [(0,0,0),(0,1x,1)]\n"),
       "line 10: malformed number \"1x\""},
      {"up.usda", "#usda 1.0\n(\n    upAxis = \"X\"\n)\n" + curves(good),
       "line 3: upAxis: expected \"Y\" or \"Z\", got \"X\""},
      {"deep.usda", head + "def Xform \"a\" (\n    customData = {\n" + std::string(70, '[') + "\n",
       "line 8: nesting deeper than 64 levels"},
  };
  for (const Case& c : cases) {
    const std::string path = dir.Write(c.name, c.text);
    EXPECT_EQ(ReadError(path), path + ": " + c.message) << c.name;
  }
}

TEST(StrandTargets, ObjErrors) {
  TempDir dir;
  struct Case {
    std::string name, text, message;
  };
  const std::string v3 = "v 0 0 0\nv 0 0 1\nv 0 0 2\n";
  const std::vector<Case> cases = {
      {"abc.obj", "v 0 abc 0\n", "line 1: expected a finite number for the vertex's value 2, got \"abc\""},
      {"nan.obj", "v 0 0 nan\n", "line 1: expected a finite number for the vertex's value 3, got \"nan\""},
      {"two.obj", "v 0 0\n", "line 1: expected 'v x y z' (optionally a weight, or r g b), got 2 values"},
      {"index.obj", v3 + "l 1 8x\n", "line 4: expected a non-zero vertex index, got \"8x\""},
      {"zero.obj", v3 + "l 0 1\n", "line 4: expected a non-zero vertex index, got \"0\""},
      {"one.obj", v3 + "l 1\n", "line 4: an 'l' element needs at least 2 vertices, got 1"},
      {"range.obj", v3 + "l 2 9\n", "line 4: vertex index 9 refers to no vertex (the file has 3)"},
      {"relative.obj", "l -1 -2\n" + v3, "line 1: vertex index \"-1\" refers to no vertex (0 defined so far)"},
      {"nolines.obj", v3 + "f 1 2 3\n", "no 'l' elements (polylines) in the file"},
      {"curv.obj", v3 + "curv 0 1 1 2\n", "line 4: free-form curves and surfaces ('curv') are not supported: only 'l' polylines are read"},
      {"repeated.obj", v3 + "l 1 2\nl 3 3\n", "strand 1 (line 5), point 1: repeated point (the same as point 0, (0, 0, 2) m): a zero-length segment has no tangent"},
  };
  for (const Case& c : cases) {
    const std::string path = dir.Write(c.name, c.text);
    EXPECT_EQ(ReadError(path), path + ": " + c.message) << c.name;
  }
  // Beyond 1e4 m once converted: the unit is probably wrong.
  StrandTargetOptions mm_as_m;
  const std::string far = dir.Write("far.obj", "v 0 0 0\nv 0 0 20000\nl 1 2\n");
  EXPECT_EQ(ReadError(far, mm_as_m), far + ": strand 0 (line 3), point 1: coordinates (0, 0, 20000) m beyond the limit of 1e4 m (check the length unit)");
}

TEST(StrandTargets, FileAndOptionErrors) {
  TempDir dir;
  const std::string txt = dir.Write("a.txt", "v 0 0 0\n");
  EXPECT_EQ(ReadError(txt), txt + ": unknown strand file extension \".txt\" (expected .hair, .data, .usda or .obj)");
  EXPECT_EQ(ReadError(dir.File("missing.obj")), dir.File("missing.obj") + ": cannot open: No such file or directory");
  StrandTargetOptions bad;
  bad.default_width = -1.0;
  EXPECT_EQ(ReadError(Data("polylines.obj"), bad), "strand target options: default_width: expected a finite width >= 0 (m)");
  // .hair: the reader's own errors, then the strand checks (a repeated point).
  HairCurves repeated = MakeCurves({3}, false, 9);
  repeated.points[2] = repeated.points[1];
  std::string error;
  ASSERT_TRUE(WriteHairFile(dir.File("r.hair"), repeated, {}, false, &error)) << error;
  EXPECT_EQ(ReadError(dir.File("r.hair")).rfind(dir.File("r.hair") + ": strand 0, point 2: repeated point", 0), 0u);
  const std::string short_hair = dir.Write("s.hair", "HAIR");
  EXPECT_EQ(ReadError(short_hair), short_hair + ": header: truncated, expected 128 bytes, got 4");
  // A .data file announcing 2^32 - 1 strands in 100 bytes fails from the header, via the file.
  std::string huge;
  Put32(&huge, 0xffffffffu);
  huge.resize(100, '\0');
  const std::string huge_path = dir.Write("huge.data", huge);
  EXPECT_EQ(ReadError(huge_path), huge_path + ": header: negative strand count -1 (bytes 0-3 read as a little-endian int32)");
}

// Found by the fuzzer (tests/fuzz/fuzz_usda_targets.cpp): a prim name holding newlines made the
// message span several lines. Every message is one line of bounded length.
TEST(StrandTargets, UsdaMessageIsOneBoundedLineWhateverTheNames) {
  // A prim name with newlines (parse stage), an interpolation token with one (the check of
  // the parsed prims), and a prim name with carriage returns and NULs quoted by a check after
  // the reader (a repeated point; found by the hour-long fuzz run of usda_targets).
  for (const char* name : {"usda_prim_name_newline.usda", "usda_interpolation_newline.usda",
                           "usda_prim_name_control_later_check.usda"}) {
    const std::string path = std::string(RINGLET_TEST_DATA_DIR) + "/robustness/" + name;
    HairCurves curves;
    std::string why;
    ASSERT_FALSE(ReadStrandTargets(path, StrandTargetOptions{}, &curves, &why)) << name;
    for (const char c : why) {
      const unsigned char u = static_cast<unsigned char>(c);
      EXPECT_TRUE(u >= 0x20 && u != 0x7f) << "control character " << int{u} << " in: " << why;
    }
    EXPECT_LT(why.size(), path.size() + 500) << why;
    EXPECT_EQ(curves.NumStrands(), 0);
  }
}

}  // namespace
}  // namespace ringlet
