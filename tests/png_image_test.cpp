// PNG images (src/io/png_image.cpp, io/srgb.h): the sRGB transfer function at published points,
// quantization and clamping, a round trip within one 8-bit sRGB step, atomic writes that never
// overwrite silently, and corrupt or truncated files rejected with one line (libpng errors are
// caught, never a crash).
#include "ringlet/png_image.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>

#include "io/srgb.h"
#include "ringlet/atomic_file.h"

namespace ringlet {
namespace {

using internal::LinearToSrgb;
using internal::LinearToSrgb8;
using internal::SrgbToLinear;

// A fresh empty directory, removed by the destructor.
class TempDirectory {
 public:
  TempDirectory() {
    std::string pattern = ::testing::TempDir() + "ringlet_png_XXXXXX";
    path_ = ::mkdtemp(pattern.data()) ? pattern : std::string();
  }
  ~TempDirectory() {
    std::error_code ec;
    if (!path_.empty()) std::filesystem::remove_all(path_, ec);
  }
  std::string File(const std::string& name) const { return path_ + "/" + name; }
  int Count() const {
    return static_cast<int>(std::distance(std::filesystem::directory_iterator(path_),
                                          std::filesystem::directory_iterator()));
  }

 private:
  std::string path_;
};

std::string Contents(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void Overwrite(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

// A w x h image of uniform random linear values in [0, 1], fixed seed.
Image RandomImage(int width, int height, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Image image;
  image.width = width;
  image.height = height;
  for (int i = 0; i < width * height; ++i) image.pixels.emplace_back(u(rng), u(rng), u(rng));
  return image;
}

// Big-endian uint32 at offset.
uint32_t BigEndian32(const std::string& bytes, size_t offset) {
  uint32_t v = 0;
  for (size_t i = 0; i < 4; ++i) v = (v << 8) | static_cast<unsigned char>(bytes[offset + i]);
  return v;
}

// ---------------------------------------------------------------------------------------------
// The transfer function.

TEST(SrgbTransfer, PublishedValues) {
  // IEC 61966-2-1: 1.055 * 0.5^(1/2.4) - 0.055 = 0.73535698..., the "50% linear grey is sRGB
  // 188" of every colour-management text; 0.18 (photographic middle grey) -> 0.46135613.
  EXPECT_NEAR(LinearToSrgb(0.5), 0.7353569830524495, 1e-12);
  EXPECT_NEAR(LinearToSrgb(0.18), 0.4613561295004416, 1e-12);
  // Inverse: sRGB 0.5 -> ((0.5 + 0.055) / 1.055)^2.4 = 0.21404114.
  EXPECT_NEAR(SrgbToLinear(0.5), 0.21404114048223255, 1e-12);
  // The end points are exact: 12.92 * 0 = 0, 1.055 * 1 - 0.055 = 1.
  EXPECT_EQ(LinearToSrgb(0.0), 0.0);
  EXPECT_NEAR(LinearToSrgb(1.0), 1.0, 1e-15);
  EXPECT_NEAR(SrgbToLinear(1.0), 1.0, 1e-15);
}

TEST(SrgbTransfer, BranchesMeetAtTheBoundary) {
  // At c = 0.0031308 the linear branch gives 12.92 c = 0.040449936 and the power branch
  // 1.055 c^(1/2.4) - 0.055 = 0.0404499075: the standard's constants make them agree to 3e-8.
  const double c = 0.0031308;
  EXPECT_DOUBLE_EQ(LinearToSrgb(c), 12.92 * c);
  EXPECT_NEAR(LinearToSrgb(std::nextafter(c, 1.0)), 0.0404499075, 1e-9);
  EXPECT_NEAR(LinearToSrgb(c), LinearToSrgb(std::nextafter(c, 1.0)), 3e-8);
  // Below the boundary the encoding is linear with slope 12.92.
  EXPECT_DOUBLE_EQ(LinearToSrgb(0.001), 0.01292);
}

TEST(SrgbTransfer, DecodeInvertsEncode) {
  for (double x = 0.0; x <= 1.0; x += 1.0 / 1024) {
    EXPECT_NEAR(SrgbToLinear(LinearToSrgb(x)), x, 1e-8) << x;
  }
}

TEST(SrgbTransfer, QuantizesAndClamps) {
  EXPECT_EQ(LinearToSrgb8(0.5), 188);        // 0.73535698 * 255 = 187.516 -> 188
  EXPECT_EQ(LinearToSrgb8(0.0031308), 10);   // 0.040449936 * 255 = 10.31 -> 10
  EXPECT_EQ(LinearToSrgb8(0.18), 118);       // 0.46135613 * 255 = 117.65 -> 118
  EXPECT_EQ(LinearToSrgb8(1.0), 255);
  EXPECT_EQ(LinearToSrgb8(0.0), 0);
  EXPECT_EQ(LinearToSrgb8(-3.0), 0);
  EXPECT_EQ(LinearToSrgb8(7.5), 255);
  EXPECT_EQ(LinearToSrgb8(std::numeric_limits<double>::infinity()), 255);
  EXPECT_EQ(LinearToSrgb8(std::numeric_limits<double>::quiet_NaN()), 0);
}

// ---------------------------------------------------------------------------------------------
// Files.

TEST(PngImage, RoundTripWithinOneQuantizationStep) {
  TempDirectory dir;
  const Image image = RandomImage(7, 5, 42);
  std::string error;
  ASSERT_TRUE(WritePng(dir.File("a.png"), image, 1.0, false, &error)) << error;
  Image back;
  ASSERT_TRUE(ReadPng(dir.File("a.png"), &back, &error)) << error;
  ASSERT_EQ(back.width, 7);
  ASSERT_EQ(back.height, 5);
  ASSERT_EQ(back.pixels.size(), 35u);
  // 8-bit sRGB rounds to the nearest code: in the encoded domain the error is at most half a
  // step, 0.5/255, plus float rounding of the stored linear values (1e-6). In the linear domain
  // that is at most 0.5/255 * max d(decode)/dv = 0.5/255 * 2.4/1.055 = 0.00446 (at v = 1).
  double worst_encoded = 0.0, worst_linear = 0.0;
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const double a = image.pixels[i][c], b = back.pixels[i][c];
      worst_encoded = std::max(worst_encoded, std::abs(LinearToSrgb(a) - LinearToSrgb(b)));
      worst_linear = std::max(worst_linear, std::abs(a - b));
    }
  }
  EXPECT_LE(worst_encoded, 0.5 / 255 + 1e-6);
  EXPECT_LE(worst_linear, 0.5 / 255 * 2.4 / 1.055 + 1e-6);
  EXPECT_GT(worst_linear, 0.0);  // it did quantize: the test compares two different things
  // Rows are top first: the first pixel read back is the first written.
  EXPECT_NEAR(back.At(0, 0)[0], image.At(0, 0)[0], 0.0045);
  EXPECT_NEAR(back.At(6, 4)[2], image.At(6, 4)[2], 0.0045);
}

TEST(PngImage, ExposureScalesBeforeEncoding) {
  TempDirectory dir;
  Image image;
  image.width = 2;
  image.height = 1;
  image.pixels = {Eigen::Vector3f(0.25f, 0.125f, 0.0f), Eigen::Vector3f(0.6f, 0.6f, 0.6f)};
  std::string error;
  ASSERT_TRUE(WritePng(dir.File("e.png"), image, 2.0, false, &error)) << error;
  Image back;
  ASSERT_TRUE(ReadPng(dir.File("e.png"), &back, &error)) << error;
  // 0.25 * 2 = 0.5 -> code 188 -> SrgbToLinear(188/255); 0.6 * 2 = 1.2 clamps to 1.
  EXPECT_FLOAT_EQ(back.At(0, 0)[0], static_cast<float>(SrgbToLinear(188.0 / 255)));
  EXPECT_NEAR(back.At(0, 0)[1], 0.25, 0.0045);
  EXPECT_EQ(back.At(0, 0)[2], 0.0f);
  EXPECT_EQ(back.At(1, 0), Eigen::Vector3f(1.0f, 1.0f, 1.0f));
}

TEST(PngImage, ClampsOutOfRangeAndNonFiniteValues) {
  TempDirectory dir;
  Image image;
  image.width = 1;
  image.height = 2;
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  image.pixels = {Eigen::Vector3f(-1.0f, 5.0f, nan), Eigen::Vector3f(inf, -inf, 1.0f)};
  std::string error;
  ASSERT_TRUE(WritePng(dir.File("c.png"), image, 1.0, false, &error)) << error;
  Image back;
  ASSERT_TRUE(ReadPng(dir.File("c.png"), &back, &error)) << error;
  EXPECT_EQ(back.At(0, 0), Eigen::Vector3f(0.0f, 1.0f, 0.0f));
  EXPECT_EQ(back.At(0, 1), Eigen::Vector3f(1.0f, 0.0f, 1.0f));
}

TEST(PngImage, WritesAnSrgbChunkAndTheHeader) {
  TempDirectory dir;
  std::string error;
  ASSERT_TRUE(WritePng(dir.File("h.png"), RandomImage(33, 17, 1), 1.0, false, &error)) << error;
  const std::string bytes = Contents(dir.File("h.png"));
  // PNG signature, then IHDR: width and height big-endian at bytes 16 and 20, bit depth 8,
  // colour type 2 (RGB) (PNG specification, section 11.2.2).
  ASSERT_GE(bytes.size(), 33u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
  EXPECT_EQ(bytes.substr(12, 4), "IHDR");
  EXPECT_EQ(BigEndian32(bytes, 16), 33u);
  EXPECT_EQ(BigEndian32(bytes, 20), 17u);
  EXPECT_EQ(bytes[24], 8);
  EXPECT_EQ(bytes[25], 2);
  // The sRGB chunk: length 1, type "sRGB", rendering intent 0 (perceptual).
  const size_t srgb = bytes.find("sRGB");
  ASSERT_NE(srgb, std::string::npos);
  EXPECT_EQ(BigEndian32(bytes, srgb - 4), 1u);
  EXPECT_EQ(bytes[srgb + 4], 0);
}

TEST(PngImage, RefusesToOverwriteWithoutPermission) {
  TempDirectory dir;
  const std::string path = dir.File("o.png");
  std::string error;
  ASSERT_TRUE(WritePng(path, RandomImage(4, 4, 1), 1.0, false, &error)) << error;
  const std::string first = Contents(path);
  EXPECT_FALSE(WritePng(path, RandomImage(4, 4, 2), 1.0, false, &error));
  EXPECT_EQ(error, path + ": already exists");
  EXPECT_EQ(Contents(path), first);
  EXPECT_EQ(dir.Count(), 1);  // no temporary file left behind
  ASSERT_TRUE(WritePng(path, RandomImage(4, 4, 2), 1.0, true, &error)) << error;
  EXPECT_NE(Contents(path), first);
  EXPECT_EQ(dir.Count(), 1);
}

TEST(PngImage, BadPathsAndImagesAreOneLineErrors) {
  TempDirectory dir;
  std::string error;
  const std::string missing_dir = dir.File("no_such_dir/x.png");
  EXPECT_FALSE(WritePng(missing_dir, RandomImage(2, 2, 1), 1.0, false, &error));
  EXPECT_EQ(error.rfind(missing_dir + ": ", 0), 0u) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir.File("no_such_dir")));

  Image empty;
  EXPECT_FALSE(WritePng(dir.File("empty.png"), empty, 1.0, false, &error));
  EXPECT_EQ(error, dir.File("empty.png") +
                       ": cannot write an image of 0 x 0 pixels (expected at least 1 x 1)");
  Image wrong = RandomImage(3, 3, 1);
  wrong.pixels.pop_back();
  EXPECT_FALSE(WritePng(dir.File("wrong.png"), wrong, 1.0, false, &error));
  EXPECT_EQ(error, dir.File("wrong.png") + ": image has 8 pixels, expected 3 x 3");
  EXPECT_FALSE(WritePng(dir.File("nan.png"), RandomImage(2, 2, 1), std::nan(""), false, &error));
  EXPECT_NE(error.find("exposure must be a finite number >= 0"), std::string::npos) << error;
  EXPECT_EQ(dir.Count(), 0);

  Image image;
  EXPECT_FALSE(ReadPng(dir.File("none.png"), &image, &error));
  EXPECT_EQ(error.rfind(dir.File("none.png") + ": cannot open", 0), 0u) << error;
}

TEST(PngImage, CorruptAndTruncatedFilesAreRejected) {
  TempDirectory dir;
  const std::string good = dir.File("good.png");
  std::string error;
  ASSERT_TRUE(WritePng(good, RandomImage(40, 30, 3), 1.0, false, &error)) << error;
  const std::string bytes = Contents(good);
  Image image = RandomImage(1, 1, 9);
  const Image before = image;
  const auto expect_rejected = [&](const std::string& name, const std::string& contents,
                                   const std::string& message) {
    const std::string path = dir.File(name);
    Overwrite(path, contents);
    EXPECT_FALSE(ReadPng(path, &image, &error)) << name;
    EXPECT_EQ(error.rfind(path + ": " + message, 0), 0u) << name << ": " << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    EXPECT_EQ(image.pixels, before.pixels) << name << ": image modified on failure";
  };
  expect_rejected("empty.png", "", "not a PNG file (bad signature)");
  expect_rejected("text.png", "hello, this is not an image at all", "not a PNG file");
  // Cut in the middle of the image data, and just after the signature.
  expect_rejected("half.png", bytes.substr(0, bytes.size() / 2), "invalid PNG: ");
  expect_rejected("signature_only.png", bytes.substr(0, 8), "invalid PNG: ");
  expect_rejected("no_end.png", bytes.substr(0, bytes.size() - 12), "invalid PNG: ");
  // A flipped byte inside the IHDR data: the chunk's CRC no longer matches.
  std::string flipped = bytes;
  flipped[18] = static_cast<char>(flipped[18] ^ 0x55);
  expect_rejected("bad_crc.png", flipped, "invalid PNG: ");
  // Garbage in the middle of the compressed data.
  std::string garbage = bytes;
  for (size_t i = bytes.size() / 2; i < bytes.size() / 2 + 64; ++i) garbage[i] = '\x7f';
  expect_rejected("garbage.png", garbage, "invalid PNG: ");
}

}  // namespace
}  // namespace ringlet
