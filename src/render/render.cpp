// The tracer: validation, tiles in parallel, and the path integrator (render.h).
#include "ringlet/render.h"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <numbers>
#include <sstream>

#include "render/camera.h"
#include "render/embree_scene.h"
#include "render/sampler.h"
#include "ringlet/denoise.h"

namespace ringlet {
namespace render {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
// Russian roulette starts at this bounce (pbrt-v3's rrDepth is 3 as well).
constexpr int kRouletteBounce = 3;

// The lights in the form the integrator uses them.
struct Lights {
  // Key light: a uniform disk of radiance key_radiance on the cone of directions within
  // angular_radius of key_direction. The irradiance it gives a surface facing it is the
  // radiance times the cap's projected solid angle, integral cos(theta) dw = pi sin^2(r)
  // (exact for a uniform spherical cap; and pi sin^2(r) cos(theta_n) on a surface tilted by
  // theta_n while the whole cap is above its horizon), so key_radiance = E / (pi sin^2 r).
  // Dividing by the solid angle 2 pi (1 - cos r) instead would be off by (1 + cos r) / 2,
  // 1e-4 for r = 0.02 rad.
  bool key_on = false;
  Vec3 key_direction = Vec3::UnitZ();
  double key_cos_max = 1.0;
  double key_pdf = 0.0;  // 1 / (2 pi (1 - cos r)), uniform cone sampling (1/sr)
  Rgb key_radiance = Rgb::Zero();
  Frame key_frame{Vec3::UnitZ()};
  // Environment: blended linearly in the z of the direction.
  bool environment_on = false;
  Rgb top = Rgb::Zero();
  Rgb bottom = Rgb::Zero();

  Rgb Key(const Vec3& w) const {
    return key_on && w.dot(key_direction) >= key_cos_max ? key_radiance : Rgb::Zero();
  }
  Rgb Environment(const Vec3& w) const {
    const double a = 0.5 * (w.z() + 1.0);
    return (1.0 - a) * bottom + a * top;
  }
};

Lights MakeLights(const RenderScene& scene) {
  Lights lights;
  const KeyLight& key = scene.key;
  lights.key_on = key.irradiance.maxCoeff() > 0.0;
  lights.key_direction = key.direction.normalized();
  lights.key_cos_max = std::cos(key.angular_radius);
  // 1 - cos r = 2 sin^2(r / 2): no cancellation for small r.
  const double one_minus_cos = 2.0 * std::pow(std::sin(0.5 * key.angular_radius), 2);
  lights.key_pdf = 1.0 / (2.0 * std::numbers::pi * one_minus_cos);
  lights.key_radiance =
      key.irradiance / (std::numbers::pi * std::pow(std::sin(key.angular_radius), 2));
  lights.key_frame = Frame(lights.key_direction);
  lights.top = scene.environment.top;
  lights.bottom = scene.environment.bottom;
  lights.environment_on = std::max(lights.top.maxCoeff(), lights.bottom.maxCoeff()) > 0.0;
  return lights;
}

// Rec. 709 luminance of linear RGB.
double Luminance(const Rgb& c) { return 0.2126 * c.x() + 0.7152 * c.y() + 0.0722 * c.z(); }

// Everything a sample needs, shared read-only by the threads.
struct Context {
  const EmbreeScene* scene;
  const FibreScattering* fibre;
  const RenderScene* render_scene;
  const RenderOptions* options;
  Lights lights;
  PinholeCamera camera;
  // The denoiser's albedo guide of a fibre hit: the fibre's directional albedo seen at normal
  // incidence through its axis (h = 0, theta_o = 0), dry and wet, blended by the strand's
  // wetness. One colour per strand rather than per hit: the guide should say which surface a
  // pixel sees (hair of this colour), not carry the lobes' dependence on where in the fibre a
  // sample landed, which would be noise in the guide (and would cost a lobe setup per sample).
  Rgb fibre_albedo_dry = Rgb::Zero();
  Rgb fibre_albedo_wet = Rgb::Zero();
};

// A scattering vertex: a fibre or the Lambertian body, with where rays leave from.
struct Vertex {
  bool fibre = false;
  FibreFrame frame;              // fibre
  Vec3 wo_local = Vec3::Zero();  // fibre
  Vec3 normal = Vec3::UnitZ();   // body, facing wo
  Frame body_frame{Vec3::UnitZ()};
  Vec3 origin = Vec3::Zero();
  RayIgnore ignore;

  // f(wo, wi) including the cosine (fibre_scattering.h's convention; Lambert: albedo cos / pi).
  Rgb Eval(const Context& c, const Vec3& wi) const {
    if (fibre) return c.fibre->Eval(wo_local, frame.ToLocal(wi), frame.hit);
    return c.render_scene->body_albedo * (std::max(0.0, normal.dot(wi)) * std::numbers::inv_pi);
  }
  double Pdf(const Context& c, const Vec3& wi) const {
    if (fibre) return c.fibre->Pdf(wo_local, frame.ToLocal(wi), frame.hit);
    return std::max(0.0, normal.dot(wi)) * std::numbers::inv_pi;
  }
  // A direction to sample the environment with: uniform on the sphere for fibres (they scatter
  // all around), cosine-weighted for the body.
  Vec3 SampleEnvironment(double u1, double u2, double* pdf) const {
    if (fibre) {
      *pdf = kUniformSpherePdf;
      return UniformSphere(u1, u2);
    }
    const Vec3 wi = CosineHemisphere(body_frame, u1, u2);
    *pdf = std::max(0.0, normal.dot(wi)) * std::numbers::inv_pi;
    return wi;
  }
  double EnvironmentPdf(const Vec3& wi) const {
    if (fibre) return kUniformSpherePdf;
    return std::max(0.0, normal.dot(wi)) * std::numbers::inv_pi;
  }
};

Vertex MakeVertex(const Context& c, const SurfaceHit& hit, const Vec3& wo) {
  Vertex v;
  if (hit.kind == HitKind::kHair) {
    v.fibre = true;
    v.frame = MakeFibreFrame(hit, wo, c.render_scene->orientation_seed);
    v.wo_local = v.frame.ToLocal(wo);
    v.origin = hit.p;
    v.ignore = c.scene->IgnoreFor(hit);
  } else {
    // The body is closed and seen from outside; flip anyway if a ray arrives from inside. Shading
    // uses the smooth normal (SurfaceHit::shading_normal) on the side of the geometric one that
    // faces wo; rays leave from the geometric surface.
    const bool front = hit.normal.dot(wo) >= 0.0;
    const Vec3 geometric = front ? hit.normal : Vec3(-hit.normal);
    v.normal = front ? hit.shading_normal : Vec3(-hit.shading_normal);
    v.body_frame = Frame(v.normal);
    v.origin = hit.p + c.scene->body_offset() * geometric;
  }
  return v;
}

// What reaches the vertex from direction wi (unit) of the lights, through the scene: 1 or 0 in
// kPathTraced (fibres opaque), the fibres' transmittance product in kFibreTransmittance.
Rgb Visibility(const Context& c, const Vertex& v, const Vec3& wi, std::int64_t* rays) {
  if (c.options->shadows == ShadowMode::kFibreTransmittance) {
    if (c.fibre == nullptr) {
      ++*rays;
      return c.scene->Occluded(v.origin, wi, 0.0, kInfinity, v.ignore) ? Rgb::Zero() : Rgb::Ones();
    }
    return ShadowTransmittance(*c.scene, *c.fibre, c.render_scene->orientation_seed, v.origin, wi,
                               0.0, kInfinity, v.ignore, rays);
  }
  ++*rays;
  return c.scene->Occluded(v.origin, wi, 0.0, kInfinity, v.ignore) ? Rgb::Zero() : Rgb::Ones();
}

// Next-event estimation at v: one key-light sample (uniform cone) and one environment sample,
// each weighted against BSDF sampling by the power heuristic when mis is true.
Rgb DirectLight(const Context& c, const Vertex& v, bool mis, PixelSampler* sampler,
                std::int64_t* rays) {
  Rgb radiance = Rgb::Zero();
  const Lights& lights = c.lights;
  const auto [u1, u2] = sampler->Get2D();
  const auto [u3, u4] = sampler->Get2D();
  if (lights.key_on) {
    const Vec3 wi = UniformCone(lights.key_frame, lights.key_cos_max, u1, u2);
    const Rgb f = v.Eval(c, wi);
    if (f.maxCoeff() > 0.0) {
      const double weight = mis ? PowerHeuristic(lights.key_pdf, v.Pdf(c, wi)) : 1.0;
      const Rgb visible = Visibility(c, v, wi, rays);
      radiance += f.cwiseProduct(visible).cwiseProduct(lights.key_radiance) *
                  (weight / lights.key_pdf);
    }
  }
  if (lights.environment_on) {
    double pdf = 0.0;
    const Vec3 wi = v.SampleEnvironment(u3, u4, &pdf);
    const Rgb f = pdf > 0.0 ? v.Eval(c, wi) : Rgb::Zero();
    if (f.maxCoeff() > 0.0) {
      const double weight = mis ? PowerHeuristic(pdf, v.Pdf(c, wi)) : 1.0;
      const Rgb visible = Visibility(c, v, wi, rays);
      radiance += f.cwiseProduct(visible).cwiseProduct(lights.Environment(wi)) * (weight / pdf);
    }
  }
  return radiance;
}

// Scales value down so that its largest channel is at most clamp (0: no clamp), keeping its hue.
Rgb Clamped(const Rgb& value, double clamp) {
  const double m = value.maxCoeff();
  return clamp > 0.0 && m > clamp ? Rgb(value * (clamp / m)) : value;
}

// What the denoiser's guides record of a camera sample's first hit.
struct FirstHit {
  Rgb albedo = Rgb::Zero();      // body_albedo, the fibre's albedo, or 0 for the background
  Vec3 normal = Vec3::Zero();    // body normal facing the camera, fibre tangent, or 0
  double depth = 0.0;            // distance from the camera (m), 0 for the background
};

// The radiance arriving along the camera ray (org, dir): path tracing with next-event
// estimation and MIS (Veach 1997, ch. 9; pbrt-v3's PathIntegrator), or direct light through
// fibre transmittance in kFibreTransmittance. With options.clamp > 0, every contribution of a
// path of two or more scattering events (indirect light) is clamped (Clamped) before it is added.
Rgb TraceSample(const Context& c, const Vec3& org, Vec3 dir, PixelSampler* sampler,
                std::int64_t* rays, FirstHit* first) {
  const bool direct_only = c.options->shadows == ShadowMode::kFibreTransmittance;
  const double clamp = c.options->clamp;
  ++*rays;
  SurfaceHit hit = c.scene->Intersect(org, dir, 0.0, kInfinity, RayIgnore());
  if (hit.kind == HitKind::kNone) return c.lights.Environment(dir) + c.lights.Key(dir);
  Rgb radiance = Rgb::Zero();
  Rgb beta = Rgb::Ones();
  for (int bounce = 0;; ++bounce) {
    const Vertex v = MakeVertex(c, hit, -dir);
    if (bounce == 0) {
      first->depth = hit.t;
      if (v.fibre) {
        const double w = v.frame.hit.wetness;
        first->albedo = (1.0 - w) * c.fibre_albedo_dry + w * c.fibre_albedo_wet;
        first->normal = v.frame.x;
      } else {
        first->albedo = c.render_scene->body_albedo;
        first->normal = v.normal;
      }
    }
    const Rgb direct = beta.cwiseProduct(DirectLight(c, v, !direct_only, sampler, rays));
    radiance += bounce == 0 ? direct : Clamped(direct, clamp);
    if (direct_only) break;

    // Sample the next direction from the scattering model: (u0, u3) pick the lobe and the
    // azimuth, (u1, u2) the longitudinal angle (hair_bsdf.cpp's Sample).
    const auto [u0, u3] = sampler->Get2D();
    const auto [u1, u2] = sampler->Get2D();
    const std::array<double, 4> u = {u0, u1, u2, u3};
    Vec3 wi;
    Rgb weight;
    double pdf = 0.0;
    if (v.fibre) {
      const ScatterSample s = c.fibre->Sample(v.wo_local, v.frame.hit, u);
      wi = v.frame.ToWorld(s.wi);
      weight = s.weight;
      pdf = s.pdf;
    } else {
      wi = CosineHemisphere(v.body_frame, u[0], u[1]);
      pdf = std::max(0.0, v.normal.dot(wi)) * std::numbers::inv_pi;
      weight = c.render_scene->body_albedo;  // (albedo cos / pi) / (cos / pi)
    }
    if (!(pdf > 0.0) || !(weight.maxCoeff() > 0.0)) break;
    beta = beta.cwiseProduct(weight);

    // Follow it; if it escapes, the lights it sees count with the BSDF strategy's MIS weight.
    ++*rays;
    hit = c.scene->Intersect(v.origin, wi, 0.0, kInfinity, v.ignore);
    if (hit.kind == HitKind::kNone) {
      const Rgb seen =
          c.lights.Environment(wi) * PowerHeuristic(pdf, v.EnvironmentPdf(wi)) +
          c.lights.Key(wi) * PowerHeuristic(pdf, c.lights.key_pdf);
      const Rgb escaped = beta.cwiseProduct(seen);
      radiance += bounce == 0 ? escaped : Clamped(escaped, clamp);
      break;
    }
    if (bounce + 1 > c.options->max_bounces) break;
    // Russian roulette (Arvo & Kirk 1990): continue with probability q = min(1, max beta)
    // and divide by q, unbiased.
    if (bounce + 1 >= kRouletteBounce) {
      const double q = std::min(1.0, beta.maxCoeff());
      if (sampler->Get1D() >= q) break;
      beta /= q;
    }
    dir = wi;
  }
  return radiance;
}

bool CheckRgb(const Rgb& value, const char* field, double max, std::string* why) {
  if (value.allFinite() && value.minCoeff() >= 0.0 && value.maxCoeff() <= max) return true;
  std::ostringstream message;
  message << field << ": expected finite values in [0, " << max << "], got (" << value.x()
          << ", " << value.y() << ", " << value.z() << ")";
  *why = message.str();
  return false;
}

bool CheckInt(long long value, long long min, long long max, const char* field, std::string* why) {
  if (value >= min && value <= max) return true;
  std::ostringstream message;
  message << field << ": expected an integer in [" << min << ", " << max << "], got " << value;
  *why = message.str();
  return false;
}

// Whether every coordinate of p lies within kMaxSceneCoordinate (false for NaN).
template <typename Vector>
bool WithinScene(const Vector& p) {
  for (int c = 0; c < 3; ++c) {
    if (!(std::abs(static_cast<double>(p[c])) <= kMaxSceneCoordinate)) return false;
  }
  return true;
}

// "field: expected coordinates within +-1e4 m (the renderer's limit), got (x, y, z)".
template <typename Vector>
bool OutsideScene(const std::string& field, const Vector& p, std::string* why) {
  std::ostringstream message;
  message << field << ": expected coordinates within +-" << kMaxSceneCoordinate
          << " m (the renderer's limit), got (" << p[0] << ", " << p[1] << ", " << p[2] << ")";
  *why = message.str();
  return false;
}



// Checks everything Render relies on; one line naming the field on failure.
bool CheckInputs(const RenderScene& scene, const RenderOptions& options, PinholeCamera* camera,
                 std::string* why) {
  constexpr long long kMaxSide = 1 << 16;
  if (!CheckInt(options.width, 1, kMaxSide, "options.width", why) ||
      !CheckInt(options.height, 1, kMaxSide, "options.height", why) ||
      !CheckInt(options.samples_per_pixel, 1, 1 << 20, "options.samples_per_pixel", why) ||
      !CheckInt(options.max_bounces, 0, 1 << 16, "options.max_bounces", why) ||
      !CheckInt(options.threads, 0, 1 << 12, "options.threads", why) ||
      !CheckInt(options.tile_size, 1, kMaxSide, "options.tile_size", why)) {
    return false;
  }
  if (!(options.clamp >= 0.0) || std::isnan(options.clamp)) {
    std::ostringstream message;
    message << "options.clamp: expected a radiance >= 0 (0 = off), got " << options.clamp;
    *why = message.str();
    return false;
  }
  if (options.pattern != SamplePattern::kSobol && options.pattern != SamplePattern::kIndependent) {
    *why = "options.pattern: expected kSobol or kIndependent";
    return false;
  }
  if (!CheckRenderSize(options.width, options.height, options.samples_per_pixel, why)) {
    *why = "options: " + *why;
    return false;
  }
  if (!MakePinholeCamera(scene.camera, options.width, options.height, camera, why)) return false;
  if (scene.hair != nullptr) {
    if (scene.fibre == nullptr) {
      *why = "fibre: a FibreScattering model is required when hair is set";
      return false;
    }
    if (!CheckHairCurves(*scene.hair, "hair", why)) return false;
    if (scene.hair->points.size() >= std::numeric_limits<std::uint32_t>::max()) {
      *why = "hair.points: more than 2^32 - 2 points (Embree's 32-bit indices)";
      return false;
    }
    // Embree asserts on rays it cannot represent: every coordinate is bounded first.
    for (size_t i = 0; i < scene.hair->points.size(); ++i) {
      if (!WithinScene(scene.hair->points[i])) {
        return OutsideScene("hair.points[" + std::to_string(i) + "]", scene.hair->points[i], why);
      }
      if (!(scene.hair->widths[i] <= kMaxSceneCoordinate)) {
        std::ostringstream message;
        message << "hair.widths[" << i << "]: expected at most " << kMaxSceneCoordinate
                << " m (the renderer's limit), got " << scene.hair->widths[i];
        *why = message.str();
        return false;
      }
    }
  }
  if (scene.body != nullptr && !scene.body->Bounds().isEmpty()) {
    const Box3& bounds = scene.body->Bounds();
    if (!WithinScene(bounds.min())) return OutsideScene("body.bounds.min", bounds.min(), why);
    if (!WithinScene(bounds.max())) return OutsideScene("body.bounds.max", bounds.max(), why);
  }
  if (!WithinScene(scene.camera.position)) {
    return OutsideScene("camera.position", scene.camera.position, why);
  }
  if (!WithinScene(scene.camera.look_at)) {
    return OutsideScene("camera.look_at", scene.camera.look_at, why);
  }
  if (!CheckRgb(scene.body_albedo, "body_albedo", 1.0, why)) return false;
  const KeyLight& key = scene.key;
  if (!key.direction.allFinite() || !(key.direction.norm() > 0.0)) {
    *why = "key.direction: expected a finite non-zero vector";
    return false;
  }
  if (!(key.angular_radius > 0.0 && key.angular_radius < 0.5 * std::numbers::pi)) {
    std::ostringstream message;
    message << "key.angular_radius: expected a number in (0, pi/2) (rad), got "
            << key.angular_radius;
    *why = message.str();
    return false;
  }
  constexpr double kMaxFinite = std::numeric_limits<double>::max();
  return CheckRgb(key.irradiance, "key.irradiance", kMaxFinite, why) &&
         CheckRgb(scene.environment.top, "environment.top", kMaxFinite, why) &&
         CheckRgb(scene.environment.bottom, "environment.bottom", kMaxFinite, why);
}

}  // namespace
}  // namespace render

bool CheckRenderSize(int width, int height, int samples_per_pixel, std::string* why) {
  const std::int64_t pixels = std::int64_t{width} * height;
  if (pixels > kMaxRenderPixels) {
    if (why) {
      *why = "width x height = " + std::to_string(width) + " x " + std::to_string(height) + " = " +
             std::to_string(pixels) + " pixels, more than the limit of 2^26 = " +
             std::to_string(kMaxRenderPixels) + " (e.g. 8192 x 8192)";
    }
    return false;
  }
  // pixels <= 2^26 and samples_per_pixel < 2^31: the product fits in 64 bits.
  const std::int64_t samples = pixels * samples_per_pixel;
  if (samples > kMaxRenderSamples) {
    if (why) {
      *why = "width x height x samples_per_pixel = " + std::to_string(width) + " x " +
             std::to_string(height) + " x " + std::to_string(samples_per_pixel) + " = " +
             std::to_string(samples) + " camera samples, more than the limit of 2^30 = " +
             std::to_string(kMaxRenderSamples);
    }
    return false;
  }
  return true;
}

bool Render(const RenderScene& scene, const RenderOptions& options, Image* image,
            RenderStats* stats, std::string* error) {
  using namespace render;
  const auto start = std::chrono::steady_clock::now();
  std::string why;
  Context c;
  if (image == nullptr) {
    if (error != nullptr) *error = "image: expected a non-null output image";
    return false;
  }
  if (!CheckInputs(scene, options, &c.camera, &why)) {
    if (error != nullptr) *error = why;
    return false;
  }
  c.render_scene = &scene;
  c.options = &options;
  c.fibre = scene.hair != nullptr ? scene.fibre.get() : nullptr;
  c.lights = MakeLights(scene);
  if (c.fibre != nullptr && options.denoise) {
    FibreHit axis;  // h = 0, dry
    c.fibre_albedo_dry = c.fibre->Albedo(Vec3::UnitZ(), axis);
    axis.wetness = 1.0;
    c.fibre_albedo_wet = c.fibre->Albedo(Vec3::UnitZ(), axis);
  }

  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  std::unique_ptr<EmbreeScene> embree;
  const auto build_start = std::chrono::steady_clock::now();
  arena.execute([&] { embree = EmbreeScene::Create(scene.hair, scene.body.get(), &why); });
  const double build_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - build_start).count();
  if (embree == nullptr) {
    if (error != nullptr) *error = why;
    return false;
  }
  c.scene = embree.get();

  // Tiles in row-major order; each pixel's samples use their own random streams, so the
  // result does not depend on which thread renders which tile.
  const int width = options.width;
  const int height = options.height;
  const int tile = options.tile_size;
  const long tiles_x = (width + tile - 1) / tile;
  const long tiles_y = (height + tile - 1) / tile;
  const long tiles = tiles_x * tiles_y;
  const int spp = options.samples_per_pixel;
  Image result;
  result.width = width;
  result.height = height;
  result.pixels.assign(static_cast<size_t>(width) * height, Eigen::Vector3f::Zero());
  // Per pixel: the sum of its finite samples so far and their number (passes add to them in
  // sample order, so the mean is the same whatever the passes).
  const size_t pixels = static_cast<size_t>(width) * height;
  std::vector<Rgb> sums(pixels, Rgb::Zero());
  std::vector<int> counts(pixels, 0);
  // The denoiser's guides, summed over each pixel's finite samples like the colour: luminance
  // squared (for the variance), first-hit albedo, normal and depth.
  const bool guides = options.denoise;
  std::vector<double> sums_luminance2(guides ? pixels : 0, 0.0);
  std::vector<Rgb> sums_albedo(guides ? pixels : 0, Rgb::Zero());
  std::vector<Vec3> sums_normal(guides ? pixels : 0, Vec3::Zero());
  std::vector<double> sums_depth(guides ? pixels : 0, 0.0);
  std::atomic<std::int64_t> rays{0};
  std::atomic<std::int64_t> nan_samples{0};
  std::mutex progress_mutex;
  long tiles_done = 0;
  // The passes: [0, 1), [1, 2), [2, 4), [4, 8), ... up to spp; one pass without pass_done.
  std::vector<int> pass_end;
  if (options.pass_done) {
    for (int end = 1; end < spp; end = std::min(spp, 2 * end)) pass_end.push_back(end);
  }
  pass_end.push_back(spp);
  const long total_tiles = tiles * static_cast<long>(pass_end.size());
  const auto cancelled = [&options] {
    return options.cancel != nullptr && options.cancel->load(std::memory_order_relaxed);
  };

  auto render_tile = [&](long index, int s_begin, int s_end) {
    if (cancelled()) return;
    const int x0 = static_cast<int>(index % tiles_x) * tile;
    const int y0 = static_cast<int>(index / tiles_x) * tile;
    const int x1 = std::min(x0 + tile, width);
    const int y1 = std::min(y0 + tile, height);
    std::int64_t tile_rays = 0;
    std::int64_t tile_nans = 0;
    for (int y = y0; y < y1; ++y) {
      for (int x = x0; x < x1; ++x) {
        const std::uint64_t pixel = static_cast<std::uint64_t>(y) * width + x;
        Rgb& sum = sums[pixel];
        int& valid = counts[pixel];
        for (int s = s_begin; s < s_end; ++s) {
          PixelSampler sampler(options.seed, pixel, static_cast<std::uint64_t>(s),
                               options.pattern == SamplePattern::kSobol);
          // Box filter: a uniform point in the pixel (its centre without jitter).
          const auto [jx, jy] = sampler.Get2D();
          const double px = x + (options.jitter ? jx : 0.5);
          const double py = y + (options.jitter ? jy : 0.5);
          FirstHit first;
          const Rgb value = TraceSample(c, c.camera.position, c.camera.Direction(px, py),
                                        &sampler, &tile_rays, &first);
          if (!value.allFinite()) {
            ++tile_nans;
            continue;
          }
          sum += value;
          ++valid;
          if (guides) {
            const double l = Luminance(value);
            sums_luminance2[pixel] += l * l;
            sums_albedo[pixel] += first.albedo;
            sums_normal[pixel] += first.normal;
            sums_depth[pixel] += first.depth;
          }
        }
        if (valid > 0) result.At(x, y) = (sum / valid).cast<float>();
      }
    }
    rays += tile_rays;
    nan_samples += tile_nans;
    if (options.progress) {
      std::lock_guard<std::mutex> lock(progress_mutex);
      options.progress(++tiles_done, total_tiles);
    }
  };
  int s_begin = 0;
  for (const int s_end : pass_end) {
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<long>(0, tiles, 1), [&](const tbb::blocked_range<long>& r) {
        for (long i = r.begin(); i != r.end(); ++i) render_tile(i, s_begin, s_end);
      });
    });
    if (cancelled()) {
      if (error != nullptr) *error = "cancelled";
      return false;
    }
    if (options.pass_done) options.pass_done(result, s_end);
    s_begin = s_end;
  }

  double denoise_seconds = 0.0;
  if (options.denoise) {
    const auto denoise_start = std::chrono::steady_clock::now();
    DenoiseGuides g;
    g.width = width;
    g.height = height;
    g.albedo.assign(pixels, Eigen::Vector3f::Zero());
    g.normal.assign(pixels, Eigen::Vector3f::Zero());
    g.depth.assign(pixels, 0.0f);
    g.variance.assign(pixels, -1.0f);
    for (size_t i = 0; i < pixels; ++i) {
      const int n = counts[i];
      if (n == 0) continue;
      g.albedo[i] = (sums_albedo[i] / n).cast<float>();
      g.normal[i] = (sums_normal[i] / n).cast<float>();
      g.depth[i] = static_cast<float>(sums_depth[i] / n);
      if (n > 1) {
        // The unbiased sample variance of the luminance over n, the variance of the mean.
        const double mean = Luminance(sums[i]) / n;
        const double sample_variance =
            std::max(0.0, (sums_luminance2[i] - n * mean * mean) / (n - 1));
        g.variance[i] = static_cast<float>(sample_variance / n);
      }
    }
    DenoiseOptions denoise_options;
    bool denoised = false;
    arena.execute([&] { denoised = DenoiseImage(result, g, denoise_options, &result, &why); });
    if (!denoised) {
      if (error != nullptr) *error = why;
      return false;
    }
    denoise_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - denoise_start).count();
  }

  *image = std::move(result);
  if (stats != nullptr) {
    stats->denoise_seconds = denoise_seconds;
    stats->camera_rays = static_cast<std::int64_t>(width) * height * spp;
    stats->rays = rays.load();
    stats->nan_samples = nan_samples.load();
    stats->hair_segments = embree->hair_segments();
    stats->body_primitives = embree->body_primitives();
    stats->build_seconds = build_seconds;
    stats->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return true;
}

bool RenderLabelMaps(const RenderScene& scene, const RenderOptions& options,
                     double min_width_pixels, RenderLabels* labels, std::string* error) {
  using namespace render;
  std::string why;
  PinholeCamera camera;
  if (labels == nullptr) {
    if (error != nullptr) *error = "labels: expected a non-null output";
    return false;
  }
  if (!CheckInputs(scene, options, &camera, &why)) {
    if (error != nullptr) *error = why;
    return false;
  }
  if (!(min_width_pixels >= 0.0) || !std::isfinite(min_width_pixels)) {
    if (error != nullptr) *error = "min_width_pixels: expected a finite number >= 0";
    return false;
  }
  // The traced hair: widths of at least min_width_pixels pixel footprints at each point's depth.
  HairCurves widened;
  const HairCurves* hair = scene.hair;
  if (hair != nullptr && min_width_pixels > 0.0) {
    widened = *hair;
    const double per_depth = min_width_pixels * 2.0 * camera.half_height / camera.height;
    for (size_t i = 0; i < widened.points.size(); ++i) {
      const double z = (widened.points[i].cast<double>() - camera.position).dot(camera.forward);
      widened.widths[i] = std::max(widened.widths[i], static_cast<float>(per_depth * std::abs(z)));
    }
    hair = &widened;
  }
  tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
  std::unique_ptr<EmbreeScene> embree;
  arena.execute([&] { embree = EmbreeScene::Create(hair, scene.body.get(), &why); });
  if (embree == nullptr) {
    if (error != nullptr) *error = why;
    return false;
  }
  const int width = options.width;
  const int height = options.height;
  const size_t pixels = static_cast<size_t>(width) * height;
  RenderLabels out;
  out.width = width;
  out.height = height;
  out.hair.assign(pixels, 0);
  out.depth.assign(pixels, 0.0f);
  out.direction.assign(pixels, Eigen::Vector2f::Zero());
  // Rows in parallel; every pixel is one ray, written only by its row.
  arena.execute([&] {
    tbb::parallel_for(0, height, [&](int y) {
      for (int x = 0; x < width; ++x) {
        const size_t pixel = static_cast<size_t>(y) * width + x;
        const Vec3 dir = camera.Direction(x + 0.5, y + 0.5);
        const SurfaceHit hit = embree->Intersect(camera.position, dir, 0.0, kInfinity, RayIgnore{});
        if (hit.kind == HitKind::kNone) continue;
        out.depth[pixel] = static_cast<float>(hit.t * dir.dot(camera.forward));
        if (hit.kind != HitKind::kHair) continue;
        out.hair[pixel] = 1;
        const Eigen::Vector2d d(hit.tangent.dot(camera.right), hit.tangent.dot(camera.up));
        const double n = d.norm();
        if (n >= 1e-6) out.direction[pixel] = (d / n).cast<float>();
      }
    });
  });
  *labels = std::move(out);
  return true;
}

}  // namespace ringlet
