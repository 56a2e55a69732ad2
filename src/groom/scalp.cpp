// Scalp regions, Poisson-disk roots by dart throwing, combed root frames (scalp.h).
#include "ringlet/scalp.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <sstream>
#include <unordered_map>

#include "groom/random.h"

namespace ringlet {
namespace {

constexpr double kPi = std::numbers::pi;

bool IsFinite(const Vec3& v) { return v.allFinite(); }

// Coefficients of theta_max(phi) = a0 + a1 cos(phi) + a2 cos(2 phi) through the three given
// hairline angles: at phi = 0: a0 + a1 + a2 = front; at pi/2: a0 - a2 = side; at pi:
// a0 - a1 + a2 = back.
struct Hairline {
  double a0, a1, a2;
};

Hairline HairlineCoefficients(const SphereScalp& s) {
  const double mean_front_back = 0.5 * (s.hairline_front + s.hairline_back);
  return Hairline{0.5 * (mean_front_back + s.hairline_side),
                  0.5 * (s.hairline_front - s.hairline_back),
                  0.5 * (mean_front_back - s.hairline_side)};
}

// Exact range of theta_max over all azimuths. With x = cos(phi), cos(2 phi) = 2x^2 - 1, so
// theta_max = (a0 - a2) + a1 x + 2 a2 x^2 is a quadratic on x in [-1, 1]: its extremes are at
// x = +-1 or at the vertex x = -a1 / (4 a2).
void HairlineRange(const Hairline& h, double* lo, double* hi) {
  auto at = [&](double x) { return (h.a0 - h.a2) + h.a1 * x + 2.0 * h.a2 * x * x; };
  *lo = std::min(at(-1.0), at(1.0));
  *hi = std::max(at(-1.0), at(1.0));
  if (h.a2 != 0.0) {
    const double x = -h.a1 / (4.0 * h.a2);
    if (x > -1.0 && x < 1.0) {
      *lo = std::min(*lo, at(x));
      *hi = std::max(*hi, at(x));
    }
  }
}

// A candidate root before combing.
struct Candidate {
  Vec3 position;
  Vec3 normal;
  int triangle;
};

// Integer cell of a uniform grid of cell size r; roots closer than r are in the same or
// neighbouring cells, so a query visits 27 cells.
struct Cell {
  int64_t x, y, z;
  bool operator==(const Cell&) const = default;
};
struct CellHash {
  size_t operator()(const Cell& c) const {
    const uint64_t h = groom::SplitMix64::Mix(static_cast<uint64_t>(c.x) * 0x9E3779B97F4A7C15ull ^
                                              static_cast<uint64_t>(c.y) * 0xC2B2AE3D27D4EB4Full ^
                                              static_cast<uint64_t>(c.z) * 0x165667B19E3779F9ull);
    return static_cast<size_t>(h);
  }
};

// Random sequential dart throwing with a spatial grid (Cook, "Stochastic sampling in computer
// graphics", ACM TOG 5(1), 1986, the Poisson-disk "dart throwing" process; the background grid
// of cell size r as in Bridson, "Fast Poisson disk sampling in arbitrary dimensions", SIGGRAPH
// 2007 sketches). A candidate is accepted when no accepted point is within r. Candidates are
// uniform on the surface, so stopping at `count` accepted points leaves a homogeneous set.
// Rejected alternative: Bridson's annulus growth needs a flat parameter domain; on a curved
// scalp or a triangle soup, uniform darts are simpler and exact in distribution.
template <class Generate>
void ThrowDarts(Generate&& generate, double r, int count, int64_t max_darts,
                std::vector<Candidate>* accepted, int64_t* darts) {
  std::unordered_map<Cell, std::vector<int>, CellHash> grid;
  grid.reserve(static_cast<size_t>(count) * 2);
  const double r2 = r * r;
  auto cell_of = [&](const Vec3& p) {
    return Cell{static_cast<int64_t>(std::floor(p.x() / r)),
                static_cast<int64_t>(std::floor(p.y() / r)),
                static_cast<int64_t>(std::floor(p.z() / r))};
  };
  accepted->clear();
  *darts = 0;
  while (static_cast<int>(accepted->size()) < count && *darts < max_darts) {
    ++*darts;
    const Candidate c = generate();
    const Cell home = cell_of(c.position);
    bool free = true;
    for (int64_t dx = -1; dx <= 1 && free; ++dx) {
      for (int64_t dy = -1; dy <= 1 && free; ++dy) {
        for (int64_t dz = -1; dz <= 1 && free; ++dz) {
          const auto it = grid.find(Cell{home.x + dx, home.y + dy, home.z + dz});
          if (it == grid.end()) continue;
          for (int k : it->second) {
            if (((*accepted)[k].position - c.position).squaredNorm() < r2) {
              free = false;
              break;
            }
          }
        }
      }
    }
    if (!free) continue;
    grid[home].push_back(static_cast<int>(accepted->size()));
    accepted->push_back(c);
  }
}

// Shared tail of both samplers: disk radius, darts, frames, summary.
template <class Generate>
void SampleAndComb(Generate&& generate, const HeadFrame& head, double area,
                   const RootSamplingOptions& options, const CombOptions& comb,
                   std::vector<Root>* roots, RootSamplingSummary* summary) {
  // r = sqrt(packing A / N): see RootSamplingOptions.
  const double r = std::sqrt(options.packing * area / options.count);
  std::vector<Candidate> accepted;
  int64_t darts = 0;
  ThrowDarts(generate, r, options.count,
             static_cast<int64_t>(options.count) * options.trials_per_root, &accepted, &darts);

  roots->clear();
  roots->reserve(accepted.size());
  for (const Candidate& c : accepted) {
    Root root;
    root.position = c.position;
    root.normal = c.normal;
    root.frame = CombedRootFrame(c.position, c.normal, head, comb, &root.parting_side);
    root.head = ComputeHeadCoordinates(head, c.position);
    root.triangle = c.triangle;
    roots->push_back(root);
  }

  RootSamplingSummary s;
  s.requested = options.count;
  s.achieved = static_cast<int>(roots->size());
  s.disk_radius = r;
  s.area = area;
  s.darts = darts;
  std::ostringstream m;
  m << "placed " << s.achieved << " of " << s.requested << " roots (disk radius " << r * 1e3
    << " mm, scalp area " << area * 1e4 << " cm^2, " << darts << " darts)";
  if (s.achieved < s.requested) {
    m << "; the dart budget ran out: lower 'packing' or raise 'trials_per_root'";
  }
  s.message = m.str();
  if (summary) *summary = s;
}

}  // namespace

bool IsValid(const HeadFrame& head, std::string* why) {
  if (!IsFinite(head.centre) || !IsFinite(head.up) || !IsFinite(head.front)) {
    if (why) *why = "head: centre, up and front must be finite 3-vectors";
    return false;
  }
  const double nu = head.up.norm();
  const double nf = head.front.norm();
  if (nu == 0.0 || nf == 0.0) {
    if (why) *why = "head: up and front must be non-zero vectors";
    return false;
  }
  if (head.up.cross(head.front).norm() < 1e-6 * nu * nf) {
    if (why) *why = "head: up and front must not be parallel";
    return false;
  }
  return true;
}

Mat3 HeadAxes(const HeadFrame& head) {
  const Vec3 up = head.up.normalized();
  const Vec3 front = (head.front - up * up.dot(head.front)).normalized();
  Mat3 axes;
  axes.col(0) = up;
  axes.col(1) = front;
  axes.col(2) = up.cross(front);  // left
  return axes;
}

HeadCoordinates ComputeHeadCoordinates(const HeadFrame& head, const Vec3& p) {
  const Mat3 axes = HeadAxes(head);
  const Vec3 d = p - head.centre;
  const double along_up = d.dot(axes.col(0));
  const double x = d.dot(axes.col(1));  // toward the face
  const double y = d.dot(axes.col(2));  // toward the left
  HeadCoordinates c;
  // atan2 of (|component off the axis|, component along it): accurate at every angle.
  c.polar_angle = std::atan2(std::hypot(x, y), along_up);
  c.azimuth = std::atan2(y, x);
  c.height = along_up;
  return c;
}

bool IsValid(const SphereScalp& scalp, std::string* why) {
  if (!IsValid(scalp.head, why)) return false;
  if (!(std::isfinite(scalp.radius) && scalp.radius > 0.0)) {
    if (why) *why = "scalp.radius: expected a finite number > 0 (m)";
    return false;
  }
  const std::pair<const char*, double> angles[] = {{"hairline_front", scalp.hairline_front},
                                                   {"hairline_side", scalp.hairline_side},
                                                   {"hairline_back", scalp.hairline_back}};
  for (const auto& [name, value] : angles) {
    if (!(std::isfinite(value) && value > 0.0 && value < kPi)) {
      if (why) *why = std::string("scalp.") + name + ": expected a polar angle in (0, pi) rad";
      return false;
    }
  }
  double lo = 0.0, hi = 0.0;
  HairlineRange(HairlineCoefficients(scalp), &lo, &hi);
  if (!(lo > 0.0 && hi < kPi)) {
    if (why) {
      *why =
          "scalp hairline: the curve through hairline_front/side/back leaves (0, pi) between "
          "them; bring the three angles closer together";
    }
    return false;
  }
  return true;
}

double HairlinePolarAngle(const SphereScalp& scalp, double azimuth) {
  const Hairline h = HairlineCoefficients(scalp);
  return h.a0 + h.a1 * std::cos(azimuth) + h.a2 * std::cos(2.0 * azimuth);
}

bool InScalp(const SphereScalp& scalp, const Vec3& p, double angle_tolerance) {
  const HeadCoordinates c = ComputeHeadCoordinates(scalp.head, p);
  return c.polar_angle <= HairlinePolarAngle(scalp, c.azimuth) + angle_tolerance;
}

double ScalpArea(const SphereScalp& scalp) {
  // Area of {theta <= theta_max(phi)} on a sphere: integral of R^2 sin(theta) dtheta dphi
  // = R^2 * integral_0^{2 pi} (1 - cos theta_max(phi)) dphi; trapezoidal rule (periodic).
  constexpr int kSteps = 4096;
  double sum = 0.0;
  for (int i = 0; i < kSteps; ++i) {
    const double phi = 2.0 * kPi * i / kSteps;
    sum += 1.0 - std::cos(HairlinePolarAngle(scalp, phi));
  }
  return scalp.radius * scalp.radius * sum * (2.0 * kPi / kSteps);
}

bool IsValid(const MeshScalp& scalp, std::string* why) {
  if (!IsValid(scalp.head, why)) return false;
  for (size_t i = 0; i < scalp.vertices.size(); ++i) {
    if (!IsFinite(scalp.vertices[i])) {
      if (why) *why = "scalp.vertices[" + std::to_string(i) + "]: expected finite coordinates";
      return false;
    }
  }
  if (scalp.triangles.empty()) {
    if (why) *why = "scalp.triangles: expected at least one triangle";
    return false;
  }
  const int nv = static_cast<int>(scalp.vertices.size());
  for (size_t k = 0; k < scalp.triangles.size(); ++k) {
    for (int v : scalp.triangles[k]) {
      if (v < 0 || v >= nv) {
        if (why) {
          *why = "scalp.triangles[" + std::to_string(k) + "]: vertex index " + std::to_string(v) +
                 " is outside [0, " + std::to_string(nv) + ")";
        }
        return false;
      }
    }
  }
  if (!(ScalpArea(scalp) > 0.0)) {
    if (why) *why = "scalp.triangles: the total area must be positive";
    return false;
  }
  return true;
}

double ScalpArea(const MeshScalp& scalp) {
  double area = 0.0;
  for (const auto& t : scalp.triangles) {
    const Vec3& a = scalp.vertices[t[0]];
    area += 0.5 * (scalp.vertices[t[1]] - a).cross(scalp.vertices[t[2]] - a).norm();
  }
  return area;
}

bool IsValid(const RootSamplingOptions& options, std::string* why) {
  if (options.count < 1) {
    if (why) *why = "roots.count: expected an integer >= 1";
    return false;
  }
  if (!(std::isfinite(options.packing) && options.packing > 0.0 && options.packing <= 0.69)) {
    if (why) {
      *why = "roots.packing: expected N r^2 / A in (0, 0.69] (dart throwing jams near 0.697)";
    }
    return false;
  }
  if (options.trials_per_root < 1) {
    if (why) *why = "roots.trials_per_root: expected an integer >= 1";
    return false;
  }
  return true;
}

bool IsValid(const CombOptions& comb, std::string* why) {
  if (!(std::isfinite(comb.tilt) && comb.tilt >= 0.0 && comb.tilt <= 0.5 * kPi)) {
    if (why) *why = "comb.tilt: expected an angle in [0, pi/2] rad from the scalp normal";
    return false;
  }
  const std::pair<const char*, const Vec3*> vectors[] = {
      {"direction", &comb.direction},
      {"fallback_direction", &comb.fallback_direction},
      {"parting_normal", &comb.parting_normal}};
  for (const auto& [name, v] : vectors) {
    if (!IsFinite(*v) || v->norm() == 0.0) {
      if (why) *why = std::string("comb.") + name + ": expected a finite, non-zero 3-vector";
      return false;
    }
  }
  if (!(std::isfinite(comb.parting_offset))) {
    if (why) *why = "comb.parting_offset: expected a finite distance (m)";
    return false;
  }
  if (!(std::isfinite(comb.parting_strength) && comb.parting_strength >= 0.0)) {
    if (why) *why = "comb.parting_strength: expected a finite number >= 0";
    return false;
  }
  if (!(std::isfinite(comb.face_sweep) && comb.face_sweep >= 0.0)) {
    if (why) *why = "comb.face_sweep: expected a finite number >= 0";
    return false;
  }
  return true;
}

Mat3 CombedRootFrame(const Vec3& position, const Vec3& normal, const HeadFrame& head,
                     const CombOptions& comb, int* parting_side) {
  const Vec3 n = normal.normalized();
  auto tangential = [&](const Vec3& v) -> Vec3 { return v - n * n.dot(v); };

  // Comb direction in the tangent plane; the fallback covers the whorl of `direction`.
  Vec3 c = tangential(comb.direction);
  if (c.norm() < 1e-3 * comb.direction.norm()) c = tangential(comb.fallback_direction);
  if (c.norm() < 1e-3 * comb.fallback_direction.norm()) c = n.unitOrthogonal();
  c.normalize();

  // Away from the face: around the head toward the back, the direction of growing |phi| (phi the
  // azimuth from the face), weighted (1 + cos phi) / 2 (CombOptions::face_sweep). Where that
  // direction is normal to the scalp it has no tangential part and is skipped.
  if (comb.face_sweep > 0.0) {
    const Mat3 axes = HeadAxes(head);  // columns up, front, left
    const double phi = ComputeHeadCoordinates(head, position).azimuth;
    const double side = phi >= 0.0 ? 1.0 : -1.0;
    const Vec3 b =
        tangential(side * (-std::sin(phi) * axes.col(1) + std::cos(phi) * axes.col(2)));
    if (b.norm() > 1e-9) {
      c += comb.face_sweep * 0.5 * (1.0 + std::cos(phi)) * b.normalized();
      c = c.norm() > 1e-12 ? Vec3(c.normalized()) : Vec3(b.normalized());
    }
  }

  // Parting: drop the component toward the part, add a lean away from it.
  int side = 0;
  if (comb.parting) {
    const double h = comb.parting_normal.dot(position - head.centre) - comb.parting_offset;
    side = h >= 0.0 ? 1 : -1;
    const Vec3 m = tangential(comb.parting_normal);
    // Where the normal is parallel to the parting normal (far from the part, e.g. at the ears)
    // "away from the part" has no tangential direction; the comb direction alone applies.
    if (m.norm() > 1e-9 * comb.parting_normal.norm()) {
      const Vec3 u = side * m.normalized();
      c -= std::min(0.0, c.dot(u)) * u;
      c += comb.parting_strength * u;
      c = c.norm() > 1e-12 ? c.normalized() : u;
    }
  }
  if (parting_side) *parting_side = side;

  // t leans from n toward c by `tilt`; n1 lateral, n2 = t x n1 (see CombOptions).
  const Vec3 t = std::cos(comb.tilt) * n + std::sin(comb.tilt) * c;
  const Vec3 n1 = n.cross(c).normalized();
  Mat3 frame;
  frame.col(0) = n1;
  frame.col(1) = t.cross(n1);
  frame.col(2) = t;
  return frame;
}

bool SampleRoots(const SphereScalp& scalp, const RootSamplingOptions& options,
                 const CombOptions& comb, std::vector<Root>* roots, RootSamplingSummary* summary,
                 std::string* why) {
  if (!IsValid(scalp, why) || !IsValid(options, why) || !IsValid(comb, why)) return false;
  const Hairline h = HairlineCoefficients(scalp);
  double lo = 0.0, hi = 0.0;
  HairlineRange(h, &lo, &hi);
  const Mat3 axes = HeadAxes(scalp.head);
  const double cos_cap = std::cos(hi);

  // Uniform on the cap theta <= max theta_max (z = cos theta uniform: Archimedes' hat-box
  // theorem), kept when inside the hairline. Rejection keeps the distribution uniform by area.
  groom::SplitMix64 rng(groom::StreamSeed(options.seed, 0));
  auto generate = [&]() -> Candidate {
    for (;;) {
      const double z = rng.Uniform(cos_cap, 1.0);
      const double phi = rng.Uniform(-kPi, kPi);
      if (z < std::cos(h.a0 + h.a1 * std::cos(phi) + h.a2 * std::cos(2.0 * phi))) continue;
      const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
      const Vec3 n = axes * Vec3(z, s * std::cos(phi), s * std::sin(phi));
      return Candidate{scalp.head.centre + scalp.radius * n, n, -1};
    }
  };
  SampleAndComb(generate, scalp.head, ScalpArea(scalp), options, comb, roots, summary);
  return true;
}

bool SampleRoots(const MeshScalp& scalp, const RootSamplingOptions& options,
                 const CombOptions& comb, std::vector<Root>* roots, RootSamplingSummary* summary,
                 std::string* why) {
  if (!IsValid(scalp, why) || !IsValid(options, why) || !IsValid(comb, why)) return false;

  // Cumulative areas for choosing a triangle with probability proportional to its area, and
  // outward normals (turned away from the head centre).
  const size_t nt = scalp.triangles.size();
  std::vector<double> cumulative(nt);
  std::vector<Vec3> normals(nt);
  double total = 0.0;
  for (size_t k = 0; k < nt; ++k) {
    const auto& t = scalp.triangles[k];
    const Vec3& a = scalp.vertices[t[0]];
    const Vec3& b = scalp.vertices[t[1]];
    const Vec3& c = scalp.vertices[t[2]];
    const Vec3 cross = (b - a).cross(c - a);
    total += 0.5 * cross.norm();
    cumulative[k] = total;
    Vec3 n = cross.norm() > 0.0 ? cross.normalized() : Vec3::UnitZ();
    if (n.dot((a + b + c) / 3.0 - scalp.head.centre) < 0.0) n = -n;
    normals[k] = n;
  }

  groom::SplitMix64 rng(groom::StreamSeed(options.seed, 0));
  auto generate = [&]() -> Candidate {
    const double u = rng.Uniform() * total;
    // First triangle whose cumulative area exceeds u: zero-area triangles are never chosen.
    size_t k = static_cast<size_t>(std::upper_bound(cumulative.begin(), cumulative.end(), u) -
                                   cumulative.begin());
    k = std::min(k, nt - 1);
    while (k > 0 && cumulative[k] == cumulative[k - 1]) --k;  // guard rounding at the end
    const auto& t = scalp.triangles[k];
    // Uniform point on the triangle (Osada et al. 2002, eq. 1).
    const double r1 = std::sqrt(rng.Uniform());
    const double r2 = rng.Uniform();
    const Vec3 p = (1.0 - r1) * scalp.vertices[t[0]] + r1 * (1.0 - r2) * scalp.vertices[t[1]] +
                   r1 * r2 * scalp.vertices[t[2]];
    return Candidate{p, normals[k], static_cast<int>(k)};
  };
  SampleAndComb(generate, scalp.head, total, options, comb, roots, summary);
  return true;
}

}  // namespace ringlet
