// Local measures of a hanging curl along the strand, from solved curvatures (docs/validation.md,
// "Hanging curls"). Header-only; used by tests/hanging_curl_test.cpp and tools/hanging_curl_study.
//
// Each segment of constant Omega = (kappa1, kappa2, tau) is an exact circular helix whose centreline
// has curvature kappa = |(kappa1, kappa2)| and torsion tau (../shared/DESIGN.md, "A helical segment
// in closed form"), so its radius and pitch are the classical
//   R = kappa / (kappa^2 + tau^2),   p = 2 pi tau / (kappa^2 + tau^2)
// (e.g. do Carmo, Differential Geometry of Curves and Surfaces, sec. 1-5, the helix example). The
// measures below are taken at segment midpoints and are therefore exact for the discrete strand.
#pragma once

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "ringlet/math.h"
#include "ringlet/strand_geometry.h"
#include "ringlet/strand_model.h"

namespace ringlet::curls {

/// Per-segment measures of the equilibrium, root to tip.
struct CurlProfile {
  std::vector<double> s;          ///< arc length of the segment midpoint (m)
  std::vector<double> segment_length;  ///< l_i (m)
  std::vector<double> curvature;  ///< kappa = |(kappa1, kappa2)| (1/m)
  std::vector<double> torsion;    ///< tau (1/m)
  std::vector<double> radius;     ///< helix radius kappa / (kappa^2 + tau^2) (m)
  std::vector<double> pitch;      ///< helix pitch 2 pi |tau| / (kappa^2 + tau^2) (m)
  /// Drop along gravity per unit arc length over the segment, (r_i - r_(i+1)).g_hat / l_i: 1 for
  /// a straight vertical segment, sin(alpha) for a helix with vertical axis and pitch angle alpha.
  std::vector<double> descent;
  double length = 0.0;  ///< L (m)
};

inline CurlProfile MeasureCurl(const StrandModel& model, const VecX& q) {
  CurlProfile p;
  const int n = model.NumSegments();
  const StrandGeometry geometry = ComputeGeometry(model, q);
  const Vec3 down = model.gravity.norm() > 0 ? Vec3(model.gravity.normalized()) : Vec3(0, 0, -1);
  double s0 = 0.0;
  for (int i = 0; i < n; ++i) {
    const double l = model.segment_lengths[i];
    const double kappa = q.segment<2>(3 * i).norm(), tau = q(3 * i + 2);
    const double omega2 = kappa * kappa + tau * tau;
    p.s.push_back(s0 + 0.5 * l);
    p.segment_length.push_back(l);
    p.curvature.push_back(kappa);
    p.torsion.push_back(tau);
    // A straight segment (Omega = 0) is a helix of zero radius and undefined pitch: report 0, inf.
    p.radius.push_back(omega2 > 0 ? kappa / omega2 : 0.0);
    p.pitch.push_back(omega2 > 0 ? 2.0 * std::numbers::pi * std::abs(tau) / omega2
                                 : std::numeric_limits<double>::infinity());
    p.descent.push_back((geometry.points[i + 1] - geometry.points[i]).dot(down) / l);
    s0 += l;
  }
  p.length = s0;
  return p;
}

/// Length of the stretched part: the measure of {s in [0, L] : kappa(s) < fraction * kappa0},
/// kappa(s) interpolated linearly between segment midpoints (constant beyond the first and last
/// midpoints). A measure rather than "the first crossing from the root" so that a clamp boundary
/// layer or a local dip inside the curls moves it continuously instead of by jumps (m).
inline double StretchedLength(const CurlProfile& p, double kappa0, double fraction = 0.5) {
  const double threshold = fraction * kappa0;
  const int n = static_cast<int>(p.s.size());
  double stretched = 0.0;
  // Ends: [0, s_0] and [s_(n-1), L] carry the first and last segment's value.
  if (p.curvature.front() < threshold) stretched += p.s.front();
  if (p.curvature.back() < threshold) stretched += p.length - p.s.back();
  for (int i = 0; i + 1 < n; ++i) {
    const double a = p.curvature[i] - threshold, b = p.curvature[i + 1] - threshold;
    const double h = p.s[i + 1] - p.s[i];
    if (a < 0 && b < 0) {
      stretched += h;
    } else if (a < 0 || b < 0) {
      // One crossing inside: the part below the threshold is h * (negative part fraction).
      const double t = a / (a - b);  // where the linear interpolant crosses, in [0, 1]
      stretched += a < 0 ? t * h : (1.0 - t) * h;
    }
  }
  return stretched;
}

/// Curl irregularity: how much the centreline's curvature and torsion wobble from curl to curl
/// once the slow stretching by the weight is removed. For every segment whose window of one
/// natural turn, 2 pi / |Omega0| of arc length centred on it, lies inside [s_from, s_to], take
/// the deviation of (kappa, tau) from their arc-length mean over the window; return the RMS of
/// |deviation| / |Omega0| over those segments (dimensionless; 0 for a perfect helix, and for a
/// helix whose radius and pitch change slowly along the strand). -1 if no window fits.
inline double CurlIrregularity(const CurlProfile& p, double omega0, double s_from, double s_to) {
  const double half = std::numbers::pi / omega0;
  const int n = static_cast<int>(p.s.size());
  double sum = 0.0;
  int count = 0;
  for (int i = 0; i < n; ++i) {
    if (p.s[i] - half < s_from || p.s[i] + half > s_to) continue;
    double weight = 0.0, kappa = 0.0, tau = 0.0;
    for (int j = 0; j < n; ++j) {
      if (std::abs(p.s[j] - p.s[i]) > half) continue;
      weight += p.segment_length[j];
      kappa += p.segment_length[j] * p.curvature[j];
      tau += p.segment_length[j] * p.torsion[j];
    }
    kappa /= weight;
    tau /= weight;
    const double dk = p.curvature[i] - kappa, dt = p.torsion[i] - tau;
    sum += dk * dk + dt * dt;
    ++count;
  }
  return count > 0 ? std::sqrt(sum / count) / omega0 : -1.0;
}

/// Largest distance of the centreline (sampled 4 points per segment) from its best-fitting plane
/// (the plane through the centroid normal to the covariance's smallest principal axis), over L.
inline double OutOfPlaneDeviation(const StrandModel& model, const VecX& q) {
  const std::vector<Vec3> points = SampleCentreline(model, q, 4);
  Vec3 centroid = Vec3::Zero();
  for (const Vec3& x : points) centroid += x;
  centroid /= static_cast<double>(points.size());
  Mat3 covariance = Mat3::Zero();
  for (const Vec3& x : points) covariance += (x - centroid) * (x - centroid).transpose();
  Eigen::SelfAdjointEigenSolver<Mat3> eigen(covariance);
  const Vec3 normal = eigen.eigenvectors().col(0);  // eigenvalues ascending
  double deviation = 0.0;
  for (const Vec3& x : points) deviation = std::max(deviation, std::abs((x - centroid).dot(normal)));
  return deviation / model.Length();
}

/// The three shapes of Miller et al. (PRL 112, 068103, 2014).
enum class CurlRegime { kPlanar, kLocalizedHelix, kGlobalHelix };

inline const char* RegimeName(CurlRegime regime) {
  switch (regime) {
    case CurlRegime::kPlanar: return "planar";
    case CurlRegime::kLocalizedHelix: return "localized";
    case CurlRegime::kGlobalHelix: return "global";
  }
  return "?";
}

/// Classification rule (docs/validation.md, "Hanging curls"): planar when the centreline leaves
/// its best plane by less than kPlanarTolerance L; otherwise a localized helix when the stretched
/// part (StretchedLength at half the natural curvature) exceeds kLocalizedFraction L, else a
/// global helix (curls reach up to the root).
inline constexpr double kPlanarTolerance = 1e-3;
inline constexpr double kLocalizedFraction = 0.2;

inline CurlRegime Classify(double out_of_plane, double stretched_fraction) {
  if (out_of_plane < kPlanarTolerance) return CurlRegime::kPlanar;
  return stretched_fraction > kLocalizedFraction ? CurlRegime::kLocalizedHelix
                                                 : CurlRegime::kGlobalHelix;
}

}  // namespace ringlet::curls
