// The ray tracer (render.h): a white furnace, exact fibre coverage and h, determinism across
// thread counts, shadow transmittance through fibres, a Lambertian sphere under the key light,
// and bad options. The fibre models here are this file's own simple ones (not HairBsdf).
#include "ringlet/render.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "render/camera.h"
#include "render/embree_scene.h"
#include "render/sampler.h"
#include "ringlet/hair_bsdf.h"

namespace ringlet {
namespace {

constexpr double kPi = std::numbers::pi;

// Scatters albedo uniformly over the sphere: f = albedo / (4 pi), so integral f dw = albedo
// (albedo 1: the white furnace's energy-conserving fibre); straight-through transmittance T.
class IsotropicFibre final : public FibreScattering {
 public:
  explicit IsotropicFibre(double albedo = 1.0, double transmittance = 1.0)
      : albedo_(albedo), transmittance_(transmittance) {}
  Rgb Eval(const Vec3&, const Vec3&, const FibreHit&) const override {
    return Rgb::Constant(albedo_ / (4.0 * kPi));
  }
  ScatterSample Sample(const Vec3&, const FibreHit&, const std::array<double, 4>& u) const override {
    ScatterSample s;
    s.wi = render::UniformSphere(u[0], u[1]);
    s.pdf = 1.0 / (4.0 * kPi);
    s.weight = Rgb::Constant(albedo_);
    return s;
  }
  double Pdf(const Vec3&, const Vec3&, const FibreHit&) const override { return 1.0 / (4.0 * kPi); }
  Rgb Transmittance(const Vec3&, const FibreHit&) const override {
    return Rgb::Constant(transmittance_);
  }

 private:
  double albedo_;
  double transmittance_;
};

// Absorbs everything: a fibre appears black, opaque to shadows.
class BlackFibre final : public FibreScattering {
 public:
  Rgb Eval(const Vec3&, const Vec3&, const FibreHit&) const override { return Rgb::Zero(); }
  ScatterSample Sample(const Vec3&, const FibreHit&, const std::array<double, 4>&) const override {
    return ScatterSample();
  }
  double Pdf(const Vec3&, const Vec3&, const FibreHit&) const override { return 0.0; }
  Rgb Transmittance(const Vec3&, const FibreHit&) const override { return Rgb::Zero(); }
};

// Transmittance (1 + h) / 2 in every channel: shadow rays report the h they crossed at.
class HReportingFibre final : public FibreScattering {
 public:
  Rgb Eval(const Vec3&, const Vec3&, const FibreHit&) const override { return Rgb::Zero(); }
  ScatterSample Sample(const Vec3&, const FibreHit&, const std::array<double, 4>&) const override {
    return ScatterSample();
  }
  double Pdf(const Vec3&, const Vec3&, const FibreHit&) const override { return 0.0; }
  Rgb Transmittance(const Vec3&, const FibreHit& hit) const override {
    return Rgb::Constant(0.5 * (1.0 + hit.h));
  }
};

// A broken model: infinite Eval, NaN sample weights. The tracer stops a path at a NaN weight
// (its `> 0` guards are false for NaN); the infinite Eval makes infinite samples, which must be
// counted and dropped.
class NanFibre final : public FibreScattering {
 public:
  Rgb Eval(const Vec3&, const Vec3&, const FibreHit&) const override {
    return Rgb::Constant(std::numeric_limits<double>::infinity());
  }
  ScatterSample Sample(const Vec3&, const FibreHit&, const std::array<double, 4>&) const override {
    ScatterSample s;
    s.wi = Vec3::UnitZ();
    s.pdf = 1.0;
    s.weight = Rgb::Constant(std::nan(""));
    return s;
  }
  double Pdf(const Vec3&, const Vec3&, const FibreHit&) const override { return 1.0; }
  Rgb Transmittance(const Vec3&, const FibreHit&) const override { return Rgb::Ones(); }
};

// Appends a polyline strand of constant width (m).
void AddStrand(HairCurves* hair, const std::vector<Vec3>& points, double width) {
  hair->point_counts.push_back(static_cast<std::uint32_t>(points.size()));
  for (const Vec3& p : points) {
    hair->points.push_back(p.cast<float>());
    hair->widths.push_back(static_cast<float>(width));
  }
}

// A straight strand from a to b with n points.
std::vector<Vec3> Line(const Vec3& a, const Vec3& b, int n) {
  std::vector<Vec3> points;
  for (int i = 0; i < n; ++i) points.push_back(a + (b - a) * (static_cast<double>(i) / (n - 1)));
  return points;
}

std::shared_ptr<const Body> SphereBody(const Vec3& center, double radius) {
  auto body = std::make_shared<Body>();
  std::string error;
  EXPECT_TRUE(Body::Create({Sphere{center, radius, "ball"}}, {}, body.get(), &error)) << error;
  return body;
}

// Ray-sphere intersection: the nearest t > 0 of o + t d (d unit), or -1.
double HitSphere(const Vec3& o, const Vec3& d, const Vec3& c, double r) {
  const Vec3 oc = o - c;
  const double b = oc.dot(d);
  const double disc = b * b - (oc.squaredNorm() - r * r);
  if (disc < 0.0) return -1.0;
  const double t = -b - std::sqrt(disc);
  return t > 0.0 ? t : -1.0;
}

// The furnace scene: a sphere of radius 0.1 m at the origin, 24 wavy radial strands around
// its silhouette (seen from -y) and 10 strands in front of its lower part; 4 mm fibres.
struct FurnaceScene {
  HairCurves hair;
  RenderScene scene;
  FurnaceScene(double body_albedo) {
    for (int k = 0; k < 24; ++k) {
      const double a = 2.0 * kPi * k / 24.0;
      const Vec3 radial(std::cos(a), 0.0, std::sin(a));
      std::vector<Vec3> points;
      for (int i = 0; i < 9; ++i) {
        const double s = i / 8.0;
        points.push_back((0.1 + 0.1 * s) * radial + Vec3(0.0, 0.01 * std::sin(6.0 * s), 0.0));
      }
      AddStrand(&hair, points, 0.004);
    }
    for (int k = 0; k < 10; ++k) {
      const double z = -0.1 + 0.002 * k;
      AddStrand(&hair, Line(Vec3(-0.15, -0.12 - 0.003 * k, z), Vec3(0.15, -0.12, z + 0.01), 6),
                0.004);
    }
    scene.hair = &hair;
    scene.fibre = std::make_shared<IsotropicFibre>(1.0);
    scene.body = SphereBody(Vec3::Zero(), 0.1);
    scene.body_albedo = Rgb::Constant(body_albedo);
    scene.key.irradiance = Rgb::Zero();
    scene.environment.top = Rgb::Ones();
    scene.environment.bottom = Rgb::Ones();
    scene.camera = FrameCamera(Eigen::AlignedBox3d(Vec3(-0.2, -0.2, -0.2), Vec3(0.2, 0.2, 0.2)),
                               Vec3(0.0, 1.0, 0.0), 0.6, 1.0);
  }
};

// K independent renders (seeds 1..K) of n x n pixels: per pixel mean and sample standard
// deviation of the K estimates.
void RenderMany(const RenderScene& scene, RenderOptions options, int k, std::vector<double>* mean,
                std::vector<double>* sd) {
  const int n = options.width * options.height;
  std::vector<double> sum(n, 0.0), sum2(n, 0.0);
  for (int s = 0; s < k; ++s) {
    options.seed = 1000 + s;
    Image image;
    RenderStats stats;
    std::string error;
    ASSERT_TRUE(Render(scene, options, &image, &stats, &error)) << error;
    EXPECT_EQ(stats.nan_samples, 0);
    for (int i = 0; i < n; ++i) {
      const double v = image.pixels[i].mean();
      sum[i] += v;
      sum2[i] += v * v;
    }
  }
  mean->assign(n, 0.0);
  sd->assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    (*mean)[i] = sum[i] / k;
    (*sd)[i] = std::sqrt(std::max(0.0, (sum2[i] - k * (*mean)[i] * (*mean)[i]) / (k - 1)));
  }
}

// White furnace (Veach's / pbrt's furnace test): uniform unit environment, energy-conserving
// fibres (integral f = 1) and a white body: every pixel's expected value is exactly 1 (up to
// paths still bouncing after max_bounces, negligible at 64 here). The noise is measured: 16
// independent renders per pixel give a mean m and standard deviation s; each pixel must satisfy
// |m - 1| <= 6 s / sqrt(16) (a t-statistic of 15 dof beyond 6 has probability 2e-5), and the
// image mean must be 1 within 4 of its standard errors.
TEST(RenderTest, WhiteFurnaceIsOneEverywhere) {
  FurnaceScene furnace(1.0);
  RenderOptions options;
  options.width = 48;
  options.height = 48;
  options.samples_per_pixel = 8;
  options.max_bounces = 64;
  options.threads = 2;
  constexpr int kRenders = 16;
  std::vector<double> mean, sd;
  RenderMany(furnace.scene, options, kRenders, &mean, &sd);
  double total = 0.0, variance = 0.0;
  int noisy = 0;
  for (size_t i = 0; i < mean.size(); ++i) {
    const double se = sd[i] / std::sqrt(kRenders);
    EXPECT_LE(std::abs(mean[i] - 1.0), 6.0 * se + 1e-6) << "pixel " << i << " sd " << sd[i];
    total += mean[i];
    variance += se * se;
    if (sd[i] > 0.0) ++noisy;
  }
  // Anti-vacuity: many pixels see fibres or the body (noisy), not just the environment (the
  // frame's half height holds 1.1 bounding radii, 0.38 m: the body covers pi (0.1 / 0.38 *
  // 24)^2 ~ 125 pixels, the fibres about 200 more; 336 measured).
  EXPECT_GT(noisy, 250);
  const double image_mean = total / mean.size();
  const double image_se = std::sqrt(variance) / mean.size();
  EXPECT_NEAR(image_mean, 1.0, 4.0 * image_se) << "se " << image_se;
  EXPECT_LT(image_se, 0.01);
  std::printf("furnace: mean %.5f se %.5f\n", image_mean, image_se);
}

// RenderOptions::cancel: unset, the image is bit-identical to a render without it; set from the
// progress callback after the first tile (one thread), Render fails with "cancelled" and leaves
// the image untouched.
TEST(RenderTest, CancelStopsBetweenTilesAndAnUnsetFlagChangesNothing) {
  FurnaceScene furnace(1.0);
  RenderOptions options;
  options.width = 24;
  options.height = 24;
  options.samples_per_pixel = 2;
  options.threads = 1;
  options.tile_size = 8;
  Image plain, with_flag;
  std::string error;
  ASSERT_TRUE(Render(furnace.scene, options, &plain, nullptr, &error)) << error;
  std::atomic<bool> cancel{false};
  options.cancel = &cancel;
  ASSERT_TRUE(Render(furnace.scene, options, &with_flag, nullptr, &error)) << error;
  ASSERT_EQ(plain.pixels.size(), with_flag.pixels.size());
  EXPECT_EQ(std::memcmp(plain.pixels.data(), with_flag.pixels.data(),
                        plain.pixels.size() * sizeof(plain.pixels[0])),
            0);
  long tiles_seen = 0;
  options.progress = [&](long done, long) {
    tiles_seen = done;
    cancel.store(true);
  };
  Image untouched;
  untouched.width = 3;
  EXPECT_FALSE(Render(furnace.scene, options, &untouched, nullptr, &error));
  EXPECT_EQ(error, "cancelled");
  EXPECT_EQ(untouched.width, 3);
  EXPECT_EQ(tiles_seen, 1);  // 9 tiles; the rest skipped
}

// The same furnace with a grey body (albedo 0.5): the body's pixels lose energy, so they are
// clearly below 1 (at least 3 standard errors), while pixels seeing only the sky stay 1.
TEST(RenderTest, GreyBodyInFurnaceIsDarker) {
  FurnaceScene furnace(0.5);
  RenderOptions options;
  options.width = 32;
  options.height = 32;
  options.samples_per_pixel = 8;
  options.max_bounces = 64;
  options.jitter = false;  // pixel centres: we know which pixels see the body
  constexpr int kRenders = 8;
  std::vector<double> mean, sd;
  RenderMany(furnace.scene, options, kRenders, &mean, &sd);
  render::PinholeCamera camera;
  std::string why;
  ASSERT_TRUE(render::MakePinholeCamera(furnace.scene.camera, 32, 32, &camera, &why));
  int body_pixels = 0;
  for (int y = 0; y < 32; ++y) {
    for (int x = 0; x < 32; ++x) {
      const Vec3 d = camera.Direction(x + 0.5, y + 0.5);
      const double t = HitSphere(camera.position, d, Vec3::Zero(), 0.1);
      if (t < 0.0) continue;
      const Vec3 p = camera.position + t * d;
      if (std::hypot(p.x(), p.z()) > 0.07 || p.z() < -0.07) continue;  // clear of the strands
      ++body_pixels;
      const int i = y * 32 + x;
      EXPECT_LT(mean[i], 1.0 - 3.0 * sd[i] / std::sqrt(kRenders)) << x << "," << y;
      EXPECT_LT(mean[i], 0.9) << x << "," << y;
    }
  }
  EXPECT_GT(body_pixels, 30);
  EXPECT_EQ(mean[0], 1.0);  // a corner sees the sky only
}

// One straight horizontal fibre (along x, radius 1 cm) seen from -y through pixel centres:
// exactly the pixels whose centre ray passes within the radius of the axis are covered (black
// fibre in front of a white sky). The distance of a ray (o, d) from the x axis is that of two
// lines: |(o - 0) . (d x e_x)| / |d x e_x|.
TEST(RenderTest, FibreCoversExactlyThePixelsWithinItsRadius) {
  constexpr double kRadius = 0.01;
  HairCurves hair;
  AddStrand(&hair, Line(Vec3(-1.0, 0.0, 0.0), Vec3(1.0, 0.0, 0.0), 5), 2.0 * kRadius);
  RenderScene scene;
  scene.hair = &hair;
  scene.fibre = std::make_shared<BlackFibre>();
  scene.key.irradiance = Rgb::Zero();
  scene.environment.top = scene.environment.bottom = Rgb::Ones();
  scene.camera.position = Vec3(0.0, -1.0, 0.003);  // off-centre: rows not symmetric
  scene.camera.look_at = Vec3(0.0, 0.0, 0.003);
  scene.camera.vertical_fov = 0.2;
  RenderOptions options;
  options.width = 48;
  options.height = 64;
  options.samples_per_pixel = 1;
  options.jitter = false;
  Image image;
  RenderStats stats;
  std::string error;
  ASSERT_TRUE(Render(scene, options, &image, &stats, &error)) << error;
  EXPECT_EQ(stats.hair_segments, 4);
  render::PinholeCamera camera;
  ASSERT_TRUE(render::MakePinholeCamera(scene.camera, 48, 64, &camera, &error));
  int covered = 0, clear = 0, borderline = 0;
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 48; ++x) {
      const Vec3 d = camera.Direction(x + 0.5, y + 0.5);
      const Vec3 n = d.cross(Vec3::UnitX());
      const double distance = std::abs(camera.position.dot(n)) / n.norm();
      if (std::abs(distance - kRadius) < 1e-4 * kRadius) {
        ++borderline;  // float rounding decides
        continue;
      }
      const bool inside = distance < kRadius;
      EXPECT_EQ(image.At(x, y).x(), inside ? 0.0f : 1.0f) << x << "," << y << " d " << distance;
      (inside ? covered : clear) += 1;
    }
  }
  // 2 cm at 1 m over a 0.2 rad, 64-pixel field: 2e-2 / (2 tan(0.1) / 64) = 6.4 rows of 48.
  EXPECT_GE(covered, 6 * 48);
  EXPECT_LE(covered, 7 * 48);
  EXPECT_GT(clear, 0);
  EXPECT_LE(borderline, 48);
}

// The h of a hit at a known offset: a ray parallel to y at height z = o r over the fibre along
// x hits with h = o (x = e_x, z = -d's part normal to x, y = z x x = +-e_z); reversed
// direction, or a fibre running from tip to root the other way, flips the sign.
TEST(RenderTest, FibreHitOffsetIsOffsetOverRadius) {
  constexpr double kRadius = 0.002;
  HairCurves hair;
  AddStrand(&hair, Line(Vec3(-1.0, 0.0, 0.0), Vec3(1.0, 0.0, 0.0), 3), 2.0 * kRadius);
  AddStrand(&hair, Line(Vec3(1.0, 0.5, 0.0), Vec3(-1.0, 0.5, 0.0), 3), 2.0 * kRadius);
  std::string error;
  auto scene = render::EmbreeScene::Create(&hair, nullptr, &error);
  ASSERT_NE(scene, nullptr) << error;
  for (double offset : {-0.95, -0.5, -0.1, 0.0, 0.3, 0.7, 0.95}) {
    // From -y, toward +y: y axis of the frame = (0, -1, 0) x e_x = +e_z.
    render::SurfaceHit hit = scene->Intersect(Vec3(0.3, -1.0, offset * kRadius), Vec3::UnitY(),
                                              0.0, 10.0, render::RayIgnore());
    ASSERT_EQ(hit.kind, render::HitKind::kHair);
    EXPECT_EQ(hit.strand, 0);
    render::FibreFrame frame = render::MakeFibreFrame(hit, -Vec3::UnitY(), 1);
    EXPECT_NEAR(frame.hit.h, offset, 2e-4) << offset;
    EXPECT_NEAR(hit.t, 1.0 - kRadius * std::sqrt(1.0 - offset * offset), 1e-5);  // floats
    EXPECT_NEAR(frame.ToLocal(-Vec3::UnitY()).z(), 1.0, 1e-12);  // wo = +z of the frame
    // From +y, toward -y, the fibre's back side: h = -offset.
    hit = scene->Intersect(Vec3(-0.4, 0.25, offset * kRadius), -Vec3::UnitY(), 0.0, 10.0,
                           render::RayIgnore());
    ASSERT_EQ(hit.kind, render::HitKind::kHair);
    frame = render::MakeFibreFrame(hit, Vec3::UnitY(), 1);
    EXPECT_NEAR(frame.hit.h, -offset, 2e-4) << offset;
    // The strand at y = 0.5 runs toward -x: tangent -e_x, h = -offset seen from -y.
    hit = scene->Intersect(Vec3(0.1, 0.2, offset * kRadius), Vec3::UnitY(), 0.0, 10.0,
                           render::RayIgnore());
    ASSERT_EQ(hit.kind, render::HitKind::kHair);
    EXPECT_EQ(hit.strand, 1);
    EXPECT_NEAR(hit.tangent.x(), -1.0, 1e-12);
    frame = render::MakeFibreFrame(hit, -Vec3::UnitY(), 1);
    EXPECT_NEAR(frame.hit.h, -offset, 2e-4) << offset;
  }
  // Per-strand orientation: in [0, pi), a function of (seed, strand) only.
  render::SurfaceHit a = scene->Intersect(Vec3(0.3, -1.0, 0.0), Vec3::UnitY(), 0.0, 10.0, {});
  render::SurfaceHit b = scene->Intersect(Vec3(0.1, 0.2, 0.0), Vec3::UnitY(), 0.0, 10.0, {});
  const double angle_a = render::MakeFibreFrame(a, -Vec3::UnitY(), 7).hit.major_axis_angle;
  EXPECT_GE(angle_a, 0.0);
  EXPECT_LT(angle_a, kPi);
  EXPECT_EQ(angle_a, render::MakeFibreFrame(a, Vec3::UnitZ(), 7).hit.major_axis_angle);
  EXPECT_NE(angle_a, render::MakeFibreFrame(b, -Vec3::UnitY(), 7).hit.major_axis_angle);
  EXPECT_NE(angle_a, render::MakeFibreFrame(a, -Vec3::UnitY(), 8).hit.major_axis_angle);
}

// The ellipse's orientation from HairCurves::major_axes: a fibre along x seen from -y (frame:
// x = e_x, z = -e_y toward the viewer, y = z cross x = +e_z). A major axis along +-e_z lies
// along the frame's y: angle 0; along e_y (toward or away from the viewer, along z): pi/2; at
// 45 degrees between +e_z and -e_y: pi/4; between +e_z and +e_y: 3 pi/4 (angles of a line, in
// [0, pi)). Interpolated between the segment's points; a zero axis falls back to the seeded one.
TEST(RenderTest, MajorAxisAngleFollowsTheCurvesAxes) {
  constexpr double kRadius = 0.002;
  const auto angle_for = [&](const Vec3f& axis0, const Vec3f& axis1, double x) {
    HairCurves hair;
    AddStrand(&hair, Line(Vec3(-1.0, 0.0, 0.0), Vec3(1.0, 0.0, 0.0), 2), 2.0 * kRadius);
    hair.major_axes = {axis0, axis1};
    std::string error;
    auto scene = render::EmbreeScene::Create(&hair, nullptr, &error);
    EXPECT_NE(scene, nullptr) << error;
    const render::SurfaceHit hit =
        scene->Intersect(Vec3(x, -1.0, 0.3 * kRadius), Vec3::UnitY(), 0.0, 10.0, {});
    EXPECT_EQ(hit.kind, render::HitKind::kHair);
    return render::MakeFibreFrame(hit, -Vec3::UnitY(), 1).hit.major_axis_angle;
  };
  const Vec3f ez = Vec3f::UnitZ(), ey = Vec3f::UnitY();
  const float c = static_cast<float>(std::sqrt(0.5));
  EXPECT_NEAR(angle_for(ez, ez, 0.0), 0.0, 1e-7);
  EXPECT_NEAR(angle_for(-ez, -ez, 0.0), 0.0, 1e-7);
  EXPECT_NEAR(angle_for(ey, ey, 0.0), kPi / 2.0, 1e-7);
  EXPECT_NEAR(angle_for(-ey, -ey, 0.0), kPi / 2.0, 1e-7);
  EXPECT_NEAR(angle_for(Vec3f(0.0f, -c, c), Vec3f(0.0f, -c, c), 0.0), kPi / 4.0, 1e-6);
  EXPECT_NEAR(angle_for(Vec3f(0.0f, c, c), Vec3f(0.0f, c, c), 0.0), 3.0 * kPi / 4.0, 1e-6);
  // Halfway along a segment whose axis turns from e_z to -e_y: their mean, 45 degrees.
  EXPECT_NEAR(angle_for(ez, -ey, 0.0), kPi / 4.0, 1e-5);
  // A quarter of the way (x = -0.5): axis 0.75 e_z - 0.25 e_y, angle atan(1/3).
  EXPECT_NEAR(angle_for(ez, -ey, -0.5), std::atan(1.0 / 3.0), 1e-5);
  // No axis (zero): the seeded random angle of the strand, as without major_axes.
  HairCurves plain;
  AddStrand(&plain, Line(Vec3(-1.0, 0.0, 0.0), Vec3(1.0, 0.0, 0.0), 2), 2.0 * kRadius);
  std::string error;
  auto scene = render::EmbreeScene::Create(&plain, nullptr, &error);
  ASSERT_NE(scene, nullptr) << error;
  const render::SurfaceHit hit = scene->Intersect(Vec3(0.0, -1.0, 0.0), Vec3::UnitY(), 0.0, 10.0, {});
  EXPECT_EQ(angle_for(Vec3f::Zero(), Vec3f::Zero(), 0.0),
            render::MakeFibreFrame(hit, -Vec3::UnitY(), 1).hit.major_axis_angle);
}

// A small lit scene: hair in front of a sphere, key light and sky.
struct LitScene {
  HairCurves hair;
  RenderScene scene;
  LitScene() {
    for (int k = 0; k < 40; ++k) {
      const double a = 2.0 * kPi * k / 40.0;
      AddStrand(&hair,
                Line(0.1 * Vec3(std::cos(a), -0.3, std::sin(a)),
                     0.18 * Vec3(std::cos(a + 0.3), -0.5, std::sin(a + 0.3)), 7),
                0.002);
    }
    scene.hair = &hair;
    scene.fibre = std::make_shared<IsotropicFibre>(0.7, 0.5);
    scene.body = SphereBody(Vec3::Zero(), 0.1);
    scene.camera = FrameCamera(Eigen::AlignedBox3d(Vec3(-0.2, -0.2, -0.2), Vec3(0.2, 0.2, 0.2)),
                               Vec3(0.2, 1.0, -0.1), 0.6, 1.5);
  }
};

bool SameImage(const Image& a, const Image& b) {
  return a.width == b.width && a.height == b.height &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(a.pixels[0])) == 0;
}

// Same seed, bit-identical images on 1 and 2 threads (and tile sizes); another seed differs.
TEST(RenderTest, DeterministicForAnyThreadCount) {
  LitScene lit;
  for (ShadowMode mode : {ShadowMode::kPathTraced, ShadowMode::kFibreTransmittance}) {
    RenderOptions options;
    options.width = 36;
    options.height = 24;
    options.samples_per_pixel = 4;
    options.shadows = mode;
    options.seed = 42;
    Image one, two, other;
    RenderStats stats_one, stats_two;
    std::string error;
    options.threads = 1;
    ASSERT_TRUE(Render(lit.scene, options, &one, &stats_one, &error)) << error;
    options.threads = 2;
    options.tile_size = 7;
    ASSERT_TRUE(Render(lit.scene, options, &two, &stats_two, &error)) << error;
    EXPECT_TRUE(SameImage(one, two));
    EXPECT_EQ(stats_one.rays, stats_two.rays);
    EXPECT_EQ(stats_one.camera_rays, 36 * 24 * 4);
    EXPECT_GT(stats_one.rays, stats_one.camera_rays);
    options.seed = 43;
    ASSERT_TRUE(Render(lit.scene, options, &other, nullptr, &error)) << error;
    EXPECT_FALSE(SameImage(one, other));
    double sum = 0.0;
    for (const auto& p : one.pixels) sum += p.sum();
    EXPECT_GT(sum, 0.0);
  }
}

// The firefly clamp (RenderOptions::clamp) bounds every indirect contribution and leaves direct
// light alone. A path of max_bounces = 4 adds at most two contributions per bounce after the
// first (the lights seen from the vertex, and the bounce ray escaping): each sample, and so each
// pixel's mean, is at most its direct-only value (max_bounces = 0, the same sample numbers for
// the first vertex) plus 2 x 4 x clamp per channel. A clamp of 1e-12 gives the direct-only
// image (to 1e-9), a clamp of 1e30 the unclamped one bit for bit, and an active clamp darkens
// the furnace (its bias: the image mean drops below the unclamped one).
TEST(RenderTest, ClampBoundsIndirectContributions) {
  FurnaceScene furnace(1.0);
  RenderOptions options;
  options.width = 64;
  options.height = 64;
  options.samples_per_pixel = 4;
  options.threads = 2;
  options.max_bounces = 0;
  Image direct, unclamped, huge, tiny, clamped;
  std::string error;
  ASSERT_TRUE(Render(furnace.scene, options, &direct, nullptr, &error)) << error;
  options.max_bounces = 4;
  ASSERT_TRUE(Render(furnace.scene, options, &unclamped, nullptr, &error)) << error;
  options.clamp = 1e30;
  ASSERT_TRUE(Render(furnace.scene, options, &huge, nullptr, &error)) << error;
  EXPECT_TRUE(SameImage(unclamped, huge));
  options.clamp = 1e-12;
  ASSERT_TRUE(Render(furnace.scene, options, &tiny, nullptr, &error)) << error;
  constexpr double kClamp = 0.05;
  options.clamp = kClamp;
  ASSERT_TRUE(Render(furnace.scene, options, &clamped, nullptr, &error)) << error;
  double mean_unclamped = 0.0, mean_clamped = 0.0;
  int indirect = 0;
  for (size_t i = 0; i < direct.pixels.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(tiny.pixels[i][c], direct.pixels[i][c], 1e-9) << i;
      EXPECT_LE(clamped.pixels[i][c], direct.pixels[i][c] + 2 * 4 * kClamp + 1e-6) << i;
    }
    if (unclamped.pixels[i].x() > direct.pixels[i].x() + 1e-6) ++indirect;
    mean_unclamped += unclamped.pixels[i].mean() / direct.pixels.size();
    mean_clamped += clamped.pixels[i].mean() / direct.pixels.size();
  }
  // Anti-vacuity: many pixels get indirect light (the fibres and the body see each other; 11
  // of 32 x 32 pixels at 1 spp, so about 150 expected here).
  EXPECT_GT(indirect, 60);
  EXPECT_LT(mean_clamped, mean_unclamped);
  std::printf("clamp %.2f: furnace mean %.4f (unclamped %.4f), %d pixels with indirect light\n",
              kClamp, mean_clamped, mean_unclamped, indirect);
  options.clamp = -1.0;
  EXPECT_FALSE(Render(furnace.scene, options, &clamped, nullptr, &error));
  EXPECT_NE(error.find("options.clamp"), std::string::npos) << error;
}

// Stratified samples (kSobol) estimate a pixel with less error than independent ones at the same
// sample count: the Lambertian sphere under the key light (exact: albedo / pi E cos theta), 8
// samples per pixel with jitter, so edge pixels integrate the sphere's coverage. The error of
// each pattern is measured against a 1024-spp render of the same scene (kIndependent, another
// seed), over 4 seeds.
TEST(RenderTest, SobolSamplesHaveLessErrorThanIndependentOnes) {
  RenderScene scene;
  scene.body = SphereBody(Vec3::Zero(), 0.5);
  scene.body_albedo = Rgb::Constant(0.8);
  scene.key.direction = Vec3(0.6, -1.0, 0.8).normalized();
  scene.key.angular_radius = 0.05;
  scene.environment.top = Rgb::Constant(0.3);
  scene.environment.bottom = Rgb::Constant(0.1);
  scene.camera.position = Vec3(0.0, -3.0, 0.0);
  scene.camera.look_at = Vec3::Zero();
  scene.camera.vertical_fov = 0.4;
  RenderOptions options;
  options.width = 24;
  options.height = 24;
  options.threads = 2;
  options.samples_per_pixel = 1024;
  options.pattern = SamplePattern::kIndependent;
  options.seed = 999;
  Image reference;
  std::string error;
  ASSERT_TRUE(Render(scene, options, &reference, nullptr, &error)) << error;
  options.samples_per_pixel = 8;
  double mse[2] = {0.0, 0.0};
  for (int p = 0; p < 2; ++p) {
    options.pattern = p == 0 ? SamplePattern::kSobol : SamplePattern::kIndependent;
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
      options.seed = seed;
      Image image;
      ASSERT_TRUE(Render(scene, options, &image, nullptr, &error)) << error;
      for (size_t i = 0; i < image.pixels.size(); ++i) {
        mse[p] += (image.pixels[i] - reference.pixels[i]).squaredNorm();
      }
    }
  }
  std::printf("8 spp: MSE sobol %.3e, independent %.3e (ratio %.2f)\n", mse[0], mse[1],
              mse[1] / mse[0]);
  // Independent samples' MSE is the variance / 8; a stratified 2D estimate of a smooth
  // integrand converges faster. The measured ratio is printed; at least 2 is required.
  EXPECT_GT(mse[1] / mse[0], 2.0);
}

// Wet fibres render darker (hair_bsdf.h, "Wet fibres"): the same strands with the Chiang model,
// dry and with HairCurves::wetness = 1, same seed and samples; the mean of the pixels that see
// hair drops. A wrong wetness count is rejected naming the field.
TEST(RenderTest, WetHairIsDarker) {
  LitScene lit;
  HairOptics optics;
  optics.sigma_a = AbsorptionFromMelanin(1.3, 0.2);
  lit.scene.fibre = std::make_shared<HairBsdf>(optics);
  lit.scene.body = nullptr;
  lit.scene.environment.top = lit.scene.environment.bottom = Rgb::Zero();
  RenderOptions options;
  options.width = 48;
  options.height = 32;
  options.samples_per_pixel = 16;
  options.threads = 2;
  Image dry, wet;
  std::string error;
  ASSERT_TRUE(Render(lit.scene, options, &dry, nullptr, &error)) << error;
  lit.hair.wetness.assign(lit.hair.point_counts.size(), 1.0f);
  ASSERT_TRUE(Render(lit.scene, options, &wet, nullptr, &error)) << error;
  double sum_dry = 0.0, sum_wet = 0.0;
  for (size_t i = 0; i < dry.pixels.size(); ++i) {
    sum_dry += dry.pixels[i].sum();
    sum_wet += wet.pixels[i].sum();
  }
  ASSERT_GT(sum_dry, 0.0);
  std::printf("wet / dry mean radiance %.3f\n", sum_wet / sum_dry);
  EXPECT_LT(sum_wet, 0.9 * sum_dry);
  lit.hair.wetness.pop_back();
  EXPECT_FALSE(Render(lit.scene, options, &wet, nullptr, &error));
  EXPECT_NE(error.find("hair.wetness"), std::string::npos) << error;
  lit.hair.wetness.push_back(1.5f);
  EXPECT_FALSE(Render(lit.scene, options, &wet, nullptr, &error));
  EXPECT_NE(error.find("hair.wetness[39]"), std::string::npos) << error;
}

// The progress callback runs once per tile, counting up to the total.
TEST(RenderTest, ProgressCountsTiles) {
  LitScene lit;
  RenderOptions options;
  options.width = 20;
  options.height = 10;
  options.samples_per_pixel = 1;
  options.tile_size = 8;  // 3 x 2 tiles
  options.threads = 2;
  std::vector<long> done;
  long total = 0;
  options.progress = [&](long d, long t) {
    done.push_back(d);
    total = t;
  };
  Image image;
  std::string error;
  ASSERT_TRUE(Render(lit.scene, options, &image, nullptr, &error)) << error;
  EXPECT_EQ(total, 6);
  ASSERT_EQ(done.size(), 6u);
  for (size_t i = 0; i < done.size(); ++i) EXPECT_EQ(done[i], static_cast<long>(i) + 1);
}

// Progressive passes (the studio's render panel): passes of 1, 1, 2, 4, 8 and the rest of 21
// samples, the image after each pass the mean of the samples so far, and the final image
// bit-identical to the render without passes; the pass after 1 sample equals a 1-spp render,
// the one after 4 a 4-spp render (sample s has the same stream in both).
TEST(RenderTest, ProgressivePassesEndInTheSameImage) {
  LitScene lit;
  RenderOptions options;
  options.width = 24;
  options.height = 16;
  options.samples_per_pixel = 21;
  options.threads = 2;
  options.seed = 7;
  Image plain, progressive, one, four;
  std::string error;
  ASSERT_TRUE(Render(lit.scene, options, &plain, nullptr, &error)) << error;
  options.samples_per_pixel = 1;
  ASSERT_TRUE(Render(lit.scene, options, &one, nullptr, &error)) << error;
  options.samples_per_pixel = 4;
  ASSERT_TRUE(Render(lit.scene, options, &four, nullptr, &error)) << error;
  options.samples_per_pixel = 21;
  std::vector<int> taken;
  std::vector<Image> passes;
  options.pass_done = [&](const Image& image, int samples) {
    taken.push_back(samples);
    passes.push_back(image);
  };
  long last_done = 0, last_total = 0;
  options.progress = [&](long d, long t) {
    last_done = d;
    last_total = t;
  };
  ASSERT_TRUE(Render(lit.scene, options, &progressive, nullptr, &error)) << error;
  EXPECT_EQ(taken, (std::vector<int>{1, 2, 4, 8, 16, 21}));
  EXPECT_TRUE(SameImage(plain, progressive));
  EXPECT_TRUE(SameImage(passes.back(), plain));
  EXPECT_TRUE(SameImage(passes[0], one));
  EXPECT_TRUE(SameImage(passes[2], four));
  EXPECT_FALSE(SameImage(passes[0], plain));  // anti-vacuity: the passes differ
  EXPECT_EQ(last_total, 6);  // 24 x 16 pixels in 32-pixel tiles: 1 tile, 6 passes
  EXPECT_EQ(last_done, last_total);

  // Cancelled from the first pass on: false, "cancelled", the image untouched.
  std::atomic<bool> cancel{false};
  options.cancel = &cancel;
  options.pass_done = [&](const Image&, int) { cancel = true; };
  Image untouched;
  untouched.width = 3;
  EXPECT_FALSE(Render(lit.scene, options, &untouched, nullptr, &error));
  EXPECT_EQ(error, "cancelled");
  EXPECT_EQ(untouched.width, 3);
}

// Shadow rays through a comb of N parallel fibres of transmittance T get T^N (straight through
// the axes, any h); beside the comb 1; the body blocks (0); h is that of the crossing.
TEST(RenderTest, ShadowThroughFibresMultipliesTransmittance) {
  constexpr double kRadius = 0.005;
  constexpr int kFibres = 5;
  HairCurves hair;
  for (int k = 1; k <= kFibres; ++k) {
    AddStrand(&hair, Line(Vec3(-1.0, 0.0, 0.1 * k), Vec3(1.0, 0.0, 0.1 * k), 4), 2.0 * kRadius);
  }
  auto body = SphereBody(Vec3(5.0, 0.0, 1.0), 0.3);
  std::string error;
  auto scene = render::EmbreeScene::Create(&hair, body.get(), &error);
  ASSERT_NE(scene, nullptr) << error;
  const IsotropicFibre fibre(1.0, 0.6);
  std::int64_t rays = 0;
  const double inf = std::numeric_limits<double>::infinity();
  // Straight up through all five (one crossing through a joint at x = 1/3: counted once).
  for (double x : {0.05, 1.0 / 3.0, -0.7}) {
    const Rgb t = render::ShadowTransmittance(*scene, fibre, 1, Vec3(x, 0.0, 0.0), Vec3::UnitZ(),
                                              0.0, inf, {}, &rays);
    EXPECT_NEAR(t.x(), std::pow(0.6, kFibres), 1e-12) << x;  // 0.07776
  }
  EXPECT_EQ(rays, 3 * (kFibres + 1));
  // Slanted at 45 degrees along the fibres (x-z plane): crosses each at x = z, all five.
  Rgb t = render::ShadowTransmittance(*scene, fibre, 1, Vec3(0.0, 0.001, 0.0),
                                      Vec3(1.0, 0.0, 1.0).normalized(), 0.0, inf, {}, nullptr);
  EXPECT_NEAR(t.x(), std::pow(0.6, kFibres), 1e-12);
  // Beside the comb.
  t = render::ShadowTransmittance(*scene, fibre, 1, Vec3(0.0, 2.0 * kRadius, 0.0), Vec3::UnitZ(),
                                  0.0, inf, {}, nullptr);
  EXPECT_EQ(t.x(), 1.0);
  // Stopping before the third fibre (tfar) sees two.
  t = render::ShadowTransmittance(*scene, fibre, 1, Vec3(0.0, 0.0, 0.0), Vec3::UnitZ(), 0.0,
                                  0.25, {}, nullptr);
  EXPECT_NEAR(t.x(), 0.36, 1e-12);
  // Toward the body sphere: blocked.
  t = render::ShadowTransmittance(*scene, fibre, 1, Vec3(0.0, 0.0, 1.0), Vec3::UnitX(), 0.0, inf,
                                  {}, nullptr);
  EXPECT_EQ(t.x(), 0.0);
  // Below min_throughput (0.1^5 < 1e-4) the ray stops: 0.
  const IsotropicFibre dark(1.0, 0.1);
  t = render::ShadowTransmittance(*scene, dark, 1, Vec3(0.0, 0.0, 0.0), Vec3::UnitZ(), 0.0, inf,
                                  {}, nullptr);
  EXPECT_EQ(t.x(), 0.0);
  // h of each crossing: a ray along +z at y = o r crosses with wo = -e_z, frame z = -e_z,
  // y = (-e_z) x e_x = -e_y, so h = -o; transmittance (1 + h) / 2 per fibre.
  const HReportingFibre reporting;
  t = render::ShadowTransmittance(*scene, reporting, 1, Vec3(0.0, 0.4 * kRadius, 0.0),
                                  Vec3::UnitZ(), 0.0, inf, {}, nullptr);
  EXPECT_NEAR(t.x(), std::pow(0.5 * (1.0 - 0.4), kFibres), 1e-4);
}

// The same comb in a full render (kFibreTransmittance): a white floor sphere lit by a key light
// straight above, through the comb of N fibres of transmittance T. A pixel whose floor point's
// shadow ray crosses all fibres (here: all shadow rays, the disk is 1e-4 rad wide and the comb
// fibres are stacked exactly above each other) is T^N of an unshadowed pixel, closed form
// albedo / pi E cos.
TEST(RenderTest, FibreTransmittanceShadowOnTheBody) {
  HairCurves hair;
  constexpr int kFibres = 3;
  // Fibres (radius 2 cm) along y, stacked over the floor's top at z = 0: every floor point
  // with |x| < 1 cm is under all three; the camera looks from the +x side, so the fibres
  // hide a band of floor far from that strip.
  for (int k = 1; k <= kFibres; ++k) {
    AddStrand(&hair, Line(Vec3(0.0, -0.5, 0.1 * k), Vec3(0.0, 0.5, 0.1 * k), 3), 0.04);
  }
  RenderScene scene;
  scene.hair = &hair;
  scene.fibre = std::make_shared<IsotropicFibre>(0.0, 0.5);
  scene.body = SphereBody(Vec3(0.0, 0.0, -100.0), 100.0);  // a floor at z = 0 near the axis
  scene.body_albedo = Rgb::Constant(0.8);
  scene.key.direction = Vec3::UnitZ();
  scene.key.angular_radius = 1e-4;
  scene.key.irradiance = Rgb::Constant(2.0);
  scene.environment.top = scene.environment.bottom = Rgb::Zero();
  scene.camera.position = Vec3(0.5, 0.0, 0.4);
  scene.camera.look_at = Vec3(0.0, 0.0, 0.0);
  scene.camera.vertical_fov = 0.4;
  RenderOptions options;
  options.width = 41;
  options.height = 41;
  options.samples_per_pixel = 4;
  options.jitter = false;
  options.shadows = ShadowMode::kFibreTransmittance;
  Image image;
  std::string error;
  ASSERT_TRUE(Render(scene, options, &image, nullptr, &error)) << error;
  render::PinholeCamera camera;
  ASSERT_TRUE(render::MakePinholeCamera(scene.camera, 41, 41, &camera, &error));
  int shadowed = 0, lit = 0;
  for (int y = 0; y < 41; ++y) {
    for (int x = 0; x < 41; ++x) {
      const Vec3 d = camera.Direction(x + 0.5, y + 0.5);
      const double t = HitSphere(camera.position, d, Vec3(0.0, 0.0, -100.0), 100.0);
      if (t < 0.0) continue;
      const Vec3 p = camera.position + t * d;
      const Vec3 n = (p - Vec3(0.0, 0.0, -100.0)) / 100.0;
      // Skip floor points hidden behind a fibre from the camera, and the shadows' edges.
      if (std::abs(p.x()) > 0.01 && std::abs(p.x()) < 0.03) continue;
      bool hidden = false;
      for (int k = 1; k <= kFibres; ++k) {
        // Ray-line distance to the fibre axis (0, s, 0.1 k).
        const Vec3 m = d.cross(Vec3::UnitY());
        if (std::abs((camera.position - Vec3(0.0, 0.0, 0.1 * k)).dot(m)) / m.norm() < 0.025) {
          hidden = true;
        }
      }
      if (hidden) continue;
      const double lambert = 0.8 / kPi * 2.0 * n.z();
      const bool under = std::abs(p.x()) < 0.01;
      const double expected = under ? lambert * std::pow(0.5, kFibres) : lambert;  // T^N = 1/8
      EXPECT_NEAR(image.At(x, y).x(), expected, 1e-3 * lambert) << x << "," << y;
      (under ? shadowed : lit) += 1;
    }
  }
  EXPECT_GT(shadowed, 3);
  EXPECT_GT(lit, 100);
}

// A Lambertian sphere under the key light only: L = albedo / pi * E * cos(theta), theta between
// the normal and the light (exact for a uniform disk fully above the horizon, render.h), at
// every pixel centre. The only noise is the cosine's variation over the 0.02 rad cone: a
// sample's cos has standard deviation ~ sin(theta) 0.02 / 2, so at 64 spp the standard error is
// 1.25e-3 sin(theta) in units of albedo E / pi; the tolerance is 8 of those.
TEST(RenderTest, LambertianSphereUnderKeyLight) {
  constexpr double kAlbedo = 0.8;
  constexpr double kIrradiance = 2.5;
  RenderScene scene;
  scene.body = SphereBody(Vec3::Zero(), 0.5);
  scene.body_albedo = Rgb::Constant(kAlbedo);
  scene.key.direction = Vec3(0.6, -1.0, 0.8).normalized();
  scene.key.angular_radius = 0.02;
  scene.key.irradiance = Rgb::Constant(kIrradiance);
  scene.environment.top = scene.environment.bottom = Rgb::Zero();
  scene.camera.position = Vec3(0.0, -3.0, 0.0);
  scene.camera.look_at = Vec3::Zero();
  scene.camera.vertical_fov = 0.4;
  RenderOptions options;
  options.width = 32;
  options.height = 32;
  options.samples_per_pixel = 64;
  options.jitter = false;
  Image image;
  RenderStats stats;
  std::string error;
  ASSERT_TRUE(Render(scene, options, &image, &stats, &error)) << error;
  EXPECT_EQ(stats.body_primitives, 1);
  render::PinholeCamera camera;
  ASSERT_TRUE(render::MakePinholeCamera(scene.camera, 32, 32, &camera, &error));
  const Vec3 l = scene.key.direction.normalized();
  int checked = 0;
  double worst = 0.0;
  for (int y = 0; y < 32; ++y) {
    for (int x = 0; x < 32; ++x) {
      const Vec3 d = camera.Direction(x + 0.5, y + 0.5);
      const double t = HitSphere(camera.position, d, Vec3::Zero(), 0.5);
      const float value = image.At(x, y).x();
      if (t < 0.0) {
        EXPECT_EQ(value, 0.0f);
        continue;
      }
      const Vec3 n = (camera.position + t * d) / 0.5;
      const double cos_theta = n.dot(l);
      if (cos_theta < -0.03) {
        EXPECT_EQ(value, 0.0f);  // turned away from the whole disk
      } else if (cos_theta > 0.1) {
        const double expected = kAlbedo / kPi * kIrradiance * cos_theta;
        const double sin_theta = std::sqrt(1.0 - cos_theta * cos_theta);
        const double tolerance = kAlbedo / kPi * kIrradiance * (0.01 * sin_theta + 1e-6);
        EXPECT_NEAR(value, expected, tolerance) << x << "," << y;
        worst = std::max(worst, std::abs(value - expected) / expected);
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 100);
  std::printf("Lambertian sphere: %d pixels, worst relative error %.2e\n", checked, worst);
}

// A fibre model that returns non-finite values: its samples are counted in stats and dropped, the image stays
// finite (pixels seeing only the sky keep their value 1).
TEST(RenderTest, NanSamplesAreCountedAndDropped) {
  HairCurves hair;
  AddStrand(&hair, Line(Vec3(-1.0, 0.0, 0.0), Vec3(1.0, 0.0, 0.0), 3), 0.05);
  RenderScene scene;
  scene.hair = &hair;
  scene.fibre = std::make_shared<NanFibre>();
  scene.key.irradiance = Rgb::Zero();
  scene.environment.top = scene.environment.bottom = Rgb::Ones();
  RenderOptions options;
  options.width = 16;
  options.height = 16;
  options.samples_per_pixel = 2;
  Image image;
  RenderStats stats;
  std::string error;
  ASSERT_TRUE(Render(scene, options, &image, &stats, &error)) << error;
  EXPECT_GT(stats.nan_samples, 0);
  EXPECT_LT(stats.nan_samples, stats.camera_rays);
  for (const auto& p : image.pixels) EXPECT_TRUE(p.allFinite());
  EXPECT_EQ(image.At(0, 0), Eigen::Vector3f::Ones());
}

// Bad options and scenes: false, one line naming the field, the image untouched.
TEST(RenderTest, RejectsBadInput) {
  HairCurves good_hair;
  AddStrand(&good_hair, Line(Vec3(-1.0, 0.0, 0.0), Vec3(1.0, 0.0, 0.0), 3), 0.01);
  HairCurves bad_hair = good_hair;
  bad_hair.point_counts[0] = 2;
  HairCurves far_hair = good_hair;
  far_hair.points[1] = Vec3f::Constant(1e18f);
  HairCurves wide_hair = good_hair;
  wide_hair.widths[0] = 1e18f;
  auto far_body = std::make_shared<Body>();
  {
    std::string why;
    ASSERT_TRUE(
        Body::Create({Sphere{Vec3(1e18, 1e18, 1e18), 1.0, "far"}}, {}, far_body.get(), &why))
        << why;
  }
  struct Case {
    const char* field;
    std::function<void(RenderScene*, RenderOptions*)> mutate;
  };
  const std::vector<Case> cases = {
      {"options.width", [](RenderScene*, RenderOptions* o) { o->width = 0; }},
      {"options.height", [](RenderScene*, RenderOptions* o) { o->height = -3; }},
      {"options.samples_per_pixel",
       [](RenderScene*, RenderOptions* o) { o->samples_per_pixel = 0; }},
      {"options.max_bounces", [](RenderScene*, RenderOptions* o) { o->max_bounces = -1; }},
      {"options.threads", [](RenderScene*, RenderOptions* o) { o->threads = -2; }},
      {"options.tile_size", [](RenderScene*, RenderOptions* o) { o->tile_size = 0; }},
      {"camera.vertical_fov", [](RenderScene* s, RenderOptions*) { s->camera.vertical_fov = 0.0; }},
      {"camera.vertical_fov", [](RenderScene* s, RenderOptions*) { s->camera.vertical_fov = kPi; }},
      {"camera.vertical_fov",
       [](RenderScene* s, RenderOptions*) { s->camera.vertical_fov = std::nan(""); }},
      {"camera.position",
       [](RenderScene* s, RenderOptions*) { s->camera.position.x() = std::nan(""); }},
      {"camera.look_at",
       [](RenderScene* s, RenderOptions*) { s->camera.look_at = s->camera.position; }},
      {"camera.up", [](RenderScene* s, RenderOptions*) { s->camera.up = Vec3::UnitY(); }},
      {"camera.up", [](RenderScene* s, RenderOptions*) { s->camera.up = Vec3::Zero(); }},
      {"fibre", [](RenderScene* s, RenderOptions*) { s->fibre = nullptr; }},
      {"hair", [&](RenderScene* s, RenderOptions*) { s->hair = &bad_hair; }},
      {"body_albedo", [](RenderScene* s, RenderOptions*) { s->body_albedo.y() = 1.5; }},
      {"key.direction", [](RenderScene* s, RenderOptions*) { s->key.direction = Vec3::Zero(); }},
      {"key.angular_radius", [](RenderScene* s, RenderOptions*) { s->key.angular_radius = 0.0; }},
      {"key.angular_radius", [](RenderScene* s, RenderOptions*) { s->key.angular_radius = 2.0; }},
      {"key.irradiance", [](RenderScene* s, RenderOptions*) { s->key.irradiance.x() = -1.0; }},
      {"environment.top",
       [](RenderScene* s, RenderOptions*) { s->environment.top.z() = std::nan(""); }},
      {"environment.bottom",
       [](RenderScene* s, RenderOptions*) {
         s->environment.bottom.x() = std::numeric_limits<double>::infinity();
       }},
      // Issue 16: coordinates Embree cannot trace (it asserted on ray.valid()) are refused.
      {"hair.points[1]: expected coordinates within +-10000 m",
       [&](RenderScene* s, RenderOptions*) { s->hair = &far_hair; }},
      {"hair.widths[0]", [&](RenderScene* s, RenderOptions*) { s->hair = &wide_hair; }},
      {"body.bounds.min", [&](RenderScene* s, RenderOptions*) { s->body = far_body; }},
      {"camera.position",
       [](RenderScene* s, RenderOptions*) { s->camera.position = Vec3(0.0, -1e18, 0.0); }},
  };
  for (const Case& c : cases) {
    RenderScene scene;
    scene.hair = &good_hair;
    scene.fibre = std::make_shared<BlackFibre>();
    RenderOptions options;
    options.width = 4;
    options.height = 4;
    options.samples_per_pixel = 1;
    c.mutate(&scene, &options);
    Image image;
    image.width = 1;
    image.height = 1;
    image.pixels = {Eigen::Vector3f(7.0f, 8.0f, 9.0f)};
    std::string error;
    EXPECT_FALSE(Render(scene, options, &image, nullptr, &error)) << c.field;
    EXPECT_EQ(error.rfind(c.field, 0), 0u) << c.field << " vs " << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    EXPECT_EQ(image.width, 1);
    EXPECT_EQ(image.pixels[0], Eigen::Vector3f(7.0f, 8.0f, 9.0f));
  }
  // The good scene renders.
  RenderScene scene;
  scene.hair = &good_hair;
  scene.fibre = std::make_shared<BlackFibre>();
  RenderOptions options;
  options.width = 4;
  options.height = 4;
  options.samples_per_pixel = 1;
  Image image;
  std::string error;
  EXPECT_TRUE(Render(scene, options, &image, nullptr, &error)) << error;
  EXPECT_FALSE(Render(scene, options, nullptr, nullptr, &error));
  EXPECT_EQ(error.rfind("image", 0), 0u) << error;
}

// FrameCamera: the box's bounding sphere fits the frame (its angular radius is below the
// narrower half field of view), looking along the given direction.
// A body mesh's shading normal (SurfaceHit::shading_normal): on a coarse sphere (an octahedron
// subdivided twice, 128 faces, vertices on the unit sphere) the interpolated corner normals are
// much closer to the exact sphere normal than the flat faces' normals; on a cube (90-degree
// creases, beyond the 60-degree smoothing angle) the shading normal is the face normal exactly.
std::shared_ptr<const Body> MeshBody(std::vector<Vec3> vertices,
                                     std::vector<TriangleMesh::Triangle> triangles) {
  TriangleMesh mesh;
  std::string error;
  EXPECT_TRUE(TriangleMesh::Create(std::move(vertices), std::move(triangles), "mesh", &mesh,
                                   &error))
      << error;
  auto body = std::make_shared<Body>();
  EXPECT_TRUE(Body::Create({}, {mesh}, body.get(), &error)) << error;
  return body;
}

TEST(RenderTest, MeshShadingNormalsAreSmoothButKeepCreases) {
  // Octahedron, each face split in 4 twice, vertices pushed onto the unit sphere.
  std::vector<Vec3> v = {Vec3::UnitX(), -Vec3::UnitX(), Vec3::UnitY(),
                         -Vec3::UnitY(), Vec3::UnitZ(), -Vec3::UnitZ()};
  std::vector<TriangleMesh::Triangle> t = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                           {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (int level = 0; level < 2; ++level) {
    std::map<std::pair<int, int>, int> middle;
    auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = middle.find(key);
      if (it != middle.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      return middle[key] = static_cast<int>(v.size()) - 1;
    };
    std::vector<TriangleMesh::Triangle> finer;
    for (const auto& f : t) {
      const int ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      finer.push_back({f[0], ab, ca});
      finer.push_back({ab, f[1], bc});
      finer.push_back({ca, bc, f[2]});
      finer.push_back({ab, bc, ca});
    }
    t = std::move(finer);
  }
  ASSERT_EQ(t.size(), 128u);
  const auto sphere = MeshBody(v, t);
  HairCurves no_hair;
  std::string error;
  auto scene = render::EmbreeScene::Create(&no_hair, sphere.get(), &error);
  ASSERT_NE(scene, nullptr) << error;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  double flat_error = 0.0, smooth_error = 0.0;
  const int rays = 400;
  for (int k = 0; k < rays; ++k) {
    const Vec3 towards = render::UniformSphere(uniform(rng), uniform(rng));
    const render::SurfaceHit hit =
        scene->Intersect(3.0 * towards, -towards, 0.0, 10.0, render::RayIgnore{});
    ASSERT_EQ(hit.kind, render::HitKind::kBody);
    const Vec3 exact = hit.p.normalized();
    flat_error += std::acos(std::clamp(hit.normal.dot(exact), -1.0, 1.0));
    smooth_error += std::acos(std::clamp(hit.shading_normal.dot(exact), -1.0, 1.0));
    EXPECT_NEAR(hit.shading_normal.norm(), 1.0, 1e-12);
    EXPECT_GT(hit.shading_normal.dot(hit.normal), 0.8);
  }
  // Faces of this mesh span ~20 degrees: flat normals are off by ~7 degrees on average.
  EXPECT_GT(flat_error / rays, 0.08);
  EXPECT_LT(smooth_error, 0.35 * flat_error);

  // A unit cube of 12 triangles: every hit shades with its face's own normal.
  const std::vector<Vec3> c = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),
                               Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(1, 1, 1), Vec3(0, 1, 1)};
  const std::vector<TriangleMesh::Triangle> ct = {
      {0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
      {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  const auto cube = MeshBody(c, ct);
  auto cube_scene = render::EmbreeScene::Create(&no_hair, cube.get(), &error);
  ASSERT_NE(cube_scene, nullptr) << error;
  for (int k = 0; k < rays; ++k) {
    const Vec3 towards = render::UniformSphere(uniform(rng), uniform(rng));
    const render::SurfaceHit hit = cube_scene->Intersect(Vec3(0.5, 0.5, 0.5) + 3.0 * towards,
                                                         -towards, 0.0, 10.0, render::RayIgnore{});
    ASSERT_EQ(hit.kind, render::HitKind::kBody);
    EXPECT_LT((hit.shading_normal - hit.normal).norm(), 1e-12);
  }
}

TEST(RenderTest, FrameCameraFitsTheBox) {
  const Eigen::AlignedBox3d box(Vec3(-0.1, 0.2, 0.0), Vec3(0.3, 0.4, 0.5));
  for (double aspect : {0.5, 1.0, 2.0}) {
    const Camera camera = FrameCamera(box, Vec3(1.0, 1.0, 0.0), 0.7, aspect);
    const Vec3 view = (camera.look_at - camera.position).normalized();
    EXPECT_NEAR(view.dot(Vec3(1.0, 1.0, 0.0).normalized()), 1.0, 1e-12);
    EXPECT_NEAR((camera.look_at - box.center()).norm(), 0.0, 1e-12);
    const double radius = 0.5 * box.diagonal().norm();
    const double angular = std::asin(radius / (camera.look_at - camera.position).norm());
    const double half_h = std::atan(aspect * std::tan(0.35));
    const double half_fov = std::min(0.35, half_h);
    EXPECT_LT(angular, half_fov);
    EXPECT_GT(angular, 0.8 * half_fov);  // not absurdly far
    EXPECT_EQ(camera.up, Vec3::UnitZ());
  }
  EXPECT_EQ(FrameCamera(box, Vec3(0.0, 0.0, -1.0), 0.7, 1.0).up, Vec3::UnitY());
}

}  // namespace
}  // namespace ringlet
