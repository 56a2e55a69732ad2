// From render settings to a scene: what `ringlet render`, `ringlet groom --render`, `ringlet
// style --render` and the studio's render panel all do before Render (render.h).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "ringlet/body.h"
#include "ringlet/hair_curves.h"
#include "ringlet/render.h"
#include "ringlet/render_json.h"

namespace ringlet {

/// The box the framed camera looks at: the hair's points together with the body's sphere named
/// "head" (so that short hair still shows the whole head); the body's bounds when there is no
/// hair. Empty when there is neither.
Eigen::AlignedBox3d FramingBox(const HairCurves* hair, const Body* body);

/// The scene of hair (may be null or empty) and a body (may be null) with the settings' light,
/// environment and body albedo, the fibre model from the settings' optics with `eccentricity`
/// (the hair type's, HairTypeEccentricity) and the melanins' absorption (AbsorptionFromMelanin),
/// and the settings' camera (framed on FramingBox with the image's aspect, or explicit). The hair
/// and body must outlive the scene. False with one line (invalid optics, nothing to render).
bool MakeRenderScene(const RenderSettings& settings, const HairCurves* hair,
                     std::shared_ptr<const Body> body, double eccentricity,
                     std::uint64_t orientation_seed, RenderScene* scene, std::string* error);

}  // namespace ringlet
