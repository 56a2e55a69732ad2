// Writes the CSV behind docs/images/drape_sphere.png, the paper's Figure 2 (right): "a curly hair
// strand growing on a sphere". One curly strand (the mean of the caucasian/curly preset:
// R = 1.2 cm, pitch 0.6 cm, docs/hair-types.md) is rooted on top of a sphere of radius 10 cm and
// solved under gravity with the body contact penalty (section 3.1, E_c = 1/2 k x^2) at 5 lengths.
// The strand grows: every length adds segments of the same 5 mm at the tip, and each solve starts
// from the previous equilibrium (the new segments at their natural curvature), as a growing hair
// would. The root tangent leans 60 degrees from the normal toward +x (the comb tilt of
// docs/hairstyles.md's examples is 1.0 to 1.2 rad), and the curl starts away from the sphere
// (negative kappa1^0, as ringlet groom does).
//   usage: drape_example OUT.csv   then   /usr/bin/python3 scripts/plot_drape.py OUT.csv OUT.png
// Columns: length_index, length (m), point, x, y, z (m); the first line is a comment
// "# sphere cx cy cz radius" (m). One summary line per length goes to stdout.
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "ringlet/body.h"
#include "ringlet/hair_type.h"
#include "ringlet/statics.h"
#include "ringlet/strand_geometry.h"

int main(int argc, char** argv) {
  using namespace ringlet;
  if (argc != 2) {
    std::fprintf(stderr, "usage: drape_example OUT.csv\n");
    return 2;
  }
  // The sphere: the mannequin's head (examples/bodies/mannequin.json).
  Sphere sphere;
  sphere.center = Vec3::Zero();
  sphere.radius = 0.1;
  sphere.name = "sphere";
  auto body = std::make_shared<Body>();
  std::string error;
  if (!Body::Create({sphere}, {}, body.get(), &error)) {
    std::fprintf(stderr, "drape_example: %s\n", error.c_str());
    return 1;
  }

  HairType type;
  if (!FindHairType("caucasian", "curly", &type, &error)) {
    std::fprintf(stderr, "drape_example: %s\n", error.c_str());
    return 1;
  }
  StrandModel m;
  m.section = SectionFromEllipticity(type.mean_radius, type.ellipticity);
  m.material = type.material;
  m.natural_curvature = type.MeanNaturalCurvature();
  m.natural_curvature.x() = -std::abs(m.natural_curvature.x());  // curl away from the sphere
  m.root_position = sphere.center + Vec3(0.0, 0.0, sphere.radius);
  const double tilt = 60.0 * std::numbers::pi / 180.0;
  const Vec3 tangent(std::sin(tilt), 0.0, std::cos(tilt));
  // n1 lateral (+y) = n x c for the normal n = +z and comb direction c = +x (scalp.h).
  if (!RootFrameFromTangentNormal(tangent, Vec3(0.0, 1.0, 0.0), &m.root_frame, &error)) {
    std::fprintf(stderr, "drape_example: %s\n", error.c_str());
    return 1;
  }
  m.contact.obstacle = body;
  m.contact.clearance = 0.0;  // the bare surface: the centreline rests on the sphere

  constexpr double kSegmentLength = 0.005;  // m
  const std::vector<double> lengths = {0.05, 0.10, 0.20, 0.35, 0.50};  // m
  std::FILE* f = std::fopen(argv[1], "w");
  if (f == nullptr) {
    std::fprintf(stderr, "drape_example: cannot write %s\n", argv[1]);
    return 1;
  }
  std::fprintf(f, "# sphere %.9g %.9g %.9g %.9g\n", sphere.center.x(), sphere.center.y(),
               sphere.center.z(), sphere.radius);
  std::fprintf(f, "length_index,length,point,x,y,z\n");
  VecX previous;
  int status = 0;
  for (size_t k = 0; k < lengths.size(); ++k) {
    const int n = static_cast<int>(std::lround(lengths[k] / kSegmentLength));
    m.segment_lengths = UniformSegments(lengths[k], n);
    // Growth: the solved curvatures of the shorter strand, natural curvature on the new tip.
    VecX start = m.NaturalCurvatures();
    if (previous.size() > 0) start.head(previous.size()) = previous;
    const StrandSolution s = SolveStrand(m, SolveOptions{}, &start);
    std::printf(
        "L = %.2f m: %d segments, %s, %d iterations, residual %.2g, stable %s, "
        "max penetration %.3g mm, %d samples in contact\n",
        lengths[k], n, TerminationName(s.summary.termination), s.summary.iterations,
        s.summary.residual, s.summary.stable ? "yes" : "no",
        s.summary.contact.max_penetration * 1e3, s.summary.contact.samples_in_contact);
    if (!s.summary.Converged()) status = 1;
    previous = s.curvatures;
    const std::vector<Vec3> points = SampleCentreline(m, s.curvatures, 8);
    for (size_t j = 0; j < points.size(); ++j) {
      std::fprintf(f, "%zu,%.4g,%zu,%.7g,%.7g,%.7g\n", k, lengths[k], j, points[j].x(),
                   points[j].y(), points[j].z());
    }
  }
  std::fclose(f);
  return status;
}
