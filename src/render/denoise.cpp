// The edge-avoiding a-trous denoiser (denoise.h): Dammertz et al. 2010 with SVGF's variance
// guidance (Schied et al. 2017), per pixel independent so rows run in parallel.
#include "ringlet/denoise.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

namespace ringlet {
namespace {

// Rec. 709 luminance of linear RGB.
float Luminance(const Eigen::Vector3f& c) { return 0.2126f * c.x() + 0.7152f * c.y() + 0.0722f * c.z(); }

// The B3 spline kernel of the a-trous transform (Dammertz et al. 2010, section 3).
constexpr std::array<float, 5> kKernel = {1.0f / 16, 1.0f / 4, 3.0f / 8, 1.0f / 4, 1.0f / 16};

bool Fail(std::string* why, const std::string& message) {
  if (why != nullptr) *why = message;
  return false;
}

}  // namespace

bool DenoiseOptions::IsValid(std::string* why) const {
  std::ostringstream message;
  if (iterations < 1 || iterations > 10) {
    message << "denoise.iterations: expected an integer in [1, 10], got " << iterations;
  } else if (!(sigma_luminance > 0.0) || !std::isfinite(sigma_luminance)) {
    message << "denoise.sigma_luminance: expected a finite number > 0, got " << sigma_luminance;
  } else if (!(normal_power >= 0.0) || !std::isfinite(normal_power)) {
    message << "denoise.normal_power: expected a finite number >= 0, got " << normal_power;
  } else if (!(sigma_albedo > 0.0) || !std::isfinite(sigma_albedo)) {
    message << "denoise.sigma_albedo: expected a finite number > 0, got " << sigma_albedo;
  } else if (!(sigma_depth > 0.0) || !std::isfinite(sigma_depth)) {
    message << "denoise.sigma_depth: expected a finite number > 0, got " << sigma_depth;
  } else {
    return true;
  }
  return Fail(why, message.str());
}

bool DenoiseImage(const Image& image, const DenoiseGuides& guides, const DenoiseOptions& options,
                  Image* out, std::string* why) {
  if (!options.IsValid(why)) return false;
  const int w = image.width, h = image.height;
  const size_t n = static_cast<size_t>(w) * static_cast<size_t>(h);
  if (w < 0 || h < 0 || image.pixels.size() != n || guides.width != w || guides.height != h ||
      guides.albedo.size() != n || guides.normal.size() != n || guides.depth.size() != n ||
      guides.variance.size() != n) {
    return Fail(why, "denoise: expected an image and guides of the same size (width x height "
                     "entries each)");
  }
  // 1. Demodulate: the illumination is colour / albedo where the albedo is known.
  constexpr float kMinAlbedo = 1e-3f;
  std::vector<char> geometry(n);
  std::vector<Eigen::Vector3f> albedo(n), colour(n);
  std::vector<float> variance(n);
  for (size_t i = 0; i < n; ++i) {
    geometry[i] = guides.albedo[i].maxCoeff() > 0.0f || guides.normal[i].squaredNorm() > 0.0f;
    albedo[i] = guides.albedo[i].cwiseMax(kMinAlbedo);
    colour[i] = geometry[i] ? Eigen::Vector3f(image.pixels[i].cwiseQuotient(albedo[i]))
                            : image.pixels[i];
    const float a = std::max(Luminance(albedo[i]), kMinAlbedo);
    variance[i] = guides.variance[i] / (a * a);
  }
  // Unknown variances (one sample): the variance of the luminance over the 3 x 3 neighbourhood.
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const size_t i = static_cast<size_t>(y) * w + x;
      if (guides.variance[i] >= 0.0f) continue;
      double sum = 0.0, sum2 = 0.0;
      int count = 0;
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
          const int qx = x + dx, qy = y + dy;
          if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
          const double l = Luminance(colour[static_cast<size_t>(qy) * w + qx]);
          sum += l;
          sum2 += l * l;
          ++count;
        }
      }
      const double mean = sum / count;
      variance[i] = static_cast<float>(std::max(0.0, sum2 / count - mean * mean));
    }
  }

  // 2. The a-trous iterations.
  std::vector<Eigen::Vector3f> next_colour(n);
  std::vector<float> next_variance(n);
  const float sigma_l = static_cast<float>(options.sigma_luminance);
  const float inv_albedo2 = static_cast<float>(1.0 / (options.sigma_albedo * options.sigma_albedo));
  const float sigma_z = static_cast<float>(options.sigma_depth);
  const float normal_power = static_cast<float>(options.normal_power);
  for (int level = 0; level < options.iterations; ++level) {
    const int step = 1 << level;
    tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
      for (int y = rows.begin(); y != rows.end(); ++y) {
        for (int x = 0; x < w; ++x) {
          const size_t p = static_cast<size_t>(y) * w + x;
          if (!geometry[p]) {
            next_colour[p] = colour[p];
            next_variance[p] = variance[p];
            continue;
          }
          // The variance of p blurred 3 x 3 (SVGF section 4.4), for the luminance weight.
          float blurred = 0.0f, blurred_weight = 0.0f;
          for (int dy = -1; dy <= 1; ++dy) {
            for (int dx = -1; dx <= 1; ++dx) {
              const int qx = x + dx, qy = y + dy;
              if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
              const size_t q = static_cast<size_t>(qy) * w + qx;
              if (!geometry[q]) continue;
              const float k = kKernel[dx + 2] * kKernel[dy + 2];
              blurred += k * variance[q];
              blurred_weight += k;
            }
          }
          const float l_scale = 1.0f / (sigma_l * std::sqrt(blurred / blurred_weight) + 1e-6f);
          const float l_p = Luminance(colour[p]);
          const Eigen::Vector3f& n_p = guides.normal[p];
          const float z_p = guides.depth[p];
          Eigen::Vector3f sum = Eigen::Vector3f::Zero();
          float sum_weight = 0.0f, sum_variance = 0.0f;
          for (int j = -2; j <= 2; ++j) {
            const int qy = y + j * step;
            if (qy < 0 || qy >= h) continue;
            for (int i = -2; i <= 2; ++i) {
              const int qx = x + i * step;
              if (qx < 0 || qx >= w) continue;
              const size_t q = static_cast<size_t>(qy) * w + qx;
              if (!geometry[q]) continue;
              float weight = kKernel[i + 2] * kKernel[j + 2];
              if (q != p) {
                const float cos_n = std::max(0.0f, n_p.dot(guides.normal[q]));
                const float w_n = normal_power > 0.0f ? std::pow(cos_n, normal_power) : 1.0f;
                const float w_a = std::exp(-(albedo[p] - albedo[q]).squaredNorm() * inv_albedo2);
                const float z_q = guides.depth[q];
                const float z_max = std::max(z_p, z_q);
                const float w_z =
                    z_max > 0.0f ? std::exp(-std::abs(z_p - z_q) / (sigma_z * z_max)) : 1.0f;
                const float w_l = std::exp(-std::abs(l_p - Luminance(colour[q])) * l_scale);
                weight *= w_n * w_a * w_z * w_l;
              }
              sum += weight * colour[q];
              sum_weight += weight;
              sum_variance += weight * weight * variance[q];
            }
          }
          next_colour[p] = sum / sum_weight;  // sum_weight >= the centre's kernel weight > 0
          next_variance[p] = sum_variance / (sum_weight * sum_weight);
        }
      }
    });
    colour.swap(next_colour);
    variance.swap(next_variance);
  }

  // 3. Remodulate.
  Image result;
  result.width = w;
  result.height = h;
  result.pixels.resize(n);
  for (size_t i = 0; i < n; ++i) {
    result.pixels[i] = geometry[i] ? Eigen::Vector3f(colour[i].cwiseProduct(albedo[i])) : colour[i];
  }
  *out = std::move(result);
  return true;
}

}  // namespace ringlet
