// Cutting the generated strands (wisp masters and children) at a cut region: the child strands
// are procedural (wisp.cpp) and leave their master's cut point by their offsets, jitter and frizz,
// so after the masters are cut and re-solved each drawn strand is ended where it first leaves the
// region (docs/styling.md, "Cut").
#include <cassert>
#include <cmath>

#include "ringlet/styling.h"

namespace ringlet {
namespace {

// The float point at parameter t of the segment a -> b, as ApplyStrandCuts stores it.
Vec3f PointAt(const Vec3f& a, const Vec3f& b, double t) {
  return (a.cast<double>() + t * (b - a).cast<double>()).cast<float>();
}

// How far inside the region a point is (m, >= 0 inside), given the polyline arc length from
// the root to it (m): the region's Inside, or for kMaxLength the length left.
double Margin(const CutRegion& region, const Vec3f& point, double arc_length) {
  if (region.kind == CutRegion::Kind::kMaxLength) return region.length - arc_length;
  return region.Inside(point.cast<double>());
}

}  // namespace

int ClipStrands(const CutRegion& region, const HairCurves& strands,
                std::vector<StrandCut>* cuts) {
  const int n = strands.NumStrands();
  if (static_cast<int>(cuts->size()) != n) cuts->assign(static_cast<size_t>(n), StrandCut{});
  int clipped = 0;
  size_t first = 0;
  for (int k = 0; k < n; ++k) {
    const int count = static_cast<int>(strands.point_counts[static_cast<size_t>(k)]);
    const Vec3f* p = strands.points.data() + first;
    first += static_cast<size_t>(count);
    StrandCut& cut = (*cuts)[static_cast<size_t>(k)];
    // The strand as it is drawn now: points 0 .. last, the last segment up to t_end.
    const int last_segment = cut.segment >= 0 ? cut.segment : count - 2;
    const double t_end = cut.segment >= 0 ? cut.t : 1.0;
    if (Margin(region, p[0], 0.0) < 0.0) continue;  // rooted outside: not cut
    double s = 0.0;  // polyline arc length to p[j] (m), summed in double
    for (int j = 0; j <= last_segment; ++j) {
      const double t_hi = j == last_segment ? t_end : 1.0;
      const double length = (p[j + 1] - p[j]).cast<double>().norm();
      const auto margin = [&](double t) {
        const Vec3f q = PointAt(p[j], p[j + 1], t);
        return Margin(region, q, s + (q - p[j]).cast<double>().norm());
      };
      if (margin(t_hi) >= 0.0) {
        s += length;
        continue;
      }
      // Inside at t = 0 (p[j], checked before), outside at t_hi: bisection to rounding, the
      // float point tested, so the kept end is inside.
      double lo = 0.0, hi = t_hi;
      for (int i = 0; i < 80; ++i) {
        const double mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi) break;
        (margin(mid) >= 0.0 ? lo : hi) = mid;
      }
      cut.segment = j;
      cut.t = lo;
      ++clipped;
      break;
    }
  }
  return clipped;
}

void ApplyStrandCuts(const std::vector<StrandCut>& cuts, HairCurves* strands) {
  if (cuts.empty()) return;
  const int n = strands->NumStrands();
  assert(static_cast<int>(cuts.size()) == n);
  const bool axes = !strands->major_axes.empty();
  HairCurves out;
  out.colors = strands->colors;
  out.point_counts.reserve(static_cast<size_t>(n));
  out.points.reserve(strands->points.size());
  out.widths.reserve(strands->points.size());
  if (axes) out.major_axes.reserve(strands->points.size());
  size_t first = 0;
  for (int k = 0; k < n; ++k) {
    const int count = static_cast<int>(strands->point_counts[static_cast<size_t>(k)]);
    const StrandCut& cut = cuts[static_cast<size_t>(k)];
    assert(cut.segment < count - 1);
    const int keep = cut.segment >= 0 ? cut.segment + 1 : count;
    for (int j = 0; j < keep; ++j) {
      const size_t i = first + static_cast<size_t>(j);
      out.points.push_back(strands->points[i]);
      out.widths.push_back(strands->widths[i]);
      if (axes) out.major_axes.push_back(strands->major_axes[i]);
    }
    int kept = keep;
    if (cut.segment >= 0) {
      // The end point, exactly as ClipStrands tested it (PointAt).
      const size_t a = first + static_cast<size_t>(cut.segment);
      out.points.push_back(PointAt(strands->points[a], strands->points[a + 1], cut.t));
      out.widths.push_back(static_cast<float>(
          strands->widths[a] + cut.t * (strands->widths[a + 1] - strands->widths[a])));
      if (axes) out.major_axes.push_back(strands->major_axes[a]);
      ++kept;
    }
    out.point_counts.push_back(static_cast<std::uint32_t>(kept));
    first += static_cast<size_t>(count);
  }
  *strands = std::move(out);
}

}  // namespace ringlet
