// The tracer on a synthetic head: 10,000 wavy strands of 24 points on a 10 cm sphere, 200 x 200
// pixels, 4 samples per pixel, both shadow modes, with a stand-in fibre model (the tracer's own
// cost) and with HairBsdf (Chiang 2016, elliptic). Counters: rays per second of tracing (all
// rays: camera, bounce, shadow; the Embree build excluded) and the build time. Also the cost of
// one HairBsdf evaluation and one sample, for both scattering models.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <numbers>

#include "ringlet/hair_bsdf.h"
#include "ringlet/render.h"

namespace {

using ringlet::Rgb;
using ringlet::Vec3;

// A stand-in scattering model (not HairBsdf, which lives elsewhere): isotropic, albedo 0.4,
// straight-through transmittance 0.3; it costs what the tracer costs, not what a fibre model
// costs.
class GreyFibre final : public ringlet::FibreScattering {
 public:
  Rgb Eval(const Vec3&, const Vec3&, const ringlet::FibreHit&) const override {
    return Rgb::Constant(0.4 / (4.0 * std::numbers::pi));
  }
  ringlet::ScatterSample Sample(const Vec3&, const ringlet::FibreHit&,
                                const std::array<double, 4>& u) const override {
    const double z = 1.0 - 2.0 * u[0];
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = 2.0 * std::numbers::pi * u[1];
    ringlet::ScatterSample s;
    s.wi = Vec3(r * std::cos(phi), r * std::sin(phi), z);
    s.pdf = 1.0 / (4.0 * std::numbers::pi);
    s.weight = Rgb::Constant(0.4);
    return s;
  }
  double Pdf(const Vec3&, const Vec3&, const ringlet::FibreHit&) const override {
    return 1.0 / (4.0 * std::numbers::pi);
  }
  Rgb Transmittance(const Vec3&, const ringlet::FibreHit&) const override {
    return Rgb::Constant(0.3);
  }
};

// Roots on the upper part of a 10 cm head (Fibonacci lattice), strands 25 cm long: out along
// the normal, then falling, with a 1 cm wave.
ringlet::HairCurves SyntheticHead(int strands, int points) {
  ringlet::HairCurves hair;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < strands; ++k) {
    const double z = 1.0 - 0.9 * (k + 0.5) / strands;  // polar angle up to ~84 degrees
    const double r = std::sqrt(1.0 - z * z);
    const Vec3 normal(r * std::cos(golden * k), r * std::sin(golden * k), z);
    const Vec3 side = normal.cross(Vec3::UnitZ()).normalized();
    hair.point_counts.push_back(static_cast<std::uint32_t>(points));
    for (int i = 0; i < points; ++i) {
      const double s = static_cast<double>(i) / (points - 1);
      Vec3 p = 0.1 * normal + 0.04 * s * normal - 0.25 * s * s * Vec3::UnitZ() +
               0.01 * std::sin(12.0 * s + k) * (side.allFinite() ? side : Vec3::UnitX());
      // Keep the falling part outside the head.
      const double d = p.norm();
      if (d < 0.102) p *= 0.102 / d;
      hair.points.push_back(p.cast<float>());
      hair.widths.push_back(80e-6f);
    }
  }
  return hair;
}

void BM_RenderHead(benchmark::State& state) {
  static const ringlet::HairCurves hair = SyntheticHead(10000, 24);
  auto body = std::make_shared<ringlet::Body>();
  std::string error;
  ringlet::Body::Create({ringlet::Sphere{Vec3::Zero(), 0.1, "head"}}, {}, body.get(), &error);
  ringlet::RenderScene scene;
  scene.hair = &hair;
  if (state.range(1) == 0) {
    scene.fibre = std::make_shared<GreyFibre>();
  } else {
    ringlet::HairOptics optics;
    optics.sigma_a = ringlet::AbsorptionFromMelanin(1.3, 0.2);
    optics.eccentricity = 0.705;  // caucasian ellipticity 1.41
    scene.fibre = std::make_shared<ringlet::HairBsdf>(optics);
  }
  scene.body = body;
  Eigen::AlignedBox3d box;
  for (const auto& p : hair.points) box.extend(p.cast<double>());
  scene.camera = ringlet::FrameCamera(box, Vec3(0.3, 1.0, -0.2), 0.6, 1.0);
  ringlet::RenderOptions options;
  options.width = 200;
  options.height = 200;
  options.samples_per_pixel = 4;
  options.max_bounces = 16;
  options.shadows = state.range(0) == 0 ? ringlet::ShadowMode::kPathTraced
                                        : ringlet::ShadowMode::kFibreTransmittance;
  std::int64_t rays = 0;
  double seconds = 0.0;
  double build_seconds = 0.0;
  for (auto _ : state) {
    ringlet::Image image;
    ringlet::RenderStats stats;
    if (!ringlet::Render(scene, options, &image, &stats, &error)) {
      state.SkipWithError(error.c_str());
      return;
    }
    rays += stats.rays;
    seconds += stats.seconds;
    build_seconds += stats.build_seconds;
    benchmark::DoNotOptimize(image.pixels.data());
  }
  // Rays per second of tracing (the Embree build excluded), and the build's share.
  state.counters["rays_per_s"] = static_cast<double>(rays) / (seconds - build_seconds);
  state.counters["build_ms"] = 1e3 * build_seconds / state.iterations();
  state.counters["rays_per_render"] = static_cast<double>(rays) / state.iterations();
  state.counters["segments"] = static_cast<double>(hair.points.size() - hair.point_counts.size());
}
// Args: shadow mode (0 path traced, 1 fibre transmittance), fibre (0 stand-in, 1 HairBsdf).
BENCHMARK(BM_RenderHead)
    ->Args({0, 0})
    ->Args({1, 0})
    ->Args({0, 1})
    ->Args({1, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// One HairBsdf Eval or Sample on pseudo-random directions and offsets (fixed sequence).
void BM_HairBsdf(benchmark::State& state) {
  ringlet::HairOptics optics;
  optics.model = state.range(0) == 0 ? ringlet::HairScatteringModel::kChiang2016
                                     : ringlet::HairScatteringModel::kMarschner2003;
  optics.sigma_a = ringlet::AbsorptionFromMelanin(1.3, 0.2);
  optics.eccentricity = 0.705;
  const ringlet::HairBsdf bsdf(optics);
  const bool sample = state.range(1) == 1;
  std::uint64_t k = 0;
  for (auto _ : state) {
    ++k;
    const double a = 0.6180339887 * k, b = 0.7548776662 * k, c = 0.5698402910 * k;
    const double u0 = a - std::floor(a), u1 = b - std::floor(b), u2 = c - std::floor(c);
    const double st = 2.0 * u0 - 1.0, ct = std::sqrt(1.0 - st * st);
    const Vec3 wo(st, 0.0, ct);
    const ringlet::FibreHit hit{2.0 * u1 - 1.0, u2 * std::numbers::pi};
    if (sample) {
      benchmark::DoNotOptimize(bsdf.Sample(wo, hit, {u1, u2, u0, 0.5}));
    } else {
      const double pt = 2.0 * u2 - 1.0, pc = std::sqrt(1.0 - pt * pt);
      const double phi = 2.0 * std::numbers::pi * u1;
      benchmark::DoNotOptimize(bsdf.Eval(wo, Vec3(pt, pc * std::cos(phi), pc * std::sin(phi)), hit));
    }
  }
}
// Args: model (0 Chiang 2016, 1 Marschner 2003), operation (0 Eval, 1 Sample).
BENCHMARK(BM_HairBsdf)->Args({0, 0})->Args({0, 1})->Args({1, 0})->Args({1, 1});

}  // namespace

BENCHMARK_MAIN();
