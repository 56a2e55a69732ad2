// From render settings to a scene (render_setup.h).
#include "ringlet/render_setup.h"

#include "ringlet/hair_bsdf.h"

namespace ringlet {

Eigen::AlignedBox3d FramingBox(const HairCurves* hair, const Body* body) {
  Eigen::AlignedBox3d box;  // empty
  if (hair) {
    for (const Vec3f& p : hair->points) box.extend(p.cast<double>());
  }
  if (body) {
    if (box.isEmpty()) return body->Bounds();
    if (const Sphere* head = body->FindSphere("head")) {
      box.extend(head->center - Vec3::Constant(head->radius));
      box.extend(head->center + Vec3::Constant(head->radius));
    }
  }
  return box;
}

bool MakeRenderScene(const RenderSettings& s, const HairCurves* hair,
                     std::shared_ptr<const Body> body, double eccentricity,
                     std::uint64_t orientation_seed, RenderScene* out, std::string* error) {
  const bool has_hair = hair && hair->NumStrands() > 0;
  RenderScene scene;
  if (has_hair) {
    scene.hair = hair;
    HairOptics optics = s.optics;
    optics.eccentricity = eccentricity;
    optics.sigma_a = AbsorptionFromMelanin(s.eumelanin, s.pheomelanin);
    const std::string why = CheckHairOptics(optics);
    if (!why.empty()) {
      *error = "hair optics: " + why;
      return false;
    }
    scene.fibre = std::make_shared<HairBsdf>(optics);
  }
  scene.body = std::move(body);
  if (!has_hair && !scene.body) {
    *error = "nothing to render: no strands and no body";
    return false;
  }
  scene.body_albedo = s.body_albedo;
  scene.orientation_seed = orientation_seed;
  scene.key = s.key;
  scene.environment = s.environment;
  const double aspect = static_cast<double>(s.options.width) / s.options.height;
  if (s.camera.kind == CameraSettings::Kind::kFramed) {
    const Eigen::AlignedBox3d box = FramingBox(has_hair ? hair : nullptr, scene.body.get());
    scene.camera = FrameCamera(box, s.camera.view_direction, s.camera.vertical_fov, aspect);
  } else {
    scene.camera.position = s.camera.position;
    scene.camera.look_at = s.camera.look_at;
    scene.camera.up = s.camera.up;
    scene.camera.vertical_fov = s.camera.vertical_fov;
  }
  *out = std::move(scene);
  return true;
}

}  // namespace ringlet
