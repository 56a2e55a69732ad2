// Hair type presets from published measurements, helix conversions, per-strand sampling.
#include "ringlet/hair_type.h"

#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>

#include "groom/random.h"
#include "ringlet/scene_json.h"  // kDefaultRadius

namespace ringlet {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();

// ---------------------------------------------------------------------------------------------
// Section by origin. Franbourg, Hallegot, Baltenneck, Toutain & Leroy, "Current research on
// ethnic hair", J. Am. Acad. Dermatol. 48(6 Suppl):S115-S119, 2003, table of typical physical
// characteristics: mean +- 95% confidence interval, ellipticity = maximum / minimum diameter.
//   Asian            (n = 173): area 5063 +- 179 um^2, ellipticity 1.29 +- 0.03
//   Caucasian        (n = 171): area 4079 +- 170 um^2, ellipticity 1.41 +- 0.03
//   African American (n = 251): area 4210 +- 122 um^2, ellipticity 1.66 +- 0.02
// (read as reproduced in a review chapter "Hair Ethnicity", Table 3, which cites it).
// Conversions (ours): mean radius r = sqrt(A / pi), the radius of the circle of the same area,
// which is what CrossSection's r = sqrt(a b) preserves; the CI is taken as 1.96 SD / sqrt(n)
// with n the number of fibres measured, so SD = CI sqrt(n) / 1.96; SD of r by the delta method,
// SD_r = SD_A / (2 pi r). If n counted subjects rather than fibres the fibre-to-fibre SD would be
// larger: these are lower bounds on the natural scatter.
struct OriginData {
  std::string_view name;
  double area_um2, area_ci_um2, ellipticity, ellipticity_ci;
  int n;
};
constexpr std::array<OriginData, 3> kOrigins = {{
    {"asian", 5063.0, 179.0, 1.29, 0.03, 173},
    {"caucasian", 4079.0, 170.0, 1.41, 0.03, 171},
    {"african", 4210.0, 122.0, 1.66, 0.02, 251},
}};

// ---------------------------------------------------------------------------------------------
// Natural curl by curl class: helix radius R (mean, SD), pitch ratio p / (2 pi R) (= tan of the
// angle between the helix tangent and its circle), relative SD of the pitch factor.
// - straight: R = infinity. Nagase et al., "Characterization of curved hair of Japanese women
//   with reference to internal structures and amino acid composition", J. Cosmet. Sci. 59:317-332,
//   2008: even "straight" fibres have finite curl radii, at most 16 cm among 2300 fibres. We give
//   straight strands kappa1^0 ~ Normal(0, 1 / 0.16 m) (chosen: a curl radius of 16 cm at 1 SD).
// - wavy: R = 4.4 +- 2.3 cm (mean +- SD), Nagase et al. 2008, all 2300 fibres of 230 Japanese
//   women (53% straight, 32% slightly wavy, 10% wavy, 5% frizzy). Chosen as the wavy class.
// - curly: R = 1.2 cm, SD 0.45 cm. Nagase et al. call fibres of curl radius 0.6 to 2.5 cm
//   "typical highly curved hair"; we take the geometric centre sqrt(0.6 * 2.5) = 1.22 cm and a
//   log-normal whose +-2 sigma spans the band (sigma_log = ln(2.5/0.6)/4 = 0.357, SD = 0.37 R).
//   Chosen.
// - kinky: R = 2 mm, SD 0.6 mm. Afro-textured hair forms "tight circles with diameters of only a
//   few millimetres" (Wikipedia, "Afro-textured hair", Structure); chosen: 4 mm diameter, 30% SD.
// - pitch ratios 1, 0.5, 0.25 (wavy, curly, kinky) and 20% pitch scatter are chosen: open,
//   wave-like spirals for wavy hair, ringlets for curly, tight coils for kinky. No measured
//   pitch distribution was found; the paper (Bertails et al. 2005, Fig. 3) gives none either.
struct CurlData {
  std::string_view name;
  double radius, radius_std, pitch_ratio, pitch_rel_std, straight_curvature_std;
};
constexpr std::array<CurlData, 4> kCurls = {{
    {"straight", kInf, 0.0, 0.0, 0.0, 1.0 / 0.16},
    {"wavy", 0.044, 0.023, 1.0, 0.2, 0.0},
    {"curly", 0.012, 0.0045, 0.5, 0.2, 0.0},
    {"kinky", 0.002, 0.0006, 0.25, 0.2, 0.0},
}};

// Usual curl of each origin (the brief's pairing; Bertails et al. 2005 Fig. 3 shows smooth,
// curly and African hair).
constexpr std::array<std::string_view, 3> kDefaultCurl = {"straight", "wavy", "kinky"};

// Chosen: strand-to-strand length scatter of 5% (a hairstyle's cut sets the length; this keeps
// tips from ending on one line).
constexpr double kLengthFactorStd = 0.05;

constexpr std::array<std::string_view, 3> kOriginNames = {"asian", "caucasian", "african"};
constexpr std::array<std::string_view, 4> kCurlNames = {"straight", "wavy", "curly", "kinky"};

std::string JoinNames(std::span<const std::string_view> names) {
  std::string s;
  for (size_t i = 0; i < names.size(); ++i) {
    if (i) s += ", ";
    s += names[i];
  }
  return s;
}

// Log-normal with the given mean and standard deviation: ln X ~ Normal(mu, s^2) with
// s^2 = ln(1 + (sd/mean)^2), mu = ln(mean) - s^2/2 (Johnson, Kotz & Balakrishnan, Continuous
// Univariate Distributions vol. 1, ch. 14: E X = exp(mu + s^2/2), Var X = (exp(s^2) - 1) E[X]^2).
double LogNormal(groom::SplitMix64& rng, double mean, double sd) {
  const double z = rng.Normal();  // drawn even when sd = 0, so the stream layout is fixed
  if (sd == 0.0) return mean;
  const double s2 = std::log1p((sd / mean) * (sd / mean));
  return std::exp(std::log(mean) - 0.5 * s2 + std::sqrt(s2) * z);
}

}  // namespace

HelixCurvature CurvatureFromHelix(double radius, double pitch) {
  if (std::isinf(radius)) return HelixCurvature{0.0, 0.0};
  const double c = pitch / (2.0 * kPi);
  const double d = radius * radius + c * c;
  if (d == 0.0) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    return HelixCurvature{nan, nan};
  }
  return HelixCurvature{radius / d, c / d};
}

HelixShape HelixFromCurvature(double curvature, double torsion) {
  const double d = curvature * curvature + torsion * torsion;
  if (d == 0.0) return HelixShape{kInf, kInf};
  return HelixShape{curvature / d, 2.0 * kPi * torsion / d};
}

bool HairType::IsStraight() const { return std::isinf(curl_radius); }

Vec3 HairType::MeanNaturalCurvature() const {
  if (IsStraight()) return Vec3::Zero();
  const HelixCurvature k = CurvatureFromHelix(curl_radius, curl_pitch);
  return Vec3(k.curvature, 0.0, (handedness < 0 ? -1.0 : 1.0) * k.torsion);
}

bool IsValid(const HairType& t, std::string* why) {
  auto fail = [&](const std::string& message) {
    if (why) *why = message;
    return false;
  };
  if (!(std::isfinite(t.mean_radius) && t.mean_radius > 0.0))
    return fail("hair_type.mean_radius: expected a finite number > 0 (m)");
  if (!(std::isfinite(t.mean_radius_std) && t.mean_radius_std >= 0.0))
    return fail("hair_type.mean_radius_std: expected a finite number >= 0 (m)");
  if (!(std::isfinite(t.ellipticity) && t.ellipticity >= 1.0))
    return fail("hair_type.ellipticity: expected a finite a/b >= 1");
  if (!(std::isfinite(t.ellipticity_std) && t.ellipticity_std >= 0.0))
    return fail("hair_type.ellipticity_std: expected a finite number >= 0");
  if (t.ellipticity == 1.0 && t.ellipticity_std > 0.0)
    return fail("hair_type.ellipticity_std: must be 0 when the mean ellipticity is 1");
  if (!(t.curl_radius > 0.0) || std::isnan(t.curl_radius))
    return fail("hair_type.curl_radius: expected a number > 0 (m) or +infinity (straight)");
  if (!t.IsStraight()) {
    if (!(std::isfinite(t.curl_radius_std) && t.curl_radius_std >= 0.0))
      return fail("hair_type.curl_radius_std: expected a finite number >= 0 (m)");
    if (!std::isfinite(t.curl_pitch) || t.curl_pitch < 0.0)
      return fail("hair_type.curl_pitch: expected a finite number >= 0 (m)");
    if (!(std::isfinite(t.curl_pitch_rel_std) && t.curl_pitch_rel_std >= 0.0))
      return fail("hair_type.curl_pitch_rel_std: expected a finite number >= 0");
  }
  if (!(std::isfinite(t.straight_curvature_std) && t.straight_curvature_std >= 0.0))
    return fail("hair_type.straight_curvature_std: expected a finite number >= 0 (1/m)");
  if (t.handedness < -1 || t.handedness > 1)
    return fail("hair_type.handedness: expected -1 (left), 0 (random) or +1 (right)");
  std::string material_why;
  if (!IsValid(t.material, &material_why)) return fail("hair_type.material: " + material_why);
  if (!(std::isfinite(t.length_factor_std) && t.length_factor_std >= 0.0))
    return fail("hair_type.length_factor_std: expected a finite number >= 0");
  return true;
}

std::span<const std::string_view> HairOrigins() { return kOriginNames; }
std::span<const std::string_view> CurlTypes() { return kCurlNames; }

std::string_view DefaultCurl(std::string_view origin) {
  for (size_t i = 0; i < kOriginNames.size(); ++i) {
    if (kOriginNames[i] == origin) return kDefaultCurl[i];
  }
  return {};
}

bool FindHairType(std::string_view origin, std::string_view curl, HairType* type,
                  std::string* why) {
  const OriginData* o = nullptr;
  for (const OriginData& d : kOrigins) {
    if (d.name == origin) o = &d;
  }
  if (!o) {
    if (why) {
      *why = "hair_type.origin: unknown \"" + std::string(origin) + "\"; expected one of " +
             JoinNames(kOriginNames);
    }
    return false;
  }
  if (curl.empty()) curl = DefaultCurl(origin);
  const CurlData* c = nullptr;
  for (const CurlData& d : kCurls) {
    if (d.name == curl) c = &d;
  }
  if (!c) {
    if (why) {
      *why = "hair_type.curl: unknown \"" + std::string(curl) + "\"; expected one of " +
             JoinNames(kCurlNames);
    }
    return false;
  }

  HairType t;
  t.origin = std::string(o->name);
  t.curl = std::string(c->name);
  // Section (Franbourg et al. 2003; conversions in the comment above kOrigins).
  const double r_um = std::sqrt(o->area_um2 / kPi);
  const double area_sd_um2 = o->area_ci_um2 * std::sqrt(static_cast<double>(o->n)) / 1.96;
  t.mean_radius = r_um * 1e-6;
  t.mean_radius_std = area_sd_um2 / (2.0 * kPi * r_um) * 1e-6;
  t.ellipticity = o->ellipticity;
  t.ellipticity_std = o->ellipticity_ci * std::sqrt(static_cast<double>(o->n)) / 1.96;
  // Curl (comment above kCurls).
  t.curl_radius = c->radius;
  t.curl_radius_std = c->radius_std;
  t.curl_pitch = std::isinf(c->radius) ? 0.0 : 2.0 * kPi * c->radius * c->pitch_ratio;
  t.curl_pitch_rel_std = c->pitch_rel_std;
  t.straight_curvature_std = c->straight_curvature_std;
  t.handedness = 0;
  // Material: Bertails et al. 2005 section 4 (E = 10 GPa, Poisson 0.3, 1.3 g/cm^3, from Robbins)
  // for every origin: the same table gives break stresses 209.7 / 202.3 / 189.3 MPa, a 10%
  // spread that matters for breaking, not for statics; no modulus difference is used.
  t.material = Material{};
  t.length_factor_std = kLengthFactorStd;
  assert(IsValid(t, nullptr));
  *type = t;
  return true;
}

StrandParameters SampleStrand(const HairType& type, uint64_t seed, uint64_t strand_index) {
  assert(IsValid(type, nullptr));
  groom::SplitMix64 rng(groom::StreamSeed(seed, strand_index));
  StrandParameters p;

  // Section: log-normal mean radius and excess ellipticity a/b - 1 (so a/b >= 1).
  const double r = LogNormal(rng, type.mean_radius, type.mean_radius_std);
  const double excess = type.ellipticity - 1.0;
  const double excess_sample = LogNormal(rng, excess > 0.0 ? excess : 1.0, type.ellipticity_std);
  const double ellipticity = excess > 0.0 ? 1.0 + excess_sample : 1.0;
  p.section = SectionFromEllipticity(r, ellipticity);

  // Natural curl, bending about n1 (the soft axis, see scalp.h CombOptions).
  const uint64_t bits = rng.Next();
  const double sign = type.handedness != 0 ? type.handedness : ((bits >> 63) ? -1.0 : 1.0);
  if (type.IsStraight()) {
    const double kappa = type.straight_curvature_std * rng.Normal();
    p.natural_curvature = Vec3(kappa, 0.0, 0.0);
    p.helix = HelixShape{kappa != 0.0 ? 1.0 / std::abs(kappa) : kInf, 0.0};
  } else {
    const double radius = LogNormal(rng, type.curl_radius, type.curl_radius_std);
    const double factor = LogNormal(rng, 1.0, type.curl_pitch_rel_std);
    const double pitch = sign * radius * (type.curl_pitch / type.curl_radius) * factor;
    const HelixCurvature k = CurvatureFromHelix(radius, pitch);
    p.natural_curvature = Vec3(k.curvature, 0.0, k.torsion);
    p.helix = HelixShape{radius, pitch};
  }

  p.material = type.material;
  p.length_factor = LogNormal(rng, 1.0, type.length_factor_std);
  return p;
}

bool ApplyInverseHairType(std::string_view spec, uint64_t strand_index, StrandModel* model,
                          std::string* why) {
  if (spec.empty()) {
    model->section = SectionFromEccentricity(kDefaultRadius, 0.0);
    model->material = Material{};
    model->natural_curvature = Vec3::Zero();
    return true;
  }
  const size_t slash = spec.find('/');
  const std::string_view origin = spec.substr(0, slash);
  const std::string_view curl = slash == std::string_view::npos ? "" : spec.substr(slash + 1);
  HairType type;
  if (!FindHairType(origin, curl, &type, why)) return false;
  const StrandParameters p = SampleStrand(type, 1, strand_index);
  model->section = p.section;
  model->material = p.material;
  model->natural_curvature = p.natural_curvature;
  return true;
}

}  // namespace ringlet
