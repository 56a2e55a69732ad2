// Wisps: child strands in a generalized cylinder around a master (include/ringlet/wisp.h).
// Each expected number is derived in the comment above its check.
#include "ringlet/wisp.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <numbers>

#include "ringlet/strand_geometry.h"
#include "test_util.h"

namespace ringlet {
namespace {

constexpr double kFibreRadius = 50e-6;  // m (testing::MakeStrand)

// Root frame with the tangent pointing down (-z): n1 = +x, n2 = -y, so n1 x n2 = -z = t.
Mat3 DownFrame() {
  Mat3 q;
  q.col(0) = Vec3(1, 0, 0);
  q.col(1) = Vec3(0, -1, 0);
  q.col(2) = Vec3(0, 0, -1);
  return q;
}

// A master in its natural shape (a helix, or a straight line for natural = 0), n segments of
// k samples each: n k + 1 samples.
FramedCentreline Master(double length, int segments, int k, const Vec3& natural,
                        const Mat3& frame = DownFrame(), const Vec3& root = Vec3::Zero()) {
  StrandModel m = testing::MakeStrand(length, segments, 0.0, natural, frame);
  m.root_position = root;
  return SampleFramedCentreline(m, m.NaturalCurvatures(), k);
}

// Linear interpolation of the master's points at arc length s (the reference the children are
// built on; the test's own walk over the samples).
Vec3 MasterAt(const FramedCentreline& c, double s) {
  int j = 0;
  while (j < c.NumPoints() - 2 && c.arc_lengths[j + 1] < s) ++j;
  const double t = std::clamp((s - c.arc_lengths[j]) / (c.arc_lengths[j + 1] - c.arc_lengths[j]),
                              0.0, 1.0);
  return (1.0 - t) * c.points[j] + t * c.points[j + 1];
}

Vec3 Point(const HairCurves& h, int strand, int j, int m) {
  return h.points[static_cast<size_t>(strand) * m + j].cast<double>();
}

// A small sphere obstacle: d(x) = |x - c| - R, gradient (x - c)/|x - c| (exact, 1-Lipschitz).
class Sphere : public Obstacle {
 public:
  Sphere(const Vec3& centre, double radius) : centre_(centre), radius_(radius) {}
  double SignedDistance(const Vec3& x, Vec3* gradient) const override {
    const Vec3 d = x - centre_;
    const double norm = d.norm();
    if (gradient != nullptr) *gradient = norm > 0.0 ? Vec3(d / norm) : Vec3(1, 0, 0);
    return norm - radius_;
  }

 private:
  Vec3 centre_;
  double radius_;
};

// Float output: a coordinate of size <= 0.3 m is rounded to within 0.3 * 2^-24 = 1.8e-8 m.
constexpr double kFloatTolerance = 5e-8;  // m

TEST(WispRadius, Limits) {
  const double r = kFibreRadius;
  // One strand: the wisp is the fibre itself, r_w = r for any curliness and packing.
  EXPECT_EQ(WispRadius(1, r, 0.0), r);
  EXPECT_EQ(WispRadius(1, r, 5.0, 0.5), r);
  // N disks cannot be enclosed in a circle smaller than the optimal packing's: radii (in units
  // of r) 2, 1 + 2/sqrt(3), 1 + sqrt(2), 1 + sqrt(2 (1 + 1/sqrt(5))), 3, 3 for N = 2..7
  // (Graham, Lubachevsky et al., "Dense packings of congruent circles in a circle", Discrete
  // Math. 181 (1998), table 1). A random packing model must stay above them, for any phi <= 1.
  const double optimal[8] = {0, 1, 2, 1 + 2 / std::sqrt(3.0), 1 + std::sqrt(2.0),
                             1 + std::sqrt(2 * (1 + 1 / std::sqrt(5.0))), 3, 3};
  for (double phi : {kRandomPackingFraction2D, std::numbers::pi / (2 * std::sqrt(3.0)), 1.0}) {
    for (int n = 2; n <= 7; ++n) EXPECT_GE(WispRadius(n, r, 0.0, phi), optimal[n] * r) << n;
  }
  // Many strands: r_w -> r sqrt(N / phi); the ratio is 1 + sqrt(phi / N) + O(1/N) = 1.000906
  // for N = 10^6, phi = 0.82.
  const double big = WispRadius(1000000, r, 0.0);
  EXPECT_NEAR(big / (r * std::sqrt(1e6 / kRandomPackingFraction2D)),
              1.0 + std::sqrt(kRandomPackingFraction2D / 1e6), 1e-6);
  // Curliness c = tan(alpha) = 3/4: sec(alpha) = 5/4, so the packing term grows by sqrt(5/4).
  EXPECT_NEAR((WispRadius(100, r, 0.75) - r) / (WispRadius(100, r, 0.0) - r), std::sqrt(1.25),
              1e-14);
  // 100 straight fibres of 50 um: 50e-6 (1 + sqrt(99 / 0.82)) = 599.4 um.
  EXPECT_NEAR(WispRadius(100, r, 0.0), 50e-6 * (1 + std::sqrt(99 / 0.82)), 1e-15);
}

TEST(Curliness, HelixOfWholeTurns) {
  // Natural helix kappa = 60, tau = 20 1/m: tan(alpha) = kappa / tau = 3. Over exactly 3 turns
  // (length 3 * 2 pi / |Omega|) the end-to-end distance is the axial advance L |tau| / |Omega|,
  // so sqrt((L/d)^2 - 1) = kappa / tau = 3 as well.
  const Vec3 natural(60.0, 0.0, 20.0);
  EXPECT_NEAR(HelixCurliness(natural), 3.0, 1e-15);
  const double length = 3 * 2 * std::numbers::pi / natural.norm();
  const FramedCentreline helix = Master(length, 30, 4, natural);
  EXPECT_NEAR(Curliness(helix), 3.0, 1e-9);
  // Same helix with kappa split over both axes: the curliness depends on |kappa| only.
  EXPECT_NEAR(HelixCurliness(Vec3(36.0, -48.0, -20.0)), 3.0, 1e-15);
  // Straight: 0. Planar curl (tau = 0) and a closed circle: the cap.
  EXPECT_EQ(HelixCurliness(Vec3::Zero()), 0.0);
  EXPECT_NEAR(Curliness(Master(0.1, 5, 2, Vec3::Zero())), 0.0, 1e-6);
  EXPECT_EQ(HelixCurliness(Vec3(50.0, 0.0, 0.0)), kMaxCurliness);
  EXPECT_EQ(Curliness(Master(2 * std::numbers::pi / 50.0, 20, 2, Vec3(50.0, 0.0, 0.0))),
            kMaxCurliness);
}

TEST(Wisp, ChildrenStayInTheGeneralizedCylinder) {
  const FramedCentreline master = Master(0.2, 20, 4, Vec3(60.0, 0.0, 15.0));
  WispOptions o;
  o.strands_per_wisp = 300;
  o.points_per_strand = 57;
  o.length_variation = 0.0;  // so that child sample j is at s = j L / (m - 1)
  o.root_scale = 1.3;
  o.tip_scale = 0.4;
  o.profile_exponent = 0.7;
  o.jitter = 2e-4;
  o.frizz_amplitude = 1e-4;
  o.frizz_frequency = 80.0;
  o.tip_taper = 0.0;  // constant widths here (the taper has its own tests)
  const CrossSection section = SectionFromEccentricity(kFibreRadius, 0.0);
  const double rw = ResolveWispRadius(master, section, o);
  // Automatic radius: WispRadius(300, 50 um, Curliness(master)), several hundred um.
  EXPECT_EQ(rw, WispRadius(300, kFibreRadius, Curliness(master)));
  EXPECT_GT(rw, 5e-4);
  HairCurves h;
  AppendWisp(master, section, rw, o, 42, nullptr, &h);
  ASSERT_EQ(h.NumStrands(), 300);
  ASSERT_EQ(h.NumPoints(), 300 * 57);
  ASSERT_EQ(h.widths.size(), h.points.size());
  const int m = o.points_per_strand;
  const double length = master.Length();
  double max_ratio = 0.0;
  for (int k = 0; k < h.NumStrands(); ++k) {
    EXPECT_EQ(h.point_counts[k], 57u);
    for (int j = 0; j < m; ++j) {
      const double s = length * j / (m - 1);
      // |child - master| <= r_w scale(s/L) + jitter + frizz (s / L) (wisp.h).
      const double scale = o.root_scale + (o.tip_scale - o.root_scale) * std::pow(s / length, 0.7);
      const double bound = rw * scale + o.jitter + o.frizz_amplitude * s / length;
      const double distance = (Point(h, k, j, m) - MasterAt(master, s)).norm();
      EXPECT_LE(distance, bound + kFloatTolerance) << k << " " << j;
      max_ratio = std::max(max_ratio, distance / bound);
      EXPECT_FLOAT_EQ(h.widths[static_cast<size_t>(k) * m + j], 2 * kFibreRadius);
    }
  }
  // Anti-vacuity: the children fill the cylinder (some get close to its wall).
  EXPECT_GT(max_ratio, 0.8);
}

TEST(Wisp, ZeroOffsetChildEqualsMaster) {
  const FramedCentreline master = Master(0.2, 20, 4, Vec3(60.0, 0.0, 15.0));
  WispOptions o;
  o.strands_per_wisp = 5;
  o.points_per_strand = master.NumPoints();  // child samples coincide with the master's
  o.length_variation = 0.0;
  o.include_master = false;
  HairCurves h;
  AppendWisp(master, SectionFromEccentricity(kFibreRadius, 0.0), 0.0, o, 7, nullptr, &h);
  for (int k = 0; k < 5; ++k) {
    for (int j = 0; j < o.points_per_strand; ++j) {
      EXPECT_LT((Point(h, k, j, o.points_per_strand) - master.points[j]).norm(), kFloatTolerance);
    }
  }
  // Each child point carries the master's major axis n1 there (cross_section.h: a along n1),
  // the frame computed independently by SampleFramedCentreline: unit, normal to the strand.
  ASSERT_EQ(h.major_axes.size(), h.points.size());
  for (int k = 0; k < 5; ++k) {
    for (int j = 0; j < o.points_per_strand; ++j) {
      const Vec3 axis = h.major_axes[static_cast<size_t>(k) * o.points_per_strand + j].cast<double>();
      EXPECT_LT((axis - master.frames[j].col(0)).norm(), kFloatTolerance) << k << " " << j;
    }
  }
  // include_master: the first strand is the master, even with a large radius and variations.
  o.include_master = true;
  o.jitter = 1e-3;
  o.length_variation = 0.5;
  HairCurves g;
  AppendWisp(master, SectionFromEccentricity(kFibreRadius, 0.0), 1e-3, o, 7, nullptr, &g);
  for (int j = 0; j < o.points_per_strand; ++j) {
    EXPECT_LT((Point(g, 0, j, o.points_per_strand) - master.points[j]).norm(), kFloatTolerance);
  }
}

TEST(Wisp, CurlyChildrenTurnWithTheMasterFrame) {
  // A curly master (kappa = 80, tau = 10 1/m: 2.5 turns in 20 cm); no jitter, no frizz: the offset
  // expressed in the master frame, Q(s)^T (x - r), is (o1, o2, 0) r_w scale(s/L) at every sample.
  const FramedCentreline master = Master(0.2, 20, 4, Vec3(80.0, 0.0, 10.0), testing::RandomRotation(4),
                                         Vec3(0.05, 0.02, 0.1));
  WispOptions o;
  o.strands_per_wisp = 50;
  o.points_per_strand = master.NumPoints();
  o.length_variation = 0.0;
  o.include_master = false;
  const double rw = 1e-3;
  HairCurves h;
  AppendWisp(master, SectionFromEccentricity(kFibreRadius, 0.0), rw, o, 11, nullptr, &h);
  const int m = o.points_per_strand;
  double min_cos = 1.0;
  for (int k = 0; k < 50; ++k) {
    const Vec3 root_offset = master.frames[0].transpose() * (Point(h, k, 0, m) - master.points[0]);
    EXPECT_LE(root_offset.norm(), rw + kFloatTolerance);
    for (int j = 1; j < m; ++j) {
      const double scale = 1.0 + (0.5 - 1.0) * master.arc_lengths[j] / master.Length();
      const Vec3 world = Point(h, k, j, m) - master.points[j];
      const Vec3 material = master.frames[j].transpose() * world;
      EXPECT_LT((material - scale * root_offset).norm(), 2 * kFloatTolerance) << k << " " << j;
      if (root_offset.norm() > 0.3 * rw) {
        min_cos = std::min(min_cos, world.normalized().dot(
                                        (Point(h, k, 0, m) - master.points[0]).normalized()));
      }
    }
  }
  // Anti-vacuity: in world coordinates the offsets do turn around (by more than 90 degrees).
  EXPECT_LT(min_cos, 0.0);
}

// Arc length of a point lying on the master polyline (m): the closest chord's parameter.
double ArcLengthOnMaster(const FramedCentreline& c, const Vec3& x) {
  double best = 1e300, s = 0.0;
  for (int j = 0; j + 1 < c.NumPoints(); ++j) {
    const Vec3 a = c.points[j], d = c.points[j + 1] - c.points[j];
    const double t = std::clamp((x - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    const double dist = (a + t * d - x).norm();
    if (dist < best) {
      best = dist;
      s = c.arc_lengths[j] + t * (c.arc_lengths[j + 1] - c.arc_lengths[j]);
    }
  }
  return s;
}

TEST(Wisp, LengthsWithinTheVariationBounds) {
  // Radius 0: every child lies on the master polyline and its tip at arc length L_k. With
  // variation v = 0.3, L_k = L (1 - v u) in [0.7 L, L]; E[L_k / L] = 1 - v/2 = 0.85 with standard
  // error v / sqrt(12 N) = 0.0019 for N = 2000 (u uniform, variance 1/12). 4 sigma bound.
  const FramedCentreline master = Master(0.2, 20, 4, Vec3(40.0, 10.0, 15.0));
  WispOptions o;
  o.strands_per_wisp = 2000;
  o.points_per_strand = 16;
  o.length_variation = 0.3;
  o.include_master = false;
  HairCurves h;
  AppendWisp(master, SectionFromEccentricity(kFibreRadius, 0.0), 0.0, o, 5, nullptr, &h);
  const double length = master.Length();
  double sum = 0.0, min_fraction = 1.0, max_fraction = 0.0;
  for (int k = 0; k < o.strands_per_wisp; ++k) {
    const double fraction =
        ArcLengthOnMaster(master, Point(h, k, o.points_per_strand - 1, o.points_per_strand)) /
        length;
    EXPECT_GE(fraction, 0.7 - 1e-6);
    EXPECT_LE(fraction, 1.0 + 1e-6);
    sum += fraction;
    min_fraction = std::min(min_fraction, fraction);
    max_fraction = std::max(max_fraction, fraction);
  }
  EXPECT_NEAR(sum / o.strands_per_wisp, 0.85, 4 * 0.3 / std::sqrt(12.0 * 2000));
  EXPECT_LT(min_fraction, 0.71);  // the range is used
  EXPECT_GT(max_fraction, 0.99);
}

// WispLengthFractions replays AppendWisp's draws: with radius 0 every child lies on the master
// and its tip sits at arc length L_k, measured independently on the master polyline.
TEST(WispLengthFractions, MatchTheStrandsAppendWispDraws) {
  const FramedCentreline master = Master(0.25, 20, 4, Vec3(30.0, 5.0, 10.0));
  for (const bool include_master : {false, true}) {
    WispOptions o;
    o.strands_per_wisp = 50;
    o.points_per_strand = 16;
    o.length_variation = 0.4;
    o.jitter = 0.0;
    o.include_master = include_master;
    HairCurves h;
    AppendWisp(master, SectionFromEccentricity(kFibreRadius, 0.0), 0.0, o, 77, nullptr, &h);
    const std::vector<double> fractions = WispLengthFractions(o, 77);
    ASSERT_EQ(fractions.size(), 50u);
    double smallest = 1.0;
    for (int k = 0; k < o.strands_per_wisp; ++k) {
      const double measured =
          ArcLengthOnMaster(master, Point(h, k, o.points_per_strand - 1, o.points_per_strand)) /
          master.Length();
      // Float points on a 25-cm strand: ~1e-7 relative.
      EXPECT_NEAR(fractions[static_cast<size_t>(k)], measured, 1e-6) << "strand " << k;
      smallest = std::min(smallest, fractions[static_cast<size_t>(k)]);
    }
    if (include_master) {
      EXPECT_EQ(fractions[0], 1.0);
    }
    EXPECT_LT(smallest, 0.7);  // not vacuous: the variation is used
  }
}

// Root offsets rho / r_w of N children (the master frame at the root is n1, n2).
std::vector<Vec3> RootOffsets(double distance_exponent, int n, std::uint64_t seed) {
  const FramedCentreline master = Master(0.1, 5, 2, Vec3::Zero());
  WispOptions o;
  o.strands_per_wisp = n;
  o.points_per_strand = 2;
  o.distance_exponent = distance_exponent;
  o.include_master = false;
  HairCurves h;
  AppendWisp(master, SectionFromEccentricity(kFibreRadius, 0.0), 1e-3, o, seed, nullptr, &h);
  std::vector<Vec3> offsets;
  for (int k = 0; k < n; ++k) {
    offsets.push_back(master.frames[0].transpose() * (Point(h, k, 0, 2) - master.points[0]) / 1e-3);
  }
  return offsets;
}

TEST(Wisp, UniformDiskStatistics) {
  // Uniform in the unit disk: rho^2 is uniform on [0, 1], so E[rho^2] = 1/2 (var 1/12),
  // P(rho < 1/2) = 1/4 (var 3/16), E[o1] = E[o2] = 0 (var E[rho^2]/2 = 1/4). N = 20000: 4 sigma.
  const int n = 20000;
  const std::vector<Vec3> offsets = RootOffsets(1.0, n, 99);
  double rho2 = 0.0, inner = 0.0, o1 = 0.0, o2 = 0.0;
  for (const Vec3& o : offsets) {
    EXPECT_LE(o.norm(), 1.0 + 1e-4);
    rho2 += o.squaredNorm();
    inner += o.norm() < 0.5 ? 1.0 : 0.0;
    o1 += o.x();
    o2 += o.y();
  }
  EXPECT_NEAR(rho2 / n, 0.5, 4 * std::sqrt(1.0 / 12 / n));
  EXPECT_NEAR(inner / n, 0.25, 4 * std::sqrt(3.0 / 16 / n));
  EXPECT_NEAR(o1 / n, 0.0, 4 * std::sqrt(0.25 / n));
  EXPECT_NEAR(o2 / n, 0.0, 4 * std::sqrt(0.25 / n));
}

TEST(Wisp, ConcentratedDistanceStatistics) {
  // gamma = 2: rho^2 = u^2, E[rho^2] = 1/3, var = E[u^4] - 1/9 = 1/5 - 1/9 = 4/45. N = 20000.
  const int n = 20000;
  const std::vector<Vec3> offsets = RootOffsets(2.0, n, 123);
  double rho2 = 0.0;
  for (const Vec3& o : offsets) rho2 += o.squaredNorm();
  EXPECT_NEAR(rho2 / n, 1.0 / 3.0, 4 * std::sqrt(4.0 / 45 / n));
}

// 60 curly masters of random orientations hanging from a 10 cm square.
std::vector<FramedCentreline> Head(int count) {
  std::vector<FramedCentreline> masters;
  for (int i = 0; i < count; ++i) {
    const Vec3 natural(30.0 + i % 7 * 10.0, 0.0, 5.0 + i % 3 * 5.0);
    masters.push_back(Master(0.1 + 0.002 * i, 10, 3, natural, testing::RandomRotation(100 + i),
                             Vec3(0.01 * (i % 10), 0.01 * (i / 10), 0.0)));
  }
  return masters;
}

bool BitIdentical(const HairCurves& a, const HairCurves& b) {
  return a.point_counts == b.point_counts && a.points.size() == b.points.size() &&
         a.widths.size() == b.widths.size() &&
         std::memcmp(a.points.data(), b.points.data(), a.points.size() * sizeof(Vec3f)) == 0 &&
         std::memcmp(a.widths.data(), b.widths.data(), a.widths.size() * sizeof(float)) == 0;
}

TEST(GenerateWisps, DeterministicWhateverTheThreadCount) {
  const std::vector<FramedCentreline> masters = Head(60);
  const std::vector<CrossSection> sections = {SectionFromEccentricity(kFibreRadius, 0.2)};
  WispOptions o;
  o.strands_per_wisp = 40;
  o.jitter = 1e-4;
  o.frizz_amplitude = 5e-5;
  HairCurves one, two, again;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = GenerateWisps(masters, sections, o, 2024);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = GenerateWisps(masters, sections, o, 2024);
    again = GenerateWisps(masters, sections, o, 2024);
  }
  ASSERT_EQ(one.NumStrands(), 60 * 40);
  ASSERT_EQ(one.NumPoints(), 60 * 40 * 32);
  EXPECT_TRUE(BitIdentical(one, two));
  EXPECT_TRUE(BitIdentical(two, again));
  // Another seed gives another head.
  EXPECT_FALSE(BitIdentical(one, GenerateWisps(masters, sections, o, 2025)));
  // Output order is master order, and wisp i uses WispSeed(seed, i) alone.
  for (int i : {0, 17, 59}) {
    HairCurves single;
    AppendWisp(masters[i], sections[0], ResolveWispRadius(masters[i], sections[0], o), o,
               WispSeed(2024, i), nullptr, &single);
    EXPECT_EQ(std::memcmp(single.points.data(), one.points.data() + static_cast<size_t>(i) * 40 * 32,
                          single.points.size() * sizeof(Vec3f)),
              0)
        << i;
  }
}

TEST(GenerateWisps, ObstaclePushesChildrenOut) {
  // A straight master hanging down the x = 0 axis through a sphere of radius 1 mm centred at
  // (0.4 mm, 0, -5 cm): the master and many children start inside it.
  const std::vector<FramedCentreline> masters = {Master(0.1, 10, 3, Vec3::Zero())};
  const std::vector<CrossSection> sections = {SectionFromEccentricity(kFibreRadius, 0.0)};
  const Sphere sphere(Vec3(4e-4, 0.0, -0.05), 1e-3);
  WispOptions o;
  o.strands_per_wisp = 200;
  o.points_per_strand = 200;
  o.jitter = 1e-4;
  auto inside = [&](const HairCurves& h) {
    int count = 0;
    double min_distance = 1e300;
    for (const Vec3f& p : h.points) {
      const double d = sphere.SignedDistance(p.cast<double>(), nullptr);
      count += d < 0.0 ? 1 : 0;
      min_distance = std::min(min_distance, d);
    }
    return std::make_pair(count, min_distance);
  };
  const auto free = inside(GenerateWisps(masters, sections, o, 1));
  EXPECT_GT(free.first, 100);  // anti-vacuity: without the push, points are inside
  const auto pushed = inside(GenerateWisps(masters, sections, o, 1, &sphere));
  EXPECT_EQ(pushed.first, 0);
  // After the push every point is at least one fibre radius out (float rounding aside).
  EXPECT_GE(pushed.second, kFibreRadius - kFloatTolerance);
}

TEST(WispOptions, BadOptionsRejectedWithTheFieldName) {
  struct Case {
    void (*edit)(WispOptions*);
    const char* field;
  };
  const Case cases[] = {
      {[](WispOptions* o) { o->strands_per_wisp = 0; }, "strands_per_wisp"},
      {[](WispOptions* o) { o->points_per_strand = 1; }, "points_per_strand"},
      {[](WispOptions* o) { o->wisp_radius = -1e-3; }, "wisp_radius"},
      {[](WispOptions* o) { o->packing_fraction = 1.5; }, "packing_fraction"},
      {[](WispOptions* o) { o->root_scale = 0.0; }, "root_scale"},
      {[](WispOptions* o) { o->tip_scale = NAN; }, "tip_scale"},
      {[](WispOptions* o) { o->profile_exponent = -1.0; }, "profile_exponent"},
      {[](WispOptions* o) { o->distance_exponent = 0.0; }, "distance_exponent"},
      {[](WispOptions* o) { o->jitter = INFINITY; }, "jitter"},
      {[](WispOptions* o) { o->length_variation = 1.0; }, "length_variation"},
      {[](WispOptions* o) { o->frizz_amplitude = -1.0; }, "frizz_amplitude"},
      {[](WispOptions* o) { o->frizz_frequency = -2.0; }, "frizz_frequency"},
      {[](WispOptions* o) { o->tip_taper = 1.0; }, "tip_taper"},
      {[](WispOptions* o) { o->tip_taper_length = 0.0; }, "tip_taper_length"},
      {[](WispOptions* o) { o->tip_taper_length = NAN; }, "tip_taper_length"},
  };
  std::string why;
  EXPECT_TRUE(WispOptions{}.IsValid(&why)) << why;
  for (const Case& c : cases) {
    WispOptions o;
    c.edit(&o);
    why.clear();
    EXPECT_FALSE(o.IsValid(&why)) << c.field;
    EXPECT_NE(why.find(std::string("WispOptions.") + c.field), std::string::npos) << why;
    // GenerateWisps refuses them too, writing nothing.
    std::string message;
    const HairCurves h = GenerateWisps({Master(0.1, 5, 2, Vec3::Zero())},
                                       {SectionFromEccentricity(kFibreRadius, 0.0)}, o, 1,
                                       nullptr, &message);
    EXPECT_EQ(h.NumStrands(), 0);
    EXPECT_EQ(message, why);
  }
}

TEST(GenerateWisps, BadInputRejectedWithTheFieldName) {
  const WispOptions o;
  const CrossSection section = SectionFromEccentricity(kFibreRadius, 0.0);
  std::vector<FramedCentreline> masters = {Master(0.1, 5, 2, Vec3::Zero()),
                                           Master(0.1, 5, 2, Vec3::Zero())};
  std::string why;
  // Wrong number of sections.
  EXPECT_EQ(GenerateWisps(masters, {section, section, section}, o, 1, nullptr, &why).NumStrands(), 0);
  EXPECT_NE(why.find("sections"), std::string::npos) << why;
  // Invalid section.
  EXPECT_EQ(GenerateWisps(masters, {CrossSection{}}, o, 1, nullptr, &why).NumStrands(), 0);
  EXPECT_NE(why.find("sections[0]"), std::string::npos) << why;
  // A master whose arrays disagree, one with a non-rotation frame, one too short.
  masters[1].frames.pop_back();
  EXPECT_EQ(GenerateWisps(masters, {section}, o, 1, nullptr, &why).NumStrands(), 0);
  EXPECT_NE(why.find("masters[1]"), std::string::npos) << why;
  masters[1] = masters[0];
  masters[1].frames[3] *= 2.0;
  EXPECT_EQ(GenerateWisps(masters, {section}, o, 1, nullptr, &why).NumStrands(), 0);
  EXPECT_NE(why.find("masters[1].frames[3]"), std::string::npos) << why;
  masters[1].points.resize(1);
  EXPECT_EQ(GenerateWisps(masters, {section}, o, 1, nullptr, &why).NumStrands(), 0);
  EXPECT_NE(why.find("masters[1]"), std::string::npos) << why;
  // No masters: nothing to do, no error.
  EXPECT_EQ(GenerateWisps({}, {section}, o, 1, nullptr, &why).NumStrands(), 0);
}

TEST(Wisp, TaperedWidths) {
  // A taper length beyond the strand's length tapers the whole strand: width(s) = 2 r (1 - taper
  // s / L_k), at the root 2r, at the tip 2r (1 - taper).
  const FramedCentreline master = Master(0.1, 5, 2, Vec3::Zero());
  WispOptions o;
  o.strands_per_wisp = 3;
  o.points_per_strand = 11;
  o.tip_taper = 0.6;
  o.tip_taper_length = 1.0;
  HairCurves h;
  AppendWisp(master, SectionFromEccentricity(kFibreRadius, 0.0), 1e-3, o, 3, nullptr, &h);
  for (int k = 0; k < 3; ++k) {
    EXPECT_FLOAT_EQ(h.widths[k * 11], 2 * kFibreRadius);
    EXPECT_FLOAT_EQ(h.widths[k * 11 + 5], 2 * kFibreRadius * (1 - 0.6 * 0.5));
    EXPECT_FLOAT_EQ(h.widths[k * 11 + 10], 2 * kFibreRadius * 0.4);
  }
}

TEST(Wisp, DefaultTaperNarrowsTheLastSixCentimetres) {
  // The defaults (wisp.h): full diameter up to 6 cm before the tip, then linear down to 1/5 of it.
  // The master (strand 0, include_master) has the master's length 0.25 m and 26 points spaced
  // 1 cm: the taper starts at s = 0.19 m (point 19); point 22 (s = 0.22 m) is half-way,
  // 1 - 0.8 x 0.5 = 0.6; the tip 1 - 0.8 = 0.2 (hand-computed).
  const FramedCentreline master = Master(0.25, 10, 5, Vec3::Zero());
  WispOptions o;
  o.strands_per_wisp = 4;
  o.points_per_strand = 26;
  ASSERT_EQ(o.tip_taper, 0.8);
  ASSERT_EQ(o.tip_taper_length, 0.06);
  HairCurves h;
  AppendWisp(master, SectionFromEccentricity(kFibreRadius, 0.0), 1e-3, o, 5, nullptr, &h);
  ASSERT_EQ(h.NumStrands(), 4);
  const float d = static_cast<float>(2 * kFibreRadius);
  EXPECT_EQ(h.widths[0], d);
  EXPECT_EQ(h.widths[19], d);
  EXPECT_FLOAT_EQ(h.widths[22], d * 0.6f);
  EXPECT_FLOAT_EQ(h.widths[25], d * 0.2f);
  // Every child (length 0.25 (1 - 0.1 u) > 6 cm): full at the root, 0.2 at the tip, never
  // growing along the strand, and full diameter on its first 15 cm (0.9 x 0.25 - 0.06 m).
  for (int k = 0; k < 4; ++k) {
    const float* w = h.widths.data() + 26 * k;
    EXPECT_EQ(w[0], d);
    EXPECT_FLOAT_EQ(w[25], d * 0.2f);
    for (int j = 1; j < 26; ++j) EXPECT_LE(w[j], w[j - 1]) << k << " " << j;
    for (int j = 0; j <= 15; ++j) EXPECT_EQ(w[j], d) << k << " " << j;
  }
  // WidthTaperFactor itself, at hand-computed points (L_c = 0.1 m, l_t = 0.06 m).
  EXPECT_EQ(WidthTaperFactor(o, 0.04, 0.1), 1.0);
  EXPECT_NEAR(WidthTaperFactor(o, 0.07, 0.1), 1.0 - 0.8 * 0.5, 1e-15);
  EXPECT_NEAR(WidthTaperFactor(o, 0.1, 0.1), 0.2, 1e-15);
  // A strand shorter than the taper length tapers over its whole length.
  EXPECT_NEAR(WidthTaperFactor(o, 0.01, 0.02), 1.0 - 0.8 * 0.5, 1e-15);
}

}  // namespace
}  // namespace ringlet
