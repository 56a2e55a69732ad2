// Hair file exporters and the .hair reader (issue 4, item 8).
//
// Independent references: the published HAIR specification (byte offsets written as literal
// numbers below, from http://www.cemyuksel.com/research/hairmodels/ "HAIR File Format
// Specification": bytes 0-3 "HAIR", 4-7 strand count, 8-11 point count, 12-15 array bits
// (1 segments, 2 points, 4 thickness, 8 transparency, 16 colour; bits 5-31 reserved),
// 16-19 default segments, 20-23 default thickness, 24-27 default transparency, 28-39 default
// colour, 40-127 info; then the arrays in that order), Debian's tinyobjloader for OBJ, and a
// small USDA array parser written here (no USD tooling is packaged in Debian 12).
#include <gtest/gtest.h>
#include <tiny_obj_loader.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "ringlet/atomic_file.h"
#include "ringlet/body.h"
#include "ringlet/hair_file.h"
#include "ringlet/obj_export.h"
#include "ringlet/strand_export.h"
#include "ringlet/usd_export.h"

namespace ringlet {
namespace {

// ---------------------------------------------------------------------------------------------
// Test data and byte helpers (independent of the writer's constants).

// Strands with the given point counts: random points within 30 cm, widths 40..120 um, and
// (optionally) random colours. Seeded.
HairCurves MakeCurves(const std::vector<uint32_t>& counts, bool colors, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(-0.3f, 0.3f), width(40e-6f, 120e-6f), rgb(0.0f, 1.0f);
  HairCurves c;
  c.point_counts = counts;
  for (uint32_t n : counts) {
    for (uint32_t i = 0; i < n; ++i) {
      c.points.emplace_back(pos(rng), pos(rng), pos(rng));
      c.widths.push_back(width(rng));
    }
    if (colors) c.colors.emplace_back(rgb(rng), rgb(rng), rgb(rng));
  }
  return c;
}

uint32_t U32At(const std::string& b, size_t at) {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(b.at(at + i));
  return v;
}
uint16_t U16At(const std::string& b, size_t at) {
  return static_cast<uint16_t>(static_cast<unsigned char>(b.at(at)) |
                               (static_cast<unsigned char>(b.at(at + 1)) << 8));
}
float F32At(const std::string& b, size_t at) { return std::bit_cast<float>(U32At(b, at)); }

void Put32(std::string* b, uint32_t v) {
  for (int i = 0; i < 4; ++i) b->push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
void Put16(std::string* b, uint16_t v) {
  b->push_back(static_cast<char>(v & 0xff));
  b->push_back(static_cast<char>(v >> 8));
}
void PutF(std::string* b, float v) { Put32(b, std::bit_cast<uint32_t>(v)); }

// A 128-byte header laid out by the specification's byte ranges.
std::string Header(uint32_t strands, uint32_t points, uint32_t arrays, uint32_t default_segments,
                   float default_thickness, float default_transparency = 0.0f,
                   const char* info = "") {
  std::string b = "HAIR";
  Put32(&b, strands);           // bytes 4-7
  Put32(&b, points);            // bytes 8-11
  Put32(&b, arrays);            // bytes 12-15
  Put32(&b, default_segments);  // bytes 16-19
  PutF(&b, default_thickness);  // bytes 20-23
  PutF(&b, default_transparency);  // bytes 24-27
  for (int c = 0; c < 3; ++c) PutF(&b, 1.0f);  // bytes 28-39
  std::string text(88, '\0');   // bytes 40-127
  std::memcpy(text.data(), info, std::strlen(info));
  b += text;
  EXPECT_EQ(b.size(), 128u);
  return b;
}

bool SameBits(float a, float b) { return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b); }

void ExpectBitExact(const HairCurves& expected, const HairCurves& got) {
  ASSERT_EQ(got.point_counts, expected.point_counts);
  ASSERT_EQ(got.points.size(), expected.points.size());
  ASSERT_EQ(got.widths.size(), expected.widths.size());
  ASSERT_EQ(got.colors.size(), expected.colors.size());
  for (size_t i = 0; i < expected.points.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      ASSERT_TRUE(SameBits(got.points[i][c], expected.points[i][c])) << "point " << i << "," << c;
    }
    ASSERT_TRUE(SameBits(got.widths[i], expected.widths[i])) << "width " << i;
  }
  for (size_t k = 0; k < expected.colors.size(); ++k) {
    for (int c = 0; c < 3; ++c) {
      ASSERT_TRUE(SameBits(got.colors[k][c], expected.colors[k][c])) << "colour " << k;
    }
  }
}

// A fresh empty directory for file tests, removed at the end.
class TempDir {
 public:
  TempDir() {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "ringlet_export_XXXXXX").string();
    path_ = ::mkdtemp(pattern.data()) ? pattern : std::string();
  }
  ~TempDir() {
    std::error_code ignored;
    if (!path_.empty()) std::filesystem::remove_all(path_, ignored);
  }
  std::string File(const std::string& name) const { return path_ + "/" + name; }
  size_t Count() const {
    size_t n = 0;
    for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(path_)) ++n;
    return n;
  }

 private:
  std::string path_;
};

// ---------------------------------------------------------------------------------------------
// .hair

TEST(HairFile, RoundTripIsBitExactForVaryingCounts) {
  // Counts from the minimum (2) to the maximum a uint16 segment count allows (65536 points).
  HairCurves curves = MakeCurves({2, 7, 3, 32, 65536, 2}, true, 11);
  // Values whose bits a careless conversion would change: -0, a subnormal, a huge value.
  curves.points[0] = Vec3f(-0.0f, 1e-40f, 3e38f);
  curves.widths[1] = 0.0f;
  std::string bytes, error;
  ASSERT_TRUE(EncodeHairFile(curves, HairFileOptions(), &bytes, &error)) << error;
  HairCurves back;
  ASSERT_TRUE(DecodeHairFile(bytes, &back, &error)) << error;
  ExpectBitExact(curves, back);
  // Without colours the reader returns none (the default colour is not invented per strand).
  curves.colors.clear();
  ASSERT_TRUE(EncodeHairFile(curves, HairFileOptions(), &bytes, &error)) << error;
  ASSERT_TRUE(DecodeHairFile(bytes, &back, &error)) << error;
  ExpectBitExact(curves, back);
}

TEST(HairFile, HeaderFieldsSitAtTheSpecificationOffsets) {
  // Three strands of 4 points: equal counts, so no segments array and default segments = 3.
  const HairCurves curves = MakeCurves({4, 4, 4}, true, 5);
  HairFileOptions options;
  options.info = "test info";
  std::string b, error;
  ASSERT_TRUE(EncodeHairFile(curves, options, &b, &error)) << error;
  EXPECT_EQ(b.substr(0, 4), "HAIR");         // bytes 0-3
  EXPECT_EQ(U32At(b, 4), 3u);                // bytes 4-7: strands
  EXPECT_EQ(U32At(b, 8), 12u);               // bytes 8-11: points
  EXPECT_EQ(U32At(b, 12), 2u | 4u | 16u);    // bytes 12-15: points, thickness, colour
  EXPECT_EQ(U32At(b, 16), 3u);               // bytes 16-19: default segments = 4 - 1
  double mean_width = 0.0;
  for (float w : curves.widths) mean_width += w;
  EXPECT_EQ(F32At(b, 20), static_cast<float>(mean_width / 12.0));  // bytes 20-23
  EXPECT_EQ(F32At(b, 24), 0.0f);             // bytes 24-27: opaque
  for (int c = 0; c < 3; ++c) {              // bytes 28-39: mean colour
    const double mean = (double(curves.colors[0][c]) + curves.colors[1][c] + curves.colors[2][c]) / 3;
    EXPECT_EQ(F32At(b, 28 + 4 * c), static_cast<float>(mean)) << c;
  }
  EXPECT_EQ(std::string(b.data() + 40), "test info");  // bytes 40-127, zero-terminated
  for (size_t i = 40 + 9; i < 128; ++i) EXPECT_EQ(b[i], '\0') << i;
  // Arrays: points from byte 128 (3 floats each), thickness after them, then colours per point.
  ASSERT_EQ(b.size(), 128u + 12 * 12 + 4 * 12 + 12 * 12);
  EXPECT_EQ(F32At(b, 128), curves.points[0].x());
  EXPECT_EQ(F32At(b, 128 + 12 * 11 + 8), curves.points[11].z());
  EXPECT_EQ(F32At(b, 128 + 144), curves.widths[0]);
  EXPECT_EQ(F32At(b, 128 + 144 + 44), curves.widths[11]);
  EXPECT_EQ(F32At(b, 128 + 192 + 12 * 5 + 4), curves.colors[1].y());  // point 5 is in strand 1

  // Different counts: the segments array (uint16 = points - 1) comes first, right at byte 128.
  const HairCurves mixed = MakeCurves({2, 3}, false, 6);
  HairFileOptions bare;
  bare.store_thickness = false;
  ASSERT_TRUE(EncodeHairFile(mixed, bare, &b, &error)) << error;
  EXPECT_EQ(U32At(b, 12), 1u | 2u);
  EXPECT_EQ(U32At(b, 16), 0u);
  EXPECT_EQ(U16At(b, 128), 1u);
  EXPECT_EQ(U16At(b, 130), 2u);
  EXPECT_EQ(F32At(b, 132), mixed.points[0].x());
  EXPECT_EQ(b.size(), 128u + 2 * 2 + 12 * 5);
}

TEST(HairFile, NoStrandsIsAHeaderOnlyFile) {
  std::string b, error;
  ASSERT_TRUE(EncodeHairFile(HairCurves(), HairFileOptions(), &b, &error)) << error;
  ASSERT_EQ(b.size(), 128u);
  EXPECT_EQ(U32At(b, 4), 0u);
  EXPECT_EQ(U32At(b, 8), 0u);
  HairCurves back = MakeCurves({2}, true, 1);
  ASSERT_TRUE(DecodeHairFile(b, &back, &error)) << error;
  EXPECT_EQ(back.NumStrands(), 0);
  EXPECT_EQ(back.NumPoints(), 0);
  EXPECT_TRUE(back.widths.empty());
  EXPECT_TRUE(back.colors.empty());
}

TEST(HairFile, DecodesAHandBuiltFileWithOnlyPoints) {
  // Two strands of default 2 segments (3 points), default thickness 0.5 (file units).
  std::string b = Header(2, 6, 2, 2, 0.5f);
  for (int i = 0; i < 18; ++i) PutF(&b, static_cast<float>(i));
  HairCurves c;
  std::string error;
  ASSERT_TRUE(DecodeHairFile(b, &c, &error)) << error;
  EXPECT_EQ(c.point_counts, (std::vector<uint32_t>{3, 3}));
  ASSERT_EQ(c.NumPoints(), 6);
  EXPECT_EQ(c.points[4], Vec3f(12, 13, 14));
  EXPECT_EQ(c.widths, std::vector<float>(6, 0.5f));
  EXPECT_TRUE(c.colors.empty());
  // Read in centimetres: every length divided by 100.
  ASSERT_TRUE(DecodeHairFile(b, &c, &error, 100.0)) << error;
  EXPECT_FLOAT_EQ(c.points[5].z(), 0.17f);
  EXPECT_FLOAT_EQ(c.widths[0], 0.005f);
}

TEST(HairFile, DecodesEveryArrayAndSkipsTransparency) {
  // Strands of 2 and 3 points with all five arrays; colours differ along strand 1.
  std::string b = Header(2, 5, 1 | 2 | 4 | 8 | 16, 0, 1.0f);
  Put16(&b, 1);
  Put16(&b, 2);
  for (int i = 0; i < 15; ++i) PutF(&b, 0.1f * i);
  for (int i = 0; i < 5; ++i) PutF(&b, 1e-4f * (i + 1));  // thickness
  for (int i = 0; i < 5; ++i) PutF(&b, 0.25f);            // transparency
  const float rgb[5][3] = {{1, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, 1}};
  for (const auto& c : rgb) for (float v : c) PutF(&b, v);
  HairCurves c;
  std::string error;
  ASSERT_TRUE(DecodeHairFile(b, &c, &error)) << error;
  EXPECT_EQ(c.point_counts, (std::vector<uint32_t>{2, 3}));
  EXPECT_EQ(c.points[2], Vec3f(0.1f * 6, 0.1f * 7, 0.1f * 8));
  EXPECT_EQ(c.widths[4], 1e-4f * 5);  // the float written above, bit for bit
  ASSERT_EQ(c.colors.size(), 2u);
  EXPECT_EQ(c.colors[0], Vec3f(1, 0, 0));
  EXPECT_EQ(c.colors[1], Vec3f(0, 1, 0));  // the root colour of strand 1
}

TEST(HairFile, UnitsPerMetreScalesLengths) {
  const HairCurves curves = MakeCurves({3, 3}, false, 8);
  HairFileOptions options;
  options.units_per_metre = 100.0;  // centimetres
  std::string b, error;
  ASSERT_TRUE(EncodeHairFile(curves, options, &b, &error)) << error;
  EXPECT_EQ(F32At(b, 128), static_cast<float>(double(curves.points[0].x()) * 100.0));
  double mean_width = 0.0;  // default thickness: the mean width, in centimetres
  for (float w : curves.widths) mean_width += w;
  EXPECT_EQ(F32At(b, 20), static_cast<float>(mean_width / 6.0 * 100.0));
  HairCurves back;
  ASSERT_TRUE(DecodeHairFile(b, &back, &error, 100.0)) << error;
  for (int i = 0; i < 6; ++i) {
    // Two roundings (x100 to float, /100 to float): within 1 ulp of the original.
    EXPECT_NEAR(back.points[i].y(), curves.points[i].y(),
                std::abs(curves.points[i].y()) * std::numeric_limits<float>::epsilon());
    EXPECT_NEAR(back.widths[i], curves.widths[i],
                curves.widths[i] * std::numeric_limits<float>::epsilon());
  }
}

// The header's info text states the unit the file was written in (issue 14: with
// --hair-units-per-metre 100 it used to say "metres"). Expected strings written out by hand.
TEST(HairFile, InfoTextStatesTheUnitWritten) {
  const HairCurves curves = MakeCurves({3, 3}, false, 9);
  const auto info_of = [&](double units_per_metre) {
    HairFileOptions options;
    options.units_per_metre = units_per_metre;
    std::string b, error;
    EXPECT_TRUE(EncodeHairFile(curves, options, &b, &error)) << error;
    return std::string(b.data() + 40);  // bytes 40-127, zero-terminated
  };
  EXPECT_EQ(info_of(1.0),
            "ringlet hair curves; 1 unit per metre (metres); z up; thickness: diameter");
  EXPECT_EQ(info_of(100.0),
            "ringlet hair curves; 100 units per metre (centimetres); z up; thickness: diameter");
  EXPECT_EQ(info_of(1000.0),
            "ringlet hair curves; 1000 units per metre (millimetres); z up; thickness: diameter");
  EXPECT_EQ(info_of(39.37),
            "ringlet hair curves; 39.37 units per metre; z up; thickness: diameter");
  // The longest number fits the 87 characters.
  EXPECT_LE(DefaultHairInfo(1.2345678901234567e-300).size(), 87u);
  HairFileOptions long_unit;
  long_unit.units_per_metre = 1.2345678901234567e-300;
  std::string why;
  EXPECT_TRUE(long_unit.IsValid(&why)) << why;
  // An explicit info text is written as given.
  HairFileOptions mine;
  mine.info = "my own";
  std::string b, error;
  ASSERT_TRUE(EncodeHairFile(curves, mine, &b, &error)) << error;
  EXPECT_EQ(std::string(b.data() + 40), "my own");
}

// Every encode-time error: one line, naming the field.
TEST(HairFile, EncodeRejectsBadCurvesAndOptions) {
  auto expect_error = [](const HairCurves& c, const HairFileOptions& o, const std::string& field) {
    std::string bytes = "untouched", error;
    EXPECT_FALSE(EncodeHairFile(c, o, &bytes, &error)) << field;
    EXPECT_NE(error.find(field), std::string::npos) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    EXPECT_EQ(bytes, "untouched");
  };
  const HairCurves good = MakeCurves({3, 4}, true, 1);
  const HairFileOptions o;
  HairCurves c = MakeCurves({2, 65537}, false, 2);  // 65536 segments do not fit a uint16
  expect_error(c, o, "curves.point_counts[1]: 65537 points");
  c = good;
  c.point_counts[0] = 1;
  c.points.erase(c.points.begin());
  c.widths.erase(c.widths.begin());
  expect_error(c, o, "curves.point_counts[0]: expected at least 2");
  c = good;
  c.points.pop_back();
  expect_error(c, o, "curves.points: expected 7 points");
  c = good;
  c.widths.pop_back();
  expect_error(c, o, "curves.widths: expected one width per point");
  c = good;
  c.colors.pop_back();
  expect_error(c, o, "curves.colors: expected none or one per strand");
  c = good;
  c.points[5].y() = std::numeric_limits<float>::quiet_NaN();
  expect_error(c, o, "curves.points[5]: expected finite");
  c = good;
  c.widths[2] = -1e-6f;
  expect_error(c, o, "curves.widths[2]");
  c = good;
  c.colors[1].z() = std::numeric_limits<float>::infinity();
  expect_error(c, o, "curves.colors[1]");
  c = good;
  c.major_axes.assign(c.points.size() - 1, Vec3f::UnitX());
  expect_error(c, o, "curves.major_axes: expected none or one per point (7), got 6");
  c = good;
  c.major_axes.assign(c.points.size(), Vec3f::UnitX());
  c.major_axes[4].x() = std::numeric_limits<float>::quiet_NaN();
  expect_error(c, o, "curves.major_axes[4]: expected a finite direction");
  HairFileOptions bad;
  bad.info = std::string(88, 'x');
  expect_error(good, bad, "info: expected at most 87 characters");
  bad.info = "caf\xc3\xa9";
  expect_error(good, bad, "info: expected printable ASCII");
  bad = HairFileOptions();
  bad.units_per_metre = 0.0;
  expect_error(good, bad, "units_per_metre");
  // 87 characters is fine.
  bad = HairFileOptions();
  bad.info = std::string(87, 'x');
  std::string bytes, error;
  EXPECT_TRUE(EncodeHairFile(good, bad, &bytes, &error)) << error;
}

// Every malformed-file error: one line, naming the field; the output is left untouched.
TEST(HairFile, DecodeRejectsMalformedFiles) {
  std::string good;
  {
    std::string error;
    ASSERT_TRUE(EncodeHairFile(MakeCurves({2, 3}, true, 3), HairFileOptions(), &good, &error));
  }
  // good: 128 header + 4 segments + 60 points + 20 thickness + 60 colours.
  ASSERT_EQ(good.size(), 128u + 4 + 60 + 20 + 60);
  auto expect_error = [](const std::string& bytes, const std::string& field) {
    HairCurves c = MakeCurves({2}, false, 9);
    const HairCurves before = c;
    std::string error;
    EXPECT_FALSE(DecodeHairFile(bytes, &c, &error)) << field;
    EXPECT_NE(error.find(field), std::string::npos) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    EXPECT_EQ(c.points, before.points);
  };
  auto patched32 = [&](size_t at, uint32_t v) {
    std::string b = good;
    for (int i = 0; i < 4; ++i) b[at + i] = static_cast<char>((v >> (8 * i)) & 0xff);
    return b;
  };
  auto patched_float = [&](size_t at, float v) { return patched32(at, std::bit_cast<uint32_t>(v)); };
  const float nan = std::numeric_limits<float>::quiet_NaN();

  expect_error(good.substr(0, 100), "header: truncated, expected 128 bytes, got 100");
  expect_error("HAIX" + good.substr(4), "header.signature");
  expect_error(patched32(12, 2 | 4 | 16 | 1 | 32), "header.arrays: reserved bits");
  expect_error(patched32(12, 1 | 4 | 16), "header.arrays: the points array");
  expect_error(good.substr(0, good.size() - 1), "arrays: truncated");
  expect_error(good + '\0', "arrays: 1 unexpected bytes");
  expect_error(patched32(8, 6), "arrays: truncated");  // more points than bytes
  {
    std::string b = good;  // segments[1] = 0
    b[130] = 0;
    b[131] = 0;
    expect_error(b, "segments[1]: expected at least 1 segment");
  }
  {
    std::string b = good;  // segments say 2 + 2 points, the header says 5
    b[130] = 1;
    expect_error(b, "header.point_count: 5 points, but the segment counts add up to 4");
  }
  expect_error(patched_float(128 + 4 + 12 * 3 + 4, nan), "points[3]: expected finite");
  expect_error(patched_float(128 + 4 + 8, std::numeric_limits<float>::infinity()), "points[0]");
  expect_error(patched_float(128 + 4 + 60 + 8, -1.0f), "thickness[2]");
  expect_error(patched_float(128 + 4 + 60 + 8, nan), "thickness[2]");
  expect_error(patched_float(128 + 4 + 60 + 20 + 12 * 2, nan), "colors[2]");  // root of strand 1
  // Files without a segments or thickness array fall back on header defaults, checked too.
  std::string points_only = Header(1, 3, 2, 0, 1.0f);
  for (int i = 0; i < 9; ++i) PutF(&points_only, 0.0f);
  expect_error(points_only, "header.default_segments: expected at least 1");
  std::string bad_default = Header(1, 3, 2, 2, nan);
  for (int i = 0; i < 9; ++i) PutF(&bad_default, 0.0f);
  expect_error(bad_default, "header.default_thickness");
  std::string wrong_total = Header(2, 5, 2, 2, 1.0f);  // 2 strands x 3 points = 6, not 5
  for (int i = 0; i < 15; ++i) PutF(&wrong_total, 0.0f);
  expect_error(wrong_total, "header.point_count: 5 points, but the segment counts add up to 6");
  // Issue 16: 140 bytes announcing 2^32 - 1 strands (and 1 point) are refused from the header,
  // before any allocation (the reader used to resize to 17 GB first).
  std::string huge = Header(0xFFFFFFFFu, 1, 2, 1, 1.0f);
  for (int i = 0; i < 3; ++i) PutF(&huge, 0.0f);
  ASSERT_EQ(huge.size(), 140u);
  expect_error(huge, "header.strand_count: 4294967295 strands need at least 8589934590 points");
  std::string odd = Header(2, 3, 2, 1, 1.0f);  // 2 strands need 4 points
  for (int i = 0; i < 9; ++i) PutF(&odd, 0.0f);
  expect_error(odd, "header.strand_count: 2 strands need at least 4 points");
  // Reading in an invalid unit.
  HairCurves c;
  std::string error;
  EXPECT_FALSE(DecodeHairFile(good, &c, &error, -1.0));
  EXPECT_NE(error.find("units_per_metre"), std::string::npos);
  // An empty set of strands is a valid file.
  EXPECT_TRUE(DecodeHairFile(Header(0, 0, 2, 0, 1.0f), &c, &error)) << error;
  EXPECT_EQ(c.NumStrands(), 0);
}

TEST(HairFile, WriteAndReadFilesAtomically) {
  TempDir dir;
  const std::string path = dir.File("groom.hair");
  const HairCurves curves = MakeCurves({5, 9, 5}, true, 4);
  std::string error;
  ASSERT_TRUE(WriteHairFile(path, curves, HairFileOptions(), false, &error)) << error;
  HairCurves back;
  ASSERT_TRUE(ReadHairFile(path, &back, &error)) << error;
  ExpectBitExact(curves, back);
  // No overwrite unless asked; a failed encode writes nothing; read errors name the file.
  EXPECT_FALSE(WriteHairFile(path, curves, HairFileOptions(), false, &error));
  EXPECT_EQ(error, path + ": already exists");
  HairCurves bad = curves;
  bad.widths[0] = -1.0f;
  EXPECT_FALSE(WriteHairFile(dir.File("bad.hair"), bad, HairFileOptions(), false, &error));
  EXPECT_EQ(error.rfind(dir.File("bad.hair") + ": curves.widths[0]", 0), 0u) << error;
  EXPECT_EQ(dir.Count(), 1u);
  ASSERT_TRUE(WriteFileAtomically(dir.File("short.hair"), "HAIR", false, &error)) << error;
  EXPECT_FALSE(ReadHairFile(dir.File("short.hair"), &back, &error));
  EXPECT_EQ(error, dir.File("short.hair") + ": header: truncated, expected 128 bytes, got 4");
}

// ---------------------------------------------------------------------------------------------
// OBJ, read back with Debian's tinyobjloader ('l' elements land in shapes[].lines).

// Parses OBJ text with tinyobjloader (an independent reader).
struct ParsedObj {
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
};
ParsedObj ParseObj(const std::string& text) {
  ParsedObj obj;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  std::istringstream in(text);
  EXPECT_TRUE(tinyobj::LoadObj(&obj.attrib, &obj.shapes, &materials, &warn, &err, &in)) << err;
  return obj;
}

// Vertices and colours against the curves: tinyobjloader parses decimals with its own routine
// (mantissa x power of ten in double, then float), so allow 2 float ulps instead of the
// bit-exact strtof result.
void ExpectObjVertices(const tinyobj::attrib_t& attrib, const HairCurves& curves) {
  ASSERT_EQ(attrib.vertices.size(), 3 * curves.points.size());
  for (size_t i = 0; i < curves.points.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const float want = curves.points[i][c];
      EXPECT_NEAR(attrib.vertices[3 * i + c], want,
                  2 * std::numeric_limits<float>::epsilon() * std::abs(want))
          << i << "," << c;
    }
  }
  size_t next = 0;
  for (size_t k = 0; k < curves.point_counts.size(); ++k) {
    for (uint32_t i = 0; i < curves.point_counts[k]; ++i, ++next) {
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(attrib.colors[3 * next + c], curves.colors[k][c],
                    2 * std::numeric_limits<float>::epsilon());
      }
    }
  }
}

// Default: every segment of every strand is its own 2-vertex 'l' element, in order, root to
// tip; the header states units and axes.
TEST(ObjExport, TinyObjLoaderReadsEverySegment) {
  const HairCurves curves = MakeCurves({2, 6, 3, 17}, true, 21);
  std::string text, error;
  ASSERT_TRUE(EncodeObj(curves, &text, &error)) << error;
  EXPECT_EQ(text.rfind("# ringlet hair curves: 4 strands, 28 points\n", 0), 0u);
  EXPECT_NE(text.find("\n# units: metres; axes: right-handed, z up"), std::string::npos);
  EXPECT_NE(text.find("\n# one 2-vertex 'l' segment per edge, root to tip\n"), std::string::npos);
  const ParsedObj obj = ParseObj(text);
  ExpectObjVertices(obj.attrib, curves);
  ASSERT_EQ(obj.shapes.size(), 1u);
  EXPECT_EQ(obj.shapes[0].name, "hair");
  const tinyobj::lines_t& lines = obj.shapes[0].lines;
  // 1 + 5 + 2 + 16 = 24 segments, each (i, i + 1) inside a strand.
  ASSERT_EQ(lines.num_line_vertices.size(), 24u);
  size_t segment = 0;
  int first = 0;
  for (uint32_t count : curves.point_counts) {
    for (uint32_t i = 0; i + 1 < count; ++i, ++segment) {
      ASSERT_EQ(lines.num_line_vertices[segment], 2);
      EXPECT_EQ(lines.indices[2 * segment].vertex_index, first + static_cast<int>(i));
      EXPECT_EQ(lines.indices[2 * segment + 1].vertex_index, first + static_cast<int>(i) + 1);
    }
    first += static_cast<int>(count);
  }
  // Every 'l' line of the text has exactly two indices.
  std::istringstream in(text);
  std::string line;
  int l_lines = 0;
  while (std::getline(in, line)) {
    if (line.rfind("l ", 0) != 0) continue;
    ++l_lines;
    std::istringstream words(line.substr(2));
    int a = 0, b = 0, extra = 0;
    EXPECT_TRUE(words >> a >> b) << line;
    EXPECT_FALSE(words >> extra) << line;
    EXPECT_EQ(b, a + 1) << line;
  }
  EXPECT_EQ(l_lines, 24);
}

// ObjExportOptions::polylines: one 'l' polyline per strand.
TEST(ObjExport, PolylineOptionWritesOneLinePerStrand) {
  const HairCurves curves = MakeCurves({2, 6, 3, 17}, true, 21);
  ObjExportOptions options;
  options.polylines = true;
  std::string text, error;
  ASSERT_TRUE(EncodeObj(curves, options, &text, &error)) << error;
  EXPECT_NE(text.find("\n# one 'l' polyline per strand, root to tip\n"), std::string::npos);
  const ParsedObj obj = ParseObj(text);
  ExpectObjVertices(obj.attrib, curves);
  ASSERT_EQ(obj.shapes.size(), 1u);
  const tinyobj::lines_t& lines = obj.shapes[0].lines;
  ASSERT_EQ(lines.num_line_vertices.size(), curves.point_counts.size());
  size_t next = 0;
  for (size_t k = 0; k < curves.point_counts.size(); ++k) {
    ASSERT_EQ(static_cast<uint32_t>(lines.num_line_vertices[k]), curves.point_counts[k]);
    for (uint32_t i = 0; i < curves.point_counts[k]; ++i, ++next) {
      EXPECT_EQ(lines.indices[next].vertex_index, static_cast<int>(next));  // 0-based in the API
    }
  }
  EXPECT_EQ(next, curves.points.size());
}

// The body OBJ: a UV sphere per body sphere whose vertices lie on the sphere, closed and
// outward (positive divergence-theorem volume, close to 4/3 pi r^3), and a mesh as it is.
TEST(ObjExport, BodyObjHoldsTheSpheresAndMeshes) {
  // A unit tetrahedron mesh (counter-clockwise from outside) and two spheres.
  TriangleMesh tetra;
  std::string error;
  ASSERT_TRUE(TriangleMesh::Create({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)},
                                   {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}, "tetra", &tetra,
                                   &error))
      << error;
  Body body;
  ASSERT_TRUE(Body::Create({{Vec3(0.1, -0.2, 0.3), 0.1, "head"}, {Vec3(0, 0, -0.4), 0.13, ""}},
                           {tetra}, &body, &error))
      << error;
  std::string text;
  EncodeBodyObj(body, &text);
  EXPECT_NE(text.find("\n# units: metres; axes: right-handed, z up"), std::string::npos);
  const ParsedObj obj = ParseObj(text);
  ASSERT_EQ(obj.shapes.size(), 3u);
  EXPECT_EQ(obj.shapes[0].name, "head");
  EXPECT_EQ(obj.shapes[1].name, "sphere_1");
  EXPECT_EQ(obj.shapes[2].name, "tetra");
  // 48 meridians x 24 parallels: 23 rings of 48 vertices + 2 poles, 2 x 48 x 23 triangles.
  const size_t sphere_vertices = 23 * 48 + 2, sphere_triangles = 2 * 48 * 23;
  ASSERT_EQ(obj.attrib.vertices.size(), 3 * (2 * sphere_vertices + 4));
  const auto vertex = [&](int i) {
    return Vec3(obj.attrib.vertices[3 * i], obj.attrib.vertices[3 * i + 1],
                obj.attrib.vertices[3 * i + 2]);
  };
  const std::vector<Sphere>& spheres = body.spheres();
  for (int k = 0; k < 2; ++k) {
    const tinyobj::mesh_t& mesh = obj.shapes[k].mesh;
    ASSERT_EQ(mesh.num_face_vertices.size(), sphere_triangles);
    double volume = 0.0;  // sum of signed tetrahedra (centre, a, b, c) / 6
    for (size_t t = 0; t < sphere_triangles; ++t) {
      const Vec3 a = vertex(mesh.indices[3 * t].vertex_index) - spheres[k].center;
      const Vec3 b = vertex(mesh.indices[3 * t + 1].vertex_index) - spheres[k].center;
      const Vec3 c = vertex(mesh.indices[3 * t + 2].vertex_index) - spheres[k].center;
      for (const Vec3& v : {a, b, c}) {
        // float parsing: within a few float ulps of the radius
        EXPECT_NEAR(v.norm(), spheres[k].radius, 1e-6) << k << " " << t;
      }
      volume += a.dot(b.cross(c)) / 6.0;
    }
    // A polyhedron inscribed in the sphere: a little below 4/3 pi r^3 (0.5% at 48 x 24).
    const double ball = 4.0 / 3.0 * M_PI * std::pow(spheres[k].radius, 3);
    EXPECT_LT(volume, ball);
    EXPECT_GT(volume, 0.99 * ball);
  }
  const tinyobj::mesh_t& mesh = obj.shapes[2].mesh;
  ASSERT_EQ(mesh.num_face_vertices.size(), 4u);
  const int base = static_cast<int>(2 * sphere_vertices);
  // The first triangle as given: (0, 0, 0), (0, 1, 0), (1, 0, 0), in this order.
  for (int c = 0; c < 3; ++c) EXPECT_GE(mesh.indices[c].vertex_index, base);
  EXPECT_EQ(vertex(mesh.indices[0].vertex_index), Vec3(0, 0, 0));
  EXPECT_EQ(vertex(mesh.indices[1].vertex_index), Vec3(0, 1, 0));
  EXPECT_EQ(vertex(mesh.indices[2].vertex_index), Vec3(1, 0, 0));
  EXPECT_EQ(vertex(mesh.indices[11].vertex_index), Vec3(0, 0, 1));  // last triangle (1, 2, 3)
  // Empty body: the header only, no vertex.
  EncodeBodyObj(Body(), &text);
  EXPECT_EQ(text.find("\nv "), std::string::npos);
  EXPECT_EQ(text.rfind("# ringlet body: 0 spheres", 0), 0u);
}

TEST(ObjExport, RejectsBadCurvesAndWritesAtomically) {
  HairCurves curves = MakeCurves({3, 3}, false, 22);
  curves.points[4].x() = std::numeric_limits<float>::quiet_NaN();
  std::string text = "untouched", error;
  EXPECT_FALSE(EncodeObj(curves, &text, &error));
  EXPECT_NE(error.find("curves.points[4]: expected finite"), std::string::npos) << error;
  EXPECT_EQ(text, "untouched");
  TempDir dir;
  EXPECT_FALSE(WriteObj(dir.File("bad.obj"), curves, false, &error));
  EXPECT_EQ(dir.Count(), 0u);
  curves.points[4].x() = 0.0f;
  ASSERT_TRUE(WriteObj(dir.File("good.obj"), curves, false, &error)) << error;
  EXPECT_FALSE(WriteObj(dir.File("good.obj"), curves, false, &error));
  EXPECT_EQ(error, dir.File("good.obj") + ": already exists");
}

// ---------------------------------------------------------------------------------------------
// USDA, checked with a small parser written here (Debian 12 packages no USD tooling).

// The text of the bracketed array that follows "<declaration> = " (the first occurrence).
std::string ArrayAfter(const std::string& text, const std::string& declaration) {
  const size_t at = text.find(declaration + " = [");
  if (at == std::string::npos) return "";
  const size_t open = at + declaration.size() + 3;
  const size_t close = text.find(']', open);
  return text.substr(open, close - open + 1);
}

// All numbers of a bracketed array, flattened ("[(1, 2, 3), (4, 5, 6)]" -> 1..6), read with
// strtof (correctly rounded), so shortest-round-trip text must give back the same floats.
std::vector<float> Numbers(const std::string& array) {
  std::vector<float> out;
  const char* p = array.c_str();
  while (*p) {
    if (*p == '[' || *p == ']' || *p == '(' || *p == ')' || *p == ',' || *p == ' ') {
      ++p;
      continue;
    }
    char* end = nullptr;
    out.push_back(std::strtof(p, &end));
    if (end == p) return {};  // not a number: fail loudly in the caller
    p = end;
  }
  return out;
}

// Time samples "<declaration>.timeSamples = {\n  t: [...],\n ...}" as (time, numbers) pairs.
std::vector<std::pair<int, std::vector<float>>> TimeSamples(const std::string& text,
                                                            const std::string& declaration) {
  std::vector<std::pair<int, std::vector<float>>> out;
  size_t at = text.find(declaration + ".timeSamples = {\n");
  if (at == std::string::npos) return out;
  at = text.find('\n', at) + 1;
  while (true) {
    const size_t eol = text.find('\n', at);
    const std::string line = text.substr(at, eol - at);
    if (line.find('}') != std::string::npos && line.find('[') == std::string::npos) break;
    const size_t colon = line.find(':');
    const size_t open = line.find('[');
    out.emplace_back(std::atoi(line.c_str()),
                     Numbers(line.substr(open, line.rfind(']') - open + 1)));
    EXPECT_LT(colon, open);
    at = eol + 1;
  }
  return out;
}

std::vector<float> Flat(const std::vector<Vec3f>& v) {
  std::vector<float> out;
  for (const Vec3f& x : v) out.insert(out.end(), {x.x(), x.y(), x.z()});
  return out;
}
std::vector<float> Flat(const std::vector<uint32_t>& v) { return {v.begin(), v.end()}; }

// Parentheses, brackets and braces balance and quotes pair up: a crude syntax check.
void ExpectBalanced(const std::string& text) {
  int paren = 0, bracket = 0, brace = 0;
  bool quoted = false;
  for (char c : text) {
    if (c == '"') quoted = !quoted;
    if (quoted) continue;
    paren += (c == '(') - (c == ')');
    bracket += (c == '[') - (c == ']');
    brace += (c == '{') - (c == '}');
    ASSERT_GE(paren, 0);
    ASSERT_GE(bracket, 0);
    ASSERT_GE(brace, 0);
  }
  EXPECT_EQ(paren, 0);
  EXPECT_EQ(bracket, 0);
  EXPECT_EQ(brace, 0);
  EXPECT_FALSE(quoted);
}

bool HasLine(const std::string& text, const std::string& line) {
  return text.find("\n" + line + "\n") != std::string::npos;
}

TEST(UsdExport, BasisCurvesArraysAndStageMetadata) {
  HairCurves curves = MakeCurves({4, 2, 9}, true, 31);
  curves.widths[7] = 5e-4f;  // the largest width, sets the extent padding
  std::string text, error;
  ASSERT_TRUE(EncodeUsda(curves, UsdExportOptions(), &text, &error)) << error;
  EXPECT_EQ(text.rfind("#usda 1.0\n(\n", 0), 0u);
  EXPECT_TRUE(HasLine(text, "    defaultPrim = \"hair\""));
  EXPECT_TRUE(HasLine(text, "    metersPerUnit = 1"));
  EXPECT_TRUE(HasLine(text, "    upAxis = \"Z\""));
  EXPECT_TRUE(HasLine(text, "def BasisCurves \"hair\""));
  EXPECT_TRUE(HasLine(text, "    uniform token type = \"linear\""));
  EXPECT_EQ(text.find("timeSamples"), std::string::npos);
  EXPECT_EQ(text.find("startTimeCode"), std::string::npos);
  ExpectBalanced(text);

  EXPECT_EQ(Numbers(ArrayAfter(text, "    int[] curveVertexCounts")), Flat(curves.point_counts));
  const std::vector<float> points = Numbers(ArrayAfter(text, "    point3f[] points"));
  EXPECT_EQ(points, Flat(curves.points));  // bit-exact: shortest round-trip text + strtof
  ASSERT_EQ(points.size(), 45u);
  EXPECT_EQ(points[0], curves.points.front().x());
  EXPECT_EQ(points[44], curves.points.back().z());
  EXPECT_EQ(Numbers(ArrayAfter(text, "    float[] widths")), curves.widths);
  // Each primvar's interpolation follows its value (search from the '[' after " = ": the type
  // names contain ']' too).
  const std::string vertex = "] (\n        interpolation = \"vertex\"\n    )\n";
  const size_t widths_end = text.find(']', text.find("float[] widths = [") + 18);
  EXPECT_EQ(text.substr(widths_end, vertex.size()), vertex);
  EXPECT_EQ(Numbers(ArrayAfter(text, "    color3f[] primvars:displayColor")), Flat(curves.colors));
  const std::string uniform = "] (\n        interpolation = \"uniform\"\n    )\n";
  const size_t colors_end = text.find(']', text.find("primvars:displayColor = [") + 25);
  EXPECT_EQ(text.substr(colors_end, uniform.size()), uniform);
  // Extent: bounding box of the points, +- half the largest width (UsdGeomCurves::ComputeExtent).
  Vec3f lo = curves.points[0], hi = curves.points[0];
  for (const Vec3f& x : curves.points) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  const std::vector<float> extent = Numbers(ArrayAfter(text, "    float3[] extent"));
  ASSERT_EQ(extent.size(), 6u);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(extent[c], lo[c] - 2.5e-4f);
    EXPECT_EQ(extent[3 + c], hi[c] + 2.5e-4f);
  }
  // Without colours there is no displayColor; the output is deterministic.
  curves.colors.clear();
  std::string again, twice;
  ASSERT_TRUE(EncodeUsda(curves, UsdExportOptions(), &again, &error));
  ASSERT_TRUE(EncodeUsda(curves, UsdExportOptions(), &twice, &error));
  EXPECT_EQ(again.find("displayColor"), std::string::npos);
  EXPECT_EQ(again, twice);
}

TEST(UsdExport, SequenceWithFixedTopologySamplesOnlyPoints) {
  std::vector<HairCurves> frames;
  for (unsigned f = 0; f < 3; ++f) {
    frames.push_back(MakeCurves({3, 5}, true, 40));
    for (Vec3f& x : frames.back().points) x.z() -= 0.01f * static_cast<float>(f);
  }
  UsdExportOptions options;
  options.start_time_code = 10;
  options.time_codes_per_second = 30;
  std::string text, error;
  ASSERT_TRUE(EncodeUsdaSequence(frames, options, &text, &error)) << error;
  ExpectBalanced(text);
  EXPECT_TRUE(HasLine(text, "    startTimeCode = 10"));
  EXPECT_TRUE(HasLine(text, "    endTimeCode = 12"));
  EXPECT_TRUE(HasLine(text, "    timeCodesPerSecond = 30"));
  EXPECT_TRUE(HasLine(text, "    metersPerUnit = 1"));
  // Same topology, widths and colours: written once; points and extent sampled per frame.
  EXPECT_EQ(Numbers(ArrayAfter(text, "    int[] curveVertexCounts")), Flat(frames[0].point_counts));
  EXPECT_EQ(Numbers(ArrayAfter(text, "    float[] widths")), frames[0].widths);
  EXPECT_EQ(text.find("curveVertexCounts.timeSamples"), std::string::npos);
  const auto samples = TimeSamples(text, "    point3f[] points");
  ASSERT_EQ(samples.size(), 3u);
  for (int f = 0; f < 3; ++f) {
    EXPECT_EQ(samples[f].first, 10 + f);
    EXPECT_EQ(samples[f].second, Flat(frames[f].points)) << f;
  }
  EXPECT_EQ(TimeSamples(text, "    float3[] extent").size(), 3u);
}

TEST(UsdExport, SequenceWithChangingCurveCountsSamplesTopology) {
  // A grow sequence: 1 strand, then 2, then 3 (counts and per-vertex widths change).
  std::vector<HairCurves> frames = {MakeCurves({4}, false, 50), MakeCurves({4, 3}, false, 51),
                                    MakeCurves({4, 3, 6}, false, 52)};
  std::string text, error;
  ASSERT_TRUE(EncodeUsdaSequence(frames, UsdExportOptions(), &text, &error)) << error;
  ExpectBalanced(text);
  EXPECT_TRUE(HasLine(text, "    startTimeCode = 1"));
  EXPECT_TRUE(HasLine(text, "    endTimeCode = 3"));
  const auto counts = TimeSamples(text, "    int[] curveVertexCounts");
  const auto points = TimeSamples(text, "    point3f[] points");
  const auto widths = TimeSamples(text, "    float[] widths");
  ASSERT_EQ(counts.size(), 3u);
  ASSERT_EQ(points.size(), 3u);
  ASSERT_EQ(widths.size(), 3u);
  for (int f = 0; f < 3; ++f) {
    EXPECT_EQ(counts[f].first, 1 + f);
    EXPECT_EQ(counts[f].second, Flat(frames[f].point_counts));
    EXPECT_EQ(points[f].second, Flat(frames[f].points));
    EXPECT_EQ(widths[f].second, frames[f].widths);
  }
  // The interpolation metadata is declared once, before the samples.
  EXPECT_NE(text.find("    float[] widths (\n        interpolation = \"vertex\"\n    )\n"
                      "    float[] widths.timeSamples = {\n"),
            std::string::npos);
}

TEST(UsdExport, RejectsBadInput) {
  auto expect_error = [](bool ok, const std::string& error, const std::string& field) {
    EXPECT_FALSE(ok) << field;
    EXPECT_NE(error.find(field), std::string::npos) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  };
  std::string text, error;
  std::vector<HairCurves> frames = {MakeCurves({3}, true, 60), MakeCurves({3}, true, 61),
                                    MakeCurves({3}, true, 62)};
  expect_error(EncodeUsdaSequence({}, UsdExportOptions(), &text, &error), error, "frames:");
  frames[2].points[1].y() = std::numeric_limits<float>::quiet_NaN();
  expect_error(EncodeUsdaSequence(frames, UsdExportOptions(), &text, &error), error,
               "frames[2].points[1]: expected finite");
  frames[2].points[1].y() = 0.0f;
  frames[1].colors.clear();
  expect_error(EncodeUsdaSequence(frames, UsdExportOptions(), &text, &error), error,
               "frames[1].colors: expected colours in every frame or in none");
  UsdExportOptions options;
  options.prim_name = "2hair";
  expect_error(EncodeUsda(frames[0], options, &text, &error), error, "prim_name");
  options = UsdExportOptions();
  options.time_codes_per_second = 0.0;
  expect_error(EncodeUsda(frames[0], options, &text, &error), error, "time_codes_per_second");
  HairCurves bad = frames[0];
  bad.widths.push_back(1.0f);
  expect_error(EncodeUsda(bad, UsdExportOptions(), &text, &error), error, "curves.widths");
  TempDir dir;
  EXPECT_FALSE(WriteUsda(dir.File("bad.usda"), bad, UsdExportOptions(), false, &error));
  EXPECT_EQ(error.rfind(dir.File("bad.usda") + ": curves.widths", 0), 0u) << error;
  EXPECT_EQ(dir.Count(), 0u);
  ASSERT_TRUE(WriteUsda(dir.File("a.usda"), frames[0], UsdExportOptions(), false, &error));
  frames[1].colors = frames[0].colors;
  ASSERT_TRUE(WriteUsdaSequence(dir.File("s.usda"), frames, UsdExportOptions(), false, &error))
      << error;
  EXPECT_FALSE(WriteUsdaSequence(dir.File("s.usda"), frames, UsdExportOptions(), false, &error));
  EXPECT_EQ(dir.Count(), 2u);
}

// The streamed writer of `ringlet simulate`: EncodeUsdaSequence's bytes, piece by piece. The
// frames span more than one round of the writer's parallel blocks (8,192 points a block, 16 a
// round: 150,000 points); the samples also read back by the test's own parser.
TEST(UsdExport, StreamedSequenceHasTheBytesOfEncodeUsdaSequence) {
  for (const bool colors : {true, false}) {
    const std::vector<uint32_t> counts(3000, 50);
    std::vector<HairCurves> frames;
    for (unsigned f = 0; f < 3; ++f) {
      frames.push_back(MakeCurves(counts, colors, 70));
      for (Vec3f& x : frames.back().points) x.y() += 0.003f * static_cast<float>(f);
    }
    UsdExportOptions options;
    options.start_time_code = 0;
    options.time_codes_per_second = 25;
    std::string reference, error;
    ASSERT_TRUE(EncodeUsdaSequence(frames, options, &reference, &error)) << error;
    std::string streamed;
    int pieces = 0;
    UsdaSequenceWriter writer;
    ASSERT_TRUE(writer.Begin(frames[0], 3, options,
                             [&](std::string_view piece) {
                               streamed += piece;
                               ++pieces;
                               return true;
                             },
                             &error))
        << error;
    for (const HairCurves& frame : frames) ASSERT_TRUE(writer.Append(frame, &error)) << error;
    ASSERT_TRUE(writer.Finish(&error)) << error;
    EXPECT_TRUE(streamed == reference) << "colours " << colors << ": " << streamed.size()
                                       << " bytes streamed, " << reference.size() << " encoded";
    EXPECT_GT(pieces, 6);  // handed over in pieces, not as one text
    const auto samples = TimeSamples(streamed, "    point3f[] points");
    ASSERT_EQ(samples.size(), 3u);
    for (int f = 0; f < 3; ++f) {
      EXPECT_EQ(samples[f].first, f);
      EXPECT_EQ(samples[f].second, Flat(frames[f].points)) << f;
    }
  }
}

TEST(UsdExport, StreamedSequenceRefusesWhatItCannotStream) {
  std::vector<HairCurves> frames = {MakeCurves({3, 4}, true, 80), MakeCurves({3, 4}, true, 80),
                                    MakeCurves({3, 4}, true, 80)};
  auto sink = [](std::string_view) { return true; };
  std::string error;
  UsdaSequenceWriter writer;
  EXPECT_FALSE(writer.Begin(frames[0], 0, UsdExportOptions(), sink, &error));
  EXPECT_NE(error.find("frames: expected at least one frame, got 0"), std::string::npos) << error;
  ASSERT_TRUE(writer.Begin(frames[0], 3, UsdExportOptions(), sink, &error)) << error;
  ASSERT_TRUE(writer.Append(frames[0], &error)) << error;
  HairCurves wider = frames[1];
  wider.widths[2] *= 2.0f;
  EXPECT_FALSE(writer.Append(wider, &error));
  EXPECT_NE(error.find("frames[1].widths: differ from frame 0's"), std::string::npos) << error;
  HairCurves recounted = MakeCurves({4, 3}, true, 80);
  EXPECT_FALSE(writer.Append(recounted, &error));
  EXPECT_NE(error.find("frames[1].point_counts: differ"), std::string::npos) << error;
  frames[1].points[0].x() = std::numeric_limits<float>::infinity();
  EXPECT_FALSE(writer.Append(frames[1], &error));
  EXPECT_NE(error.find("frames[1].points[0]: expected finite"), std::string::npos) << error;
  frames[1].points[0].x() = 0.0f;
  ASSERT_TRUE(writer.Append(frames[1], &error)) << error;
  EXPECT_FALSE(writer.Finish(&error));
  EXPECT_NE(error.find("frames: expected 3, got 2"), std::string::npos) << error;
  ASSERT_TRUE(writer.Append(frames[2], &error)) << error;
  EXPECT_FALSE(writer.Append(frames[2], &error));
  EXPECT_NE(error.find("more frames than the 3 announced"), std::string::npos) << error;
  // A sink that refuses (a full disk): "cannot write", and nothing more is handed to it.
  int calls = 0;
  UsdaSequenceWriter refused;
  EXPECT_FALSE(refused.Begin(frames[0], 3, UsdExportOptions(),
                             [&](std::string_view) { return ++calls < 1; }, &error));
  EXPECT_EQ(error, "cannot write");
  EXPECT_FALSE(refused.Append(frames[0], &error));
  EXPECT_EQ(calls, 1);
}

// StagedDirectory: the output of `ringlet simulate`, written file by file and put in place at
// the end, all or none.
TEST(StagedDirectory, NewDirectoryAppearsOnlyAtCommitAndDiscardLeavesNothing) {
  TempDir dir;
  namespace fs = std::filesystem;
  auto names = [](const std::string& path) {
    std::vector<std::string> list;
    for (const auto& e : fs::directory_iterator(path)) list.push_back(e.path().filename());
    std::sort(list.begin(), list.end());
    return list;
  };
  std::string error;
  {
    StagedDirectory staged;
    ASSERT_TRUE(staged.Open(dir.File("a/b/out"), false, &error)) << error;
    ASSERT_TRUE(staged.WriteFile("one.txt", "first", &error)) << error;
    EXPECT_FALSE(fs::exists(dir.File("a/b/out")));
    EXPECT_EQ(fs::path(staged.staging()).parent_path(), fs::path(dir.File("a/b")));
  }  // destroyed without Commit: the staging directory and the parents it made are gone
  EXPECT_EQ(dir.Count(), 0u);

  StagedDirectory staged;
  ASSERT_TRUE(staged.Open(dir.File("a/b/out/"), false, &error)) << error;
  StagedDirectory::File file;
  ASSERT_TRUE(staged.Create("two.txt", &file, &error)) << error;
  EXPECT_TRUE(file.Write("se"));
  ASSERT_TRUE(staged.WriteFile("one.txt", "first", &error)) << error;
  EXPECT_TRUE(file.Write("cond"));
  ASSERT_TRUE(file.Close(&error)) << error;
  EXPECT_FALSE(staged.Create("one.txt", &file, &error));  // one name, one file
  EXPECT_NE(error.find("out/one.txt: cannot create: File exists"), std::string::npos) << error;
  EXPECT_FALSE(fs::exists(dir.File("a/b/out")));
  ASSERT_TRUE(staged.Commit(&error)) << error;
  EXPECT_EQ(names(dir.File("a/b")), std::vector<std::string>{"out"});
  EXPECT_EQ(names(dir.File("a/b/out")), (std::vector<std::string>{"one.txt", "two.txt"}));
  std::string text;
  ASSERT_TRUE(ReadFile(dir.File("a/b/out/two.txt"), &text, &error)) << error;
  EXPECT_EQ(text, "second");
}

TEST(StagedDirectory, ExistingDirectoryKeepsItsFilesUntilCommitAndOverwritesOnlyWithForce) {
  TempDir dir;
  namespace fs = std::filesystem;
  std::string error, text;
  ASSERT_TRUE(WriteFileAtomically(dir.File("a.txt"), "old a", false, &error)) << error;
  ASSERT_TRUE(WriteFileAtomically(dir.File("keep.txt"), "kept", false, &error)) << error;
  {
    StagedDirectory staged;  // without overwrite: the existing a.txt stops the commit
    ASSERT_TRUE(staged.Open(dir.File(""), false, &error)) << error;
    EXPECT_EQ(fs::path(staged.staging()).parent_path(), fs::path(dir.File("")).parent_path());
    ASSERT_TRUE(staged.WriteFile("a.txt", "new a", &error)) << error;
    ASSERT_TRUE(staged.WriteFile("b.txt", "new b", &error)) << error;
    EXPECT_FALSE(staged.Commit(&error));
    EXPECT_NE(error.find("a.txt: already exists; written: none; not written: a.txt, b.txt"),
              std::string::npos)
        << error;
  }
  EXPECT_EQ(dir.Count(), 2u);  // a.txt and keep.txt, no staging directory
  ASSERT_TRUE(ReadFile(dir.File("a.txt"), &text, &error)) << error;
  EXPECT_EQ(text, "old a");

  StagedDirectory staged;
  ASSERT_TRUE(staged.Open(dir.File(""), true, &error)) << error;
  ASSERT_TRUE(staged.WriteFile("a.txt", "new a", &error)) << error;
  ASSERT_TRUE(ReadFile(dir.File("a.txt"), &text, &error)) << error;
  EXPECT_EQ(text, "old a");  // replaced only at the end
  EXPECT_EQ(dir.Count(), 3u);  // and the hidden staging directory
  ASSERT_TRUE(staged.Commit(&error)) << error;
  EXPECT_EQ(dir.Count(), 2u);
  ASSERT_TRUE(ReadFile(dir.File("a.txt"), &text, &error)) << error;
  EXPECT_EQ(text, "new a");
  ASSERT_TRUE(ReadFile(dir.File("keep.txt"), &text, &error)) << error;
  EXPECT_EQ(text, "kept");
  EXPECT_FALSE(staged.Open(dir.File("a.txt"), true, &error));
  EXPECT_NE(error.find("a.txt: exists and is not a directory"), std::string::npos) << error;
}

// ---------------------------------------------------------------------------------------------
// ExportStrands: the one call of `ringlet groom`, `ringlet style` and the studio's Export

TEST(StrandExport, WritesTheFormatOfTheExtensionAndNeverReplacesSilently) {
  const HairCurves curves = MakeCurves({2, 6, 3, 17}, false, 5);
  TempDir dir;
  std::string error;
  // Each file holds exactly what its own encoder writes (the CLI's bytes).
  HairFileOptions options;
  options.units_per_metre = 100.0;
  std::string hair, usda, obj, file;
  ASSERT_TRUE(EncodeHairFile(curves, options, &hair, &error)) << error;
  ASSERT_TRUE(EncodeUsda(curves, UsdExportOptions{}, &usda, &error)) << error;
  ASSERT_TRUE(EncodeObj(curves, &obj, &error)) << error;
  for (const auto& [name, bytes] : {std::pair<std::string, std::string*>{"a.hair", &hair},
                                    {"a.usda", &usda}, {"a.obj", &obj}}) {
    ASSERT_TRUE(ExportStrands(dir.File(name), curves, options, false, &error)) << error;
    ASSERT_TRUE(ReadFile(dir.File(name), &file, &error)) << error;
    EXPECT_EQ(file, *bytes) << name;
  }
  // The .hair reader accepts it: the same points (cm back to m: scaled by 1/100).
  HairCurves back;
  ASSERT_TRUE(ReadHairFile(dir.File("a.hair"), &back, &error, 100.0)) << error;
  EXPECT_EQ(back.point_counts, curves.point_counts);
  // An existing file is kept unless overwrite; then replaced.
  const HairCurves other = MakeCurves({3, 3}, false, 6);
  EXPECT_FALSE(ExportStrands(dir.File("a.obj"), other, options, false, &error));
  EXPECT_NE(error.find("already exists"), std::string::npos) << error;
  ASSERT_TRUE(ReadFile(dir.File("a.obj"), &file, &error)) << error;
  EXPECT_EQ(file, obj);
  ASSERT_TRUE(ExportStrands(dir.File("a.obj"), other, options, true, &error)) << error;
  ASSERT_TRUE(ReadFile(dir.File("a.obj"), &file, &error)) << error;
  EXPECT_NE(file, obj);
  // An unknown extension: one line naming the path, nothing written.
  EXPECT_FALSE(ExportStrands(dir.File("a.abc"), curves, options, false, &error));
  EXPECT_EQ(error, dir.File("a.abc") + ": expected a file name ending in .hair, .usda or .obj, "
                                       "got \".abc\"");
  EXPECT_EQ(dir.Count(), 3u);
}

// ExportHairstyleStrands: every front end's strand file of a hairstyle carries the colour of its
// melanins (issue 26: the studio's Export had none, `ringlet style`'s had it).
TEST(StrandExport, HairstyleStrandsCarryTheMelaninColour) {
  const HairCurves curves = MakeCurves({2, 6, 3}, false, 7);
  RenderSettings render;
  render.eumelanin = 0.8;
  render.pheomelanin = 1.5;
  // The display colour by its formula: exp(-3 sigma_a), sigma_a = eumelanin (0.419, 0.697,
  // 1.37) + pheomelanin (0.187, 0.4, 1.05) (Chiang et al. 2016, section 4.2; hair_bsdf.h).
  const double eu = 0.8, pheo = 1.5;
  const Vec3f colour(static_cast<float>(std::exp(-3.0 * (eu * 0.419 + pheo * 0.187))),
                     static_cast<float>(std::exp(-3.0 * (eu * 0.697 + pheo * 0.4))),
                     static_cast<float>(std::exp(-3.0 * (eu * 1.37 + pheo * 1.05))));
  HairCurves coloured = curves;
  coloured.colors.assign(curves.point_counts.size(), colour);
  TempDir dir;
  std::string error, file;
  for (const StrandFormat format : {StrandFormat::kHair, StrandFormat::kUsda, StrandFormat::kObj}) {
    const std::string name = std::string("s.") + StrandFormatExtension(format);
    std::string expected, plain, again;
    ASSERT_TRUE(EncodeStrands(coloured, format, HairFileOptions{}, &expected, &error)) << error;
    ASSERT_TRUE(EncodeStrands(curves, format, HairFileOptions{}, &plain, &error)) << error;
    EXPECT_NE(plain, expected) << name << ": the colour is written";
    ASSERT_TRUE(ExportHairstyleStrands(dir.File(name), curves, render, HairFileOptions{}, false,
                                       &error))
        << error;
    ASSERT_TRUE(ReadFile(dir.File(name), &file, &error)) << error;
    EXPECT_EQ(file, expected) << name;
    // Strands already coloured (the CLI's) are encoded as they are: the same bytes.
    HairCurves precoloured = curves;
    SetMelaninColours(render, &precoloured);
    ASSERT_TRUE(EncodeHairstyleStrands(precoloured, render, format, HairFileOptions{}, &again,
                                       &error))
        << error;
    EXPECT_EQ(again, expected) << name;
  }
}

}  // namespace
}  // namespace ringlet
