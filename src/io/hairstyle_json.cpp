// Hairstyle files: JSON -> validated Hairstyle (docs/hairstyle-format.md).
//
// Every field is checked where it is read (io/json_reader.h) so that an error names the field,
// what was expected and what was found, in one line. Hairstyle::IsValid runs last as a safety net.
#include "ringlet/hairstyle_json.h"

#include <cmath>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <vector>

#include "io/json_reader.h"
#include "ringlet/atomic_file.h"
#include "io/body_member.h"
#include "ringlet/body_json.h"
#include "ringlet/masters_json.h"

namespace ringlet {
namespace {

using internal::Element;
using internal::Member;
using internal::NumberRule;
using internal::Reader;
using internal::Show;
using nlohmann::json;

constexpr NumberRule kPositiveLength{"a finite number > 0 (m)", [](double x) { return x > 0.0; }};
constexpr NumberRule kNonNegativeLength{"a finite number >= 0 (m)",
                                        [](double x) { return x >= 0.0; }};
constexpr NumberRule kAngleRule{"a finite number in (0, pi) (rad)",
                                [](double x) { return x > 0.0 && x < M_PI; }};
constexpr NumberRule kTiltRule{"a finite number in [0, pi/2] (rad)",
                               [](double x) { return x >= 0.0 && x <= M_PI / 2; }};
constexpr NumberRule kAnyNumber{"a finite number", [](double) { return true; }};
constexpr NumberRule kNonNegative{"a finite number >= 0", [](double x) { return x >= 0.0; }};
constexpr NumberRule kPositive{"a finite number > 0", [](double x) { return x > 0.0; }};
constexpr NumberRule kFraction{"a finite number in (0, 1]",
                               [](double x) { return x > 0.0 && x <= 1.0; }};
constexpr NumberRule kUnitInterval{"a finite number in [0, 1)",
                                   [](double x) { return x >= 0.0 && x < 1.0; }};
constexpr NumberRule kStiffnessRule{"a finite number >= 0 (N/m^2; 0 = the default)",
                                    [](double x) { return x >= 0.0; }};
// The hair's own section and curl (hair.ellipticity, hair.curl_radius, hair.curl_pitch): bounds
// that keep a strand's natural curvature below 1e4 1/m (1 / 0.1 mm, tighter than any measured
// hair: kinky curls have R ~ 1-5 mm, hair-types.md) and the section a real ellipse.
constexpr NumberRule kEllipticityRule{"a finite a/b in [1, 10]",
                                      [](double x) { return x >= 1.0 && x <= 10.0; }};
constexpr NumberRule kCurlRadiusRule{"a finite helix radius in [1e-4, 10] (m)",
                                     [](double x) { return x >= 1e-4 && x <= 10.0; }};
constexpr NumberRule kHairPitchRule{"a finite helix pitch in [0, 10] (m)",
                                    [](double x) { return x >= 0.0 && x <= 10.0; }};
constexpr NumberRule kCurlSpreadRule{"a finite relative standard deviation in [0, 1]",
                                     [](double x) { return x >= 0.0 && x <= 1.0; }};
constexpr NumberRule kGradingRule{"a finite number >= 1 (last/first segment length) or \"auto\"",
                                  [](double x) { return x >= 1.0; }};
constexpr NumberRule kPackingRule{"a finite number in (0, 0.69]",
                                  [](double x) { return x > 0.0 && x <= 0.69; }};
constexpr NumberRule kLayerThicknessRule{"a finite number in [0, 0.1) (m)",
                                         [](double x) { return x >= 0.0 && x < 0.1; }};

bool ReadSeed(Reader& reader, const json& object, const std::string& path, const char* key,
              std::uint64_t* seed) {
  return reader.ReadUnsigned(object, path, key, internal::kMaxExactInteger, "2^53", seed);
}

bool ParseHead(Reader& reader, const json& scalp, const std::string& path, HeadFrame* head) {
  const json* object = nullptr;
  if (!OptionalObject(reader, scalp, path, "head", &object)) return false;
  if (!object) return true;
  const std::string head_path = Member(path, "head");
  if (!reader.CheckFields(*object, head_path, {"centre", "up", "front"}) ||
      !reader.ReadVector<3>(*object, head_path, "centre", "m", false, &head->centre) ||
      !reader.ReadVector<3>(*object, head_path, "up", "a direction", false, &head->up) ||
      !reader.ReadVector<3>(*object, head_path, "front", "a direction", false, &head->front)) {
    return false;
  }
  std::string why;
  if (!IsValid(*head, &why)) return reader.Fail(head_path, why);
  return true;
}

// "scalp": a region of the head sphere by its hairline, on the sphere itself or on the triangles
// of a named body mesh whose centroids lie inside the hairline.
bool ParseScalp(Reader& reader, const json& document, const Body& body, Hairstyle* style) {
  const json* scalp = nullptr;
  if (!OptionalObject(reader, document, "", "scalp", &scalp)) return false;
  SphereScalp sphere;
  // Default head sphere: the body's sphere named "head", if any.
  if (const Sphere* head = body.FindSphere("head")) {
    sphere.head.centre = head->center;
    sphere.radius = head->radius;
  }
  std::string mesh_name;
  if (scalp) {
    const std::string path = "scalp";
    if (!reader.CheckFields(*scalp, path,
                            {"head", "radius", "hairline_front", "hairline_side", "hairline_back",
                             "mesh"}) ||
        !ParseHead(reader, *scalp, path, &sphere.head) ||
        !reader.ReadNumber(*scalp, path, "radius", kPositiveLength, false, &sphere.radius) ||
        !reader.ReadNumber(*scalp, path, "hairline_front", kAngleRule, false,
                           &sphere.hairline_front) ||
        !reader.ReadNumber(*scalp, path, "hairline_side", kAngleRule, false,
                           &sphere.hairline_side) ||
        !reader.ReadNumber(*scalp, path, "hairline_back", kAngleRule, false,
                           &sphere.hairline_back)) {
      return false;
    }
    const auto mesh = scalp->find("mesh");
    if (mesh != scalp->end()) {
      if (!mesh->is_string() || mesh->get<std::string>().empty()) {
        return reader.Expected("scalp.mesh", "the name of a body mesh (an OBJ object)", *mesh);
      }
      mesh_name = mesh->get<std::string>();
    }
  }
  std::string why;
  if (!IsValid(sphere, &why)) return reader.Fail("scalp", why);
  style->crown_polar_angle = sphere.hairline_front;  // where hair.length.crown has blended out
  if (mesh_name.empty()) {
    style->scalp = sphere;
    return true;
  }
  const TriangleMesh* mesh = nullptr;
  std::string names;
  for (const TriangleMesh& m : body.meshes()) {
    names += std::string(names.empty() ? "" : ", ") + "\"" + m.name() + "\"";
    if (m.name() == mesh_name) mesh = &m;
  }
  if (!mesh) {
    return reader.Fail("scalp.mesh", "no body mesh is named \"" + mesh_name + "\" (meshes: " +
                                         (names.empty() ? "none" : names) + ")");
  }
  MeshScalp on_mesh;
  on_mesh.head = sphere.head;
  on_mesh.vertices = mesh->vertices();
  for (const auto& t : mesh->triangles()) {
    const Vec3 centroid =
        (mesh->vertices()[t[0]] + mesh->vertices()[t[1]] + mesh->vertices()[t[2]]) / 3.0;
    if (InScalp(sphere, centroid)) on_mesh.triangles.push_back({t[0], t[1], t[2]});
  }
  if (on_mesh.triangles.empty()) {
    return reader.Fail("scalp", "no triangle of mesh \"" + mesh_name +
                                    "\" lies inside the hairline (check scalp.head and the "
                                    "hairline angles)");
  }
  if (!IsValid(on_mesh, &why)) return reader.Fail("scalp", why);
  style->scalp = std::move(on_mesh);
  return true;
}

// "masters": {"file": "masters.json"}: explicit masters (docs/hairstyle-format.md, "Explicit
// masters"). The keys that would sample them are refused with it, here and at the top level.
bool ParseMastersFile(Reader& reader, const json& document, const json& masters,
                      const std::string& base, Hairstyle* style) {
  const auto file = masters.find("file");
  if (!file->is_string() || file->get<std::string>().empty()) {
    return reader.Expected("masters.file", "the name of a masters file (JSON)", *file);
  }
  const char* why_not = "not with masters.file (the masters file gives the masters' roots, "
                        "frames and segments)";
  for (const char* key : {"count", "seed", "segments", "grading"}) {
    if (masters.contains(key)) return reader.Fail(Member("masters", key), why_not);
  }
  if (document.contains("comb")) return reader.Fail("comb", why_not);
  const auto hair = document.find("hair");
  if (hair != document.end() && hair->is_object() && hair->contains("length")) {
    return reader.Fail("hair.length", why_not);
  }
  auto explicit_masters = std::make_shared<ExplicitMasters>();
  explicit_masters->file = file->get<std::string>();
  std::filesystem::path path(explicit_masters->file);
  if (path.is_relative()) path = std::filesystem::path(base) / path;
  std::string error;
  if (!LoadMastersFile(path.string(), &explicit_masters->masters, &error)) {
    return reader.Fail("masters.file", error);
  }
  style->explicit_masters = std::move(explicit_masters);
  return true;
}

bool ParseMasters(Reader& reader, const json& document, const std::string& base,
                  Hairstyle* style) {
  const json* masters = nullptr;
  if (!OptionalObject(reader, document, "", "masters", &masters)) return false;
  if (!masters) return true;
  const std::string path = "masters";
  if (masters->contains("file") &&
      !ParseMastersFile(reader, document, *masters, base, style)) {
    return false;
  }
  if (!reader.CheckFields(*masters, path,
                          {"count", "seed", "segments", "grading", "points_per_segment",
                           "packing", "file"}) ||
      !reader.ReadInteger(*masters, path, "count", 1, kMaxMasters, &style->roots.count) ||
      !ReadSeed(reader, *masters, path, "seed", &style->roots.seed) ||
      !reader.ReadInteger(*masters, path, "segments", 1, 10000, &style->segments) ||
      !reader.ReadInteger(*masters, path, "points_per_segment", 1, 64,
                          &style->master_points_per_segment) ||
      !reader.ReadNumber(*masters, path, "packing", kPackingRule, false, &style->roots.packing)) {
    return false;
  }
  const auto grading = masters->find("grading");
  if (grading != masters->end() && grading->is_string() && *grading == "auto") {
    style->grading = 0.0;
  } else if (!reader.ReadNumber(*masters, path, "grading", kGradingRule, false,
                                &style->grading)) {
    return false;
  }
  return true;
}

bool ParseComb(Reader& reader, const json& document, Hairstyle* style) {
  const json* comb = nullptr;
  if (!OptionalObject(reader, document, "", "comb", &comb)) return false;
  if (!comb) return true;
  const std::string path = "comb";
  CombOptions& c = style->comb;
  if (!reader.CheckFields(*comb, path,
                          {"tilt", "direction", "fallback_direction", "parting", "face_sweep",
                           "curl_inward"}) ||
      !reader.ReadNumber(*comb, path, "tilt", kTiltRule, false, &c.tilt) ||
      !reader.ReadBool(*comb, path, "curl_inward", &c.curl_inward) ||
      !reader.ReadNumber(*comb, path, "face_sweep", kNonNegative, false, &c.face_sweep) ||
      !reader.ReadVector<3>(*comb, path, "direction", "a direction", false, &c.direction) ||
      !reader.ReadVector<3>(*comb, path, "fallback_direction", "a direction", false,
                            &c.fallback_direction)) {
    return false;
  }
  const json* parting = nullptr;
  if (!OptionalObject(reader, *comb, path, "parting", &parting)) return false;
  if (parting) {
    const std::string p = "comb.parting";
    c.parting = true;
    if (!reader.CheckFields(*parting, p, {"normal", "offset", "strength"}) ||
        !reader.ReadVector<3>(*parting, p, "normal", "a direction", false, &c.parting_normal) ||
        !reader.ReadNumber(*parting, p, "offset", kAnyNumber, false, &c.parting_offset) ||
        !reader.ReadNumber(*parting, p, "strength", kNonNegative, false, &c.parting_strength)) {
      return false;
    }
  }
  std::string why;
  if (!IsValid(c, &why)) return reader.Fail(path, why);
  return true;
}

// hair.ellipticity, hair.curl_radius, hair.curl_pitch and hair.curl_spread over the hair type's
// means (the groomer's section and curl): each keeps the type's relative spread between strands
// (the excess ellipticity's, the radius's) unless curl_spread sets the radius's, and a radius
// without a pitch keeps the type's helix angle (the pitch scales with the radius). A straight
// type has no helix to resize.
bool ParseHairOverrides(Reader& reader, const json& hair, HairType* type) {
  const std::string path = "hair";
  double ellipticity = type->ellipticity;
  double radius = type->curl_radius, pitch = -1.0, spread = -1.0;
  if (!reader.ReadNumber(hair, path, "ellipticity", kEllipticityRule, false, &ellipticity) ||
      !reader.ReadNumber(hair, path, "curl_radius", kCurlRadiusRule, false, &radius) ||
      !reader.ReadNumber(hair, path, "curl_pitch", kHairPitchRule, false, &pitch) ||
      !reader.ReadNumber(hair, path, "curl_spread", kCurlSpreadRule, false, &spread)) {
    return false;
  }
  const double excess = type->ellipticity - 1.0;
  type->ellipticity_std = excess > 0.0 ? type->ellipticity_std * (ellipticity - 1.0) / excess : 0.0;
  type->ellipticity = ellipticity;
  for (const char* key : {"curl_radius", "curl_pitch", "curl_spread"}) {
    if (hair.contains(key) && type->IsStraight()) {
      return reader.Fail(Member(path, key),
                         "the curl type \"" + type->curl +
                             "\" has no helix: choose \"wavy\", \"curly\" or \"kinky\"");
    }
  }
  if (hair.contains("curl_radius")) {
    const double scale = radius / type->curl_radius;
    type->curl_radius_std *= scale;
    type->curl_pitch *= scale;
    type->curl_radius = radius;
  }
  if (hair.contains("curl_pitch")) type->curl_pitch = pitch;
  if (hair.contains("curl_spread")) type->curl_radius_std = spread * type->curl_radius;
  return true;
}

bool ParseHair(Reader& reader, const json& document, Hairstyle* style) {
  const json* hair = nullptr;
  if (!OptionalObject(reader, document, "", "hair", &hair)) return false;
  std::string origin = "caucasian", curl;
  if (hair) {
    const std::string path = "hair";
    if (!reader.CheckFields(*hair, path, {"origin", "curl", "length", "seed", "ellipticity",
                                          "curl_radius", "curl_pitch", "curl_spread"}) ||
        !ReadSeed(reader, *hair, path, "seed", &style->seed)) {
      return false;
    }
    // "length": a number (m), or {"front", "side", "back"} (m): the regional length.
    const auto length = hair->find("length");
    if (length != hair->end() && length->is_object()) {
      const std::string p = "hair.length";
      style->regional_length = true;
      if (!reader.CheckFields(*length, p, {"front", "side", "back", "crown"}) ||
          !reader.ReadNumber(*length, p, "front", kPositiveLength, true, &style->length_front) ||
          !reader.ReadNumber(*length, p, "side", kPositiveLength, true, &style->length_side) ||
          !reader.ReadNumber(*length, p, "back", kPositiveLength, true, &style->length_back) ||
          !reader.ReadNumber(*length, p, "crown", kPositiveLength, false, &style->length_crown)) {
        return false;
      }
      // `length` (the reference of other defaults) becomes the mean of the three.
      style->length = (style->length_front + style->length_side + style->length_back) / 3.0;
    } else if (!reader.ReadNumber(*hair, path, "length", kPositiveLength, false,
                                  &style->length)) {
      return false;
    }
    for (const char* key : {"origin", "curl"}) {
      const auto it = hair->find(key);
      if (it == hair->end()) continue;
      if (!it->is_string()) return reader.Expected(Member(path, key), "a name", *it);
      (std::string(key) == "origin" ? origin : curl) = it->get<std::string>();
    }
  }
  std::string why;
  if (!FindHairType(origin, curl, &style->hair_type, &why)) {
    // why lists the valid names; say which field was wrong. FindHairType names its own field
    // ("hair_type.origin: ..."), which is not a key of the file: keep only what follows it.
    const bool origin_ok = !DefaultCurl(origin).empty();
    const std::string own_prefix = origin_ok ? "hair_type.curl: " : "hair_type.origin: ";
    if (why.rfind(own_prefix, 0) == 0) why.erase(0, own_prefix.size());
    return reader.Fail(origin_ok ? "hair.curl" : "hair.origin", why);
  }
  return !hair || ParseHairOverrides(reader, *hair, &style->hair_type);
}

bool ParseWisps(Reader& reader, const json& document, Hairstyle* style) {
  const json* wisps = nullptr;
  if (!OptionalObject(reader, document, "", "wisps", &wisps)) return false;
  if (!wisps) return true;
  const std::string path = "wisps";
  WispOptions& w = style->wisps;
  if (!reader.CheckFields(*wisps, path,
                          {"strands_per_wisp", "radius", "packing_fraction", "root_scale",
                           "tip_scale", "profile_exponent", "distance_exponent", "jitter",
                           "length_variation", "frizz_amplitude", "frizz_frequency",
                           "points_per_strand", "tip_taper", "tip_taper_length",
                           "include_master",
                           "spread_roots", "children"}) ||
      !reader.ReadInteger(*wisps, path, "strands_per_wisp", 1, 100000, &w.strands_per_wisp) ||
      !reader.ReadNumber(*wisps, path, "packing_fraction", kFraction, false,
                         &w.packing_fraction) ||
      !reader.ReadNumber(*wisps, path, "root_scale", kPositive, false, &w.root_scale) ||
      !reader.ReadNumber(*wisps, path, "tip_scale", kPositive, false, &w.tip_scale) ||
      !reader.ReadNumber(*wisps, path, "profile_exponent", kPositive, false,
                         &w.profile_exponent) ||
      !reader.ReadNumber(*wisps, path, "distance_exponent", kPositive, false,
                         &w.distance_exponent) ||
      !reader.ReadNumber(*wisps, path, "jitter", kNonNegativeLength, false, &w.jitter) ||
      !reader.ReadNumber(*wisps, path, "length_variation", kUnitInterval, false,
                         &w.length_variation) ||
      !reader.ReadNumber(*wisps, path, "frizz_amplitude", kNonNegativeLength, false,
                         &w.frizz_amplitude) ||
      !reader.ReadNumber(*wisps, path, "frizz_frequency", kNonNegative, false,
                         &w.frizz_frequency) ||
      !reader.ReadInteger(*wisps, path, "points_per_strand", 2, 65536, &w.points_per_strand) ||
      !reader.ReadNumber(*wisps, path, "tip_taper", kUnitInterval, false, &w.tip_taper) ||
      !reader.ReadNumber(*wisps, path, "tip_taper_length", kPositiveLength, false,
                         &w.tip_taper_length) ||
      !reader.ReadBool(*wisps, path, "include_master", &w.include_master) ||
      !reader.ReadBool(*wisps, path, "spread_roots", &style->spread_roots)) {
    return false;
  }
  const auto radius = wisps->find("radius");
  if (radius != wisps->end() && radius->is_string() && *radius == "auto") {
    w.wisp_radius = 0.0;
  } else if (!reader.ReadNumber(*wisps, path, "radius",
                                {"a finite number > 0 (m) or \"auto\"",
                                 [](double x) { return x > 0.0; }},
                                false, &w.wisp_radius)) {
    return false;
  }
  const auto children = wisps->find("children");
  if (children != wisps->end()) {
    if (children->is_string() && *children == "procedural") {
      style->solve_children = false;
    } else if (children->is_string() && *children == "solved") {
      style->solve_children = true;
    } else {
      return reader.Expected("wisps.children", "\"procedural\" or \"solved\"", *children);
    }
  }
  std::string why;
  if (!w.IsValid(&why)) return reader.Fail(path, why);
  return true;
}

bool ParseLayersAndContact(Reader& reader, const json& document, Hairstyle* style) {
  const json* layers = nullptr;
  if (!OptionalObject(reader, document, "", "layers", &layers)) return false;
  if (layers) {
    if (!reader.CheckFields(*layers, "layers", {"count", "thickness"}) ||
        !reader.ReadInteger(*layers, "layers", "count", 1, 64, &style->layers.count) ||
        !reader.ReadNumber(*layers, "layers", "thickness", kLayerThicknessRule, false,
                           &style->layers.thickness)) {
      return false;
    }
  }
  const json* contact = nullptr;
  if (!OptionalObject(reader, document, "", "contact", &contact)) return false;
  if (contact) {
    if (!reader.CheckFields(*contact, "contact", {"stiffness", "samples_per_segment"}) ||
        !reader.ReadNumber(*contact, "contact", "stiffness", kStiffnessRule, false,
                           &style->contact_stiffness) ||
        !reader.ReadInteger(*contact, "contact", "samples_per_segment", 1, 64,
                            &style->contact_samples)) {
      return false;
    }
  }
  return true;
}

// ---------------------------------------------------------------------------------------------
// "operations": the styling operations of `ringlet style` (styling.h, docs/styling.md).

constexpr NumberRule kCurlPitchRule{"a finite number (m; < 0 = left-handed)",
                                    [](double) { return true; }};
constexpr NumberRule kStiffnessFactorRule{"a finite number in (0, 1] (E_wet / E_dry)",
                                          [](double x) { return x > 0.0 && x <= 1.0; }};
constexpr NumberRule kSwellingRule{"a finite number in [1, 2] (wet / dry radius)",
                                   [](double x) { return x >= 1.0 && x <= 2.0; }};
constexpr NumberRule kWaterDensityRule{"a finite number in [0, 2000] (kg/m^3)",
                                       [](double x) { return x >= 0.0 && x <= 2000.0; }};
constexpr NumberRule kLayerFactorRule{"a finite number in [0, 1]",
                                      [](double x) { return x >= 0.0 && x <= 1.0; }};
constexpr NumberRule kHeightRule{"a finite number (m)", [](double) { return true; }};

// "select": {"indices": [...]} or {"polar_angle": [min, max], "height": [min, max]}.
// Every operation may have one (curl, wet, dry, cut, grow).
bool ParseSelection(Reader& reader, const json& operation, const std::string& operation_path,
                    StrandSelection* selection) {
  const json* object = nullptr;
  if (!OptionalObject(reader, operation, operation_path, "select", &object)) return false;
  if (!object) return true;
  const std::string path = Member(operation_path, "select");
  if (!reader.CheckFields(*object, path, {"indices", "polar_angle", "height"})) return false;
  const json* indices = nullptr;
  const char* expected_indices = "an array of master indices (integers >= 0)";
  if (!reader.ReadArray(*object, path, "indices", expected_indices, &indices)) return false;
  if (indices) {
    if (object->contains("polar_angle") || object->contains("height")) {
      return reader.Fail(path, "give either indices or polar_angle/height ranges, not both");
    }
    if (indices->empty()) {
      return reader.Expected(Member(path, "indices"), "a non-empty array of master indices",
                             *indices);
    }
    for (size_t k = 0; k < indices->size(); ++k) {
      const json& v = (*indices)[k];
      if (!v.is_number() || !std::isfinite(v.get<double>()) || v.get<double>() < 0.0 ||
          v.get<double>() > 1e9 || v.get<double>() != std::floor(v.get<double>())) {
        return reader.Expected(Element(Member(path, "indices"), k),
                               "a master index (an integer >= 0)", v);
      }
      selection->indices.push_back(static_cast<int>(v.get<double>()));
    }
    return true;
  }
  Eigen::Vector2d polar(selection->min_polar_angle, selection->max_polar_angle);
  if (!reader.ReadVector<2>(*object, path, "polar_angle", "rad, [min, max]", false, &polar)) {
    return false;
  }
  if (!(polar(0) >= 0.0 && polar(0) <= polar(1) && polar(1) <= M_PI)) {
    return reader.Expected(Member(path, "polar_angle"),
                           "[min, max] with 0 <= min <= max <= pi (rad)",
                           object->at("polar_angle"));
  }
  Eigen::Vector2d height(selection->min_height, selection->max_height);
  if (!reader.ReadVector<2>(*object, path, "height", "m, [min, max]", false, &height)) {
    return false;
  }
  if (!(height(0) <= height(1))) {
    return reader.Expected(Member(path, "height"), "[min, max] with min <= max (m)",
                           object->at("height"));
  }
  selection->min_polar_angle = polar(0);
  selection->max_polar_angle = polar(1);
  selection->min_height = height(0);
  selection->max_height = height(1);
  return true;
}

bool ParseBrushFields(Reader& reader, const json& object, const std::string& path, Brush* brush);

bool ParseCurlOperation(Reader& reader, const json& curl, const std::string& path,
                        StyleOperation* op) {
  if (!reader.CheckFields(curl, path, {"radius", "pitch", "brush", "select"})) return false;
  // "brush": {"centre": [x, y, z], "radius": r, ...brush fields}: a curl brush (CurlBrush).
  const auto brush = curl.find("brush");
  if (brush != curl.end()) {
    const std::string brush_path = Member(path, "brush");
    if (!brush->is_object()) {
      return reader.Expected(brush_path, "an object {\"centre\": [x, y, z], \"radius\": r, ...}",
                             *brush);
    }
    if (!reader.CheckFields(*brush, brush_path,
                            {"centre", "radius", "strength", "falloff", "mirror"}) ||
        !reader.ReadVector<3>(*brush, brush_path, "centre", "m, the brush centre", true,
                              &op->curl_brush.centre) ||
        !ParseBrushFields(reader, *brush, brush_path, &op->curl_brush)) {
      return false;
    }
    op->curl_brushed = true;
  }
  const auto radius = curl.find("radius");
  const char* expected_radius = "a finite number >= 0 (m) or \"inf\" (straighten)";
  if (radius == curl.end()) return reader.Missing(Member(path, "radius"), expected_radius);
  if (radius->is_string() && *radius == "inf") {
    op->curl_radius = std::numeric_limits<double>::infinity();
  } else if (!reader.ReadNumber(curl, path, "radius",
                                {expected_radius, [](double x) { return x >= 0.0; }}, true,
                                &op->curl_radius)) {
    return false;
  }
  if (!reader.ReadNumber(curl, path, "pitch", kCurlPitchRule, true, &op->curl_pitch) ||
      !ParseSelection(reader, curl, path, &op->selection)) {
    return false;
  }
  if (op->curl_radius == 0.0 && op->curl_pitch == 0.0) {
    return reader.Fail(path, "radius = pitch = 0 is not a helix");
  }
  // A helix too tight to be hair (its curvature above kMaxCurlCurvature).
  std::string field, why;
  if (!CheckCurlHelix(op->curl_radius, op->curl_pitch, &field, &why)) {
    return reader.Fail(Member(path, field), why);
  }
  return true;
}

bool ParseWetOperation(Reader& reader, const json& wet, const std::string& path,
                       StyleOperation* op) {
  WetOptions& w = op->wet;
  return reader.CheckFields(
             wet, path, {"stiffness_factor", "swelling", "water_density", "layer_factor", "select"}) &&
         ParseSelection(reader, wet, path, &op->selection) &&
         reader.ReadNumber(wet, path, "stiffness_factor", kStiffnessFactorRule, false,
                           &w.stiffness_factor) &&
         reader.ReadNumber(wet, path, "swelling", kSwellingRule, false, &w.swelling) &&
         reader.ReadNumber(wet, path, "water_density", kWaterDensityRule, false,
                           &w.water_density) &&
         reader.ReadNumber(wet, path, "layer_factor", kLayerFactorRule, false, &w.layer_factor);
}

// "cut": exactly one region ("z", "plane", "sphere" or "length") and the options.
bool ParseCutOperation(Reader& reader, const json& cut, const std::string& path,
                       StyleOperation* op) {
  if (!reader.CheckFields(cut, path,
                          {"z", "plane", "sphere", "length", "settle", "tolerance", "max_rounds",
                           "samples_per_segment", "select"}) ||
      !ParseSelection(reader, cut, path, &op->selection)) {
    return false;
  }
  const char* kinds = "exactly one of \"z\", \"plane\", \"sphere\", \"length\"";
  int given = 0;
  for (const char* key : {"z", "plane", "sphere", "length"}) given += cut.contains(key) ? 1 : 0;
  if (given == 0) {
    return reader.Fail(path, std::string("missing the region (expected ") + kinds + ")");
  }
  if (given > 1) {
    return reader.Fail(path, std::string("expected ") + kinds + ", got " + std::to_string(given));
  }
  CutRegion& region = op->cut_region;
  if (cut.contains("z")) {
    region.kind = CutRegion::Kind::kAbovePlane;
    region.normal = Vec3::UnitZ();
    if (!reader.ReadNumber(cut, path, "z", kHeightRule, true, &region.offset)) return false;
  } else if (cut.contains("plane")) {
    const json* plane = nullptr;
    if (!OptionalObject(reader, cut, path, "plane", &plane)) return false;
    const std::string p = Member(path, "plane");
    region.kind = CutRegion::Kind::kAbovePlane;
    if (!reader.CheckFields(*plane, p, {"normal", "offset"}) ||
        !reader.ReadVector<3>(*plane, p, "normal", "a direction, pointing into the kept side", true,
                              &region.normal) ||
        !reader.ReadNumber(
            *plane, p, "offset",
            {"a finite number (m; n . r >= offset is kept)", [](double) { return true; }}, true,
            &region.offset)) {
      return false;
    }
    if (!(region.normal.norm() > 0.0) || !std::isfinite(region.normal.norm())) {
      return reader.Expected(Member(p, "normal"), "a non-zero direction of finite length",
                             plane->at("normal"));
    }
  } else if (cut.contains("sphere")) {
    const json* sphere = nullptr;
    if (!OptionalObject(reader, cut, path, "sphere", &sphere)) return false;
    const std::string p = Member(path, "sphere");
    region.kind = CutRegion::Kind::kInsideSphere;
    if (!reader.CheckFields(*sphere, p, {"centre", "radius"}) ||
        !reader.ReadVector<3>(*sphere, p, "centre", "m", true, &region.centre) ||
        !reader.ReadNumber(*sphere, p, "radius", kPositiveLength, true, &region.radius)) {
      return false;
    }
  } else {
    region.kind = CutRegion::Kind::kMaxLength;
    if (!reader.ReadNumber(cut, path, "length", kPositiveLength, true, &region.length)) {
      return false;
    }
  }
  CutOptions& o = op->cut;
  if (!reader.ReadBool(cut, path, "settle", &o.settle) ||
      !reader.ReadNumber(cut, path, "tolerance", kPositiveLength, false, &o.tolerance) ||
      !reader.ReadInteger(cut, path, "max_rounds", 1, 10000, &o.max_rounds) ||
      !reader.ReadInteger(cut, path, "samples_per_segment", 1, 1024, &o.samples_per_segment)) {
    return false;
  }
  if (o.settle && region.kind == CutRegion::Kind::kMaxLength) {
    return reader.Fail(Member(path, "settle"),
                       "only for \"z\", \"plane\" and \"sphere\" cuts (a length cut is exact)");
  }
  return true;
}

bool ParseGrowOperation(Reader& reader, const json& grow, const std::string& path,
                        StyleOperation* op) {
  static constexpr NumberRule kGrowStepRule{"a finite number in (0, 1] (m)",
                                            [](double x) { return x > 0.0 && x <= kMaxGrowStep; }};
  return reader.CheckFields(grow, path, {"step", "steps", "select"}) &&
         ParseSelection(reader, grow, path, &op->selection) &&
         reader.ReadNumber(grow, path, "step", kGrowStepRule, true, &op->grow_step) &&
         reader.ReadInteger(grow, path, "steps", 1, kMaxGrowSteps, &op->grow_steps);
}

// The brush fields shared by sculpt and puff: "radius" (required), "strength", "falloff",
// "mirror" (styling.h, Brush).
bool ParseBrushFields(Reader& reader, const json& object, const std::string& path, Brush* brush) {
  static constexpr NumberRule kBrushRadiusRule{
      "a finite number in (0, 10] (m)", [](double x) { return x > 0.0 && x <= kMaxBrushRadius; }};
  static constexpr NumberRule kStrengthRule{"a finite number in (0, 1]",
                                            [](double x) { return x > 0.0 && x <= 1.0; }};
  if (!reader.ReadNumber(object, path, "radius", kBrushRadiusRule, true, &brush->radius) ||
      !reader.ReadNumber(object, path, "strength", kStrengthRule, false, &brush->strength) ||
      !reader.ReadBool(object, path, "mirror", &brush->mirror)) {
    return false;
  }
  const auto falloff = object.find("falloff");
  if (falloff != object.end()) {
    bool known = false;
    for (Brush::Falloff f :
         {Brush::Falloff::kSmooth, Brush::Falloff::kLinear, Brush::Falloff::kConstant}) {
      if (falloff->is_string() && *falloff == FalloffName(f)) {
        brush->falloff = f;
        known = true;
      }
    }
    if (!known) {
      return reader.Expected(Member(path, "falloff"), "\"smooth\", \"linear\" or \"constant\"",
                             *falloff);
    }
  }
  return true;
}

// "sculpt": {"from": [x, y, z], "to": [x, y, z], "radius": r, ...brush fields, "select"}.
bool ParseSculptOperation(Reader& reader, const json& sculpt, const std::string& path,
                          StyleOperation* op) {
  SculptStroke& stroke = op->sculpt;
  if (!reader.CheckFields(sculpt, path,
                          {"from", "to", "radius", "strength", "falloff", "mirror", "select"}) ||
      !ParseSelection(reader, sculpt, path, &op->selection) ||
      !reader.ReadVector<3>(sculpt, path, "from", "m, where the stroke starts", true,
                            &stroke.brush.centre) ||
      !reader.ReadVector<3>(sculpt, path, "to", "m, where the stroke ends", true, &stroke.to) ||
      !ParseBrushFields(reader, sculpt, path, &stroke.brush)) {
    return false;
  }
  if (!((stroke.to - stroke.brush.centre).norm() <= kMaxBrushRadius)) {
    return reader.Expected(Member(path, "to"), "a point within 10 m of \"from\"", sculpt.at("to"));
  }
  return true;
}

// "puff": {"angle": a, "centre": [x, y, z], "radius": r, ...brush fields, "select"}.
bool ParsePuffOperation(Reader& reader, const json& puff, const std::string& path,
                        StyleOperation* op) {
  static constexpr NumberRule kPuffAngleRule{
      "a finite number in [-pi/2, pi/2] (rad; > 0 lifts the roots)",
      [](double x) { return std::abs(x) <= M_PI / 2.0; }};
  return reader.CheckFields(
             puff, path, {"angle", "centre", "radius", "strength", "falloff", "mirror", "select"}) &&
         ParseSelection(reader, puff, path, &op->selection) &&
         reader.ReadNumber(puff, path, "angle", kPuffAngleRule, true, &op->puff_angle) &&
         reader.ReadVector<3>(puff, path, "centre", "m, the brush centre", true,
                              &op->puff_brush.centre) &&
         ParseBrushFields(reader, puff, path, &op->puff_brush);
}

// "length" / "clump": {"factor": f, "centre": [x, y, z], "radius": r, ...brush fields, "select"};
// "frizz": {"amplitude": a, ...}.
bool ParseBrushOperation(Reader& reader, const json& object, const std::string& path,
                         StyleOperation* op) {
  static constexpr NumberRule kFactorRule{
      "a finite number in (0, 10] (< 1 shortens / clumps, > 1 lengthens / spreads)",
      [](double x) { return x > 0.0 && x <= kMaxBrushFactor; }};
  static constexpr NumberRule kAmplitudeRule{
      "a finite number in [0, 0.05] (m)",
      [](double x) { return x >= 0.0 && x <= kMaxFrizzAmplitude; }};
  const bool frizz = op->kind == StyleOperation::Kind::kFrizz;
  const char* value = frizz ? "amplitude" : "factor";
  return reader.CheckFields(object, path,
                            {value, "centre", "radius", "strength", "falloff", "mirror", "select"}) &&
         ParseSelection(reader, object, path, &op->selection) &&
         (frizz ? reader.ReadNumber(object, path, "amplitude", kAmplitudeRule, true,
                                    &op->frizz_amplitude)
                : reader.ReadNumber(object, path, "factor", kFactorRule, true, &op->factor)) &&
         reader.ReadVector<3>(object, path, "centre", "m, the brush centre", true,
                              &op->brush.centre) &&
         ParseBrushFields(reader, object, path, &op->brush);
}

bool ParseOperations(Reader& reader, const json& document, std::vector<StyleOperation>* out) {
  const char* expected =
      "an array of operations [{\"curl\": {...}}, {\"wet\": {}}, {\"cut\": {...}}, ...]";
  const json* array = nullptr;
  if (!reader.ReadArray(document, "", "operations", expected, &array)) return false;
  std::vector<StyleOperation> operations;
  if (array) {
    const char* one_key =
        "an object with one key naming the operation (\"curl\", \"wet\", \"dry\", \"cut\", "
        "\"grow\", \"sculpt\", \"puff\", \"length\", \"clump\", \"frizz\")";
    for (size_t i = 0; i < array->size(); ++i) {
      const json& element = (*array)[i];
      const std::string path = Element("operations", i);
      if (!element.is_object() || element.size() != 1) {
        return reader.Expected(path, one_key, element);
      }
      const std::string name = element.begin().key();
      const json& value = element.begin().value();
      const std::string op_path = Member(path, name);
      StyleOperation op;
      using Kind = StyleOperation::Kind;
      bool known = false;
      for (Kind kind : {Kind::kCurl, Kind::kWet, Kind::kDry, Kind::kCut, Kind::kGrow,
                        Kind::kSculpt, Kind::kPuff, Kind::kLength, Kind::kClump, Kind::kFrizz}) {
        if (name == OperationName(kind)) {
          op.kind = kind;
          known = true;
        }
      }
      if (!known) {
        return reader.Fail(op_path,
                           "unknown operation (expected \"curl\", \"wet\", \"dry\", "
                           "\"cut\", \"grow\", \"sculpt\", \"puff\", \"length\", "
                           "\"clump\" or \"frizz\")");
      }
      if (!value.is_object()) return reader.Expected(op_path, "an object", value);
      bool ok = true;
      switch (op.kind) {
        case Kind::kCurl:
          ok = ParseCurlOperation(reader, value, op_path, &op);
          break;
        case Kind::kWet:
          ok = ParseWetOperation(reader, value, op_path, &op);
          break;
        case Kind::kDry:
          ok = reader.CheckFields(value, op_path, {"select"}) &&
               ParseSelection(reader, value, op_path, &op.selection);
          break;
        case Kind::kCut:
          ok = ParseCutOperation(reader, value, op_path, &op);
          break;
        case Kind::kGrow:
          ok = ParseGrowOperation(reader, value, op_path, &op);
          break;
        case Kind::kSculpt:
          ok = ParseSculptOperation(reader, value, op_path, &op);
          break;
        case Kind::kPuff:
          ok = ParsePuffOperation(reader, value, op_path, &op);
          break;
        case Kind::kLength:
        case Kind::kClump:
        case Kind::kFrizz:
          ok = ParseBrushOperation(reader, value, op_path, &op);
          break;
      }
      if (!ok) return false;
      // The library's own checks, as a safety net (its messages name the operation's field).
      std::string why;
      if (!op.IsValid(&why)) return reader.Fail(path, why);
      operations.push_back(std::move(op));
    }
  }
  if (out) *out = std::move(operations);
  return true;
}

// With body not null, the "body" member must be present but is not read: body stands for it.
bool ParseHairstyleDocument(Reader& reader, const json& document, const std::string& base,
                            std::shared_ptr<const Body> body, Hairstyle* out) {
  if (!document.is_object()) {
    return reader.Expected("", "a JSON object {\"body\": ..., \"scalp\": ..., ...} at the top level",
                           document);
  }
  // "render" holds render settings, read by render_json.cpp (the render commands) and ignored
  // here.
  if (!reader.CheckFields(document, "",
                          {"description", "body", "scalp", "masters", "comb", "hair", "wisps",
                           "layers", "contact", "solver", "gravity", "operations",
                           "render"})) {
    return false;
  }
  // The operations are not part of the Hairstyle (ParseStyleOperations returns them), but a
  // file with bad ones is a bad file, whichever command reads it.
  if (!ParseOperations(reader, document, nullptr)) return false;
  const auto description = document.find("description");
  if (description != document.end() && !description->is_string()) {
    return reader.Expected("description", "a string", *description);
  }
  Hairstyle style;
  if (body == nullptr) {
    if (!internal::ParseBodyMember(reader, document, base, true, &body)) return false;
  } else if (!document.contains("body")) {
    return reader.Missing("body", "a body file name or a body object");
  }
  style.body = body;
  if (!ParseScalp(reader, document, *body, &style) || !ParseMasters(reader, document, base, &style) ||
      !ParseComb(reader, document, &style) || !ParseHair(reader, document, &style) ||
      !ParseWisps(reader, document, &style) || !ParseLayersAndContact(reader, document, &style) ||
      !internal::ParseSolverObject(reader, document, "", &style.solver) ||
      !reader.ReadVector<3>(document, "", "gravity", "m/s^2", false, &style.gravity)) {
    return false;
  }
  std::string why;
  if (!style.IsValid(&why)) return reader.Fail("", why);
  *out = std::move(style);
  return true;
}

}  // namespace

bool ParseHairstyle(const nlohmann::json& document, const std::string& base_directory,
                    Hairstyle* style, std::string* error) {
  return ParseHairstyle(document, base_directory, nullptr, style, error);
}

bool ParseHairstyle(const nlohmann::json& document, const std::string& base_directory,
                    std::shared_ptr<const Body> body, Hairstyle* style, std::string* error) {
  Reader reader;
  try {
    if (ParseHairstyleDocument(reader, document, base_directory, std::move(body), style)) {
      return true;
    }
  } catch (const std::exception& e) {
    reader.Fail("", std::string("cannot read the hairstyle: ") + e.what());
  }
  if (error) *error = reader.error();
  return false;
}

bool ParseStyleOperations(const nlohmann::json& document, std::vector<StyleOperation>* operations,
                          std::string* error) {
  Reader reader;
  try {
    if (!document.is_object()) {
      reader.Expected("", "a JSON object at the top level", document);
    } else if (ParseOperations(reader, document, operations)) {
      return true;
    }
  } catch (const std::exception& e) {
    reader.Fail("operations", std::string("cannot read the operations: ") + e.what());
  }
  if (error) *error = reader.error();
  return false;
}

bool LoadHairstyle(const std::string& path, Hairstyle* style, std::string* error) {
  return LoadHairstyle(path, style, nullptr, error);
}

bool LoadHairstyle(const std::string& path, Hairstyle* style,
                   std::vector<StyleOperation>* operations, std::string* error) {
  std::string text, why;
  if (!ReadFile(path, &text, error)) return false;
  const std::string base = std::filesystem::path(path).parent_path().string();
  if (!ParseHairstyleText(text, base.empty() ? "." : base, style, operations, &why)) {
    if (error) *error = DisplayPath(path) + ": " + why;
    return false;
  }
  return true;
}

bool ParseHairstyleText(const std::string& text, const std::string& base_directory,
                        Hairstyle* style, std::vector<StyleOperation>* operations,
                        std::string* error) {
  json document;
  Hairstyle parsed;
  std::vector<StyleOperation> parsed_operations;
  if (!internal::ParseJsonText(text, &document, error) ||
      !ParseHairstyle(document, base_directory, &parsed, error) ||
      !ParseStyleOperations(document, &parsed_operations, error)) {
    return false;
  }
  *style = std::move(parsed);
  if (operations) *operations = std::move(parsed_operations);
  return true;
}

}  // namespace ringlet
