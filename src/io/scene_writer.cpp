// Scene files written from models (scene_json.h, SceneToString): what `ringlet invert` writes.
#include <nlohmann/json.hpp>

#include "ringlet/scene_json.h"

namespace ringlet {
namespace {

using ojson = nlohmann::ordered_json;

ojson Triple(const Vec3& v) { return ojson::array({v.x(), v.y(), v.z()}); }

}  // namespace

std::string SceneToString(const std::vector<StrandModel>& models) {
  ojson strands = ojson::array();
  for (const StrandModel& m : models) {
    ojson strand = ojson::object();
    strand["length"] = m.Length();
    strand["segment_lengths"] = m.segment_lengths;
    strand["radius"] = m.section.MeanRadius();
    strand["eccentricity"] = m.section.Eccentricity();
    strand["young_modulus"] = m.material.young_modulus;
    strand["poisson_ratio"] = m.material.poisson_ratio;
    strand["density"] = m.material.density;
    strand["natural_curvature"] = ojson::array({m.natural_curvature.x(), m.natural_curvature.y()});
    strand["natural_twist"] = m.natural_curvature.z();
    if (m.HasRestShape()) {
      ojson rest = ojson::array();
      for (int i = 0; i < m.NumSegments(); ++i) rest.push_back(Triple(m.NaturalCurvature(i)));
      strand["rest_curvatures"] = std::move(rest);
    }
    strand["root"] = {{"position", Triple(m.root_position)},
                      {"tangent", Triple(m.root_frame.col(2))},
                      {"normal", Triple(m.root_frame.col(0))}};
    strands.push_back(std::move(strand));
  }
  ojson document = ojson::object();
  document["gravity"] = Triple(models.empty() ? Vec3(0.0, 0.0, -9.81) : models.front().gravity);
  document["strands"] = std::move(strands);
  return document.dump(1) + "\n";
}

}  // namespace ringlet
