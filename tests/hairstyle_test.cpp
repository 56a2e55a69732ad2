// Full hairstyles (src/groom/hairstyle.cpp, paper section 3): the hull-layer rule, the master
// models built from a hairstyle, the groom (determinism across thread counts, counts,
// convergence, penetration of masters and children into the body) and the volume hull layers
// give to a head of hair; a single strand draped over the mannequin's head.
#include "ringlet/hairstyle.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "ringlet/body_json.h"
#include "ringlet/hairstyle_json.h"
#include "ringlet/contact.h"
#include "ringlet/strand_geometry.h"

namespace ringlet {
namespace {

std::string Examples() { return RINGLET_EXAMPLES_DIR; }

// The default sphere mannequin (examples/bodies/mannequin.json: head of radius 0.1 m at the
// origin, jaw, neck, chest, shoulders, arms, back), loaded once.
std::shared_ptr<const Body> Mannequin() {
  static const std::shared_ptr<const Body> body = [] {
    auto b = std::make_shared<Body>();
    std::string error;
    EXPECT_TRUE(LoadBody(Examples() + "/bodies/mannequin.json", b.get(), &error)) << error;
    return b;
  }();
  return body;
}

// A small hairstyle on the mannequin: `masters` wavy caucasian masters of 20 cm, 10 segments,
// 4 strands per wisp of 12 points, 4 hull layers of 3 mm. Solved in well under a second.
Hairstyle SmallStyle(int masters = 40) {
  Hairstyle style;
  style.body = Mannequin();
  style.scalp = SphereScalp{};  // head sphere of radius 0.1 m at the origin, default hairline
  style.roots.count = masters;
  style.roots.seed = 3;
  std::string why;
  EXPECT_TRUE(FindHairType("caucasian", "wavy", &style.hair_type, &why)) << why;
  style.length = 0.2;
  style.segments = 10;
  style.wisps.strands_per_wisp = 4;
  style.wisps.points_per_strand = 12;
  style.wisps.tip_scale = 0.5;
  style.layers = HullLayers{4, 0.003};
  style.seed = 7;
  return style;
}

HairstyleMasters MustBuild(const Hairstyle& style) {
  HairstyleMasters masters;
  std::string why;
  EXPECT_TRUE(BuildMasters(style, &masters, &why)) << why;
  return masters;
}

Groom MustGroom(const Hairstyle& style, int threads = 0) {
  Groom groom;
  BatchOptions batch;
  batch.threads = threads;
  std::string why;
  EXPECT_TRUE(GroomHairstyle(style, batch, &groom, &why)) << why;
  return groom;
}

// Bitwise equality of two arrays of trivially copyable values (0.0 and -0.0 differ, NaN equals
// itself): what "bit-identical" means.
template <typename T>
bool SameBits(const T* a, const T* b, size_t count) {
  return std::memcmp(a, b, count * sizeof(T)) == 0;
}

// The polar angle of p from the +z axis seen from the origin, computed independently of the
// scalp code: atan2(|p x z|, p . z) (no acos of a dot product).
double PolarAngleFromZ(const Vec3& p) { return std::atan2(p.cross(Vec3::UnitZ()).norm(), p.z()); }

// ---------------------------------------------------------------------------------------------
// HullLayerOf: l = min(count - 1, floor(count (1 - theta / theta_max))).

TEST(HullLayerOf, RuleAtChosenAngles) {
  const HullLayers four{4, 0.003};
  const double theta_max = 2.0;
  // theta = 0 (the crown): 4 (1 - 0) = 4 -> min(3, 4) = 3, the outermost layer.
  EXPECT_EQ(HullLayerOf(four, 0.0, theta_max), 3);
  // theta = 0.5: 4 (1 - 0.25) = 3 -> 3.
  EXPECT_EQ(HullLayerOf(four, 0.5, theta_max), 3);
  // theta = 0.6: 4 (1 - 0.3) = 2.8 -> 2.
  EXPECT_EQ(HullLayerOf(four, 0.6, theta_max), 2);
  // theta = 1.0: 4 (1 - 0.5) = 2 exactly -> 2.
  EXPECT_EQ(HullLayerOf(four, 1.0, theta_max), 2);
  // theta = 1.2: 4 (1 - 0.6) = 1.6 -> 1.
  EXPECT_EQ(HullLayerOf(four, 1.2, theta_max), 1);
  // theta = 1.5: 4 (1 - 0.75) = 1 exactly (all binary fractions) -> 1.
  EXPECT_EQ(HullLayerOf(four, 1.5, theta_max), 1);
  // theta = 1.6: 4 (1 - 0.8) = 0.8 -> 0.
  EXPECT_EQ(HullLayerOf(four, 1.6, theta_max), 0);
  // theta = theta_max (the lowest root): 0, the innermost layer, touching the bare body.
  EXPECT_EQ(HullLayerOf(four, theta_max, theta_max), 0);
  // Outside [0, theta_max] the ratio is clamped: below 0 -> 3, beyond theta_max -> 0.
  EXPECT_EQ(HullLayerOf(four, -0.1, theta_max), 3);
  EXPECT_EQ(HullLayerOf(four, 2.5, theta_max), 0);
  // Ten layers, theta_max = 1: theta = 0.25 gives 10 * 0.75 = 7.5 -> 7.
  EXPECT_EQ(HullLayerOf(HullLayers{10, 0.001}, 0.25, 1.0), 7);
  // Without a positive theta_max (every root at the crown) there is nothing to grade: 0.
  EXPECT_EQ(HullLayerOf(four, 0.0, 0.0), 0);
}

TEST(HullLayerOf, OneLayerIsAlwaysZero) {
  const HullLayers one{1, 0.003};
  for (double theta = 0.0; theta <= 2.0; theta += 0.125) {
    EXPECT_EQ(HullLayerOf(one, theta, 2.0), 0) << "theta " << theta;
  }
}

TEST(HullLayerOf, LayersIncreaseTowardTheCrown) {
  for (int count : {2, 3, 4, 7}) {
    const HullLayers layers{count, 0.002};
    int previous = count - 1;  // at the crown
    bool saw_zero = false, saw_top = false;
    // Sweep from the crown (theta = 0) to the lowest root (theta_max = 1.9 rad).
    for (int k = 0; k <= 190; ++k) {
      const double theta = 0.01 * k;
      const int layer = HullLayerOf(layers, theta, 1.9);
      EXPECT_GE(layer, 0);
      EXPECT_LE(layer, count - 1);
      EXPECT_LE(layer, previous) << "count " << count << ", theta " << theta;
      previous = layer;
      saw_zero = saw_zero || layer == 0;
      saw_top = saw_top || layer == count - 1;
    }
    EXPECT_TRUE(saw_zero && saw_top) << "count " << count << ": not every layer is used";
  }
}

// ---------------------------------------------------------------------------------------------
// BuildMasters.

TEST(BuildMasters, OneModelPerRootWithTheSampledStrand) {
  const Hairstyle style = SmallStyle(30);
  const HairstyleMasters m = MustBuild(style);
  ASSERT_EQ(m.roots.size(), 30u) << m.root_summary.message;
  ASSERT_EQ(m.models.size(), m.roots.size());
  ASSERT_EQ(m.layers.size(), m.roots.size());
  ASSERT_EQ(m.wisp_radii.size(), m.roots.size());
  for (size_t i = 0; i < m.models.size(); ++i) {
    SCOPED_TRACE("master " + std::to_string(i));
    const StrandModel& model = m.models[i];
    // Model i takes the parameters of strand i of the hair type with the hairstyle's seed.
    const StrandParameters p = SampleStrand(style.hair_type, style.seed, i);
    EXPECT_EQ(model.section.a, p.section.a);
    EXPECT_EQ(model.section.b, p.section.b);
    // ... with kappa1^0 made negative so that the curl starts away from the scalp (BuildMasters).
    EXPECT_EQ(model.natural_curvature,
              Vec3(-std::abs(p.natural_curvature.x()), p.natural_curvature.y(),
                   p.natural_curvature.z()));
    EXPECT_EQ(model.material.young_modulus, p.material.young_modulus);
    EXPECT_EQ(model.material.density, p.material.density);
    // The segment lengths sum to length * length_factor (a sum of 10 doubles: a few ulps).
    EXPECT_EQ(model.NumSegments(), style.segments);
    EXPECT_NEAR(model.Length(), style.length * p.length_factor, 1e-14);
    // "auto" grading: segments grow from root to tip.
    EXPECT_LE(model.segment_lengths.front(), model.segment_lengths.back());
    // The root's position and comb frame, unchanged.
    EXPECT_EQ(model.root_position, m.roots[i].position);
    EXPECT_EQ(model.root_frame, m.roots[i].frame);
    EXPECT_EQ(model.gravity, style.gravity);
    // Contact with the hairstyle's body, its stiffness (0 = default) and samples.
    EXPECT_EQ(model.contact.obstacle.get(), style.body.get());
    EXPECT_EQ(model.contact.stiffness, style.contact_stiffness);
    EXPECT_EQ(model.contact.samples_per_segment, style.contact_samples);
  }
}

TEST(BuildMasters, ClearanceIsWispRadiusPlusLayerOffset) {
  const Hairstyle style = SmallStyle(40);
  const HairstyleMasters m = MustBuild(style);
  ASSERT_EQ(m.models.size(), 40u);
  // The largest polar angle of the roots, from their positions (head centre at the origin, up
  // +z), not from Root::head.
  double theta_max = 0.0;
  for (const Root& r : m.roots) theta_max = std::max(theta_max, PolarAngleFromZ(r.position));
  std::vector<int> used(style.layers.count, 0);
  for (size_t i = 0; i < m.models.size(); ++i) {
    SCOPED_TRACE("master " + std::to_string(i));
    const StrandParameters p = SampleStrand(style.hair_type, style.seed, i);
    // r_w from the strand count, fibre radius and the curliness of the natural shape: the
    // end-to-end distance d of the gravity-free master, c = sqrt((L/d)^2 - 1) (wisp.h).
    const StrandGeometry natural = ComputeGeometry(m.models[i], m.models[i].NaturalCurvatures());
    const double length = m.models[i].Length();
    const double d = (natural.points.back() - natural.points.front()).norm();
    const double c = std::min(kMaxCurliness, std::sqrt(std::max(0.0, length * length / (d * d) - 1.0)));
    const double r_w =
        WispRadius(style.wisps.strands_per_wisp, p.section.MeanRadius(), c,
                   style.wisps.packing_fraction);
    EXPECT_DOUBLE_EQ(m.wisp_radii[i], r_w);
    // 4 fibres of ~35 um: r_w is a fraction of a millimetre.
    EXPECT_GT(r_w, 50e-6);
    EXPECT_LT(r_w, 1e-3);
    const int layer = HullLayerOf(style.layers, PolarAngleFromZ(m.roots[i].position), theta_max);
    EXPECT_EQ(m.layers[i], layer);
    ++used[layer];
    // tip_scale = 0.5 < 1: the clearance is r_w itself plus the layer offset.
    EXPECT_DOUBLE_EQ(m.models[i].contact.clearance,
                     r_w * std::max(1.0, style.wisps.tip_scale) + layer * style.layers.thickness);
  }
  // Anti-vacuity: the roots span the layers (crown and hairline both present).
  EXPECT_GT(used.front(), 0);
  EXPECT_GT(used.back(), 0);
}

TEST(BuildMasters, TipScaleAboveOneWidensTheClearance) {
  Hairstyle style = SmallStyle(20);
  style.wisps.tip_scale = 2.5;
  style.layers = HullLayers{1, 0.003};
  const HairstyleMasters m = MustBuild(style);
  ASSERT_FALSE(m.models.empty());
  for (size_t i = 0; i < m.models.size(); ++i) {
    EXPECT_EQ(m.layers[i], 0);
    // One layer: no offset; the wisp is widest at the tip, 2.5 r_w.
    EXPECT_DOUBLE_EQ(m.models[i].contact.clearance, 2.5 * m.wisp_radii[i]);
  }
}

TEST(BuildMasters, FixedWispRadiusIsUsed) {
  Hairstyle style = SmallStyle(20);
  style.wisps.wisp_radius = 0.002;
  const HairstyleMasters m = MustBuild(style);
  ASSERT_FALSE(m.models.empty());
  for (size_t i = 0; i < m.models.size(); ++i) {
    EXPECT_EQ(m.wisp_radii[i], 0.002);
    EXPECT_DOUBLE_EQ(m.models[i].contact.clearance, 0.002 + m.layers[i] * 0.003);
  }
}

TEST(BuildMasters, SpreadRootsRaisesTheRootScale) {
  Hairstyle style = SmallStyle(30);
  const HairstyleMasters spread = MustBuild(style);
  double mean_radius = 0.0;
  for (double r : spread.wisp_radii) mean_radius += r / spread.wisp_radii.size();
  // root_scale = max(wisps.root_scale, disk radius / mean r_w): 30 roots on ~0.1 m^2 are
  // centimetres apart, far more than r_w, so the disk radius wins.
  EXPECT_DOUBLE_EQ(spread.wisp_options.root_scale,
                   std::max(style.wisps.root_scale, spread.root_summary.disk_radius / mean_radius));
  EXPECT_GT(spread.wisp_options.root_scale, 10.0);
  style.spread_roots = false;
  EXPECT_EQ(MustBuild(style).wisp_options.root_scale, style.wisps.root_scale);
}

TEST(BuildMasters, DeterministicForASeed) {
  const Hairstyle style = SmallStyle(30);
  const HairstyleMasters a = MustBuild(style);
  const HairstyleMasters b = MustBuild(style);
  ASSERT_EQ(a.models.size(), b.models.size());
  for (size_t i = 0; i < a.models.size(); ++i) {
    EXPECT_EQ(a.roots[i].position, b.roots[i].position);
    EXPECT_EQ(a.models[i].root_frame, b.models[i].root_frame);
    EXPECT_EQ(a.models[i].segment_lengths, b.models[i].segment_lengths);
    EXPECT_EQ(a.models[i].natural_curvature, b.models[i].natural_curvature);
    EXPECT_EQ(a.models[i].contact.clearance, b.models[i].contact.clearance);
  }
  // Another root seed moves the roots.
  Hairstyle other = style;
  other.roots.seed = style.roots.seed + 1;
  const HairstyleMasters c = MustBuild(other);
  ASSERT_EQ(c.models.size(), a.models.size());
  int moved = 0;
  for (size_t i = 0; i < a.roots.size(); ++i) moved += a.roots[i].position != c.roots[i].position;
  EXPECT_EQ(moved, static_cast<int>(a.roots.size()));
}

TEST(BuildMasters, RejectsAnInvalidHairstyle) {
  HairstyleMasters m;
  std::string why;
  Hairstyle style = SmallStyle(10);
  style.body = nullptr;
  EXPECT_FALSE(BuildMasters(style, &m, &why));
  EXPECT_NE(why.find("body"), std::string::npos) << why;
  style = SmallStyle(10);
  style.layers.count = 0;
  EXPECT_FALSE(BuildMasters(style, &m, &why));
  EXPECT_NE(why.find("layers.count"), std::string::npos) << why;
  style = SmallStyle(10);
  style.grading = 0.5;
  EXPECT_FALSE(BuildMasters(style, &m, &why));
  EXPECT_NE(why.find("masters.grading"), std::string::npos) << why;
  EXPECT_TRUE(m.models.empty());
}

// ---------------------------------------------------------------------------------------------
// GroomHairstyle.

TEST(GroomHairstyle, BitIdenticalOnOneAndTwoThreads) {
  const Hairstyle style = SmallStyle(40);
  const Groom one = MustGroom(style, 1);
  const Groom two = MustGroom(style, 2);
  ASSERT_EQ(one.solutions.size(), two.solutions.size());
  for (size_t i = 0; i < one.solutions.size(); ++i) {
    const VecX& a = one.solutions[i].curvatures;
    const VecX& b = two.solutions[i].curvatures;
    ASSERT_EQ(a.size(), b.size());
    EXPECT_TRUE(SameBits(a.data(), b.data(), a.size())) << "master " << i;
    EXPECT_EQ(one.solutions[i].summary.iterations, two.solutions[i].summary.iterations);
  }
  ASSERT_EQ(one.strands.point_counts, two.strands.point_counts);
  ASSERT_EQ(one.strands.points.size(), two.strands.points.size());
  EXPECT_TRUE(
      SameBits(one.strands.points.data(), two.strands.points.data(), one.strands.points.size()));
  EXPECT_TRUE(
      SameBits(one.strands.widths.data(), two.strands.widths.data(), one.strands.widths.size()));
  EXPECT_EQ(one.summary.iterations, two.summary.iterations);
}

// BatchOptions::cancel set during the master solve (from the progress callback): the groom
// stops with why = "cancelled" and leaves *groom untouched (no wisps grown from skipped masters).
TEST(GroomHairstyle, CancelStopsWithCancelledAndLeavesTheGroomUntouched) {
  const Hairstyle style = SmallStyle(20);
  std::atomic<bool> cancel{false};
  BatchOptions batch;
  batch.threads = 1;
  batch.cancel = &cancel;
  batch.progress = [&cancel](int finished, int) {
    if (finished == 2) cancel.store(true);
  };
  Groom groom;
  groom.summary.masters = -7;  // a marker that must survive
  std::string why;
  EXPECT_FALSE(GroomHairstyle(style, batch, &groom, &why));
  EXPECT_EQ(why, "cancelled");
  EXPECT_EQ(groom.summary.masters, -7);
  EXPECT_TRUE(groom.strands.points.empty());
}

TEST(GroomHairstyle, CountsAndConvergence) {
  const Hairstyle style = SmallStyle(40);
  const Groom g = MustGroom(style);
  const int masters = static_cast<int>(g.masters.models.size());
  ASSERT_EQ(masters, 40) << g.masters.root_summary.message;
  EXPECT_EQ(g.summary.masters, masters);
  EXPECT_EQ(g.summary.strands, masters * style.wisps.strands_per_wisp);
  EXPECT_EQ(g.strands.NumStrands(), g.summary.strands);
  EXPECT_EQ(g.summary.points, g.summary.strands * style.wisps.points_per_strand);
  EXPECT_EQ(g.strands.NumPoints(), g.summary.points);
  EXPECT_EQ(g.summary.converged, masters);
  EXPECT_EQ(g.summary.unconverged, 0);
  EXPECT_EQ(g.summary.unstable, 0);  // every master certified stable (checked by default)
  long iterations = 0;
  for (const StrandSolution& s : g.solutions) {
    EXPECT_TRUE(s.summary.Converged()) << s.summary.message;
    EXPECT_LE(s.summary.residual, style.solver.tolerance);
    EXPECT_TRUE(s.summary.stability_checked);
    EXPECT_TRUE(s.summary.stable) << "min eigenvalue " << s.summary.min_eigenvalue;
    EXPECT_GT(s.summary.min_eigenvalue, 0.0);
    iterations += s.summary.iterations;
  }
  EXPECT_EQ(g.summary.iterations, iterations);
  EXPECT_GT(iterations, masters);  // anti-vacuity: the masters did move from the natural shape
}

// The penetration bound from DefaultContactStiffness (strand_model.h):
//   k = kContactLoadFactor |f| / (kContactPenetration L),
// so a normal load F per length compresses the clearance layer by F / k. Draped over a sphere of
// radius R a strand carries F ~ |f| (1 + L/R) (weight plus tension |f| L over curvature 1/R), so
// the depth into the layer is at most (1 + L/R) (kContactPenetration / kContactLoadFactor) L,
// and the depth into the body itself (the layer minus the clearance) is smaller still. R is the
// smallest sphere the hair can reach (the mannequin's jaw and neck, 0.055 m); a safety factor of
// 2 covers the concentrated load near the clamped root.
double PenetrationBound(double length, double smallest_radius) {
  return 2.0 * (1.0 + length / smallest_radius) * (kContactPenetration / kContactLoadFactor) *
         length;
}

// The deepest point of a solved strand into its clearance layer, max(0, clearance - d), over
// points at arc length >= from_arc_length (m), sampled 8 per segment. Near the root the strand
// necessarily starts inside its layer (the root is on the skin, d = 0, and a master of layer l
// has clearance r_w + l thickness): that is geometry, not compliance of the penalty, so the
// bound below only applies away from the root.
double DeepestIntoLayer(const StrandModel& model, const VecX& curvatures, const Body& body,
                        double from_arc_length) {
  const FramedCentreline c = SampleFramedCentreline(model, curvatures, 8);
  double deepest = 0.0;
  for (int j = 0; j < c.NumPoints(); ++j) {
    if (c.arc_lengths[j] < from_arc_length) continue;
    deepest =
        std::max(deepest, model.contact.clearance - body.SignedDistance(c.points[j], nullptr));
  }
  return deepest;
}

TEST(GroomHairstyle, MastersStayOutOfTheBody) {
  const Hairstyle style = SmallStyle(40);
  const Groom g = MustGroom(style);
  double longest = 0.0;
  for (const StrandModel& m : g.masters.models) longest = std::max(longest, m.Length());
  const double bound = PenetrationBound(longest, 0.055);
  // L = 0.2 m: 2 (1 + 3.6) 1e-4 0.2 ~ 0.19 mm.
  EXPECT_LT(bound, 0.25e-3);
  double deepest_body = 0.0, deepest_layer_away = 0.0;
  int in_contact = 0;
  for (size_t i = 0; i < g.solutions.size(); ++i) {
    const StrandModel& model = g.masters.models[i];
    const VecX& q = g.solutions[i].curvatures;
    in_contact += MeasureContact(model, q).samples_in_contact > 0;
    // Independently of the contact code: the body's distance at 8 points per segment.
    const std::vector<Vec3> points = SampleCentreline(model, q, 8);
    for (size_t j = 1; j < points.size(); ++j) {
      deepest_body = std::max(deepest_body, -style.body->SignedDistance(points[j], nullptr));
    }
    // Beyond the first 5 cm, where the clamped root no longer holds the strand in its layer:
    // reported, not bounded. Wavy masters press their curls into the head, a load that the
    // weight-based DefaultContactStiffness does not account for (measured: 0.36 mm, where the
    // bound for weight and tension is 0.23 mm); harmless while it stays inside the clearance,
    // which the body-penetration check below covers.
    deepest_layer_away =
        std::max(deepest_layer_away, DeepestIntoLayer(model, q, *style.body, 0.05));
  }
  std::printf(
      "masters: %d of %zu touch their layer; deepest into the body %.4g mm (summary "
      "%.4g mm), into the layer beyond 5 cm %.4g mm; bound %.4g mm\n",
      in_contact, g.solutions.size(), deepest_body * 1e3, g.summary.max_penetration * 1e3,
      deepest_layer_away * 1e3, bound * 1e3);
  EXPECT_GT(in_contact, 0);  // anti-vacuity: the masters do rest on the head
  EXPECT_LT(deepest_body, bound);
  EXPECT_LT(g.summary.max_penetration, bound);
}

TEST(GroomHairstyle, NoChildPointInsideTheBody) {
  const Hairstyle style = SmallStyle(40);
  const Groom g = MustGroom(style);
  // GrowWisps pushes every point closer than the fibre radius (~35 um) back out to it; points are
  // stored as floats (relative rounding 6e-8, 2e-8 m at 0.3 m), so 1 um is ample.
  const double tolerance = 1e-6;
  double deepest = -1.0;
  int near_surface = 0;
  for (const Vec3f& p : g.strands.points) {
    const double d = style.body->SignedDistance(p.cast<double>(), nullptr);
    deepest = std::max(deepest, -d);
    near_surface += d < 1e-3;
  }
  std::printf("children: deepest point %.4g mm below the surface; %d of %d points within 1 mm\n",
              deepest * 1e3, near_surface, g.strands.NumPoints());
  EXPECT_LE(deepest, tolerance);
  EXPECT_GT(near_surface, 0);  // anti-vacuity: the hair does lie on the body
}

// The effect the hull layers exist for (Lee & Ko 2001, the paper's section 3.1): hair rooted
// near the crown is kept further out, so the head of hair gets volume. Measured on the top half
// of the head (z > 0, where the hair rests on the skull), as the mean distance of the master
// points from the head centre and as the outer radius (their largest distance).
TEST(GroomHairstyle, LayersGiveVolume) {
  Hairstyle flat = SmallStyle(40);
  flat.layers = HullLayers{1, 0.003};
  Hairstyle layered = SmallStyle(40);
  layered.layers = HullLayers{4, 0.003};
  struct Volume {
    double mean = 0.0, outer = 0.0;
    int points = 0;
  };
  auto measure = [](const Groom& g) {
    Volume v;
    for (size_t i = 0; i < g.solutions.size(); ++i) {
      for (const Vec3& p : SampleCentreline(g.masters.models[i], g.solutions[i].curvatures, 4)) {
        if (p.z() <= 0.0) continue;
        v.mean += p.norm();
        v.outer = std::max(v.outer, p.norm());
        ++v.points;
      }
    }
    v.mean /= std::max(1, v.points);
    return v;
  };
  const Groom g_flat = MustGroom(flat);
  const Groom g_layered = MustGroom(layered);
  const Volume a = measure(g_flat), b = measure(g_layered);
  double mean_layer = 0.0;
  for (int l : g_layered.masters.layers)
    mean_layer += static_cast<double>(l) / g_layered.masters.layers.size();
  std::printf(
      "top half: 1 layer mean %.2f mm, outer %.2f mm (%d points, max penetration %.3g "
      "mm); 4 layers of 3 mm mean %.2f mm, outer %.2f mm (%d points, max penetration "
      "%.3g mm); mean layer %.2f\n",
      a.mean * 1e3, a.outer * 1e3, a.points, g_flat.summary.max_penetration * 1e3, b.mean * 1e3,
      b.outer * 1e3, b.points, g_layered.summary.max_penetration * 1e3, mean_layer);
  ASSERT_GT(a.points, 100);
  ASSERT_GT(b.points, 100);
  // The same roots and strands (layers change only the clearance), so the difference is the
  // layers' doing. Points resting on the head move out by their layer's offset, 3 mm per layer;
  // points standing off the head move less. Ask for at least one third of the mean offset.
  EXPECT_GT(b.mean - a.mean, mean_layer * 0.003 / 3.0);
  // The outermost hair (crown masters, layer 3) lies further out too.
  EXPECT_GT(b.outer, a.outer);
}

// comb.curl_inward: short wavy masters (13 cm: light, their weight cannot pull the wave down)
// keep their curl's sense at the root. Started away from the head (the default) the curl lifts
// them off the crown; started into it, it presses them onto the head. Measured: how far each
// master rises above its root, and the distance of its points from the head's surface.
TEST(GroomHairstyle, CurlInwardLaysShortWavyHairOnTheHead) {
  Hairstyle away = SmallStyle(60);
  away.length = 0.13;
  away.comb.tilt = 1.5;  // combed back, nearly along the scalp, as examples/hairstyles/wavy.json
  away.comb.direction = Vec3(0.0, -1.0, -0.3);
  away.comb.face_sweep = 1.5;
  Hairstyle inward = away;
  inward.comb.curl_inward = true;
  const HairstyleMasters built = MustBuild(inward);
  for (const StrandModel& m : built.models) ASSERT_GT(m.natural_curvature.x(), 0.0);
  for (const StrandModel& m : MustBuild(away).models) ASSERT_LT(m.natural_curvature.x(), 0.0);
  struct Shape {
    double rise = 0.0, height = 0.0;  // mean over masters: max z - root z; mean |p| - 0.1 (m)
    int rising = 0;                   // masters rising more than 2 cm above their root
  };
  auto measure = [](const Groom& g) {
    Shape s;
    int points = 0;
    for (size_t i = 0; i < g.solutions.size(); ++i) {
      const std::vector<Vec3> p =
          SampleCentreline(g.masters.models[i], g.solutions[i].curvatures, 4);
      double top = p[0].z();
      for (const Vec3& x : p) {
        top = std::max(top, x.z());
        s.height += x.norm() - 0.1;
        ++points;
      }
      s.rise += (top - p[0].z()) / static_cast<double>(g.solutions.size());
      if (top - p[0].z() > 0.02) ++s.rising;
    }
    s.height /= points;
    return s;
  };
  const Groom g_away = MustGroom(away), g_inward = MustGroom(inward);
  EXPECT_EQ(g_away.summary.unconverged + g_inward.summary.unconverged, 0);
  const Shape a = measure(g_away), b = measure(g_inward);
  std::printf("curl away: mean rise %.1f mm, %d of 60 masters rise > 2 cm, mean height above "
              "the head %.1f mm; curl inward: %.1f mm, %d, %.1f mm\n",
              a.rise * 1e3, a.rising, a.height * 1e3, b.rise * 1e3, b.rising, b.height * 1e3);
  ASSERT_GT(a.rising, 5);  // anti-vacuity: the default does lift short wavy hair
  EXPECT_LT(b.rise, 0.5 * a.rise);
  EXPECT_LT(b.rising, a.rising / 2);
  EXPECT_LT(b.height, a.height);
}

// The main job's head and its straight and bob cousins (examples/hairstyles): short, light
// strands at the top of the head stood up from it (issue 15's "flyaway curls at the crown"),
// because (1) the top of the head took the fringe's length (12-13 cm: w L^3 / E I of 5-11, too
// light for gravity to lay them down), (2) straight hair's small natural curvature started
// away from the head, and (3) wavy masters drew their curl radius from the whole population's
// spread (52 %: a tail of 1-2 cm curls among 4.4 cm waves). The files now give the crown its
// own length (hair.length.crown), start every curl into the head (comb.curl_inward) and give
// the wavy head one person's spread (hair.curl_spread 0.25). Measured: the masters with a point
// above the head's centre (ear level and up) more than 2.5 cm from the body, with the files as
// they are and with those three fields taken out (300 masters each, fewer than the files' 1000
// for time; the masters alone, wisps follow them).
TEST(GroomHairstyle, ExamplesLayTheTopOfTheHeadDown) {
  auto standing = [](const Hairstyle& style) {
    Hairstyle s = style;
    s.roots.count = 300;
    s.wisps.strands_per_wisp = 1;
    const Groom g = MustGroom(s);
    EXPECT_EQ(g.summary.unconverged, 0);
    const double centre_z = s.body->FindSphere("head") ? s.body->FindSphere("head")->center.z()
                                                       : 0.0;
    int count = 0;
    for (size_t i = 0; i < g.solutions.size(); ++i) {
      for (const Vec3& x :
           SampleCentreline(g.masters.models[i], g.solutions[i].curvatures, 4)) {
        if (x.z() > centre_z && s.body->SignedDistance(x, nullptr) > 0.025) {
          ++count;
          break;
        }
      }
    }
    return count;
  };
  for (const char* name : {"wavy", "straight", "bob"}) {
    Hairstyle style;
    std::string error;
    ASSERT_TRUE(LoadHairstyle(Examples() + "/hairstyles/" + name + ".json", &style, &error))
        << error;
    ASSERT_GT(style.length_crown, 0.0) << name;
    ASSERT_TRUE(style.comb.curl_inward || std::string(name) == "wavy") << name;
    Hairstyle before = style;
    before.length_crown = 0.0;
    before.comb.curl_inward = std::string(name) == "wavy";  // wavy.json had it already
    HairType type;
    ASSERT_TRUE(FindHairType(style.hair_type.origin, style.hair_type.curl, &type, &error));
    before.hair_type.curl_radius_std = type.curl_radius_std;
    const int now = standing(style), then = standing(before);
    std::printf("%s: %d of 300 masters stand more than 2.5 cm off the head above its centre "
                "(%d without the crown length, curl sense and spread)\n", name, now, then);
    EXPECT_LE(now, 6) << name;   // 2 %
    EXPECT_GE(then, 2 * now + 4) << name;  // the three fields do it
  }
}

TEST(GroomHairstyle, RejectsInvalidInputWithoutTouchingTheResult) {
  Hairstyle style = SmallStyle(10);
  style.wisps.strands_per_wisp = 0;
  Groom groom;
  groom.summary.masters = -7;  // a marker: must survive the failed call
  std::string why;
  EXPECT_FALSE(GroomHairstyle(style, BatchOptions{}, &groom, &why));
  EXPECT_NE(why.find("wisps"), std::string::npos) << why;
  EXPECT_EQ(groom.summary.masters, -7);
}

// ---------------------------------------------------------------------------------------------
// A single strand on the mannequin (examples/bodies/mannequin.json).

TEST(Mannequin, StrandOnTheHeadHangsDownAndDrapes) {
  const std::shared_ptr<const Body> body = Mannequin();
  const Sphere* head = body->FindSphere("head");
  ASSERT_NE(head, nullptr);
  // Root on the head sphere at 20 degrees from the crown, on the right side (+x), combed down
  // (tangent 1.2 rad from the normal, toward -z).
  const double theta = 20.0 * M_PI / 180.0;
  const Vec3 normal(std::sin(theta), 0.0, std::cos(theta));
  HeadFrame frame;
  frame.centre = head->center;
  const Vec3 root = head->center + head->radius * normal;
  HairType type;
  std::string why;
  ASSERT_TRUE(FindHairType("asian", "straight", &type, &why)) << why;
  StrandModel model;
  model.section = SectionFromEllipticity(type.mean_radius, type.ellipticity);
  model.material = type.material;
  model.root_position = root;
  model.root_frame = CombedRootFrame(root, normal, frame, CombOptions{});
  model.segment_lengths = GradedSegments(0.3, 15, 4.0);
  model.contact.obstacle = body;
  model.contact.clearance = 0.5e-3;
  ASSERT_TRUE(IsValid(model, &why)) << why;

  const StrandSolution s = SolveStrand(model, GroomSolveOptions());
  ASSERT_TRUE(s.summary.Converged()) << s.summary.message;
  const std::vector<Vec3> points = SampleCentreline(model, s.curvatures, 8);
  const Vec3& tip = points.back();
  // Hangs down: a 30 cm strand rooted 9.4 cm above the head centre ends well below the head
  // centre (the hair falls past the ear).
  EXPECT_LT(tip.z(), root.z() - 0.15);
  EXPECT_LT(tip.z(), head->center.z());
  // Drapes: it touches the head, yet no point enters the body beyond the penetration bound.
  const ContactMeasure c = MeasureContact(model, s.curvatures);
  EXPECT_GT(c.samples_in_contact, 0);
  const double bound = PenetrationBound(model.Length(), 0.055);
  double deepest = 0.0;
  for (size_t j = 1; j < points.size(); ++j) {
    deepest = std::max(deepest, -body->SignedDistance(points[j], nullptr));
  }
  const double deepest_layer = DeepestIntoLayer(model, s.curvatures, *body, 0.05);
  std::printf(
      "draped strand: tip at (%.1f, %.1f, %.1f) mm, %d samples in contact, deepest %.4g "
      "mm into the body, %.4g mm into the layer beyond 5 cm; bound %.4g mm\n",
      tip.x() * 1e3, tip.y() * 1e3, tip.z() * 1e3, c.samples_in_contact, deepest * 1e3,
      deepest_layer * 1e3, bound * 1e3);
  EXPECT_LT(deepest, bound);
  EXPECT_LT(deepest_layer, bound);
  // Without the body the same strand would hang through the head: its free shape enters it,
  // so the contact was doing the work (anti-vacuity).
  StrandModel free = model;
  free.contact.obstacle = nullptr;
  const StrandSolution f = SolveStrand(free, GroomSolveOptions());
  double free_deepest = 0.0;
  for (const Vec3& p : SampleCentreline(free, f.curvatures, 8)) {
    free_deepest = std::max(free_deepest, -body->SignedDistance(p, nullptr));
  }
  std::printf("the same strand without the body enters it by %.1f mm\n", free_deepest * 1e3);
  EXPECT_GT(free_deepest, 0.01);
}

}  // namespace
}  // namespace ringlet

namespace ringlet {
namespace {

// Every strand a solved rod (issue 11, Hairstyle::solve_children): each child is an equilibrium
// of its own (converged, certified stable, residual below tolerance when re-checked here by an
// independent solve from its result), keeps its root, is as long as the wisp made it (the
// master's length times the child's fraction, tested against AppendWisp in wisp_test), differs
// from the procedural child, and the groom is bit-identical on 1 and 2 threads.
TEST(GroomHairstyle, SolvedChildrenAreCertifiedEquilibria) {
  Hairstyle style = SmallStyle(12);
  const Groom procedural = MustGroom(style);
  style.solve_children = true;
  const Groom solved = MustGroom(style, 2);
  const GroomSummary& s = solved.summary;
  const int n = style.wisps.strands_per_wisp;
  EXPECT_EQ(s.children_solved, 12 * (n - 1));  // the master strand of each wisp stays
  EXPECT_EQ(s.children_unconverged, 0);
  EXPECT_EQ(s.children_unstable, 0);
  EXPECT_GT(s.children_iterations, 0);
  ASSERT_EQ(solved.strands.NumPoints(), procedural.strands.NumPoints());
  const int count = style.wisps.points_per_strand;
  double moved = 0.0;
  for (int k = 0; k < solved.strands.NumStrands(); ++k) {
    const size_t a = static_cast<size_t>(k) * count;
    // Same root; the rod's length is lp = L_master (L_k / L), so the chords inscribed in it are
    // never longer than lp and, on these wavy curls, shorter by a few %.
    EXPECT_EQ(solved.strands.points[a], procedural.strands.points[a]);
    const int wisp = k / n, child = k % n;
    const std::vector<double> fractions = WispLengthFractions(
        procedural.masters.wisp_options, WispSeed(style.seed, static_cast<std::uint64_t>(wisp)));
    const double lp = procedural.masters.models[static_cast<size_t>(wisp)].Length() *
                      fractions[static_cast<size_t>(child)];
    double ls = 0.0;
    for (int p = 1; p < count; ++p) {
      ls += (solved.strands.points[a + p] - solved.strands.points[a + p - 1]).norm();
      moved = std::max<double>(
          moved, (solved.strands.points[a + p] - procedural.strands.points[a + p]).norm());
    }
    EXPECT_LE(ls, lp * (1.0 + 1e-6)) << "strand " << k;
    EXPECT_GE(ls, 0.97 * lp) << "strand " << k;
  }
  EXPECT_GT(moved, 1e-4);  // not vacuous: the solved children are not the procedural ones
  const Groom one_thread = MustGroom(style, 1);
  EXPECT_TRUE(SameBits(one_thread.strands.points.data(), solved.strands.points.data(),
                       solved.strands.points.size()));
  EXPECT_TRUE(SameBits(one_thread.strands.major_axes.data(), solved.strands.major_axes.data(),
                       solved.strands.major_axes.size()));
}

}  // namespace
}  // namespace ringlet
