// An edge-avoiding a-trous wavelet denoiser for path-traced images (Dammertz, Sewtz, Hanika &
// Lensch, "Edge-avoiding a-trous wavelet transform for fast global illumination filtering", HPG
// 2010), guided by albedo, normal and depth buffers and by the per-pixel variance of the Monte
// Carlo estimate as in Schied et al., "Spatiotemporal variance-guided filtering", HPG 2017
// (SVGF, without its temporal part). No denoising library is packaged in Debian 12.
#pragma once

#include <string>
#include <vector>

#include "ringlet/render.h"

namespace ringlet {

/// What the renderer knows of each pixel besides its colour: the means over the pixel's samples
/// of the first hit's albedo, normal and depth, and the variance of the pixel's mean luminance.
/// Every vector has width * height entries (row-major, top row first), like Image::pixels.
struct DenoiseGuides {
  int width = 0;
  int height = 0;
  /// Reflectance of the first hit per channel, in [0, 1] (the body's albedo; for a fibre the
  /// renderer gives its directional albedo FibreScattering::Albedo at normal incidence through
  /// the axis, one colour per strand); 0 where the camera sees the background.
  std::vector<Eigen::Vector3f> albedo;
  /// Unit body normal facing the camera or fibre tangent (root to tip) of the first hit, world
  /// coordinates, averaged (so shorter than 1 where a pixel sees several); 0 for the background.
  std::vector<Eigen::Vector3f> normal;
  /// Distance from the camera to the first hit (m), 0 for the background.
  std::vector<float> depth;
  /// Variance of the pixel's mean luminance (radiance^2): the sample variance of its samples'
  /// luminance over the number of samples; negative where unknown (one sample), then estimated
  /// from the 3 x 3 neighbourhood.
  std::vector<float> variance;
};

/// The filter's parameters. The weight of pixel q in pixel p's average at iteration i (step
/// 2^i pixels) is h(dx) h(dy) w_l w_n w_a w_z, h = (1, 4, 6, 4, 1)/16 the B3 spline kernel of
/// the a-trous transform, and the edge-stopping functions
///   w_l = exp(-|l_p - l_q| / (sigma_luminance sqrt(var_p) + 1e-6))   (SVGF eq. 5, luminance of
///         the demodulated colour, var_p the filtered variance blurred 3 x 3)
///   w_n = max(0, n_p . n_q)^normal_power                              (SVGF eq. 4)
///   w_a = exp(-|a_p - a_q|^2 / sigma_albedo^2)                        (Dammertz eq. 6 style)
///   w_z = exp(-|z_p - z_q| / (sigma_depth max(z_p, z_q)))              (relative depth)
/// The colour is divided by the albedo before filtering and multiplied back after (SVGF's
/// demodulation), so texture and the hair/skin boundary are kept by the guides, not blurred.
/// The variance is filtered alongside with the squared weights (SVGF eq. 3's propagation).
struct DenoiseOptions {
  // Defaults chosen on the main job (docs/rendering.md, "Noise"): among 17 settings, the one
  // with the least error E|d(x1) - x2|^2 of the denoised render of one seed against the raw
  // render of another (an unbiased ranking of the denoised image's mean squared error).
  int iterations = 4;              ///< a-trous levels, steps 1, 2, 4, ...; in [1, 10]
  double sigma_luminance = 2.0;    ///< > 0 (SVGF uses 4)
  double normal_power = 4.0;       ///< >= 0 (SVGF uses 128 for meshes; fibres' tangents vary)
  double sigma_albedo = 0.3;       ///< > 0 (reflectance units)
  double sigma_depth = 0.5;        ///< > 0 (fraction of the depth)

  /// Checks every field; says which field and what was expected.
  bool IsValid(std::string* why) const;
};

/// Denoises image with the guides (same size) into *out (may be image itself). Deterministic
/// and independent of the thread count. Pixels with zero albedo and zero normal (background)
/// are copied unchanged and take no part in their neighbours' averages. Returns false with one
/// line (sizes that differ, invalid options) and leaves *out untouched.
bool DenoiseImage(const Image& image, const DenoiseGuides& guides, const DenoiseOptions& options,
                  Image* out, std::string* why);

}  // namespace ringlet
