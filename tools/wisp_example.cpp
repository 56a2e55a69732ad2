// Writes the CSV behind docs/images/wisp.png: one straight and one curly 20-cm master, solved
// under gravity from a horizontal root, each with a wisp of 60 strands (default WispOptions plus
// a little jitter and frizz). The wisp radius is set to 5 mm so the wisps show at the scale of a
// 20-cm strand; the automatic radius of each master is printed (about 0.5 and 1.2 mm). Columns: wisp, strand, point, x, y, z (m); strand 0 is the master.
//   usage: wisp_example OUT.csv   then   /usr/bin/python3 scripts/plot_wisp.py OUT.csv OUT.png
#include <cstdio>
#include <string>
#include <vector>

#include "ringlet/statics.h"
#include "ringlet/strand_geometry.h"
#include "ringlet/wisp.h"

int main(int argc, char** argv) {
  using namespace ringlet;
  if (argc != 2) {
    std::fprintf(stderr, "usage: wisp_example OUT.csv\n");
    return 2;
  }
  std::vector<FramedCentreline> masters;
  for (int curly = 0; curly < 2; ++curly) {
    StrandModel m;
    m.segment_lengths = UniformSegments(0.2, 30);
    m.section = SectionFromEccentricity(50e-6, 0.0);
    if (curly) m.natural_curvature = Vec3(60.0, 0.0, 12.0);
    m.root_position = Vec3(0.0, 0.06 * curly, 0.0);
    m.root_frame.col(0) = Vec3(0, 0, 1);   // n1 up
    m.root_frame.col(1) = Vec3(0, -1, 0);  // n2 = t x n1
    m.root_frame.col(2) = Vec3(1, 0, 0);   // tangent horizontal
    const StrandSolution s = SolveStrand(m);
    if (!s.summary.Converged()) {
      std::fprintf(stderr, "wisp_example: master %d did not converge: %s\n", curly,
                   s.summary.message.c_str());
      return 1;
    }
    masters.push_back(SampleFramedCentreline(m, s.curvatures, 4));
  }
  WispOptions o;
  o.strands_per_wisp = 60;
  o.points_per_strand = 121;
  o.wisp_radius = 5e-3;
  o.jitter = 5e-4;
  o.frizz_amplitude = 3e-4;
  std::string why;
  const HairCurves h =
      GenerateWisps(masters, {SectionFromEccentricity(50e-6, 0.0)}, o, 2005, nullptr, &why);
  if (h.NumStrands() == 0) {
    std::fprintf(stderr, "wisp_example: %s\n", why.c_str());
    return 1;
  }
  std::FILE* f = std::fopen(argv[1], "w");
  if (f == nullptr) {
    std::fprintf(stderr, "wisp_example: cannot write %s\n", argv[1]);
    return 1;
  }
  std::fprintf(f, "wisp,strand,point,x,y,z\n");
  size_t p = 0;
  for (int k = 0; k < h.NumStrands(); ++k) {
    for (std::uint32_t j = 0; j < h.point_counts[k]; ++j, ++p) {
      std::fprintf(f, "%d,%d,%u,%.7g,%.7g,%.7g\n", k / o.strands_per_wisp, k % o.strands_per_wisp,
                   j, h.points[p].x(), h.points[p].y(), h.points[p].z());
    }
  }
  std::fclose(f);
  for (int i = 0; i < 2; ++i) {
    WispOptions automatic = o;
    automatic.wisp_radius = 0.0;
    std::printf("wisp %d: curliness %.3f, automatic r_w %.3g m (drawn with %.3g m)\n", i,
                Curliness(masters[i]),
                ResolveWispRadius(masters[i], SectionFromEccentricity(50e-6, 0.0), automatic),
                o.wisp_radius);
  }
  return 0;
}
