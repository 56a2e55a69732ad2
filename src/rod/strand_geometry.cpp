// Strand reconstruction from curvatures: products of closed-form helical segments.
#include "ringlet/strand_geometry.h"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "ringlet/helix.h"

namespace ringlet {

StrandGeometry ComputeGeometry(const StrandModel& model, const VecX& curvatures,
                               std::vector<Vec3>* segment_moments) {
  const int n = model.NumSegments();
  assert(curvatures.size() == 3 * n);
  StrandGeometry g;
  g.points.resize(n + 1);
  g.frames.resize(n + 1);
  if (segment_moments) segment_moments->resize(n);
  g.points[0] = model.root_position;
  g.frames[0] = model.root_frame;
  for (int i = 0; i < n; ++i) {
    const HelixSegment s =
        EvaluateHelixSegment(curvatures.segment<3>(3 * i), model.segment_lengths[i]);
    g.points[i + 1] = g.points[i] + g.frames[i] * s.chord;
    g.frames[i + 1] = g.frames[i] * s.rotation;
    if (segment_moments) (*segment_moments)[i] = s.moment;
  }
  return g;
}

StrandGeometry ComputeGeometry(const StrandModel& model, const VecX& curvatures) {
  return ComputeGeometry(model, curvatures, nullptr);
}

std::vector<Vec3> SampleCentreline(const StrandModel& model, const VecX& curvatures,
                                   int points_per_segment) {
  assert(points_per_segment >= 1);
  const int n = model.NumSegments();
  const StrandGeometry g = ComputeGeometry(model, curvatures);
  std::vector<Vec3> points;
  points.reserve(static_cast<size_t>(n) * points_per_segment + 1);
  for (int i = 0; i < n; ++i) {
    const Vec3 omega = curvatures.segment<3>(3 * i);
    points.push_back(g.points[i]);
    for (int k = 1; k < points_per_segment; ++k) {
      const double u = model.segment_lengths[i] * k / points_per_segment;
      points.push_back(g.points[i] + g.frames[i] * HelixChord(omega, u));
    }
  }
  points.push_back(g.points[n]);
  return points;
}

std::vector<Vec3> SampleCentrelineAt(const StrandModel& model, const VecX& curvatures,
                                     const std::vector<double>& arc_lengths) {
  const int n = model.NumSegments();
  std::vector<Vec3> points;
  if (n == 0) return points;
  const StrandGeometry g = ComputeGeometry(model, curvatures);
  points.reserve(arc_lengths.size());
  int i = 0;         // segment holding the current arc length
  double start = 0;  // arc length at the start of segment i (m)
  for (double s : arc_lengths) {
    s = std::isfinite(s) ? std::max(s, 0.0) : 0.0;
    // Advance to the segment that holds s (arc lengths are nondecreasing); past the tip, the
    // last segment's end.
    while (i < n - 1 && s > start + model.segment_lengths[i]) {
      start += model.segment_lengths[i];
      ++i;
    }
    const double l = model.segment_lengths[i];
    const double u = std::min(s - start, l);
    if (u <= 0.0) {
      points.push_back(g.points[i]);
    } else if (u >= l) {
      points.push_back(g.points[i + 1]);
    } else {
      points.push_back(g.points[i] + g.frames[i] * HelixChord(curvatures.segment<3>(3 * i), u));
    }
  }
  return points;
}

FramedCentreline SampleFramedCentreline(const StrandModel& model, const VecX& curvatures,
                                        int points_per_segment) {
  assert(points_per_segment >= 1);
  const int n = model.NumSegments();
  const StrandGeometry g = ComputeGeometry(model, curvatures);
  FramedCentreline c;
  const size_t size = static_cast<size_t>(n) * points_per_segment + 1;
  c.points.reserve(size);
  c.frames.reserve(size);
  c.arc_lengths.reserve(size);
  double s = 0.0;  // arc length at the start of segment i (m)
  for (int i = 0; i < n; ++i) {
    const Vec3 omega = curvatures.segment<3>(3 * i);
    const double l = model.segment_lengths[i];
    c.points.push_back(g.points[i]);
    c.frames.push_back(g.frames[i]);
    c.arc_lengths.push_back(s);
    for (int k = 1; k < points_per_segment; ++k) {
      // One closed-form evaluation gives both the partial chord p(u) and rotation R(u).
      const double u = l * k / points_per_segment;
      const HelixSegment partial = EvaluateHelixSegment(omega, u);
      c.points.push_back(g.points[i] + g.frames[i] * partial.chord);
      c.frames.push_back(g.frames[i] * partial.rotation);
      c.arc_lengths.push_back(s + u);
    }
    s += l;
  }
  c.points.push_back(g.points[n]);
  c.frames.push_back(g.frames[n]);
  c.arc_lengths.push_back(s);
  return c;
}

}  // namespace ringlet
