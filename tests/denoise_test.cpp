// Tests of the a-trous denoiser (denoise.h) on synthetic images whose clean version is known:
// the error drops by a measured factor, steps of albedo and of normal stay sharp (where a plain
// blur of the same footprint smears them), background pixels are untouched, bad sizes rejected.
#include "ringlet/denoise.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

namespace ringlet {
namespace {

constexpr int kSize = 64;

struct Synthetic {
  Image clean, noisy;
  DenoiseGuides guides;
};

// A 64 x 64 image: left half (x < 32) albedo a_left and normal n_left, right half a_right and
// n_right; illumination smooth along x and y, times light_right on the right half; the noisy
// image is clean x (1 + sigma g), g standard normal (seeded), and the guides carry the exact
// variance of that noise (clean luminance sigma)^2.
Synthetic MakeSynthetic(const Eigen::Vector3f& a_left, const Eigen::Vector3f& a_right,
                        const Eigen::Vector3f& n_left, const Eigen::Vector3f& n_right,
                        float light_right, float sigma) {
  Synthetic s;
  s.clean.width = s.noisy.width = s.guides.width = kSize;
  s.clean.height = s.noisy.height = s.guides.height = kSize;
  std::mt19937 rng(12345);
  std::normal_distribution<float> gauss(0.0f, 1.0f);
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const bool right = x >= kSize / 2;
      const float light =
          (0.6f + 0.4f * std::sin(0.05f * x) * std::cos(0.04f * y)) * (right ? light_right : 1.0f);
      const Eigen::Vector3f albedo = right ? a_right : a_left;
      const Eigen::Vector3f clean = albedo * light;
      const float g = gauss(rng);
      s.clean.pixels.push_back(clean);
      s.noisy.pixels.push_back(clean * (1.0f + sigma * g));
      s.guides.albedo.push_back(albedo);
      s.guides.normal.push_back(right ? n_right : n_left);
      s.guides.depth.push_back(1.0f);
      const float l = 0.2126f * clean.x() + 0.7152f * clean.y() + 0.0722f * clean.z();
      s.guides.variance.push_back(l * l * sigma * sigma);
    }
  }
  return s;
}

double Rmse(const Image& a, const Image& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.pixels.size(); ++i) sum += (a.pixels[i] - b.pixels[i]).squaredNorm();
  return std::sqrt(sum / (3.0 * a.pixels.size()));
}

// Mean over the rows of (out - clean) / clean in column x (first channel): the systematic error
// that bleeding across an edge leaves (the residual noise, ~7 % per pixel after denoising,
// averages out over the 64 rows to ~1 %).
double ColumnBias(const Image& out, const Image& clean, int x) {
  double sum = 0.0;
  for (int y = 0; y < kSize; ++y) {
    sum += (out.At(x, y).x() - clean.At(x, y).x()) / clean.At(x, y).x();
  }
  return std::abs(sum / kSize);
}

// The same a-trous B3 footprint (DenoiseOptions' iterations) without edge stopping: what the
// guides prevent.
Image PlainBlur(const Image& in) {
  const float k[5] = {1.0f / 16, 1.0f / 4, 3.0f / 8, 1.0f / 4, 1.0f / 16};
  Image a = in;
  for (int level = 0; level < DenoiseOptions().iterations; ++level) {
    Image b = a;
    const int step = 1 << level;
    for (int y = 0; y < kSize; ++y) {
      for (int x = 0; x < kSize; ++x) {
        Eigen::Vector3f sum = Eigen::Vector3f::Zero();
        float weight = 0.0f;
        for (int j = -2; j <= 2; ++j) {
          for (int i = -2; i <= 2; ++i) {
            const int qx = x + i * step, qy = y + j * step;
            if (qx < 0 || qy < 0 || qx >= kSize || qy >= kSize) continue;
            sum += k[i + 2] * k[j + 2] * a.At(qx, qy);
            weight += k[i + 2] * k[j + 2];
          }
        }
        b.At(x, y) = sum / weight;
      }
    }
    a = b;
  }
  return a;
}

TEST(DenoiseTest, ReducesTheErrorAndKeepsAnAlbedoStep) {
  // Noise of 30 % per pixel (the relative noise of a 16-spp hair render's pixels is of this
  // order); albedo 0.2 | 0.8 across x = 32, same normal: only the albedo guide (and the
  // demodulation) separates the halves.
  const Eigen::Vector3f n(0, 0, 1);
  const Synthetic s = MakeSynthetic(Eigen::Vector3f::Constant(0.2f), Eigen::Vector3f::Constant(0.8f),
                                    n, n, 1.0f, 0.3f);
  Image out;
  std::string error;
  ASSERT_TRUE(DenoiseImage(s.noisy, s.guides, DenoiseOptions(), &out, &error)) << error;
  const double before = Rmse(s.noisy, s.clean), after = Rmse(out, s.clean);
  std::printf("albedo step: RMSE %.4f -> %.4f (factor %.1f)\n", before, after, before / after);
  EXPECT_GT(before / after, 4.0);
  // The columns next to the step keep their side's value: biased by less than 3 % on average,
  // where the plain blur is off by more than 20 % (anti-vacuity: the step would be smeared
  // without the guides).
  const Image blur = PlainBlur(s.noisy);
  for (int x : {kSize / 2 - 1, kSize / 2}) {
    EXPECT_LT(ColumnBias(out, s.clean, x), 0.03) << "column " << x;
    EXPECT_GT(ColumnBias(blur, s.clean, x), 0.20) << "column " << x;
  }
}

TEST(DenoiseTest, KeepsANormalStep) {
  // Same albedo; the right half faces another way (normals at 90 degrees) and is lit 3 times
  // more: only the normal guide (and the luminance weight) separates the halves.
  const Eigen::Vector3f grey = Eigen::Vector3f::Constant(0.5f);
  const Synthetic s =
      MakeSynthetic(grey, grey, Eigen::Vector3f(0, 0, 1), Eigen::Vector3f(1, 0, 0), 3.0f, 0.3f);
  Image out;
  std::string error;
  ASSERT_TRUE(DenoiseImage(s.noisy, s.guides, DenoiseOptions(), &out, &error)) << error;
  const double before = Rmse(s.noisy, s.clean), after = Rmse(out, s.clean);
  std::printf("normal step: RMSE %.4f -> %.4f (factor %.1f)\n", before, after, before / after);
  EXPECT_GT(before / after, 4.0);
  const Image blur = PlainBlur(s.noisy);
  for (int x : {kSize / 2 - 1, kSize / 2}) {
    EXPECT_LT(ColumnBias(out, s.clean, x), 0.03) << "column " << x;
    EXPECT_GT(ColumnBias(blur, s.clean, x), 0.20) << "column " << x;
  }
}

TEST(DenoiseTest, LeavesTheBackgroundAndNoiselessPixelsAlone) {
  // Background pixels (zero albedo and normal) are copied; a noiseless image with zero variance
  // comes back unchanged up to float rounding (every neighbour of a different value gets weight
  // exp(-inf) = 0 from the luminance term).
  const Eigen::Vector3f n(0, 0, 1);
  Synthetic s = MakeSynthetic(Eigen::Vector3f::Constant(0.2f), Eigen::Vector3f::Constant(0.8f), n,
                              n, 1.0f, 0.0f);
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const size_t i = static_cast<size_t>(y) * kSize + x;
      s.guides.albedo[i].setZero();
      s.guides.normal[i].setZero();
      s.noisy.pixels[i] = Eigen::Vector3f(0.3f, 0.4f, 5.0f);
    }
  }
  Image out;
  std::string error;
  ASSERT_TRUE(DenoiseImage(s.noisy, s.guides, DenoiseOptions(), &out, &error)) << error;
  double worst = 0.0;
  for (size_t i = 0; i < out.pixels.size(); ++i) {
    if (i < 8u * kSize) {
      EXPECT_EQ(out.pixels[i], s.noisy.pixels[i]);
    } else {
      worst = std::max(worst, static_cast<double>(
                                  (out.pixels[i] - s.noisy.pixels[i]).cwiseAbs().maxCoeff() /
                                  s.noisy.pixels[i].maxCoeff()));
    }
  }
  EXPECT_LT(worst, 1e-5);
}

TEST(DenoiseTest, RejectsMismatchedSizesAndBadOptions) {
  const Eigen::Vector3f n(0, 0, 1);
  Synthetic s = MakeSynthetic(Eigen::Vector3f::Constant(0.2f), Eigen::Vector3f::Constant(0.8f), n,
                              n, 1.0f, 0.1f);
  Image out;
  std::string error;
  s.guides.depth.pop_back();
  EXPECT_FALSE(DenoiseImage(s.noisy, s.guides, DenoiseOptions(), &out, &error));
  EXPECT_NE(error.find("same size"), std::string::npos) << error;
  EXPECT_TRUE(out.pixels.empty());
  s.guides.depth.push_back(1.0f);
  DenoiseOptions bad;
  bad.iterations = 0;
  EXPECT_FALSE(DenoiseImage(s.noisy, s.guides, bad, &out, &error));
  EXPECT_NE(error.find("denoise.iterations"), std::string::npos) << error;
  bad = DenoiseOptions();
  bad.sigma_albedo = -1.0;
  EXPECT_FALSE(DenoiseImage(s.noisy, s.guides, bad, &out, &error));
  EXPECT_NE(error.find("denoise.sigma_albedo"), std::string::npos) << error;
}

}  // namespace
}  // namespace ringlet
