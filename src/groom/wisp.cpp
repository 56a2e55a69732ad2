// Wisps: child strands in a generalized cylinder around a master strand (the paper's section 3,
// after Choe & Ko, IEEE TVCG 11(2), 2005). Formulas and sources: docs/wisps.md.
#include "ringlet/wisp.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cassert>
#include <climits>
#include <cmath>
#include <complex>
#include <numbers>
#include <sstream>

namespace ringlet {
namespace {

// SplitMix64 (Steele, Lea & Flood, "Fast splittable pseudorandom number generators", OOPSLA 2014;
// the constants of Java's SplittableRandom). Our own generator because the std:: distributions
// are implementation-defined, which would break bit-identical output across standard libraries.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t Next() {
    state_ += 0x9e3779b97f4a7c15ULL;
    return Mix(state_);
  }
  /// Uniform double in [0, 1) with 53 random bits.
  double Uniform() { return static_cast<double>(Next() >> 11) * 0x1.0p-53; }
  static std::uint64_t Mix(std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }

 private:
  std::uint64_t state_;
};

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr int kJitterModes = 3;  // wavelengths L, L/2, L/3
constexpr int kObstacleProjections = 4;

// The random parameters of one child, all drawn up front so the stream consumption per child is
// fixed (a child's parameters never depend on the options that switch features off).
struct ChildParameters {
  double length_fraction = 1.0;  // L_k / L
  double o1 = 0.0, o2 = 0.0;     // offset in the unit disk (material e1, e2)
  double jitter_weight[2][kJitterModes] = {};  // per component, summing to 1
  double jitter_phase[2][kJitterModes] = {};   // rad
  double frizz_frequency = 0.0;                // turns per metre
  double frizz_phase = 0.0;                    // rad
};

ChildParameters DrawChild(const WispOptions& o, SplitMix64* rng) {
  ChildParameters c;
  c.length_fraction = 1.0 - o.length_variation * rng->Uniform();
  // Distance distribution: rho = u^(gamma/2), theta = 2 pi v. For gamma = 1 this is the inverse
  // CDF of the uniform density in the unit disk, P(rho <= x) = x^2 (Devroye, "Non-Uniform Random
  // Variate Generation", 1986, ch. V); in general E[rho^2] = E[u^gamma] = 1/(gamma + 1).
  const double u = rng->Uniform();
  const double v = rng->Uniform();
  const double rho = std::pow(u, 0.5 * o.distance_exponent);
  c.o1 = rho * std::cos(kTwoPi * v);
  c.o2 = rho * std::sin(kTwoPi * v);
  for (int a = 0; a < 2; ++a) {
    double sum = 0.0;
    for (int m = 0; m < kJitterModes; ++m) {
      // Weights in (0, 1], normalized below; never all zero.
      c.jitter_weight[a][m] = 1.0 - rng->Uniform();
      c.jitter_phase[a][m] = kTwoPi * rng->Uniform();
      sum += c.jitter_weight[a][m];
    }
    for (int m = 0; m < kJitterModes; ++m) c.jitter_weight[a][m] /= sum;
  }
  c.frizz_frequency = o.frizz_frequency * (0.75 + 0.5 * rng->Uniform());
  c.frizz_phase = kTwoPi * rng->Uniform();
  return c;
}

// Writes one child of options.points_per_strand points at points/widths. The master's samples
// are walked once (the child's arc lengths increase), the sinusoids of jitter and frizz advance by
// a constant rotation per step (s_j = j h), so a point costs a handful of multiply-adds.
void WriteChild(const FramedCentreline& master, double fibre_radius, double wisp_radius,
                const WispOptions& o, const ChildParameters& c, bool exact_master,
                const Obstacle* obstacle, Vec3f* points, float* widths, Vec3f* major_axes) {
  const int m = o.points_per_strand;
  const double length = master.Length();
  const double child_length = exact_master ? length : length * c.length_fraction;
  const double h = child_length / (m - 1);
  const bool jitter = !exact_master && o.jitter > 0.0;
  const bool frizz = !exact_master && o.frizz_amplitude > 0.0;

  // Rotors e^{i phase} and their per-step increments e^{i omega h}.
  std::complex<double> jz[2][kJitterModes], jstep[kJitterModes];
  if (jitter) {
    for (int mode = 0; mode < kJitterModes; ++mode) {
      jstep[mode] = std::polar(1.0, kTwoPi * (mode + 1) * h / length);
      for (int a = 0; a < 2; ++a) jz[a][mode] = std::polar(1.0, c.jitter_phase[a][mode]);
    }
  }
  std::complex<double> fz, fstep;
  if (frizz) {
    fz = std::polar(1.0, c.frizz_phase);
    fstep = std::polar(1.0, kTwoPi * c.frizz_frequency * h);
  }
  // |j| <= jitter: each component is a convex combination of sines (|.| <= 1), scaled by 1/sqrt 2.
  const double jitter_scale = o.jitter / std::numbers::sqrt2;
  const double o1 = exact_master ? 0.0 : c.o1;
  const double o2 = exact_master ? 0.0 : c.o2;

  const int last = master.NumPoints() - 1;
  int interval = 0;  // master samples [interval, interval + 1] contain s
  for (int j = 0; j < m; ++j) {
    const double s = j == m - 1 ? child_length : j * h;
    while (interval < last - 1 && master.arc_lengths[interval + 1] < s) ++interval;
    const double s0 = master.arc_lengths[interval];
    const double s1 = master.arc_lengths[interval + 1];
    const double t = std::clamp((s - s0) / (s1 - s0), 0.0, 1.0);

    // Offset in the material (e1, e2) plane.
    const double scale = wisp_radius * WispRadiusScale(o, std::min(s / length, 1.0));
    double d1 = scale * o1;
    double d2 = scale * o2;
    if (jitter) {
      double j1 = 0.0, j2 = 0.0;
      for (int mode = 0; mode < kJitterModes; ++mode) {
        j1 += c.jitter_weight[0][mode] * jz[0][mode].imag();
        j2 += c.jitter_weight[1][mode] * jz[1][mode].imag();
        jz[0][mode] *= jstep[mode];
        jz[1][mode] *= jstep[mode];
      }
      d1 += jitter_scale * j1;
      d2 += jitter_scale * j2;
    }
    if (frizz) {
      const double amplitude = o.frizz_amplitude * s / child_length;
      d1 += amplitude * fz.real();
      d2 += amplitude * fz.imag();
      fz *= fstep;
    }

    // x = lerp(r) + lerp(n1) d1 + lerp(n2) d2: the linear interpolation of the children placed at
    // the master's samples, so |x - lerp(r)| <= |d|.
    const Mat3& qa = master.frames[interval];
    const Mat3& qb = master.frames[interval + 1];
    Vec3 x = (1.0 - t) * master.points[interval] + t * master.points[interval + 1];
    const Vec3 n1 = (1.0 - t) * qa.col(0) + t * qb.col(0);
    if (d1 != 0.0 || d2 != 0.0) {
      x += n1 * d1 + ((1.0 - t) * qa.col(1) + t * qb.col(1)) * d2;
    }
    // The child's cross-section is oriented as the master's at the same arc length: its major
    // axis along the master's n1 (cross_section.h), for the renderer's elliptic fibres.
    major_axes[j] = n1.normalized().cast<float>();

    // Optional push out of the body along the distance gradient.
    if (obstacle != nullptr) {
      for (int k = 0; k < kObstacleProjections; ++k) {
        Vec3 gradient;
        const double d = obstacle->SignedDistance(x, &gradient);
        if (d >= fibre_radius) break;
        x += (fibre_radius - d) * gradient;
      }
    }
    points[j] = x.cast<float>();
    widths[j] = static_cast<float>(2.0 * fibre_radius * WidthTaperFactor(o, s, child_length));
  }
}

// Writes one wisp: N strands of m points into the given arrays (pre-sized by the caller).
void WriteWisp(const FramedCentreline& master, const CrossSection& section, double wisp_radius,
               const WispOptions& o, std::uint64_t seed, const Obstacle* obstacle,
               std::uint32_t* counts, Vec3f* points, float* widths, Vec3f* major_axes) {
  SplitMix64 rng(seed);
  const double fibre_radius = section.MeanRadius();
  const int m = o.points_per_strand;
  for (int k = 0; k < o.strands_per_wisp; ++k) {
    const bool exact_master = o.include_master && k == 0;
    const ChildParameters c = exact_master ? ChildParameters{} : DrawChild(o, &rng);
    counts[k] = static_cast<std::uint32_t>(m);
    WriteChild(master, fibre_radius, wisp_radius, o, c, exact_master, obstacle,
               points + static_cast<size_t>(k) * m, widths + static_cast<size_t>(k) * m,
               major_axes + static_cast<size_t>(k) * m);
  }
}

bool Fail(std::string* why, const std::string& message) {
  if (why != nullptr) *why = message;
  return false;
}

std::string Got(double value) {
  std::ostringstream s;
  s << value;
  return s.str();
}

}  // namespace

double HelixCurliness(const Vec3& natural_curvature) {
  const double kappa = std::hypot(natural_curvature.x(), natural_curvature.y());
  const double tau = std::abs(natural_curvature.z());
  if (kappa >= kMaxCurliness * tau) return kappa == 0.0 ? 0.0 : kMaxCurliness;
  return kappa / tau;
}

double Curliness(const FramedCentreline& strand) {
  assert(strand.NumPoints() >= 2);
  const double length = strand.arc_lengths.back() - strand.arc_lengths.front();
  const double distance = (strand.points.back() - strand.points.front()).norm();
  // tan(alpha) = sqrt(sec^2 alpha - 1), sec alpha = L / d for a helix of whole turns.
  if (distance * std::sqrt(1.0 + kMaxCurliness * kMaxCurliness) <= length) return kMaxCurliness;
  const double ratio = length / distance;
  return ratio <= 1.0 ? 0.0 : std::sqrt(ratio * ratio - 1.0);
}

double WispRadius(int strands, double fibre_radius, double curliness, double packing_fraction) {
  assert(strands >= 1 && fibre_radius > 0.0 && curliness >= 0.0);
  assert(packing_fraction > 0.0 && packing_fraction <= 1.0);
  // Area per fibre in the section: pi r^2 sec(alpha) / phi, sec(alpha) = sqrt(1 + tan^2 alpha).
  const double secant = std::sqrt(1.0 + curliness * curliness);
  return fibre_radius * (1.0 + std::sqrt((strands - 1) * secant / packing_fraction));
}

double WispRadiusScale(const WispOptions& o, double fraction) {
  if (o.root_scale == o.tip_scale) return o.root_scale;
  const double shape = o.profile_exponent == 1.0 ? fraction : std::pow(fraction, o.profile_exponent);
  return o.root_scale + (o.tip_scale - o.root_scale) * shape;
}

bool WispOptions::IsValid(std::string* why) const {
  auto positive = [&](double value, const char* field) {
    return std::isfinite(value) && value > 0.0
               ? true
               : Fail(why, std::string("WispOptions.") + field + ": expected a finite number > 0, got " +
                               Got(value));
  };
  auto non_negative = [&](double value, const char* field) {
    return std::isfinite(value) && value >= 0.0
               ? true
               : Fail(why, std::string("WispOptions.") + field +
                               ": expected a finite number >= 0, got " + Got(value));
  };
  auto unit_interval = [&](double value, const char* field) {
    return value >= 0.0 && value < 1.0
               ? true
               : Fail(why, std::string("WispOptions.") + field + ": expected a number in [0, 1), got " +
                               Got(value));
  };
  constexpr int kMaxCount = 1000000;
  if (strands_per_wisp < 1 || strands_per_wisp > kMaxCount) {
    return Fail(why, "WispOptions.strands_per_wisp: expected an integer in [1, 1000000], got " +
                         std::to_string(strands_per_wisp));
  }
  if (points_per_strand < 2 || points_per_strand > kMaxCount) {
    return Fail(why, "WispOptions.points_per_strand: expected an integer in [2, 1000000], got " +
                         std::to_string(points_per_strand));
  }
  if (!non_negative(wisp_radius, "wisp_radius")) return false;
  if (!(packing_fraction > 0.0 && packing_fraction <= 1.0)) {
    return Fail(why, "WispOptions.packing_fraction: expected a number in (0, 1], got " +
                         Got(packing_fraction));
  }
  return positive(root_scale, "root_scale") && positive(tip_scale, "tip_scale") &&
         positive(profile_exponent, "profile_exponent") &&
         positive(distance_exponent, "distance_exponent") && non_negative(jitter, "jitter") &&
         unit_interval(length_variation, "length_variation") &&
         non_negative(frizz_amplitude, "frizz_amplitude") &&
         non_negative(frizz_frequency, "frizz_frequency") && unit_interval(tip_taper, "tip_taper") &&
         positive(tip_taper_length, "tip_taper_length");
}

double WidthTaperFactor(const WispOptions& options, double s, double child_length) {
  const double taper_length = std::min(options.tip_taper_length, child_length);
  const double into_taper = s - (child_length - taper_length);
  if (into_taper <= 0.0) return 1.0;
  return 1.0 - options.tip_taper * std::min(into_taper / taper_length, 1.0);
}

namespace {

// IsValidMaster with the field path prefixed by `name` ("master", "masters[3]").
bool ValidateMaster(const FramedCentreline& c, const std::string& name, std::string* why) {
  const size_t n = c.points.size();
  if (n < 2) return Fail(why, name + ": expected >= 2 samples, got " + std::to_string(n));
  if (c.frames.size() != n || c.arc_lengths.size() != n) {
    return Fail(why, name + ": points, frames and arc_lengths must have the same size (" +
                         std::to_string(n) + ", " + std::to_string(c.frames.size()) + ", " +
                         std::to_string(c.arc_lengths.size()) + ")");
  }
  if (c.arc_lengths[0] != 0.0) {
    return Fail(why, name + ".arc_lengths[0]: expected 0, got " + Got(c.arc_lengths[0]));
  }
  for (size_t j = 0; j < n; ++j) {
    if (!c.points[j].allFinite()) {
      return Fail(why, name + ".points[" + std::to_string(j) + "]: not finite");
    }
    if (j > 0 && !(c.arc_lengths[j] > c.arc_lengths[j - 1] && std::isfinite(c.arc_lengths[j]))) {
      return Fail(why, name + ".arc_lengths[" + std::to_string(j) +
                           "]: expected finite and strictly increasing");
    }
    const Mat3& q = c.frames[j];
    if (!q.allFinite() || (q.transpose() * q - Mat3::Identity()).cwiseAbs().maxCoeff() > 1e-6 ||
        q.determinant() <= 0.0) {
      return Fail(why, name + ".frames[" + std::to_string(j) + "]: expected a proper rotation");
    }
  }
  return true;
}

}  // namespace

bool IsValidMaster(const FramedCentreline& master, std::string* why) {
  return ValidateMaster(master, "master", why);
}

double ResolveWispRadius(const FramedCentreline& master, const CrossSection& section,
                         const WispOptions& options) {
  if (options.wisp_radius > 0.0) return options.wisp_radius;
  return WispRadius(options.strands_per_wisp, section.MeanRadius(), Curliness(master),
                    options.packing_fraction);
}

std::vector<double> WispLengthFractions(const WispOptions& options, std::uint64_t seed) {
  // The same draws as WriteWisp, in the same order.
  SplitMix64 rng(seed);
  std::vector<double> fractions(static_cast<size_t>(options.strands_per_wisp), 1.0);
  for (int k = 0; k < options.strands_per_wisp; ++k) {
    if (options.include_master && k == 0) continue;
    fractions[static_cast<size_t>(k)] = DrawChild(options, &rng).length_fraction;
  }
  return fractions;
}

std::uint64_t WispSeed(std::uint64_t seed, std::uint64_t index) {
  // Two rounds of the SplitMix64 finalizer so nearby (seed, index) pairs give unrelated streams.
  return SplitMix64::Mix(SplitMix64::Mix(seed) ^ (index + 0x9e3779b97f4a7c15ULL * (index + 1)));
}

void AppendWisp(const FramedCentreline& master, const CrossSection& section, double wisp_radius,
                const WispOptions& options, std::uint64_t seed, const Obstacle* obstacle,
                HairCurves* curves) {
  assert(options.IsValid(nullptr) && IsValidMaster(master, nullptr) && wisp_radius >= 0.0);
  const size_t strands = curves->point_counts.size();
  const size_t points = curves->points.size();
  const size_t n = static_cast<size_t>(options.strands_per_wisp);
  const size_t m = static_cast<size_t>(options.points_per_strand);
  curves->point_counts.resize(strands + n);
  curves->points.resize(points + n * m);
  curves->widths.resize(points + n * m);
  curves->major_axes.resize(points, Vec3f::Zero());  // curves without axes: zero (unknown)
  curves->major_axes.resize(points + n * m);
  WriteWisp(master, section, wisp_radius, options, seed, obstacle,
            curves->point_counts.data() + strands, curves->points.data() + points,
            curves->widths.data() + points, curves->major_axes.data() + points);
}

HairCurves GenerateWisps(const std::vector<FramedCentreline>& masters,
                         const std::vector<CrossSection>& sections, const WispOptions& options,
                         std::uint64_t seed, const Obstacle* obstacle, std::string* why,
                         const std::vector<double>* wisp_radii,
                         const std::vector<WispOptions>* per_master_options) {
  // Validate everything before writing anything.
  if (!options.IsValid(why)) return {};
  if (per_master_options) {
    if (per_master_options->size() != masters.size()) {
      Fail(why, "per_master_options: expected one per master (" + std::to_string(masters.size()) +
                    "), got " + std::to_string(per_master_options->size()));
      return {};
    }
    for (size_t i = 0; i < per_master_options->size(); ++i) {
      const WispOptions& o = (*per_master_options)[i];
      std::string reason;
      if (!o.IsValid(&reason)) {
        Fail(why, "per_master_options[" + std::to_string(i) + "]: " + reason);
        return {};
      }
      if (o.strands_per_wisp != options.strands_per_wisp ||
          o.points_per_strand != options.points_per_strand) {
        Fail(why, "per_master_options[" + std::to_string(i) +
                      "]: expected the strands_per_wisp and points_per_strand of the options");
        return {};
      }
    }
  }
  if (wisp_radii) {
    if (wisp_radii->size() != masters.size()) {
      Fail(why, "wisp_radii: expected one per master (" + std::to_string(masters.size()) +
                    "), got " + std::to_string(wisp_radii->size()));
      return {};
    }
    for (size_t i = 0; i < wisp_radii->size(); ++i) {
      if (!(std::isfinite((*wisp_radii)[i]) && (*wisp_radii)[i] >= 0.0)) {
        Fail(why, "wisp_radii[" + std::to_string(i) + "]: expected a finite number >= 0 (m), got " +
                      Got((*wisp_radii)[i]));
        return {};
      }
    }
  }
  if (!(sections.size() == 1 || sections.size() == masters.size())) {
    Fail(why, "sections: expected 1 or one per master (" + std::to_string(masters.size()) +
                  "), got " + std::to_string(sections.size()));
    return {};
  }
  for (size_t i = 0; i < sections.size(); ++i) {
    std::string reason;
    if (!IsValid(sections[i], &reason)) {
      Fail(why, "sections[" + std::to_string(i) + "]: " + reason);
      return {};
    }
  }
  for (size_t i = 0; i < masters.size(); ++i) {
    if (!ValidateMaster(masters[i], "masters[" + std::to_string(i) + "]", why)) return {};
  }
  const size_t n = static_cast<size_t>(options.strands_per_wisp);
  const size_t m = static_cast<size_t>(options.points_per_strand);
  const double total_points = static_cast<double>(masters.size()) * n * m;
  if (total_points > static_cast<double>(INT_MAX)) {
    Fail(why, "WispOptions: masters x strands_per_wisp x points_per_strand = " + Got(total_points) +
                  " points exceeds the HairCurves limit of 2^31 - 1");
    return {};
  }

  // Every wisp has exactly N strands of m points, so wisp i owns a fixed slice of the output and
  // the parallel loop writes disjoint ranges: the result cannot depend on the thread count.
  HairCurves curves;
  curves.point_counts.resize(masters.size() * n);
  curves.points.resize(masters.size() * n * m);
  curves.widths.resize(masters.size() * n * m);
  curves.major_axes.resize(masters.size() * n * m);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, masters.size()),
                    [&](const tbb::blocked_range<size_t>& range) {
                      for (size_t i = range.begin(); i != range.end(); ++i) {
                        const CrossSection& section = sections.size() == 1 ? sections[0] : sections[i];
                        const WispOptions& o =
                            per_master_options ? (*per_master_options)[i] : options;
                        const double radius = wisp_radii ? (*wisp_radii)[i]
                                                         : ResolveWispRadius(masters[i], section, o);
                        WriteWisp(masters[i], section, radius, o, WispSeed(seed, i), obstacle,
                                  curves.point_counts.data() + i * n,
                                  curves.points.data() + i * n * m,
                                  curves.widths.data() + i * n * m,
                                  curves.major_axes.data() + i * n * m);
                      }
                    });
  return curves;
}

}  // namespace ringlet
