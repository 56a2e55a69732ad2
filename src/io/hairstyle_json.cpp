// Hairstyle files: JSON -> validated Hairstyle (docs/hairstyle-format.md).
//
// Every field is checked where it is read (io/json_reader.h) so that an error names the field,
// what was expected and what was found, in one line. Hairstyle::IsValid runs last as a safety net.
#include "ringlet/hairstyle_json.h"

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "io/json_reader.h"
#include "ringlet/atomic_file.h"
#include "ringlet/body_json.h"

namespace ringlet {
namespace {

using nlohmann::json;
using internal::Member;
using internal::NumberRule;
using internal::Reader;
using internal::Show;

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
constexpr NumberRule kGradingRule{"a finite number >= 1 (last/first segment length) or \"auto\"",
                                  [](double x) { return x >= 1.0; }};
constexpr NumberRule kSeedRule{"an integer between 0 and 2^53",
                               [](double x) { return x >= 0.0 && x <= 9007199254740992.0 &&
                                                     x == std::floor(x); }};
constexpr NumberRule kPackingRule{"a finite number in (0, 0.69]",
                                  [](double x) { return x > 0.0 && x <= 0.69; }};
constexpr NumberRule kLayerThicknessRule{"a finite number in [0, 0.1) (m)",
                                         [](double x) { return x >= 0.0 && x < 0.1; }};

// An optional object member: null when absent, an error when not an object.
bool OptionalObject(Reader& reader, const json& parent, const std::string& parent_path,
                    const char* key, const json** out) {
  *out = nullptr;
  const auto it = parent.find(key);
  if (it == parent.end()) return true;
  if (!it->is_object()) return reader.Expected(Member(parent_path, key), "an object", *it);
  *out = &*it;
  return true;
}

bool ReadSeed(Reader& reader, const json& object, const std::string& path, const char* key,
              std::uint64_t* seed) {
  double value = static_cast<double>(*seed);
  if (!reader.ReadNumber(object, path, key, kSeedRule, false, &value)) return false;
  *seed = static_cast<std::uint64_t>(value);
  return true;
}

// "body": a file name (a body JSON file, docs/body.md) or the body object itself.
bool ParseBodyMember(Reader& reader, const json& document, const std::string& base,
                     std::shared_ptr<const Body>* out) {
  const auto it = document.find("body");
  const char* expected = "a body file name or a body object {\"spheres\": [...], \"meshes\": [...]}";
  if (it == document.end()) return reader.Missing("body", expected);
  auto body = std::make_shared<Body>();
  std::string error;
  if (it->is_string()) {
    std::filesystem::path file(it->get<std::string>());
    if (file.is_relative()) file = std::filesystem::path(base) / file;
    if (!LoadBody(file.string(), body.get(), &error)) return reader.Fail("body", error);
  } else if (it->is_object()) {
    if (!ParseBody(*it, "body", base, body.get(), &error)) return reader.Fail("", error);
  } else {
    return reader.Expected("body", expected, *it);
  }
  *out = std::move(body);
  return true;
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

bool ParseMasters(Reader& reader, const json& document, Hairstyle* style) {
  const json* masters = nullptr;
  if (!OptionalObject(reader, document, "", "masters", &masters)) return false;
  if (!masters) return true;
  const std::string path = "masters";
  if (!reader.CheckFields(*masters, path,
                          {"count", "seed", "segments", "grading", "points_per_segment",
                           "packing"}) ||
      !reader.ReadInteger(*masters, path, "count", 1, 1000000, &style->roots.count) ||
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
  if (!reader.CheckFields(*comb, path, {"tilt", "direction", "fallback_direction", "parting"}) ||
      !reader.ReadNumber(*comb, path, "tilt", kTiltRule, false, &c.tilt) ||
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

bool ParseHair(Reader& reader, const json& document, Hairstyle* style) {
  const json* hair = nullptr;
  if (!OptionalObject(reader, document, "", "hair", &hair)) return false;
  std::string origin = "caucasian", curl;
  if (hair) {
    const std::string path = "hair";
    if (!reader.CheckFields(*hair, path, {"origin", "curl", "length", "seed"}) ||
        !reader.ReadNumber(*hair, path, "length", kPositiveLength, false, &style->length) ||
        !ReadSeed(reader, *hair, path, "seed", &style->seed)) {
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
  return true;
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
                           "points_per_strand", "tip_taper", "include_master",
                           "spread_roots"}) ||
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

bool ParseHairstyleDocument(Reader& reader, const json& document, const std::string& base,
                            Hairstyle* out) {
  if (!document.is_object()) {
    return reader.Expected("", "a JSON object {\"body\": ..., \"scalp\": ..., ...} at the top level",
                           document);
  }
  // "render" holds render settings, read by render_json.cpp (the render commands) and ignored
  // here.
  if (!reader.CheckFields(document, "",
                          {"description", "body", "scalp", "masters", "comb", "hair", "wisps",
                           "layers", "contact", "solver", "gravity", "render"})) {
    return false;
  }
  const auto description = document.find("description");
  if (description != document.end() && !description->is_string()) {
    return reader.Expected("description", "a string", *description);
  }
  Hairstyle style;
  std::shared_ptr<const Body> body;
  if (!ParseBodyMember(reader, document, base, &body)) return false;
  style.body = body;
  if (!ParseScalp(reader, document, *body, &style) || !ParseMasters(reader, document, &style) ||
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
  Reader reader;
  try {
    if (ParseHairstyleDocument(reader, document, base_directory, style)) return true;
  } catch (const std::exception& e) {
    reader.Fail("", std::string("cannot read the hairstyle: ") + e.what());
  }
  if (error) *error = reader.error();
  return false;
}

bool LoadHairstyle(const std::string& path, Hairstyle* style, std::string* error) {
  std::string text, why;
  if (!ReadFile(path, &text, error)) return false;
  json document;
  const std::string base = std::filesystem::path(path).parent_path().string();
  if (!internal::ParseJsonText(text, &document, &why) ||
      !ParseHairstyle(document, base.empty() ? "." : base, style, &why)) {
    if (error) *error = path + ": " + why;
    return false;
  }
  return true;
}

}  // namespace ringlet
