// Virtual hairdressing (paper, section 3.2): model edits followed by warm-started re-solves.
#include "ringlet/styling.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <variant>

#include "ringlet/hair_type.h"
#include "ringlet/helix.h"
#include "ringlet/inverse.h"
#include "ringlet/strand_geometry.h"
#include "ringlet/wisp.h"

namespace ringlet {
namespace {

bool Fail(std::string* why, const std::string& message) {
  if (why) *why = message;
  return false;
}

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string Number(double x) {
  std::ostringstream s;
  s.precision(6);
  s << x;
  return s.str();
}

// Re-solves masters `which` from the warm starts `warm` (one per entry of which) and writes the
// solutions back; adds iterations to the report and sets *unconverged to the number left
// unconverged. With batch.cancel, solves in blocks and returns false (solutions of the finished
// blocks written) as soon as the flag is set; each strand's solve is the same either way.
bool Resolve(StyledHair* state, const std::vector<int>& which, const std::vector<VecX>& warm,
             const BatchOptions& batch, OperationReport* report, int* unconverged = nullptr) {
  const size_t total = which.size();
  // Blocks of a few strands per thread: small enough to stop within ~0.1 s of a cancel, large
  // enough that the parallel loop stays busy (solve times vary 100x between strands).
  const size_t block = batch.cancel ? 32 : std::max<size_t>(total, 1);
  int left = 0;
  for (size_t begin = 0; begin < total; begin += block) {
    if (batch.cancel && batch.cancel->load(std::memory_order_relaxed)) return false;
    const size_t end = std::min(total, begin + block);
    std::vector<StrandModel> models;
    models.reserve(end - begin);
    for (size_t k = begin; k < end; ++k) models.push_back(state->masters.models[which[k]]);
    const std::vector<VecX> block_warm(warm.begin() + begin, warm.begin() + end);
    BatchOptions block_batch = batch;
    if (batch.progress) {
      block_batch.progress = [&batch, begin, total](int finished, int) {
        batch.progress(static_cast<int>(begin) + finished, static_cast<int>(total));
      };
    }
    std::vector<StrandSolution> solved =
        SolveStrands(models, state->style.solver, block_batch, &block_warm);
    for (size_t k = begin; k < end; ++k) {
      StrandSolution& s = solved[k - begin];
      report->iterations += s.summary.iterations;
      if (!s.summary.Converged()) ++left;
      state->solutions[which[k]] = std::move(s);
    }
  }
  if (batch.cancel && batch.cancel->load(std::memory_order_relaxed)) return false;
  if (unconverged) *unconverged = left;
  return true;
}

constexpr const char* kCancelled = "cancelled";

// The tip of a strand at its equilibrium (m).
Vec3 TipOf(const StrandModel& model, const VecX& curvatures) {
  return ComputeGeometry(model, curvatures).points.back();
}

// The first `segments` curvature triples of `q`, continued by `fallback`'s triples beyond q's
// size and then by copies of the last available triple: a warm start for a grid that shares
// its first segments with q's.
VecX WarmStart(const VecX& q, const VecX& fallback, int segments) {
  VecX out(3 * segments);
  for (int i = 0; i < segments; ++i) {
    if (3 * i + 2 < q.size()) {
      out.segment<3>(3 * i) = q.segment<3>(3 * i);
    } else if (3 * i + 2 < fallback.size()) {
      out.segment<3>(3 * i) = fallback.segment<3>(3 * i);
    } else {
      out.segment<3>(3 * i) = out.segment<3>(3 * (i - 1));
    }
  }
  return out;
}

std::string Summary(const OperationReport& r) {
  std::string s = r.name + ": " + std::to_string(r.strands) + " masters re-solved, " +
                  std::to_string(r.iterations) + " iterations";
  if (r.rounds > 1) s += ", " + std::to_string(r.rounds) + " rounds";
  if (r.unconverged > 0) s += ", " + std::to_string(r.unconverged) + " unconverged";
  return s;
}

bool CheckCurl(double radius, double pitch, std::string* why) {
  if (radius == 0.0 && pitch == 0.0) {
    return Fail(why, "curl.radius, curl.pitch: R = p = 0 is not a helix");
  }
  std::string field, message;
  if (CheckCurlHelix(radius, pitch, &field, &message)) return true;
  return Fail(why, "curl." + field + ": " + message);
}

bool CheckGrow(double step, int steps, std::string* why) {
  if (!(std::isfinite(step) && step > 0.0 && step <= kMaxGrowStep)) {
    return Fail(why, "grow.step: expected a length in (0, " + Number(kMaxGrowStep) + "] (m), got " +
                         Number(step));
  }
  if (steps < 1 || steps > kMaxGrowSteps) {
    return Fail(why, "grow.steps: expected an integer from 1 to " + std::to_string(kMaxGrowSteps) +
                         ", got " + std::to_string(steps));
  }
  if (!(step * steps <= kMaxGrowLength)) {
    return Fail(why, "grow.step, grow.steps: expected at most " + Number(kMaxGrowLength) +
                         " m of growth in all (step x steps), got " + Number(step) + " m x " +
                         std::to_string(steps) + " = " + Number(step * steps) + " m");
  }
  return true;
}

// The checks of Cut that do not need the hair.
bool CheckCut(const CutRegion& region, const CutOptions& options, std::string* why) {
  if (!region.IsValid(why) || !options.IsValid(why)) return false;
  if (options.settle && region.kind == CutRegion::Kind::kMaxLength) {
    return Fail(why, "cut.settle: only for plane and sphere cuts (a length cut is exact)");
  }
  return true;
}

}  // namespace

bool CheckCurlHelix(double radius, double pitch, std::string* field, std::string* why) {
  const auto fail = [&](const char* name, const std::string& message) {
    if (field) *field = name;
    return Fail(why, message);
  };
  // R = +infinity (straight) is allowed; NaN fails the comparison.
  if (!(radius >= 0.0)) {
    return fail("radius", "expected a number >= 0 (m; inf = straight), got " + Number(radius));
  }
  if (!std::isfinite(pitch)) {
    return fail("pitch", "expected a finite number (m; < 0 = left-handed), got " + Number(pitch));
  }
  if (radius == 0.0 && pitch == 0.0) return fail("radius", "R = p = 0 is not a helix");
  // A tiny helix has a huge (or, once R^2 + c^2 underflows, infinite) curvature: refused here,
  // before it reaches the models and the wisp radius.
  const HelixCurvature k = CurvatureFromHelix(radius, pitch);
  const auto too_tight = [&](const char* name, const char* what, double value) {
    return fail(name, "expected a helix with curvature and torsion at most " +
                          Number(kMaxCurlCurvature) +
                          " 1/m (R or |p| / (2 pi) at least 5e-06 m), "
                          "got R = " +
                          Number(radius) + " m, p = " + Number(pitch) + " m (" + what + " " +
                          (std::isfinite(value) ? Number(value) + " 1/m" : "not finite") + ")");
  };
  if (!(std::abs(k.curvature) <= kMaxCurlCurvature)) {
    return too_tight("radius", "curvature", k.curvature);
  }
  if (!(std::abs(k.torsion) <= kMaxCurlCurvature)) return too_tight("pitch", "torsion", k.torsion);
  return true;
}

bool WetOptions::IsValid(std::string* why) const {
  if (!(stiffness_factor > 0.0 && stiffness_factor <= 1.0)) {
    return Fail(why, "wet.stiffness_factor: expected a number in (0, 1] (E_wet / E_dry)");
  }
  if (!(swelling >= 1.0 && swelling <= 2.0)) {
    return Fail(why, "wet.swelling: expected a number in [1, 2] (wet / dry radius)");
  }
  if (!(water_density >= 0.0 && water_density <= 2000.0)) {
    return Fail(why, "wet.water_density: expected a number in [0, 2000] (kg/m^3)");
  }
  if (!(layer_factor >= 0.0 && layer_factor <= 1.0)) {
    return Fail(why, "wet.layer_factor: expected a number in [0, 1]");
  }
  return true;
}

bool MakeStyledHair(const Hairstyle& style, const Groom& groom, StyledHair* state,
                    std::string* why) {
  if (groom.solutions.size() != groom.masters.models.size()) {
    return Fail(why, "groom: expected one solution per master");
  }
  for (size_t i = 0; i < groom.solutions.size(); ++i) {
    if (groom.solutions[i].curvatures.size() != 3 * groom.masters.models[i].NumSegments()) {
      return Fail(why, "groom: solution " + std::to_string(i) + " does not match its master");
    }
  }
  StyledHair s;
  s.style = style;
  s.masters = groom.masters;
  s.solutions = groom.solutions;
  *state = std::move(s);
  return true;
}

bool IsWet(const StyledHair& state, int master) {
  return state.wet && (state.wet_masters.empty() || state.wet_masters[master]);
}

double MasterClearance(const StyledHair& state, int master) {
  const Hairstyle& style = state.style;
  // The same expression as BuildMasters (bit for bit when dry: thickness * 1 is not rounded).
  const double thickness = IsWet(state, master)
                               ? style.layers.thickness * state.wet_options.layer_factor
                               : style.layers.thickness;
  // contact_radii may be empty in a HairstyleMasters made by hand: r_w max(1, tip_scale).
  const std::vector<double>& radii = state.masters.contact_radii;
  const double base = radii.size() == state.masters.models.size()
                          ? radii[master]
                          : state.masters.wisp_radii[master] * std::max(1.0, style.wisps.tip_scale);
  return base + state.masters.layers[master] * thickness;
}

// ---------------------------------------------------------------------------------------------
// Selection

bool StrandSelection::IsValid(int masters, std::string* why) const {
  for (int i : indices) {
    if (i < 0 || i >= masters) {
      return Fail(why, "selection.indices: " + std::to_string(i) + " is not a master index (0 to " +
                           std::to_string(masters - 1) + ")");
    }
  }
  if (!(min_polar_angle >= 0.0 && max_polar_angle <= std::numbers::pi &&
        min_polar_angle <= max_polar_angle)) {
    return Fail(why,
                "selection.polar_angle: expected 0 <= min <= max <= pi (rad), got [" +
                    Number(min_polar_angle) + ", " + Number(max_polar_angle) + "]");
  }
  if (std::isnan(min_height) || std::isnan(max_height) || min_height > max_height) {
    return Fail(why, "selection.height: expected min <= max (m), got [" + Number(min_height) +
                         ", " + Number(max_height) + "]");
  }
  return true;
}

bool StrandSelection::Selects(int index, const Root& root) const {
  if (!indices.empty()) return std::find(indices.begin(), indices.end(), index) != indices.end();
  return root.head.polar_angle >= min_polar_angle && root.head.polar_angle <= max_polar_angle &&
         root.head.height >= min_height && root.head.height <= max_height;
}

// ---------------------------------------------------------------------------------------------
// Curl

// After master i's natural curvature changed (Curl, CurlBrush): the wisp thickness follows the
// curliness (BuildMasters), from the dry fibre radius, and the new shape's clearance is
// r_w max(1, tip_scale) as BuildMasters gives it (an explicit master's own clearance belonged
// to its old shape).
namespace {
void FitWispToCurl(StyledHair* state, int i) {
  StrandModel& m = state->masters.models[i];
  const WispOptions& wisps = state->style.wisps;
  if (wisps.wisp_radius <= 0.0) {
    const CrossSection& dry = IsWet(*state, i) ? state->dry.sections[i] : m.section;
    state->masters.wisp_radii[i] = WispRadius(wisps.strands_per_wisp, dry.MeanRadius(),
                                              HelixCurliness(m.natural_curvature),
                                              wisps.packing_fraction);
  }
  if (state->masters.contact_radii.size() == state->masters.models.size()) {
    state->masters.contact_radii[i] =
        state->masters.wisp_radii[i] * std::max(1.0, wisps.tip_scale);
  }
  m.contact.clearance = MasterClearance(*state, i);
}
}  // namespace

bool Curl(StyledHair* state, double radius, double pitch, const StrandSelection& selection,
          const BatchOptions& batch, OperationReport* report, std::string* why) {
  const auto start = std::chrono::steady_clock::now();
  if (!CheckCurl(radius, pitch, why)) return false;
  const int n = static_cast<int>(state->masters.models.size());
  if (!selection.IsValid(n, why)) return false;

  const HelixCurvature helix = CurvatureFromHelix(radius, pitch);
  // BuildMasters' convention: the hairstyle's comb says whether the curl starts away from the
  // head (kappa1^0 <= 0, the default) or into it.
  const Vec3 natural(CurlStartSign(state->style.comb) * helix.curvature, 0.0, helix.torsion);

  OperationReport r;
  r.name = "curl";
  std::vector<int> which;
  std::vector<VecX> warm;
  for (int i = 0; i < n; ++i) {
    if (!selection.Selects(i, state->masters.roots[i])) continue;
    StrandModel& m = state->masters.models[i];
    // Warm start: the old equilibrium shifted by the change of natural curvature (the linear
    // elastic response about the rest shape moves with it).
    // A curl replaces the rest shape: a per-segment one (inverse statics) is dropped.
    VecX q = state->solutions[i].curvatures;
    for (int k = 0; k < m.NumSegments(); ++k) {
      q.segment<3>(3 * k) += natural - m.NaturalCurvature(k);
    }
    m.natural_curvature = natural;
    m.rest_curvatures.resize(0);
    m.contact.support_offsets.clear();  // chosen for the dropped rest shape
    FitWispToCurl(state, i);
    which.push_back(i);
    warm.push_back(std::move(q));
  }
  r.strands = static_cast<int>(which.size());
  if (!Resolve(state, which, warm, batch, &r, &r.unconverged)) return Fail(why, kCancelled);
  r.seconds = SecondsSince(start);
  r.message = Summary(r) + " (R = " + Number(radius) + " m, p = " + Number(pitch) + " m)";
  if (report) *report = r;
  return true;
}

bool CurlBrush(StyledHair* state, double radius, double pitch, const Brush& brush,
               const StrandSelection& selection, const BatchOptions& batch,
               OperationReport* report, std::string* why) {
  const auto start = std::chrono::steady_clock::now();
  if (!CheckCurl(radius, pitch, why)) return false;
  std::string message;
  if (!brush.IsValid(&message)) return Fail(why, "curl.brush." + message);
  const int n = static_cast<int>(state->masters.models.size());
  if (!selection.IsValid(n, why)) return false;
  const HelixCurvature helix = CurvatureFromHelix(radius, pitch);
  const Vec3 target(CurlStartSign(state->style.comb) * helix.curvature, 0.0, helix.torsion);
  // Omega + w (target - Omega), exactly the target at w = 1.
  const auto toward = [&target](const Vec3& omega, double w) -> Vec3 {
    return w == 1.0 ? target : Vec3(omega + w * (target - omega));
  };
  OperationReport r;
  r.name = "curl";
  std::vector<int> which;
  std::vector<VecX> warm;
  for (int i = 0; i < n; ++i) {
    if (!selection.Selects(i, state->masters.roots[i])) continue;
    const double w = MasterBrushWeight(*state, i, brush);
    if (w == 0.0) continue;
    StrandModel& m = state->masters.models[i];
    VecX q = state->solutions[i].curvatures;
    const Vec3 natural = toward(m.natural_curvature, w);
    if (m.HasRestShape()) {
      for (int k = 0; k < m.NumSegments(); ++k) {
        const Vec3 rest = m.rest_curvatures.segment<3>(3 * k);
        const Vec3 next = toward(rest, w);
        q.segment<3>(3 * k) += next - rest;
        m.rest_curvatures.segment<3>(3 * k) = next;
      }
    } else {
      // As Curl: the old equilibrium shifted by the change of natural curvature.
      for (int k = 0; k < m.NumSegments(); ++k) {
        q.segment<3>(3 * k) += natural - m.NaturalCurvature(k);
      }
    }
    m.natural_curvature = natural;
    m.contact.support_offsets.clear();
    FitWispToCurl(state, i);
    which.push_back(i);
    warm.push_back(std::move(q));
  }
  r.strands = static_cast<int>(which.size());
  if (!Resolve(state, which, warm, batch, &r, &r.unconverged)) return Fail(why, kCancelled);
  r.seconds = SecondsSince(start);
  r.message = Summary(r) + " (brush toward R = " + Number(radius) + " m, p = " + Number(pitch) +
              " m)";
  if (report) *report = r;
  return true;
}

// ---------------------------------------------------------------------------------------------
// Wet and dry

bool Wet(StyledHair* state, const WetOptions& options, const BatchOptions& batch,
         OperationReport* report, std::string* why, const StrandSelection& selection) {
  const auto start = std::chrono::steady_clock::now();
  if (!options.IsValid(why)) return false;
  const int n = static_cast<int>(state->masters.models.size());
  if (!selection.IsValid(n, why)) return false;
  // The selected masters that are still dry (a brushed Wet may have wet some already).
  std::vector<int> which;
  for (int i = 0; i < n; ++i) {
    if (selection.Selects(i, state->masters.roots[i]) && !IsWet(*state, i)) which.push_back(i);
  }
  if (which.empty()) return Fail(why, "wet: the hair is already wet (dry it first)");
  if (state->wet && (options.stiffness_factor != state->wet_options.stiffness_factor ||
                     options.swelling != state->wet_options.swelling ||
                     options.water_density != state->wet_options.water_density ||
                     options.layer_factor != state->wet_options.layer_factor)) {
    return Fail(why, "wet: the options differ from those of the masters already wet (dry them "
                     "first)");
  }
  state->dry.sections.resize(n);
  state->dry.materials.resize(n);
  if (!state->wet) state->wet_masters.assign(n, false);
  state->wet = true;
  state->wet_options = options;
  std::vector<VecX> warm(which.size());
  for (size_t k = 0; k < which.size(); ++k) {
    const int i = which[k];
    state->wet_masters[i] = true;
    StrandModel& m = state->masters.models[i];
    state->dry.sections[i] = m.section;
    state->dry.materials[i] = m.material;
    // Robbins 2002 (the paper's [Rob02], section 3.2): E / 10, radius + 13%.
    const double dry_area = m.section.Area();
    m.section.a *= options.swelling;
    m.section.b *= options.swelling;
    const double wet_area = m.section.Area();
    m.material.young_modulus *= options.stiffness_factor;
    // The swelling volume is filled with water: mass per length rho A + rho_w (A' - A).
    m.material.density =
        (m.material.density * dry_area + options.water_density * (wet_area - dry_area)) / wet_area;
    m.contact.clearance = MasterClearance(*state, i);
    warm[k] = state->solutions[i].curvatures;
  }
  OperationReport r;
  r.name = "wet";
  r.strands = static_cast<int>(which.size());
  if (!Resolve(state, which, warm, batch, &r, &r.unconverged)) return Fail(why, kCancelled);
  r.seconds = SecondsSince(start);
  r.message = Summary(r) + " (E x " + Number(options.stiffness_factor) + ", radius x " +
              Number(options.swelling) + ", layers x " + Number(options.layer_factor) + ")";
  if (report) *report = r;
  return true;
}

bool Dry(StyledHair* state, const BatchOptions& batch, OperationReport* report,
         std::string* why, const StrandSelection& selection) {
  const auto start = std::chrono::steady_clock::now();
  if (!state->wet) return Fail(why, "dry: the hair is not wet (wet it first)");
  const int n = static_cast<int>(state->masters.models.size());
  if (!selection.IsValid(n, why)) return false;
  if (state->dry.sections.size() != static_cast<size_t>(n) ||
      state->dry.materials.size() != static_cast<size_t>(n)) {
    return Fail(why, "dry: the remembered dry parameters do not match the masters");
  }
  std::vector<int> which;
  for (int i = 0; i < n; ++i) {
    if (selection.Selects(i, state->masters.roots[i]) && IsWet(*state, i)) which.push_back(i);
  }
  if (which.empty()) return Fail(why, "dry: the selected masters are not wet (wet them first)");
  std::vector<VecX> warm(which.size());
  if (state->wet_masters.empty()) state->wet_masters.assign(n, true);
  for (size_t k = 0; k < which.size(); ++k) {
    const int i = which[k];
    state->wet_masters[i] = false;
    StrandModel& m = state->masters.models[i];
    m.section = state->dry.sections[i];
    m.material = state->dry.materials[i];
    m.contact.clearance = MasterClearance(*state, i);
    warm[k] = state->solutions[i].curvatures;
  }
  // The last wet master dried: the hair is dry.
  if (std::find(state->wet_masters.begin(), state->wet_masters.end(), true) ==
      state->wet_masters.end()) {
    state->wet = false;
    state->wet_masters.clear();
    state->dry = DryParameters{};
  }
  OperationReport r;
  r.name = "dry";
  r.strands = static_cast<int>(which.size());
  if (!Resolve(state, which, warm, batch, &r, &r.unconverged)) return Fail(why, kCancelled);
  r.seconds = SecondsSince(start);
  r.message = Summary(r);
  if (report) *report = r;
  return true;
}

// ---------------------------------------------------------------------------------------------
// Cut

double CutRegion::Inside(const Vec3& point) const {
  switch (kind) {
    case Kind::kAbovePlane:
      return normal.normalized().dot(point) - offset;
    case Kind::kInsideSphere:
      return radius - (point - centre).norm();
    case Kind::kMaxLength:
      break;
  }
  return 1.0;
}

bool CutRegion::IsValid(std::string* why) const {
  switch (kind) {
    case Kind::kAbovePlane:
      if (!normal.allFinite() || !(normal.norm() > 0.0) || !std::isfinite(normal.norm())) {
        return Fail(why, "cut.normal: expected a finite non-zero vector");
      }
      if (!std::isfinite(offset)) return Fail(why, "cut.z: expected a finite height (m)");
      return true;
    case Kind::kInsideSphere:
      if (!centre.allFinite()) return Fail(why, "cut.centre: expected 3 finite numbers (m)");
      if (!(std::isfinite(radius) && radius > 0.0)) {
        return Fail(why, "cut.radius: expected a finite number > 0 (m), got " + Number(radius));
      }
      return true;
    case Kind::kMaxLength:
      if (!(std::isfinite(length) && length > 0.0)) {
        return Fail(why, "cut.length: expected a finite number > 0 (m), got " + Number(length));
      }
      return true;
  }
  return Fail(why, "cut.kind: unknown");
}

bool CutOptions::IsValid(std::string* why) const {
  if (!(std::isfinite(tolerance) && tolerance > 0.0)) {
    return Fail(why, "cut.tolerance: expected a finite number > 0 (m)");
  }
  if (max_rounds < 1) return Fail(why, "cut.max_rounds: expected an integer >= 1");
  if (samples_per_segment < 1 || samples_per_segment > 1024) {
    return Fail(why, "cut.samples_per_segment: expected 1 to 1024");
  }
  return true;
}

double CutArcLength(const StrandModel& model, const VecX& curvatures, const CutRegion& region,
                    int samples_per_segment) {
  const double total = model.Length();
  if (region.kind == CutRegion::Kind::kMaxLength) return std::min(region.length, total);
  const StrandGeometry g = ComputeGeometry(model, curvatures);
  if (region.Inside(g.points[0]) < 0.0) return 0.0;
  const int m = std::max(1, samples_per_segment);
  double s = 0.0;  // arc length at the start of segment i
  for (int i = 0; i < model.NumSegments(); ++i) {
    const double l = model.segment_lengths[i];
    const Vec3 omega = curvatures.segment<3>(3 * i);
    // The exact point at arc length u into segment i (HelixChord, helix.h).
    const auto point = [&](double u) { return Vec3(g.points[i] + g.frames[i] * HelixChord(omega, u)); };
    double u0 = 0.0;
    for (int j = 1; j <= m; ++j) {
      const double u1 = (j == m) ? l : l * j / m;
      if (region.Inside(point(u1)) < 0.0) {
        // Bisection on [u0, u1]: inside at u0, outside at u1, to rounding.
        double lo = u0, hi = u1;
        for (int k = 0; k < 200 && hi - lo > 0.0; ++k) {
          const double mid = 0.5 * (lo + hi);
          if (mid <= lo || mid >= hi) break;
          (region.Inside(point(mid)) < 0.0 ? hi : lo) = mid;
        }
        return s + 0.5 * (lo + hi);
      }
      u0 = u1;
    }
    s += l;
  }
  return total;
}

StrandModel TruncateModel(const StrandModel& model, double arc_length, VecX* curvatures) {
  StrandModel out = model;
  out.segment_lengths.clear();
  double s = 0.0;
  for (int i = 0; i < model.NumSegments(); ++i) {
    const double l = model.segment_lengths[i];
    if (s + l >= arc_length) {
      const double rest = arc_length - s;
      if (rest > 0.0) out.segment_lengths.push_back(rest);
      break;
    }
    out.segment_lengths.push_back(l);
    s += l;
  }
  if (out.segment_lengths.empty()) out.segment_lengths.push_back(arc_length);
  // A per-segment rest shape keeps the rest curvatures of the kept segments, the cut one's too.
  if (model.HasRestShape()) {
    out.rest_curvatures = model.rest_curvatures.head(3 * out.NumSegments());
  }
  // Support offsets (inverse statics' contact forces, ContactModel) are dropped: the cut strand
  // no longer carries the loads they were chosen for.
  out.contact.support_offsets.clear();
  if (curvatures) {
    const VecX q = *curvatures;
    *curvatures = WarmStart(q, q, out.NumSegments());
  }
  return out;
}

bool Cut(StyledHair* state, const CutRegion& region, const CutOptions& options,
         const BatchOptions& batch, OperationReport* report, std::string* why,
         const StrandSelection& selection) {
  const auto start = std::chrono::steady_clock::now();
  if (!CheckCut(region, options, why)) return false;
  const int n = static_cast<int>(state->masters.models.size());
  if (!selection.IsValid(n, why)) return false;
  // Where each master first leaves the region, at the current equilibrium.
  std::vector<int> which;
  std::vector<VecX> warm;
  std::vector<StrandModel> before;     // the uncut models, for settle
  std::vector<VecX> before_q;          // and their equilibria
  std::vector<double> cut_at;
  int rooted_outside = 0;
  for (int i = 0; i < n; ++i) {
    if (!selection.Selects(i, state->masters.roots[i])) continue;
    const StrandModel& m = state->masters.models[i];
    const double s = CutArcLength(m, state->solutions[i].curvatures, region,
                                  options.samples_per_segment);
    if (s <= 0.0) {
      ++rooted_outside;
      continue;
    }
    if (s >= m.Length()) continue;
    VecX q = state->solutions[i].curvatures;
    before.push_back(m);
    before_q.push_back(q);
    state->masters.models[i] = TruncateModel(m, s, &q);
    which.push_back(i);
    warm.push_back(std::move(q));
    cut_at.push_back(s);
  }
  OperationReport r;
  r.name = "cut";
  r.strands = static_cast<int>(which.size());
  if (!Resolve(state, which, warm, batch, &r, &r.unconverged)) return Fail(why, kCancelled);

  int unsettled = 0;
  if (options.settle && !which.empty()) {
    // Per cut master, a bracket [lo, hi] of lengths with the tip inside (g > 0) at lo and
    // outside (g < 0) at hi; Illinois-modified regula falsi on g(l) = Inside(tip(l)).
    const int c = static_cast<int>(which.size());
    std::vector<double> lo(c), hi(c), g_lo(c), g_hi(c);
    std::vector<int> side(c, 0);  // which end moved last: +1 lo, -1 hi
    std::vector<bool> active(c, false);
    for (int k = 0; k < c; ++k) {
      const int i = which[k];
      const double g = region.Inside(TipOf(state->masters.models[i], state->solutions[i].curvatures));
      const double g_prev = region.Inside(TipOf(before[k], before_q[k]));
      lo[k] = cut_at[k];
      g_lo[k] = g;
      hi[k] = before[k].Length();
      g_hi[k] = g_prev;
      // Settled already, or no bracket (the tip fell below after the cut, or was already
      // inside before it: a curl that left the region and came back).
      active[k] = std::abs(g) > options.tolerance && g > 0.0 && g_prev < 0.0;
      if (std::abs(g) > options.tolerance && !active[k]) ++unsettled;
    }
    for (int round = 0; round < options.max_rounds; ++round) {
      std::vector<int> now;
      std::vector<int> now_k;
      std::vector<VecX> now_warm;
      std::vector<double> trial(c);
      for (int k = 0; k < c; ++k) {
        if (!active[k]) continue;
        const double l = (lo[k] * g_hi[k] - hi[k] * g_lo[k]) / (g_hi[k] - g_lo[k]);
        trial[k] = std::clamp(l, lo[k] + 1e-3 * (hi[k] - lo[k]), hi[k] - 1e-3 * (hi[k] - lo[k]));
        const int i = which[k];
        const VecX current = state->solutions[i].curvatures;
        state->masters.models[i] = TruncateModel(before[k], trial[k]);
        now.push_back(i);
        now_k.push_back(k);
        now_warm.push_back(WarmStart(current, before_q[k], state->masters.models[i].NumSegments()));
      }
      if (now.empty()) break;
      ++r.rounds;
      OperationReport scratch;
      if (!Resolve(state, now, now_warm, batch, &scratch)) return Fail(why, kCancelled);
      r.iterations += scratch.iterations;
      for (size_t j = 0; j < now.size(); ++j) {
        const int k = now_k[j];
        const int i = now[j];
        const double g =
            region.Inside(TipOf(state->masters.models[i], state->solutions[i].curvatures));
        if (std::abs(g) <= options.tolerance) {
          active[k] = false;
          continue;
        }
        if (g > 0.0) {
          lo[k] = trial[k];
          g_lo[k] = g;
          if (side[k] == +1) g_hi[k] *= 0.5;  // Illinois: the other end stuck twice
          side[k] = +1;
        } else {
          hi[k] = trial[k];
          g_hi[k] = g;
          if (side[k] == -1) g_lo[k] *= 0.5;
          side[k] = -1;
        }
      }
    }
    for (int k = 0; k < c; ++k) unsettled += active[k] ? 1 : 0;
    r.unconverged = 0;
    for (int i : which) r.unconverged += state->solutions[i].summary.Converged() ? 0 : 1;
  }
  // The wisps of the cut masters inherit the cut through their lengths (a child is a fixed
  // fraction of its master's length), but their offsets, jitter and frizz carry some of them
  // past the boundary: every drawn strand rooted in the region is ended where it first leaves it
  // (ClipStrands), recorded so that StyledStrands draws the same strands.
  HairCurves strands;
  if (!GrowWisps(state->style, state->masters, state->solutions, &strands, why)) return false;
  ApplyStrandCuts(state->strand_cuts, &strands);
  // Only the wisps of the selected masters are clipped (a brushed cut leaves the others whole).
  std::vector<StrandCut> previous = state->strand_cuts;
  previous.resize(strands.point_counts.size());
  int clipped = ClipStrands(region, strands, &state->strand_cuts);
  if (n > 0 && !state->strand_cuts.empty()) {
    const size_t per_wisp = state->strand_cuts.size() / static_cast<size_t>(n);
    for (int i = 0; i < n; ++i) {
      if (selection.Selects(i, state->masters.roots[i])) continue;
      for (size_t k = 0; k < per_wisp; ++k) {
        const size_t j = static_cast<size_t>(i) * per_wisp + k;
        if (state->strand_cuts[j].segment != previous[j].segment ||
            state->strand_cuts[j].t != previous[j].t) {
          state->strand_cuts[j] = previous[j];
          --clipped;
        }
      }
    }
  }
  r.seconds = SecondsSince(start);
  r.message = Summary(r) + ", " + std::to_string(clipped) + " strands clipped";
  if (rooted_outside > 0) {
    r.message += ", " + std::to_string(rooted_outside) + " rooted outside the cut region left uncut";
  }
  if (options.settle) {
    r.message += unsettled == 0 ? ", all tips settled within " + Number(options.tolerance) + " m"
                                : ", " + std::to_string(unsettled) + " tips not settled";
  }
  if (report) *report = r;
  return true;
}

bool CutBelow(StyledHair* state, double z, const CutOptions& options, const BatchOptions& batch,
              OperationReport* report, std::string* why) {
  if (!std::isfinite(z)) return Fail(why, "cut.z: expected a finite height (m), got " + Number(z));
  CutRegion region;
  region.kind = CutRegion::Kind::kAbovePlane;
  region.normal = Vec3::UnitZ();
  region.offset = z;
  return Cut(state, region, options, batch, report, why);
}

// ---------------------------------------------------------------------------------------------
// Grow

namespace {

// Adds `length` (m) at the tip of a model (Grow): the last segment lengthened, segments of
// `max_segment` appended while it would exceed that; a per-segment rest shape keeps the
// lengthened segment's rest curvatures and gives the appended ones the natural curvature.
void ExtendModel(StrandModel* model, double length, double max_segment) {
  std::vector<double>& l = model->segment_lengths;
  double last = l.back() + length;
  l.pop_back();
  while (last > max_segment) {
    l.push_back(max_segment);
    last -= max_segment;
  }
  l.push_back(last);
  // A per-segment rest shape: the lengthened last segment keeps its rest curvatures, new
  // segments get the hair type's natural curvature.
  model->contact.support_offsets.clear();  // the grown strand's samples moved (as for cut)
  if (model->HasRestShape()) {
    const Eigen::Index kept = model->rest_curvatures.size();
    model->rest_curvatures.conservativeResize(3 * model->NumSegments());
    for (Eigen::Index j = kept; j < model->rest_curvatures.size(); j += 3) {
      model->rest_curvatures.segment<3>(j) = model->natural_curvature;
    }
  }
}

}  // namespace

bool Grow(StyledHair* state, double step, int steps, const BatchOptions& batch,
          std::vector<StyledHair>* sequence, OperationReport* report, std::string* why,
          const StrandSelection& selection) {
  const auto start = std::chrono::steady_clock::now();
  if (!CheckGrow(step, steps, why)) return false;
  const int n = static_cast<int>(state->masters.models.size());
  if (!selection.IsValid(n, why)) return false;
  std::vector<int> which;
  for (int i = 0; i < n; ++i) {
    if (selection.Selects(i, state->masters.roots[i])) which.push_back(i);
  }
  // The longest segment of each master at the start: the grid resolution to keep. The growth
  // appends about step * steps / max_segment segments: more than kMaxSegments in all is refused
  // before any work (and before a loop that would never end).
  std::vector<double> max_segment(n);
  for (int i : which) {
    const auto& l = state->masters.models[i].segment_lengths;
    max_segment[i] = *std::max_element(l.begin(), l.end());
    const double segments =
        static_cast<double>(l.size()) + 1.0 + (l.back() + step * steps) / max_segment[i] + steps;
    if (!(segments <= kMaxSegments)) {
      return Fail(why, "grow.step: growing master " + std::to_string(i) + " by " +
                           Number(step * steps) + " m in " + std::to_string(steps) +
                           " steps would give it about " + Number(segments) +
                           " segments, more than the limit of " + std::to_string(kMaxSegments));
    }
  }
  OperationReport r;
  r.name = "grow";
  r.strands = static_cast<int>(which.size());
  r.rounds = steps;
  if (sequence) sequence->clear();
  // The hair regrows past the cut: the clips of earlier cuts no longer apply to the wisps of the
  // grown masters (docs/styling.md).
  if (!state->strand_cuts.empty()) {
    const size_t per_wisp = state->strand_cuts.size() / static_cast<size_t>(n);
    for (int i : which) {
      for (size_t k = 0; k < per_wisp; ++k) {
        state->strand_cuts[static_cast<size_t>(i) * per_wisp + k] = StrandCut{};
      }
    }
    if (std::all_of(state->strand_cuts.begin(), state->strand_cuts.end(),
                    [](const StrandCut& c) { return c.segment < 0; })) {
      state->strand_cuts.clear();  // nothing clipped any more (a whole-head grow)
    }
  }
  for (int t = 0; t < steps; ++t) {
    std::vector<VecX> warm(which.size());
    for (size_t k = 0; k < which.size(); ++k) {
      const int i = which[k];
      ExtendModel(&state->masters.models[i], step, max_segment[i]);
      const VecX& q = state->solutions[i].curvatures;
      warm[k] = WarmStart(q, q, state->masters.models[i].NumSegments());
    }
    if (!Resolve(state, which, warm, batch, &r, &r.unconverged)) return Fail(why, kCancelled);
    if (sequence) sequence->push_back(*state);
  }
  r.seconds = SecondsSince(start);
  r.message = Summary(r) + " (+" + Number(step * steps) + " m in " + std::to_string(steps) +
              " steps)";
  if (report) *report = r;
  return true;
}

// ---------------------------------------------------------------------------------------------
// Brushes: sculpt and puff (docs/styling.md, "Brushes")

bool Brush::IsValid(std::string* why) const {
  if (!centre.allFinite()) return Fail(why, "centre: expected a finite point (m)");
  if (!(radius > 0.0 && radius <= kMaxBrushRadius)) {
    return Fail(why, "radius: expected a length in (0, " + Number(kMaxBrushRadius) +
                         "] (m), got " + Number(radius));
  }
  if (!(strength > 0.0 && strength <= 1.0)) {
    return Fail(why, "strength: expected a number in (0, 1], got " + Number(strength));
  }
  return true;
}

double Brush::Weight(double distance) const {
  const double x = distance / radius;
  if (!(x < 1.0)) return 0.0;  // outside (and NaN)
  double f = 1.0;
  switch (falloff) {
    case Falloff::kSmooth:
      f = 1.0 - x * x * (3.0 - 2.0 * x);
      break;
    case Falloff::kLinear:
      f = 1.0 - x;
      break;
    case Falloff::kConstant:
      break;
  }
  return strength * f;
}

const char* FalloffName(Brush::Falloff falloff) {
  switch (falloff) {
    case Brush::Falloff::kSmooth:
      return "smooth";
    case Brush::Falloff::kLinear:
      return "linear";
    case Brush::Falloff::kConstant:
      return "constant";
  }
  return "smooth";
}

Vec3 MirrorAcrossHead(const HeadFrame& head, const Vec3& p) {
  const Vec3 e = HeadAxes(head).col(2);
  return p - 2.0 * (p - head.centre).dot(e) * e;
}

Vec3 MirrorVectorAcrossHead(const HeadFrame& head, const Vec3& v) {
  const Vec3 e = HeadAxes(head).col(2);
  return v - 2.0 * v.dot(e) * e;
}

const HeadFrame& HairstyleHead(const Hairstyle& style) {
  return std::visit([](const auto& scalp) -> const HeadFrame& { return scalp.head; },
                    style.scalp);
}

bool SculptStroke::IsValid(std::string* why) const {
  std::string message;
  if (!brush.IsValid(&message)) {
    // The stroke's centre is its "from".
    if (message.rfind("centre:", 0) == 0) message = "from:" + message.substr(7);
    return Fail(why, "sculpt." + message);
  }
  if (!to.allFinite()) return Fail(why, "sculpt.to: expected a finite point (m)");
  if (!((to - brush.centre).norm() <= kMaxBrushRadius)) {
    return Fail(why, "sculpt.to: expected a point within " + Number(kMaxBrushRadius) +
                         " m of from, got " + Number((to - brush.centre).norm()) + " m away");
  }
  return true;
}

namespace {

// Where Sculpt samples a master: 4 points per segment at u = l_i k / 4 (k = 1..4), as
// (segment, u) for PointForceGradients and as arc lengths for SampleCentrelineAt.
constexpr int kSculptSamplesPerSegment = 4;

struct SculptSamples {
  std::vector<PointForce> places;   // one per sample (force unused)
  std::vector<double> arc_lengths;  // s_j (m)
};

SculptSamples SculptSamplesOf(const StrandModel& model) {
  SculptSamples out;
  double start = 0.0;
  for (int i = 0; i < model.NumSegments(); ++i) {
    const double l = model.segment_lengths[i];
    for (int k = 1; k <= kSculptSamplesPerSegment; ++k) {
      const double u = l * k / kSculptSamplesPerSegment;
      out.places.push_back(PointForce{i, u, Vec3::Zero()});
      out.arc_lengths.push_back(start + u);
    }
    start += l;
  }
  return out;
}

// The curvatures of the model's own segments whose samples come closest to `targets` (least
// squares), from `start`: Levenberg-Marquardt, J = dx/dq from PointForceGradients (its columns
// are -J^T F for unit forces F = e_x, e_y, e_z at each sample), damping lambda diag(J^T J) (plus
// 1e-9 of its mean, so directions that do not move the centreline, e.g. the twist of a straight
// segment, stay where they were).
VecX FitSamples(const StrandModel& model, const SculptSamples& samples,
                const std::vector<Vec3>& targets, const VecX& start) {
  const int p = static_cast<int>(targets.size());
  std::vector<PointForce> forces;
  forces.reserve(3 * p);
  for (const PointForce& place : samples.places) {
    for (int c = 0; c < 3; ++c) forces.push_back(PointForce{place.segment, place.u, Vec3::Unit(c)});
  }
  const auto residual = [&](const VecX& q) {
    const std::vector<Vec3> x = SampleCentrelineAt(model, q, samples.arc_lengths);
    VecX r(3 * p);
    for (int j = 0; j < p; ++j) r.segment<3>(3 * j) = x[j] - targets[j];
    return r;
  };
  VecX q = start;
  VecX r = residual(q);
  double cost = r.squaredNorm();
  double lambda = 1e-3;
  for (int iteration = 0; iteration < 200 && cost > 0.0; ++iteration) {
    const MatX g = PointForceGradients(model, q, forces);  // -J^T, 3n x 3p
    MatX a = g * g.transpose();                            // J^T J
    const VecX rhs = g * r;                                // -J^T r
    const double floor = 1e-9 * a.diagonal().mean();
    bool improved = false;
    while (lambda < 1e12) {
      MatX m = a;
      m.diagonal().array() += lambda * (a.diagonal().array() + floor);
      const VecX dq = m.ldlt().solve(rhs);
      const VecX trial = q + dq;
      const VecX r_trial = residual(trial);
      const double c = r_trial.squaredNorm();
      if (std::isfinite(c) && c < cost) {
        const bool small = cost - c <= 1e-12 * cost || dq.norm() <= 1e-12 * (1.0 + q.norm());
        q = trial;
        r = r_trial;
        cost = c;
        lambda = std::max(lambda / 3.0, 1e-12);
        improved = !small;
        break;
      }
      lambda *= 4.0;
    }
    if (!improved) break;
  }
  return q;
}

}  // namespace

bool Sculpt(StyledHair* state, const SculptStroke& stroke, const StrandSelection& selection,
            const BatchOptions& batch, OperationReport* report, std::string* why) {
  const auto start = std::chrono::steady_clock::now();
  if (!stroke.IsValid(why)) return false;
  const int n = static_cast<int>(state->masters.models.size());
  if (!selection.IsValid(n, why)) return false;
  const HeadFrame& head = HairstyleHead(state->style);
  const Brush& brush = stroke.brush;
  const Vec3 d = stroke.to - brush.centre;
  const Vec3 mirror_centre = MirrorAcrossHead(head, brush.centre);
  const Vec3 mirror_d = MirrorVectorAcrossHead(head, d);

  OperationReport r;
  r.name = "sculpt";
  std::vector<int> which;
  std::vector<StrandModel> models;
  std::vector<VecX> targets;
  for (int i = 0; i < n; ++i) {
    if (!selection.Selects(i, state->masters.roots[i])) continue;
    if (batch.cancel && batch.cancel->load(std::memory_order_relaxed)) return Fail(why, kCancelled);
    const StrandModel& m = state->masters.models[i];
    const VecX& q = state->solutions[i].curvatures;
    const SculptSamples samples = SculptSamplesOf(m);
    std::vector<Vec3> points = SampleCentrelineAt(m, q, samples.arc_lengths);
    bool touched = false;
    for (Vec3& x : points) {
      const double w = brush.Weight((x - brush.centre).norm());
      const double w_mirror = brush.mirror ? brush.Weight((x - mirror_centre).norm()) : 0.0;
      if (w > 0.0 || w_mirror > 0.0) touched = true;
      x += w * d + w_mirror * mirror_d;
    }
    if (!touched) continue;
    which.push_back(i);
    targets.push_back(FitSamples(m, samples, points, q));
    models.push_back(m);
  }
  r.strands = static_cast<int>(which.size());
  if (batch.cancel && batch.cancel->load(std::memory_order_relaxed)) return Fail(why, kCancelled);
  InverseOptions options;
  options.naive = false;  // the forward solve from the inverted rest shape is the new equilibrium
  const std::vector<InverseResult> inverted =
      InvertStrands(models, targets, options, batch.threads, batch.progress);
  if (batch.cancel && batch.cancel->load(std::memory_order_relaxed)) return Fail(why, kCancelled);
  int unstable = 0;
  for (size_t k = 0; k < which.size(); ++k) {
    const InverseResult& result = inverted[k];
    StrandModel& m = state->masters.models[which[k]];
    m.rest_curvatures = result.rest_curvatures;
    m.contact.support_offsets = result.support_offsets;
    StrandSolution& solution = state->solutions[which[k]];
    solution.curvatures = result.equilibrium;
    solution.summary = result.forward;
    r.iterations += result.forward.iterations;
    if (!result.forward.Converged()) ++r.unconverged;
    if (!result.stable) ++unstable;
  }
  r.seconds = SecondsSince(start);
  r.message = Summary(r);
  if (unstable > 0) {
    r.message += ", " + std::to_string(unstable) +
                 " unstable targets (each settled in the nearest stable equilibrium)";
  }
  if (report) *report = r;
  return true;
}

bool Puff(StyledHair* state, double angle, const Brush& brush, const StrandSelection& selection,
          const BatchOptions& batch, OperationReport* report, std::string* why) {
  const auto start = std::chrono::steady_clock::now();
  if (!(std::abs(angle) <= std::numbers::pi / 2.0)) {
    return Fail(why, "puff.angle: expected a number in [-pi/2, pi/2] (rad), got " + Number(angle));
  }
  std::string message;
  if (!brush.IsValid(&message)) return Fail(why, "puff." + message);
  const int n = static_cast<int>(state->masters.models.size());
  if (!selection.IsValid(n, why)) return false;
  const HeadFrame& head = HairstyleHead(state->style);
  const Vec3 mirror_centre = MirrorAcrossHead(head, brush.centre);

  OperationReport r;
  r.name = "puff";
  std::vector<int> which;
  std::vector<VecX> warm;
  for (int i = 0; i < n; ++i) {
    Root& root = state->masters.roots[i];
    if (!selection.Selects(i, root)) continue;
    double w = brush.Weight((root.position - brush.centre).norm());
    if (brush.mirror) w = std::max(w, brush.Weight((root.position - mirror_centre).norm()));
    if (w == 0.0) continue;
    StrandModel& m = state->masters.models[i];
    const Vec3 t = m.root_frame.col(2);
    const Vec3 normal = root.normal.normalized();
    const double tilt = std::acos(std::clamp(t.dot(normal), -1.0, 1.0));
    // The new tilt from the normal, kept in [0, max(kMaxPuffTilt, tilt)] (a root already
    // flatter than the limit is not flattened further, nor lifted past the normal).
    const double goal = std::clamp(tilt - w * angle, 0.0, std::max(kMaxPuffTilt, tilt));
    const double turn = tilt - goal;  // > 0 turns t toward the normal
    const Vec3 axis = t.cross(normal);
    if (turn == 0.0 || !(axis.norm() > 1e-12)) continue;  // t along the normal: no lift axis
    const Mat3 rotation = Eigen::AngleAxisd(turn, axis.normalized()).toRotationMatrix();
    m.root_frame = rotation * m.root_frame;
    root.frame = m.root_frame;
    which.push_back(i);
    warm.push_back(state->solutions[i].curvatures);
  }
  r.strands = static_cast<int>(which.size());
  if (!Resolve(state, which, warm, batch, &r, &r.unconverged)) return Fail(why, kCancelled);
  r.seconds = SecondsSince(start);
  r.message = Summary(r) + " (angle " + Number(angle) + " rad)";
  if (report) *report = r;
  return true;
}

// ---------------------------------------------------------------------------------------------
// Length, clump and frizz brushes (docs/styling.md, "Brushes")

double MasterBrushWeight(const StyledHair& state, int master, const Brush& brush) {
  const StrandModel& m = state.masters.models[master];
  std::vector<double> arc_lengths = SculptSamplesOf(m).arc_lengths;
  arc_lengths.insert(arc_lengths.begin(), 0.0);  // the root
  const std::vector<Vec3> points =
      SampleCentrelineAt(m, state.solutions[master].curvatures, arc_lengths);
  double nearest = std::numeric_limits<double>::infinity();
  double nearest_mirror = std::numeric_limits<double>::infinity();
  const Vec3 mirror_centre =
      brush.mirror ? MirrorAcrossHead(HairstyleHead(state.style), brush.centre) : brush.centre;
  for (const Vec3& x : points) {
    nearest = std::min(nearest, (x - brush.centre).norm());
    if (brush.mirror) nearest_mirror = std::min(nearest_mirror, (x - mirror_centre).norm());
  }
  double w = brush.Weight(nearest);
  if (brush.mirror) w = std::max(w, brush.Weight(nearest_mirror));
  return w;
}

namespace {

bool CheckBrushFactor(const char* name, double factor, const Brush& brush, std::string* why) {
  if (!(factor > 0.0 && factor <= kMaxBrushFactor)) {
    return Fail(why, std::string(name) + ".factor: expected a number in (0, " +
                         Number(kMaxBrushFactor) + "], got " + Number(factor));
  }
  std::string message;
  if (!brush.IsValid(&message)) return Fail(why, std::string(name) + "." + message);
  return true;
}

bool CheckFrizz(double amplitude, const Brush& brush, std::string* why) {
  if (!(amplitude >= 0.0 && amplitude <= kMaxFrizzAmplitude)) {
    return Fail(why, "frizz.amplitude: expected a length in [0, " + Number(kMaxFrizzAmplitude) +
                         "] (m), got " + Number(amplitude));
  }
  std::string message;
  if (!brush.IsValid(&message)) return Fail(why, "frizz." + message);
  return true;
}

// The strands of wisp i as GrowWisps draws them (one AppendWisp, as RegrowWisps).
HairCurves WispOf(const StyledHair& state, int i) {
  const FramedCentreline centreline =
      SampleFramedCentreline(state.masters.models[i], state.solutions[i].curvatures,
                             state.style.master_points_per_segment);
  HairCurves wisp;
  AppendWisp(centreline, state.masters.models[i].section, state.masters.wisp_radii[i],
             MasterWispOptions(state.masters, static_cast<size_t>(i)),
             WispSeed(state.style.seed, static_cast<std::uint64_t>(i)), state.style.body.get(),
             &wisp);
  return wisp;
}

// The drawn arc length (m) of strand k of curves ended as `cut` says (ApplyStrandCuts: the
// polyline summed in double from the float points, up to the stored end point).
double ClippedArcLength(const HairCurves& curves, size_t first, int count, const StrandCut& cut) {
  const Vec3f* p = curves.points.data() + first;
  const int last = cut.segment >= 0 ? cut.segment : count - 1;
  double s = 0.0;
  for (int j = 0; j < last; ++j) s += (p[j + 1] - p[j]).cast<double>().norm();
  if (cut.segment >= 0) {
    const Vec3f end = (p[last].cast<double>() + cut.t * (p[last + 1] - p[last]).cast<double>())
                          .cast<float>();
    s += (end - p[last]).cast<double>().norm();
  }
  return s;
}

}  // namespace

bool LengthBrush(StyledHair* state, double factor, const Brush& brush,
                 const StrandSelection& selection, const BatchOptions& batch,
                 OperationReport* report, std::string* why) {
  const auto start = std::chrono::steady_clock::now();
  if (!CheckBrushFactor("length", factor, brush, why)) return false;
  const int n = static_cast<int>(state->masters.models.size());
  if (!selection.IsValid(n, why)) return false;
  std::vector<int> which;
  std::vector<double> scales;
  for (int i = 0; i < n; ++i) {
    if (!selection.Selects(i, state->masters.roots[i])) continue;
    const double w = MasterBrushWeight(*state, i, brush);
    if (w == 0.0) continue;
    const double scale = 1.0 + w * (factor - 1.0);
    if (scale == 1.0) continue;
    if (scale > 1.0) {
      const auto& l = state->masters.models[i].segment_lengths;
      const double longest = *std::max_element(l.begin(), l.end());
      const double add = (scale - 1.0) * state->masters.models[i].Length();
      const double segments = static_cast<double>(l.size()) + 1.0 + (l.back() + add) / longest;
      if (!(segments <= kMaxSegments)) {
        return Fail(why, "length.factor: lengthening master " + std::to_string(i) + " by " +
                             Number(add) + " m would give it about " + Number(segments) +
                             " segments, more than the limit of " + std::to_string(kMaxSegments));
      }
    }
    which.push_back(i);
    scales.push_back(scale);
  }
  // The drawn arc length of every clipped strand of the changed wisps, before the change.
  const size_t per_wisp = static_cast<size_t>(state->masters.wisp_options.strands_per_wisp);
  const bool clipped = !state->strand_cuts.empty();
  std::vector<std::vector<double>> clipped_lengths(which.size());
  if (clipped) {
    for (size_t k = 0; k < which.size(); ++k) {
      const HairCurves wisp = WispOf(*state, which[k]);
      size_t first = 0;
      clipped_lengths[k].assign(per_wisp, -1.0);
      for (size_t j = 0; j < per_wisp; ++j) {
        const int count = static_cast<int>(wisp.point_counts[j]);
        const StrandCut& cut = state->strand_cuts[static_cast<size_t>(which[k]) * per_wisp + j];
        if (cut.segment >= 0) clipped_lengths[k][j] = ClippedArcLength(wisp, first, count, cut);
        first += static_cast<size_t>(count);
      }
    }
  }
  std::vector<VecX> warm(which.size());
  for (size_t k = 0; k < which.size(); ++k) {
    const int i = which[k];
    StrandModel& m = state->masters.models[i];
    VecX q = state->solutions[i].curvatures;
    if (scales[k] < 1.0) {
      m = TruncateModel(m, scales[k] * m.Length(), &q);
    } else {
      const auto& l = m.segment_lengths;
      const double longest = *std::max_element(l.begin(), l.end());
      ExtendModel(&m, (scales[k] - 1.0) * m.Length(), longest);
      q = WarmStart(q, q, m.NumSegments());
    }
    warm[k] = std::move(q);
  }
  OperationReport r;
  r.name = "length";
  r.strands = static_cast<int>(which.size());
  if (!Resolve(state, which, warm, batch, &r, &r.unconverged)) return Fail(why, kCancelled);
  // The clipped strands keep their clip, scaled as their master.
  int reclipped = 0;
  if (clipped) {
    for (size_t k = 0; k < which.size(); ++k) {
      const HairCurves wisp = WispOf(*state, which[k]);
      size_t first = 0;
      for (size_t j = 0; j < per_wisp; ++j) {
        const int count = static_cast<int>(wisp.point_counts[j]);
        StrandCut& cut = state->strand_cuts[static_cast<size_t>(which[k]) * per_wisp + j];
        cut = StrandCut{};
        if (clipped_lengths[k][j] >= 0.0) {
          HairCurves one;
          one.point_counts.push_back(wisp.point_counts[j]);
          one.points.assign(wisp.points.begin() + static_cast<std::ptrdiff_t>(first),
                            wisp.points.begin() + static_cast<std::ptrdiff_t>(first + count));
          CutRegion region;
          region.kind = CutRegion::Kind::kMaxLength;
          region.length = clipped_lengths[k][j] * scales[k];
          std::vector<StrandCut> cuts(1);
          if (region.length > 0.0 && ClipStrands(region, one, &cuts) > 0) {
            cut = cuts[0];
            ++reclipped;
          }
        }
        first += static_cast<size_t>(count);
      }
    }
    if (std::all_of(state->strand_cuts.begin(), state->strand_cuts.end(),
                    [](const StrandCut& c) { return c.segment < 0; })) {
      state->strand_cuts.clear();
    }
  }
  r.seconds = SecondsSince(start);
  r.message = Summary(r) + " (factor " + Number(factor) + ")";
  if (reclipped > 0) r.message += ", " + std::to_string(reclipped) + " clipped strands rescaled";
  if (report) *report = r;
  return true;
}

bool ClumpBrush(StyledHair* state, double factor, const Brush& brush,
                const StrandSelection& selection, OperationReport* report, std::string* why) {
  const auto start = std::chrono::steady_clock::now();
  if (!CheckBrushFactor("clump", factor, brush, why)) return false;
  const int n = static_cast<int>(state->masters.models.size());
  if (!selection.IsValid(n, why)) return false;
  std::vector<double> factors = state->masters.clump_factors;
  if (factors.size() != static_cast<size_t>(n)) factors.assign(n, 1.0);
  OperationReport r;
  r.name = "clump";
  for (int i = 0; i < n; ++i) {
    if (!selection.Selects(i, state->masters.roots[i])) continue;
    const double w = MasterBrushWeight(*state, i, brush);
    if (w == 0.0) continue;
    const double k = std::clamp(factors[i] * (1.0 + w * (factor - 1.0)), 1.0 / kMaxClumpFactor,
                                kMaxClumpFactor);
    if (k == factors[i]) continue;
    factors[i] = k;
    ++r.strands;
  }
  if (r.strands > 0) state->masters.clump_factors = std::move(factors);
  r.seconds = SecondsSince(start);
  r.message = "clump: " + std::to_string(r.strands) + " wisps changed (factor " + Number(factor) +
              ")";
  if (report) *report = r;
  return true;
}

bool FrizzBrush(StyledHair* state, double amplitude, const Brush& brush,
                const StrandSelection& selection, OperationReport* report, std::string* why) {
  const auto start = std::chrono::steady_clock::now();
  if (!CheckFrizz(amplitude, brush, why)) return false;
  const int n = static_cast<int>(state->masters.models.size());
  if (!selection.IsValid(n, why)) return false;
  std::vector<double> amplitudes = state->masters.frizz_amplitudes;
  if (amplitudes.size() != static_cast<size_t>(n)) {
    amplitudes.assign(n, state->masters.wisp_options.frizz_amplitude);
  }
  OperationReport r;
  r.name = "frizz";
  for (int i = 0; i < n; ++i) {
    if (!selection.Selects(i, state->masters.roots[i])) continue;
    const double w = MasterBrushWeight(*state, i, brush);
    if (w == 0.0) continue;
    const double a = amplitudes[i] + w * (amplitude - amplitudes[i]);
    if (a == amplitudes[i]) continue;
    amplitudes[i] = a;
    ++r.strands;
  }
  if (r.strands > 0) state->masters.frizz_amplitudes = std::move(amplitudes);
  r.seconds = SecondsSince(start);
  r.message = "frizz: " + std::to_string(r.strands) + " wisps changed (amplitude " +
              Number(amplitude) + " m)";
  if (report) *report = r;
  return true;
}

// ---------------------------------------------------------------------------------------------
// Operations as data

const char* OperationName(StyleOperation::Kind kind) {
  switch (kind) {
    case StyleOperation::Kind::kCurl:
      return "curl";
    case StyleOperation::Kind::kWet:
      return "wet";
    case StyleOperation::Kind::kDry:
      return "dry";
    case StyleOperation::Kind::kCut:
      return "cut";
    case StyleOperation::Kind::kGrow:
      return "grow";
    case StyleOperation::Kind::kSculpt:
      return "sculpt";
    case StyleOperation::Kind::kPuff:
      return "puff";
    case StyleOperation::Kind::kLength:
      return "length";
    case StyleOperation::Kind::kClump:
      return "clump";
    case StyleOperation::Kind::kFrizz:
      return "frizz";
  }
  return "unknown";
}

bool StyleOperation::IsValid(std::string* why) const {
  for (int i : selection.indices) {
    if (i < 0) {
      return Fail(why, "selection.indices: expected master indices >= 0, got " + std::to_string(i));
    }
  }
  // The upper bound of the indices needs the hair: ApplyOperation checks it.
  if (!selection.IsValid(std::numeric_limits<int>::max(), why)) return false;
  switch (kind) {
    case Kind::kCurl: {
      if (!CheckCurl(curl_radius, curl_pitch, why)) return false;
      std::string message;
      if (curl_brushed && !curl_brush.IsValid(&message)) {
        return Fail(why, "curl.brush." + message);
      }
      return true;
    }
    case Kind::kWet:
      return wet.IsValid(why);
    case Kind::kDry:
      return true;
    case Kind::kCut:
      return CheckCut(cut_region, cut, why);
    case Kind::kGrow:
      return CheckGrow(grow_step, grow_steps, why);
    case Kind::kSculpt:
      return sculpt.IsValid(why);
    case Kind::kPuff: {
      if (!(std::abs(puff_angle) <= std::numbers::pi / 2.0)) {
        return Fail(why, "puff.angle: expected a number in [-pi/2, pi/2] (rad), got " +
                             Number(puff_angle));
      }
      std::string message;
      if (!puff_brush.IsValid(&message)) return Fail(why, "puff." + message);
      return true;
    }
    case Kind::kLength:
      return CheckBrushFactor("length", factor, brush, why);
    case Kind::kClump:
      return CheckBrushFactor("clump", factor, brush, why);
    case Kind::kFrizz:
      return CheckFrizz(frizz_amplitude, brush, why);
  }
  return Fail(why, "operation: unknown kind");
}

bool ApplyOperation(StyledHair* state, const StyleOperation& operation, const BatchOptions& batch,
                    std::vector<StyledHair>* grow_sequence, OperationReport* report,
                    std::string* why) {
  const StyleOperation& op = operation;
  switch (op.kind) {
    case StyleOperation::Kind::kCurl:
      if (op.curl_brushed) {
        return CurlBrush(state, op.curl_radius, op.curl_pitch, op.curl_brush, op.selection, batch,
                         report, why);
      }
      return Curl(state, op.curl_radius, op.curl_pitch, op.selection, batch, report, why);
    case StyleOperation::Kind::kWet:
      return Wet(state, op.wet, batch, report, why, op.selection);
    case StyleOperation::Kind::kDry:
      return Dry(state, batch, report, why, op.selection);
    case StyleOperation::Kind::kCut:
      return Cut(state, op.cut_region, op.cut, batch, report, why, op.selection);
    case StyleOperation::Kind::kGrow:
      return Grow(state, op.grow_step, op.grow_steps, batch, grow_sequence, report, why,
                  op.selection);
    case StyleOperation::Kind::kSculpt:
      return Sculpt(state, op.sculpt, op.selection, batch, report, why);
    case StyleOperation::Kind::kPuff:
      return Puff(state, op.puff_angle, op.puff_brush, op.selection, batch, report, why);
    case StyleOperation::Kind::kLength:
      return LengthBrush(state, op.factor, op.brush, op.selection, batch, report, why);
    case StyleOperation::Kind::kClump:
      return ClumpBrush(state, op.factor, op.brush, op.selection, report, why);
    case StyleOperation::Kind::kFrizz:
      return FrizzBrush(state, op.frizz_amplitude, op.brush, op.selection, report, why);
  }
  return Fail(why, "operation: unknown kind");
}

bool StyledStrands(const StyledHair& state, HairCurves* strands, std::string* why) {
  if (!GrowWisps(state.style, state.masters, state.solutions, strands, why)) return false;
  if (!state.strand_cuts.empty()) {
    if (state.strand_cuts.size() != strands->point_counts.size()) {
      return Fail(why, "styled state: the strand cuts do not match the wisps");
    }
    ApplyStrandCuts(state.strand_cuts, strands);
  }
  // Wetness for the renderer's optics: the strands of a wet master's wisp are wet (GrowWisps
  // writes the wisps master by master, each with the same number of strands).
  strands->wetness.clear();
  const size_t n = state.masters.models.size();
  if (state.wet && n > 0 && state.wet_masters.size() == n &&
      strands->point_counts.size() % n == 0) {
    const size_t per_wisp = strands->point_counts.size() / n;
    strands->wetness.resize(strands->point_counts.size());
    for (size_t k = 0; k < strands->wetness.size(); ++k) {
      strands->wetness[k] = state.wet_masters[k / per_wisp] ? 1.0f : 0.0f;
    }
  }
  return true;
}

}  // namespace ringlet
