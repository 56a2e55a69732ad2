// From a hairstyle to a head of hair: roots, master models, parallel solve, wisps (section 3).
#include "ringlet/hairstyle.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "ringlet/strand_geometry.h"

namespace ringlet {
namespace {

bool Fail(std::string* why, const std::string& message) {
  if (why) *why = message;
  return false;
}

double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

SolveOptions GroomSolveOptions() {
  SolveOptions options;
  options.tolerance = 1e-6;
  options.check_stability = true;
  return options;
}

int HullLayerOf(const HullLayers& layers, double polar_angle, double max_polar_angle) {
  if (layers.count <= 1 || !(max_polar_angle > 0.0)) return 0;
  const double depth = 1.0 - std::clamp(polar_angle / max_polar_angle, 0.0, 1.0);
  return std::min(layers.count - 1, static_cast<int>(std::floor(layers.count * depth)));
}

bool Hairstyle::IsValid(std::string* why) const {
  std::string reason;
  if (!body) return Fail(why, "body: required");
  const bool scalp_ok = std::visit([&](const auto& s) { return ringlet::IsValid(s, &reason); }, scalp);
  if (!scalp_ok) return Fail(why, "scalp: " + reason);
  if (!ringlet::IsValid(roots, &reason)) return Fail(why, "masters: " + reason);
  if (!ringlet::IsValid(comb, &reason)) return Fail(why, "comb: " + reason);
  if (!ringlet::IsValid(hair_type, &reason)) return Fail(why, "hair: " + reason);
  if (!(std::isfinite(length) && length > 0.0)) {
    return Fail(why, "hair.length: expected a finite number > 0 (m)");
  }
  if (segments < 1 || segments > kMaxSegments) {
    return Fail(why, "masters.segments: expected 1 to " + std::to_string(kMaxSegments));
  }
  if (!(grading == 0.0 || (std::isfinite(grading) && grading >= 1.0))) {
    return Fail(why, "masters.grading: expected \"auto\" or a ratio >= 1");
  }
  if (!(std::isfinite(contact_stiffness) && contact_stiffness >= 0.0)) {
    return Fail(why, "contact.stiffness: expected a finite number >= 0 (N/m^2; 0 = default)");
  }
  if (contact_samples < 1 || contact_samples > 64) {
    return Fail(why, "contact.samples_per_segment: expected 1 to 64");
  }
  if (layers.count < 1 || layers.count > 64) return Fail(why, "layers.count: expected 1 to 64");
  if (!(std::isfinite(layers.thickness) && layers.thickness >= 0.0 && layers.thickness < 0.1)) {
    return Fail(why, "layers.thickness: expected a finite number in [0, 0.1) (m)");
  }
  if (!wisps.IsValid(&reason)) return Fail(why, "wisps: " + reason);
  if (master_points_per_segment < 1 || master_points_per_segment > 64) {
    return Fail(why, "masters.points_per_segment: expected 1 to 64");
  }
  if (!solver.IsValid(&reason)) return Fail(why, "solver: " + reason);
  if (!gravity.allFinite()) return Fail(why, "gravity: expected 3 finite numbers (m/s^2)");
  return true;
}

bool BuildMasters(const Hairstyle& style, HairstyleMasters* masters, std::string* why) {
  if (!style.IsValid(why)) return false;
  HairstyleMasters out;
  std::string reason;
  const bool sampled = std::visit(
      [&](const auto& s) {
        return SampleRoots(s, style.roots, style.comb, &out.roots, &out.root_summary, &reason);
      },
      style.scalp);
  if (!sampled) return Fail(why, "scalp: " + reason);
  if (out.roots.empty()) return Fail(why, "scalp: no root could be placed on it");

  double max_polar = 0.0;
  for (const Root& r : out.roots) max_polar = std::max(max_polar, r.head.polar_angle);

  const int n = static_cast<int>(out.roots.size());
  out.models.resize(n);
  out.layers.resize(n);
  out.wisp_radii.resize(n);
  double radius_sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const Root& root = out.roots[i];
    const StrandParameters p = SampleStrand(style.hair_type, style.seed, static_cast<uint64_t>(i));
    StrandModel& m = out.models[i];
    m.section = p.section;
    m.material = p.material;
    // The comb frame has n2 pointing away from the scalp and dt/ds = kappa1 n1 x t = -kappa1 n2
    // (scalp.h): a negative kappa1^0 starts the curl away from the head instead of into it.
    m.natural_curvature = p.natural_curvature;
    m.natural_curvature.x() = -std::abs(m.natural_curvature.x());
    m.root_position = root.position;
    m.root_frame = root.frame;
    m.gravity = style.gravity;
    const double length = style.length * p.length_factor;
    m.segment_lengths = UniformSegments(length, style.segments);
    const double ratio =
        style.grading > 0.0 ? style.grading : RecommendedGradingRatio(m.GravityParameter());
    m.segment_lengths = GradedSegments(length, style.segments, ratio);

    // The wisp thickness (section 3.1) from its strand count and the curliness of the natural
    // (gravity-free) shape, sqrt((L/d)^2 - 1) with d its end-to-end distance: tan(alpha) for a
    // helix of whole turns, and ~0 for the nearly straight planar arcs of straight hair, which
    // HelixCurliness (kappa/|tau|) would count as infinitely curly.
    const double r_w =
        style.wisps.wisp_radius > 0.0
            ? style.wisps.wisp_radius
            : WispRadius(style.wisps.strands_per_wisp, p.section.MeanRadius(),
                         Curliness(SampleFramedCentreline(m, m.NaturalCurvatures(), 1)),
                         style.wisps.packing_fraction);
    out.wisp_radii[i] = r_w;
    radius_sum += r_w;
    out.layers[i] = HullLayerOf(style.layers, root.head.polar_angle, max_polar);
    m.contact.obstacle = style.body;
    m.contact.clearance = r_w * std::max(1.0, style.wisps.tip_scale) +
                          out.layers[i] * style.layers.thickness;
    m.contact.stiffness = style.contact_stiffness;
    m.contact.samples_per_segment = style.contact_samples;
    if (!IsValid(m, &reason)) {
      return Fail(why, "master " + std::to_string(i) + ": " + reason);
    }
  }
  out.wisp_options = style.wisps;
  if (style.spread_roots && radius_sum > 0.0) {
    out.wisp_options.root_scale = std::max(
        style.wisps.root_scale, out.root_summary.disk_radius / (radius_sum / n));
  }
  *masters = std::move(out);
  return true;
}

bool GrowWisps(const Hairstyle& style, const HairstyleMasters& masters,
               const std::vector<StrandSolution>& solutions, HairCurves* strands,
               std::string* why) {
  const size_t n = masters.models.size();
  if (solutions.size() != n) return Fail(why, "solutions: expected one per master");
  std::vector<FramedCentreline> centrelines(n);
  std::vector<CrossSection> sections(n);
  for (size_t i = 0; i < n; ++i) {
    centrelines[i] = SampleFramedCentreline(masters.models[i], solutions[i].curvatures,
                                            style.master_points_per_segment);
    sections[i] = masters.models[i].section;
  }
  std::string reason;
  HairCurves curves = GenerateWisps(centrelines, sections, masters.wisp_options, style.seed,
                                    style.body.get(), &reason, &masters.wisp_radii);
  if (curves.NumStrands() == 0 && n > 0) return Fail(why, "wisps: " + reason);
  *strands = std::move(curves);
  return true;
}

bool GroomHairstyle(const Hairstyle& style, const BatchOptions& batch, Groom* groom,
                    std::string* why) {
  Groom g;
  if (!BuildMasters(style, &g.masters, why)) return false;

  auto start = std::chrono::steady_clock::now();
  g.solutions = SolveStrands(g.masters.models, style.solver, batch);
  g.summary.solve_seconds = SecondsSince(start);

  start = std::chrono::steady_clock::now();
  if (!GrowWisps(style, g.masters, g.solutions, &g.strands, why)) return false;
  g.summary.wisp_seconds = SecondsSince(start);

  GroomSummary& s = g.summary;
  s.masters = static_cast<int>(g.solutions.size());
  s.strands = g.strands.NumStrands();
  s.points = g.strands.NumPoints();
  for (const StrandSolution& sol : g.solutions) {
    s.iterations += sol.summary.iterations;
    if (sol.summary.Converged()) {
      ++s.converged;
      if (sol.summary.stability_checked && !sol.summary.stable) ++s.unstable;
    } else {
      ++s.unconverged;
    }
    s.max_penetration = std::max(s.max_penetration, sol.summary.contact.max_penetration);
  }
  *groom = std::move(g);
  return true;
}

}  // namespace ringlet
