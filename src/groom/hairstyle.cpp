// From a hairstyle to a head of hair: roots, master models, parallel solve, wisps (section 3).
#include "ringlet/hairstyle.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <numbers>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "ringlet/helix.h"
#include "ringlet/strand_geometry.h"

namespace ringlet {
namespace {

bool Fail(std::string* why, const std::string& message) {
  if (why) *why = message;
  return false;
}

// BatchOptions::cancel was set: SolveStrands skipped strands, so nothing after it may run.
bool Cancelled(const BatchOptions& batch) {
  return batch.cancel && batch.cancel->load(std::memory_order_relaxed);
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

namespace {

// L(phi) through (0, front), (pi/2, side), (pi, back): a1 = (f - b) / 2, a0 + a2 = (f + b) / 2,
// a0 - a2 = s.
double AzimuthLength(const Hairstyle& style, double azimuth) {
  const double f = style.length_front, s = style.length_side, b = style.length_back;
  const double a1 = 0.5 * (f - b);
  const double a0 = 0.25 * (f + b) + 0.5 * s;
  const double a2 = 0.25 * (f + b) - 0.5 * s;
  return a0 + a1 * std::cos(azimuth) + a2 * std::cos(2.0 * azimuth);
}

}  // namespace

double RegionalLength(const Hairstyle& style, double azimuth, double polar_angle) {
  if (!style.regional_length) return style.length;
  const double around = AzimuthLength(style, azimuth);
  if (!(style.length_crown > 0.0)) return around;
  const double w = std::clamp(polar_angle / style.crown_polar_angle, 0.0, 1.0);
  return style.length_crown + (around - style.length_crown) * w;
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
  if (regional_length) {
    for (const auto& [name, value] : {std::pair{"front", length_front},
                                      std::pair{"side", length_side},
                                      std::pair{"back", length_back}}) {
      if (!(std::isfinite(value) && value > 0.0 && value <= 10.0)) {
        return Fail(why, std::string("hair.length.") + name +
                             ": expected a finite number in (0, 10] (m)");
      }
    }
    if (length_crown != 0.0 && !(std::isfinite(length_crown) && length_crown > 0.0 &&
                                 length_crown <= 10.0)) {
      return Fail(why, "hair.length.crown: expected a finite number in (0, 10] (m)");
    }
    if (!(crown_polar_angle > 0.0 && crown_polar_angle < std::numbers::pi)) {
      return Fail(why, "scalp.hairline_front: expected an angle in (0, pi) (rad)");
    }
    // The cosine curve may dip below its values at 0, pi/2, pi: checked on a fine grid.
    for (int k = 0; k <= 720; ++k) {
      if (!(AzimuthLength(*this, std::numbers::pi * k / 720.0) > 0.0)) {
        return Fail(why, "hair.length: the regional length curve through front, side and back "
                         "falls to 0 or below between them; bring the three values closer");
      }
    }
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
  // Limits on the products that drive work and memory (docs/robustness.md), from the requested
  // master count (an upper bound of the masters placed), before any root is sampled; with
  // explicit masters, from the file's masters and their segments.
  double masters = roots.count;
  double total_segments = masters * segments;
  if (explicit_masters) {
    const std::vector<ExplicitMaster>& given = explicit_masters->masters;
    if (given.empty()) return Fail(why, "masters.file: expected at least one master");
    masters = static_cast<double>(given.size());
    total_segments = 0.0;
    for (size_t i = 0; i < given.size(); ++i) {
      const int n = static_cast<int>(given[i].segment_lengths.size());
      total_segments += n;
      if (!CheckMethodSegments(n, solver.method, &reason)) {
        return Fail(why, "masters.file: master " + std::to_string(i) + ": " + reason +
                             " (solver.method)");
      }
    }
  } else if (!CheckMethodSegments(segments, solver.method, &reason)) {
    return Fail(why, "masters.segments: " + reason + " (solver.method)");
  }
  const double solved_per_master = solve_children ? 1.0 + wisps.strands_per_wisp : 1.0;
  const double solved_segments = solved_per_master * total_segments;
  if (solved_segments > static_cast<double>(kMaxTotalSegments)) {
    return Fail(why, std::string(solve_children ? "masters.count x (1 + wisps.strands_per_wisp)"
                                                : "masters.count") +
                         " x masters.segments = " + std::to_string(static_cast<long long>(
                                                        solved_segments)) +
                         " segments to solve, more than the limit of " +
                         std::to_string(kMaxTotalSegments));
  }
  const double points = masters * wisps.strands_per_wisp * wisps.points_per_strand;
  if (points > static_cast<double>(kMaxHairPoints)) {
    return Fail(why, "masters.count x wisps.strands_per_wisp x wisps.points_per_strand = " +
                         std::to_string(static_cast<long long>(points)) +
                         " points, more than the limit of 2^28 = " +
                         std::to_string(kMaxHairPoints));
  }
  return true;
}

namespace {

// The head frame of a scalp (sphere or mesh).
const HeadFrame& ScalpHead(const Hairstyle& style) {
  return std::visit([](const auto& s) -> const HeadFrame& { return s.head; }, style.scalp);
}

// The wisp thickness r_w of a master (section 3.1) from its strand count and the curliness of its
// natural (gravity-free) shape, sqrt((L/d)^2 - 1) with d its end-to-end distance: tan(alpha) for
// a helix of whole turns, and ~0 for the nearly straight planar arcs of straight hair, which
// HelixCurliness (kappa/|tau|) would count as infinitely curly.
double MasterWispRadius(const Hairstyle& style, const StrandModel& m) {
  if (style.wisps.wisp_radius > 0.0) return style.wisps.wisp_radius;
  return WispRadius(style.wisps.strands_per_wisp, m.section.MeanRadius(),
                    Curliness(SampleFramedCentreline(m, m.NaturalCurvatures(), 1)),
                    style.wisps.packing_fraction);
}

// BuildMasters for explicit masters: the file's models, with what they leave out taken as for a
// sampled master of the same index.
bool BuildExplicitMasters(const Hairstyle& style, HairstyleMasters* out, std::string* why) {
  const std::vector<ExplicitMaster>& given = style.explicit_masters->masters;
  const int n = static_cast<int>(given.size());
  const HeadFrame& head = ScalpHead(style);
  out->roots.resize(n);
  out->models.resize(n);
  out->layers.resize(n);
  out->wisp_radii.resize(n);
  out->contact_radii.resize(n);
  out->start_curvatures.resize(n);
  double max_polar = 0.0;
  for (int i = 0; i < n; ++i) {
    Root& root = out->roots[i];
    root.position = given[i].root_position;
    root.frame = given[i].root_frame;
    const Vec3 outward = root.position - head.centre;
    root.normal = outward.norm() > 0.0 ? Vec3(outward.normalized()) : root.frame.col(2);
    root.head = ComputeHeadCoordinates(head, root.position);
    max_polar = std::max(max_polar, root.head.polar_angle);
  }
  double radius_sum = 0.0;
  std::string reason;
  for (int i = 0; i < n; ++i) {
    const ExplicitMaster& e = given[i];
    const std::string name = "masters.file: master " + std::to_string(i) + ": ";
    const StrandParameters p = SampleStrand(style.hair_type, style.seed, static_cast<uint64_t>(i));
    StrandModel& m = out->models[i];
    m.section = e.section ? *e.section : p.section;
    m.material = e.material ? *e.material : p.material;
    if (e.natural_curvature) {
      m.natural_curvature = *e.natural_curvature;
    } else {
      m.natural_curvature = p.natural_curvature;
      m.natural_curvature.x() = CurlStartSign(style.comb) * std::abs(m.natural_curvature.x());
    }
    m.root_position = e.root_position;
    m.root_frame = e.root_frame;
    m.gravity = style.gravity;
    m.segment_lengths = e.segment_lengths;
    // The wisp thickness from the natural curl (not the rest shape, which for an inverted master
    // is bent against gravity and contact: the look of the wisp is the hair type's).
    const double r_w = e.wisp_radius ? *e.wisp_radius : MasterWispRadius(style, m);
    m.rest_curvatures = e.rest_curvatures;
    if (e.layer && (*e.layer < 0 || *e.layer >= style.layers.count)) {
      return Fail(why, name + "layer: expected 0 to layers.count - 1 = " +
                           std::to_string(style.layers.count - 1) + ", got " +
                           std::to_string(*e.layer));
    }
    out->layers[i] =
        e.layer ? *e.layer : HullLayerOf(style.layers, out->roots[i].head.polar_angle, max_polar);
    out->wisp_radii[i] = r_w;
    radius_sum += r_w;
    out->contact_radii[i] = e.clearance ? *e.clearance : r_w * std::max(1.0, style.wisps.tip_scale);
    m.contact.obstacle = style.body;
    m.contact.clearance = out->contact_radii[i] + out->layers[i] * style.layers.thickness;
    m.contact.stiffness = style.contact_stiffness;
    m.contact.samples_per_segment = style.contact_samples;
    m.contact.support_offsets = e.support_offsets;
    if (!e.support_offsets.empty() &&
        e.support_offsets.size() != static_cast<size_t>(m.NumSegments()) * style.contact_samples) {
      return Fail(why, name + "support_offsets: has " + std::to_string(e.support_offsets.size()) +
                           " entries, expected segments x contact samples = " +
                           std::to_string(m.NumSegments()) + " x " +
                           std::to_string(style.contact_samples));
    }
    if (!IsValid(m, &reason)) return Fail(why, name + reason);
    if (e.start_curvatures.size() != 0 && e.start_curvatures.size() != 3 * m.NumSegments()) {
      return Fail(why, name + "curvatures: expected one triple per segment");
    }
    out->start_curvatures[i] = e.start_curvatures;
  }
  // The spacing spread_roots compares the wisp radii with: the Poisson-disk radius that N roots
  // sampled on this scalp with roots.packing would have, sqrt(packing A / N) (scalp.h).
  RootSamplingSummary& summary = out->root_summary;
  summary.requested = summary.achieved = n;
  summary.area = std::visit([](const auto& s) { return ScalpArea(s); }, style.scalp);
  summary.disk_radius = std::sqrt(style.roots.packing * summary.area / n);
  summary.message = std::to_string(n) + " masters from " + style.explicit_masters->file;
  out->wisp_options = style.wisps;
  if (style.spread_roots && radius_sum > 0.0) {
    out->wisp_options.root_scale =
        std::max(style.wisps.root_scale, summary.disk_radius / (radius_sum / n));
  }
  return true;
}

}  // namespace

bool BuildMasters(const Hairstyle& style, HairstyleMasters* masters, std::string* why) {
  if (!style.IsValid(why)) return false;
  HairstyleMasters out;
  if (style.explicit_masters) {
    if (!BuildExplicitMasters(style, &out, why)) return false;
    *masters = std::move(out);
    return true;
  }
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
  out.contact_radii.resize(n);
  double radius_sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const Root& root = out.roots[i];
    const StrandParameters p = SampleStrand(style.hair_type, style.seed, static_cast<uint64_t>(i));
    StrandModel& m = out.models[i];
    m.section = p.section;
    m.material = p.material;
    // The comb frame has n2 pointing away from the scalp and dt/ds = kappa1 n1 x t = -kappa1 n2
    // (scalp.h): a negative kappa1^0 starts the curl away from the head, a positive one into it
    // (comb.curl_inward).
    m.natural_curvature = p.natural_curvature;
    m.natural_curvature.x() = CurlStartSign(style.comb) * std::abs(m.natural_curvature.x());
    m.root_position = root.position;
    m.root_frame = root.frame;
    m.gravity = style.gravity;
    const double length =
        RegionalLength(style, root.head.azimuth, root.head.polar_angle) * p.length_factor;
    m.segment_lengths = UniformSegments(length, style.segments);
    const double ratio =
        style.grading > 0.0 ? style.grading : RecommendedGradingRatio(m.GravityParameter());
    m.segment_lengths = GradedSegments(length, style.segments, ratio);

    // The wisp thickness (section 3.1): MasterWispRadius.
    const double r_w = MasterWispRadius(style, m);
    out.wisp_radii[i] = r_w;
    radius_sum += r_w;
    out.layers[i] = HullLayerOf(style.layers, root.head.polar_angle, max_polar);
    out.contact_radii[i] = r_w * std::max(1.0, style.wisps.tip_scale);
    m.contact.obstacle = style.body;
    m.contact.clearance = out.contact_radii[i] + out.layers[i] * style.layers.thickness;
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

WispOptions MasterWispOptions(const HairstyleMasters& masters, size_t i) {
  WispOptions o = masters.wisp_options;
  if (i < masters.clump_factors.size()) o.tip_scale *= masters.clump_factors[i];
  if (i < masters.frizz_amplitudes.size()) o.frizz_amplitude = masters.frizz_amplitudes[i];
  return o;
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
  // Per-master options only when a clump or frizz brush set some (bit for bit the same
  // otherwise).
  std::vector<WispOptions> per_master;
  if (!masters.clump_factors.empty() || !masters.frizz_amplitudes.empty()) {
    per_master.reserve(n);
    for (size_t i = 0; i < n; ++i) per_master.push_back(MasterWispOptions(masters, i));
  }
  std::string reason;
  HairCurves curves = GenerateWisps(centrelines, sections, masters.wisp_options, style.seed,
                                    style.body.get(), &reason, &masters.wisp_radii,
                                    per_master.empty() ? nullptr : &per_master);
  if (curves.NumStrands() == 0 && n > 0) return Fail(why, "wisps: " + reason);
  *strands = std::move(curves);
  return true;
}

bool RegrowWisps(const Hairstyle& style, const HairstyleMasters& masters,
                 const std::vector<StrandSolution>& solutions, const std::vector<int>& which,
                 HairCurves* strands, std::string* why) {
  const size_t n = masters.models.size();
  const WispOptions& options = masters.wisp_options;
  const size_t per_wisp = static_cast<size_t>(options.strands_per_wisp);
  const size_t points = static_cast<size_t>(options.points_per_strand);
  if (solutions.size() != n || masters.wisp_radii.size() != n) {
    return Fail(why, "solutions: expected one per master");
  }
  if (strands->point_counts.size() != n * per_wisp || strands->points.size() != n * per_wisp * points ||
      strands->widths.size() != strands->points.size() ||
      strands->major_axes.size() != strands->points.size()) {
    return Fail(why, "strands: expected the wisps of these masters (N strands of equal points)");
  }
  for (int i : which) {
    if (i < 0 || static_cast<size_t>(i) >= n) {
      return Fail(why, "which: " + std::to_string(i) + " is not a master index");
    }
  }
  // One wisp per master, into its own slice: AppendWisp on a scratch HairCurves, copied over.
  // The same calls as GenerateWisps' loop body (WriteWisp through AppendWisp).
  tbb::parallel_for(tbb::blocked_range<size_t>(0, which.size()),
                    [&](const tbb::blocked_range<size_t>& range) {
    HairCurves wisp;
    for (size_t k = range.begin(); k != range.end(); ++k) {
      const size_t i = static_cast<size_t>(which[k]);
      const FramedCentreline centreline = SampleFramedCentreline(
          masters.models[i], solutions[i].curvatures, style.master_points_per_segment);
      wisp.point_counts.clear();
      wisp.points.clear();
      wisp.widths.clear();
      wisp.major_axes.clear();
      AppendWisp(centreline, masters.models[i].section, masters.wisp_radii[i],
                 MasterWispOptions(masters, i), WispSeed(style.seed, i), style.body.get(), &wisp);
      std::copy(wisp.point_counts.begin(), wisp.point_counts.end(),
                strands->point_counts.begin() + i * per_wisp);
      const size_t at = i * per_wisp * points;
      std::copy(wisp.points.begin(), wisp.points.end(), strands->points.begin() + at);
      std::copy(wisp.widths.begin(), wisp.widths.end(), strands->widths.begin() + at);
      std::copy(wisp.major_axes.begin(), wisp.major_axes.end(), strands->major_axes.begin() + at);
    }
  });
  return true;
}

namespace {

// Points at arc lengths s_j (increasing, in [0, L]) of a solved strand, exactly on its helices,
// with the material n1 there.
void SampleAtArcLengths(const StrandModel& model, const VecX& curvatures,
                        const std::vector<double>& s, std::vector<Vec3>* points,
                        std::vector<Vec3>* axes) {
  points->clear();
  axes->clear();
  Mat3 q = model.root_frame;
  Vec3 r = model.root_position;
  double start = 0.0;
  size_t j = 0;
  const int n = model.NumSegments();
  for (int i = 0; i < n && j < s.size(); ++i) {
    const double l = model.segment_lengths[static_cast<size_t>(i)];
    const Vec3 omega = curvatures.segment<3>(3 * i);
    const bool last = i == n - 1;
    while (j < s.size() && (s[j] <= start + l || last)) {
      const double u = std::clamp(s[j] - start, 0.0, l);
      const HelixSegment part = EvaluateHelixSegment(omega, u);
      points->push_back(r + q * part.chord);
      axes->push_back((q * part.rotation).col(0));
      ++j;
    }
    const HelixSegment whole = EvaluateHelixSegment(omega, l);
    r += q * whole.chord;
    q = q * whole.rotation;
    start += l;
  }
}

}  // namespace

bool SolveChildren(const Hairstyle& style, const HairstyleMasters& masters,
                   const std::vector<StrandSolution>& solutions, const BatchOptions& batch,
                   HairCurves* strands, GroomSummary* summary, std::string* why) {
  const auto start = std::chrono::steady_clock::now();
  const size_t masters_count = masters.models.size();
  const int per_wisp = masters.wisp_options.strands_per_wisp;
  if (solutions.size() != masters_count ||
      strands->NumStrands() != static_cast<int>(masters_count) * per_wisp) {
    return Fail(why, "children: expected one solution per master and N strands per wisp");
  }
  // Offsets of each strand's first point.
  std::vector<size_t> first(static_cast<size_t>(strands->NumStrands()) + 1, 0);
  for (int k = 0; k < strands->NumStrands(); ++k) {
    first[static_cast<size_t>(k) + 1] = first[static_cast<size_t>(k)] + strands->point_counts[static_cast<size_t>(k)];
  }
  // One model per child (the master strand of a wisp, when included, stays the master), listed
  // by wisp.
  std::vector<StrandModel> models;
  std::vector<int> strand_of;
  std::vector<std::vector<int>> wisp_children(masters_count);
  for (size_t i = 0; i < masters_count; ++i) {
    const StrandModel& master = masters.models[i];
    const double ratio = master.segment_lengths.back() / master.segment_lengths.front();
    // A child is as long as the wisp made it, L_k = (L_k / L) L: not its drawn polyline, which
    // winds around a curly master and is up to 3x longer (the African head's outer fibres).
    const std::vector<double> fractions =
        WispLengthFractions(masters.wisp_options, WispSeed(style.seed, i));
    for (int c = 0; c < per_wisp; ++c) {
      if (c == 0 && masters.wisp_options.include_master) continue;
      const int k = static_cast<int>(i) * per_wisp + c;
      const size_t a = first[static_cast<size_t>(k)];
      const double length = master.Length() * fractions[static_cast<size_t>(c)];
      if (!(length > 0.0)) continue;  // a degenerate child keeps its procedural shape
      StrandModel m = master;
      m.root_position = strands->points[a].cast<double>();
      m.segment_lengths = GradedSegments(length, master.NumSegments(), ratio);
      m.contact.clearance = master.section.MeanRadius() +
                            masters.layers[i] * style.layers.thickness;
      wisp_children[i].push_back(static_cast<int>(models.size()));
      models.push_back(std::move(m));
      strand_of.push_back(k);
    }
  }
  // The method of each child. A child starts next to an equilibrium, where Newton with the exact
  // Hessian needs ~5 steps against ~30 for L-BFGS: 2.5x less CPU on the straight, wavy and curly
  // heads (loads 44-394), but 1.3x more on the light African strands (loads 6-25)
  // (docs/benchmarks.md, "Every strand a solved rod"). So with "auto" a child from load
  // kChildNewtonLoad on is solved by Newton; an explicit method is used as given.
  SolveOptions newton_options = style.solver;
  newton_options.method = Method::kNewton;
  auto options_of = [&](const StrandModel& m) -> const SolveOptions& {
    const bool newton =
        style.solver.method == Method::kAuto && m.GravityParameter() >= kChildNewtonLoad;
    return newton ? newton_options : style.solver;
  };
  // The warm start of each child: within its wisp, children are solved in order of their root's
  // distance to the master's root, each from the nearest strand of the wisp solved before it
  // (the master included), nearness being |root - root'|^2 + (L - L')^2. Against the master's
  // equilibrium for every child this saves a fifth of the Newton steps (wavy head: 5.85 -> 4.19
  // per child, 10.8 -> 7.2 energy evaluations; docs/benchmarks.md). A wisp is one sequential
  // chain and wisps run in parallel: the result does not depend on the thread count.
  std::vector<StrandSolution> children(models.size());
  std::mutex progress_mutex;
  int finished = 0;
  const int total = static_cast<int>(models.size());
  auto solve_wisp = [&](size_t i) {
    const StrandModel& master = masters.models[i];
    std::vector<int> order = wisp_children[i];
    auto root_distance = [&](int c) {
      return (models[static_cast<size_t>(c)].root_position - master.root_position).squaredNorm();
    };
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return root_distance(a) < root_distance(b); });
    auto nearness = [](const StrandModel& a, const StrandModel& b) {
      const double dl = a.Length() - b.Length();
      return (a.root_position - b.root_position).squaredNorm() + dl * dl;
    };
    for (size_t j = 0; j < order.size(); ++j) {
      if (Cancelled(batch)) return;  // the caller checks the flag after the loop
      const size_t c = static_cast<size_t>(order[j]);
      const VecX* warm = solutions[i].curvatures.size() > 0 ? &solutions[i].curvatures : nullptr;
      double best = nearness(models[c], master);
      for (size_t e = 0; e < j; ++e) {
        const size_t d = static_cast<size_t>(order[e]);
        const double n = nearness(models[c], models[d]);
        if (n < best && children[d].summary.Converged()) {  // never start from a failed solve
          best = n;
          warm = &children[d].curvatures;
        }
      }
      children[c] = SolveStrand(models[c], options_of(models[c]), warm);
      if (batch.progress) {
        std::lock_guard<std::mutex> lock(progress_mutex);
        batch.progress(++finished, total);
      }
    }
  };
  tbb::task_arena arena(batch.threads > 0 ? batch.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, masters_count, 1),
                      [&](const tbb::blocked_range<size_t>& r) {
                        for (size_t i = r.begin(); i != r.end(); ++i) solve_wisp(i);
                      });
  });
  if (Cancelled(batch)) return Fail(why, "cancelled");

  // Resample each solved child at its own point count, equally spaced in arc length.
  for (size_t c = 0; c < children.size(); ++c) {
    const StrandSolution& sol = children[c];
    ++summary->children_solved;
    summary->children_iterations += sol.summary.iterations;
    if (!sol.summary.Converged()) {
      ++summary->children_unconverged;
    } else if (sol.summary.stability_checked && !sol.summary.stable) {
      ++summary->children_unstable;
    }
    summary->children_max_penetration =
        std::max(summary->children_max_penetration, sol.summary.contact.max_penetration);
    const int k = strand_of[c];
    const size_t a = first[static_cast<size_t>(k)];
    const int count = static_cast<int>(strands->point_counts[static_cast<size_t>(k)]);
    const double length = models[c].Length();
    std::vector<double> s(static_cast<size_t>(count));
    for (int p = 0; p < count; ++p) s[static_cast<size_t>(p)] = length * p / (count - 1);
    std::vector<Vec3> points, axes;
    SampleAtArcLengths(models[c], sol.curvatures, s, &points, &axes);
    if (static_cast<int>(points.size()) != count) return Fail(why, "children: sampling failed");
    for (int p = 0; p < count; ++p) {
      strands->points[a + static_cast<size_t>(p)] = points[static_cast<size_t>(p)].cast<float>();
      if (!strands->major_axes.empty()) {
        strands->major_axes[a + static_cast<size_t>(p)] = axes[static_cast<size_t>(p)].cast<float>();
      }
    }
  }
  summary->children_seconds = SecondsSince(start);
  return true;
}

bool GroomHairstyle(const Hairstyle& style, const BatchOptions& batch, Groom* groom,
                    std::string* why) {
  Groom g;
  if (!BuildMasters(style, &g.masters, why)) return false;

  auto start = std::chrono::steady_clock::now();
  g.solutions = SolveStrands(g.masters.models, style.solver, batch,
                             g.masters.start_curvatures.empty() ? nullptr
                                                                : &g.masters.start_curvatures);
  g.summary.solve_seconds = SecondsSince(start);
  if (Cancelled(batch)) return Fail(why, "cancelled");

  start = std::chrono::steady_clock::now();
  if (!GrowWisps(style, g.masters, g.solutions, &g.strands, why)) return false;
  g.summary.wisp_seconds = SecondsSince(start);
  if (style.solve_children &&
      !SolveChildren(style, g.masters, g.solutions, batch, &g.strands, &g.summary, why)) {
    return false;
  }

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
