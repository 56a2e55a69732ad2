// Body descriptions: JSON -> validated spheres and OBJ meshes (docs/body.md).
//
// Same message style as the scene files (src/io/scene_json.cpp): one line, the field path, what
// was expected and what was found: "body.spheres[2].radius: expected a positive number (m), got
// -0.1". The path, value and field helpers are the shared ones of io/json_reader.h.
#include "ringlet/body_json.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <memory>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "io/body_member.h"
#include "io/json_reader.h"
#include "ringlet/atomic_file.h"

namespace ringlet {
namespace {

using nlohmann::json;

using internal::Element;
using internal::Member;
using internal::Reader;

constexpr const char* kPartExpected = "\"head\" or \"torso\" (the part it moves with)";

// A "moves_with" value: "head" or "torso".
bool ParsePart(Reader& reader, const json& value, const std::string& path, BodyPart* part) {
  if (value == "head") {
    *part = BodyPart::kHead;
  } else if (value == "torso") {
    *part = BodyPart::kTorso;
  } else {
    return reader.Expected(path, kPartExpected, value);
  }
  return true;
}

bool ParseSphere(Reader& reader, const json& object, const std::string& path, Sphere* sphere) {
  if (!object.is_object()) {
    return reader.Expected(path, "an object {\"center\": [x, y, z], \"radius\": r}", object);
  }
  if (!reader.CheckFields(object, path, {"name", "center", "radius", "moves_with"})) return false;

  const auto name = object.find("name");
  if (name != object.end()) {
    if (!name->is_string()) return reader.Expected(Member(path, "name"), "a string", *name);
    sphere->name = name->get<std::string>();
  }
  const auto moves_with = object.find("moves_with");
  if (moves_with != object.end()) {
    BodyPart part = BodyPart::kHead;
    if (!ParsePart(reader, *moves_with, Member(path, "moves_with"), &part)) return false;
    sphere->moves_with = part;
  }

  const char* center_expected = "an array of 3 finite numbers (m)";
  const auto center = object.find("center");
  if (center == object.end()) return reader.Missing(Member(path, "center"), center_expected);
  if (!center->is_array() || center->size() != 3) {
    return reader.Expected(Member(path, "center"), center_expected, *center);
  }
  for (size_t i = 0; i < 3; ++i) {
    const json& x = (*center)[i];
    if (!x.is_number() || !std::isfinite(x.get<double>())) {
      return reader.Expected(Member(path, "center"), center_expected, *center);
    }
    sphere->center(static_cast<int>(i)) = x.get<double>();
  }

  const char* radius_expected = "a positive number (m)";
  const auto radius = object.find("radius");
  if (radius == object.end()) return reader.Missing(Member(path, "radius"), radius_expected);
  if (!radius->is_number() || !std::isfinite(radius->get<double>()) ||
      !(radius->get<double>() > 0.0)) {
    return reader.Expected(Member(path, "radius"), radius_expected, *radius);
  }
  sphere->radius = radius->get<double>();
  return true;
}

bool ParseMesh(Reader& reader, const json& object, const std::string& path,
               const std::string& base_directory, std::vector<TriangleMesh>* meshes,
               std::vector<std::optional<BodyPart>>* parts) {
  if (!object.is_object())
    return reader.Expected(path, "an object {\"obj\": \"file.obj\"}", object);
  if (!reader.CheckFields(object, path, {"obj", "moves_with"})) return false;
  // "moves_with": one part for every object of the file, or {"object name": part, ...}.
  const char* moves_expected =
      "\"head\", \"torso\" or an object {\"OBJ object or group name\": \"head\" or \"torso\"}";
  const auto moves_with = object.find("moves_with");
  std::optional<BodyPart> all;
  std::map<std::string, BodyPart> by_name;
  if (moves_with != object.end()) {
    const std::string moves_path = Member(path, "moves_with");
    if (moves_with->is_string()) {
      BodyPart part = BodyPart::kHead;
      if (!ParsePart(reader, *moves_with, moves_path, &part)) return false;
      all = part;
    } else if (moves_with->is_object()) {
      for (const auto& item : moves_with->items()) {
        BodyPart part = BodyPart::kHead;
        if (!ParsePart(reader, item.value(), Member(moves_path, item.key()), &part)) return false;
        by_name[item.key()] = part;
      }
    } else {
      return reader.Expected(moves_path, moves_expected, *moves_with);
    }
  }
  const std::string field = Member(path, "obj");
  const char* expected = "the path of an OBJ file (relative to the body file's directory)";
  const auto obj = object.find("obj");
  if (obj == object.end()) return reader.Missing(field, expected);
  if (!obj->is_string() || obj->get<std::string>().empty()) {
    return reader.Expected(field, expected, *obj);
  }
  const std::filesystem::path relative(obj->get<std::string>());
  const std::string file = relative.is_absolute() || base_directory.empty()
                               ? relative.string()
                               : (std::filesystem::path(base_directory) / relative).string();
  std::vector<TriangleMesh> loaded;
  std::string why;
  if (!LoadObjMeshes(file, &loaded, &why)) return reader.Fail(field, why);
  for (const auto& entry : by_name) {
    const std::string& name = entry.first;  // not a structured binding: clang 14 cannot capture one
    if (std::none_of(loaded.begin(), loaded.end(),
                     [&](const TriangleMesh& m) { return m.name() == name; })) {
      std::string names;
      for (const TriangleMesh& m : loaded) names += (names.empty() ? "\"" : ", \"") + m.name() + "\"";
      return reader.Fail(Member(Member(path, "moves_with"), name),
                         "expected the name of an object or group of " + obj->get<std::string>() +
                             " (" + names + ")");
    }
  }
  for (TriangleMesh& m : loaded) {
    const auto named = by_name.find(m.name());
    parts->push_back(named != by_name.end() ? std::optional<BodyPart>(named->second) : all);
    meshes->push_back(std::move(m));
  }
  return true;
}

bool ParseBodyObject(Reader& reader, const json& document, const std::string& path,
                     const std::string& base_directory, Body* out) {
  const char* expected = "an object {\"spheres\": [...], \"meshes\": [...]}";
  if (!document.is_object()) return reader.Expected(path, expected, document);
  if (!reader.CheckFields(document, path,
                          {"spheres", "meshes", "blend", "description", "mesh_distance",
                           "grid_spacing", "grid_band"})) {
    return false;
  }
  MeshDistanceOptions mesh_distance;
  mesh_distance.mode = MeshDistanceOptions::Mode::kGrid;
  mesh_distance.spacing = kDefaultGridSpacing;
  mesh_distance.band = kDefaultGridBand;
  const auto mode_it = document.find("mesh_distance");
  if (mode_it != document.end()) {
    if (*mode_it == "exact") {
      mesh_distance.mode = MeshDistanceOptions::Mode::kExact;
    } else if (*mode_it != "grid") {
      return reader.Expected(Member(path, "mesh_distance"), "\"grid\" or \"exact\"", *mode_it);
    }
  }
  for (const auto& [key, target, what] :
       {std::tuple<const char*, double*, const char*>{"grid_spacing", &mesh_distance.spacing,
                                                      "a finite number >= 0.0001 (m)"},
        std::tuple<const char*, double*, const char*>{"grid_band", &mesh_distance.band,
                                                      "a finite number > 0 (m)"}}) {
    const auto it = document.find(key);
    if (it == document.end()) continue;
    const double minimum = target == &mesh_distance.spacing ? 1e-4 : 0.0;
    if (!it->is_number() || !std::isfinite(it->get<double>()) || !(it->get<double>() >= minimum) ||
        !(it->get<double>() > 0.0)) {
      return reader.Expected(Member(path, key), what, *it);
    }
    *target = it->get<double>();
  }
  double blend = kDefaultBodyBlend;
  const auto blend_it = document.find("blend");
  if (blend_it != document.end()) {
    if (!blend_it->is_number() || !std::isfinite(blend_it->get<double>()) ||
        blend_it->get<double>() < 0.0) {
      return reader.Expected(Member(path, "blend"), "a finite number >= 0 (m)", *blend_it);
    }
    blend = blend_it->get<double>();
  }

  const auto description = document.find("description");
  if (description != document.end() && !description->is_string()) {
    return reader.Expected(Member(path, "description"), "a string", *description);
  }

  std::vector<Sphere> spheres;
  const json* sphere_array = nullptr;
  const std::string spheres_path = Member(path, "spheres");
  if (!reader.ReadArray(document, path, "spheres", "an array of sphere objects", &sphere_array)) {
    return false;
  }
  if (sphere_array) {
    // One sphere per element as it is read (not size() of them up front); names looked up in
    // a map (a pairwise check would be quadratic in the number of spheres).
    std::map<std::string, size_t> names;
    for (size_t i = 0; i < sphere_array->size(); ++i) {
      Sphere sphere;
      if (!ParseSphere(reader, (*sphere_array)[i], Element(spheres_path, i), &sphere)) {
        return false;
      }
      if (!sphere.name.empty()) {
        const auto [it, inserted] = names.emplace(sphere.name, i);
        if (!inserted) {
          return reader.Fail(Member(Element(spheres_path, i), "name"),
                             "\"" + sphere.name + "\" is already the name of " +
                                 Element(spheres_path, it->second) + " (names must be unique)");
        }
      }
      spheres.push_back(std::move(sphere));
    }
  }

  std::vector<TriangleMesh> meshes;
  std::vector<std::optional<BodyPart>> mesh_parts;
  const json* mesh_array = nullptr;
  const std::string meshes_path = Member(path, "meshes");
  if (!reader.ReadArray(document, path, "meshes", "an array of mesh objects", &mesh_array)) {
    return false;
  }
  if (mesh_array) {
    for (size_t i = 0; i < mesh_array->size(); ++i) {
      if (!ParseMesh(reader, (*mesh_array)[i], Element(meshes_path, i), base_directory, &meshes,
                     &mesh_parts)) {
        return false;
      }
    }
  }

  if (spheres.empty() && meshes.empty()) {
    return reader.Fail(path, "a body needs at least one sphere or mesh (\"spheres\", \"meshes\")");
  }
  std::string why;
  Body body;
  if (!Body::Create(std::move(spheres), std::move(meshes), &body, &why, blend, mesh_distance,
                    mesh_parts)) {
    // Safety net: the field checks above should have caught everything.
    return reader.Fail(path, why);
  }
  *out = std::move(body);
  return true;
}

}  // namespace

bool ParseBody(const nlohmann::json& document, std::string_view path,
               const std::string& base_directory, Body* body, std::string* error) {
  Reader reader;
  try {
    if (ParseBodyObject(reader, document, std::string(path), base_directory, body)) return true;
  } catch (const std::exception& e) {
    // Not expected (every access is type-checked first), but the library never throws.
    reader.Fail(std::string(path), std::string("cannot read the body: ") + e.what());
  }
  if (error) *error = reader.error();
  return false;
}

bool LoadBody(const std::string& path, Body* body, std::string* error) {
  std::string text;
  if (!ReadFile(path, &text, error)) return false;
  std::string why;
  const std::string directory = std::filesystem::path(path).parent_path().string();
  if (!ParseBodyText(text, directory, body, &why)) {
    if (error) *error = DisplayPath(path) + ": " + why;
    return false;
  }
  return true;
}

bool ParseBodyText(const std::string& text, const std::string& base_directory, Body* body,
                   std::string* error) {
  json document;
  return internal::ParseJsonText(text, &document, error) &&
         ParseBody(document, "", base_directory, body, error);
}

namespace internal {

bool ParseBodyMember(Reader& reader, const json& document, const std::string& base_directory,
                     bool required, std::shared_ptr<const Body>* out) {
  const auto it = document.find("body");
  const char* expected = "a body file name or a body object {\"spheres\": [...], \"meshes\": [...]}";
  if (it == document.end()) return required ? reader.Missing("body", expected) : true;
  auto body = std::make_shared<Body>();
  std::string error;
  if (it->is_string()) {
    std::filesystem::path file(it->get<std::string>());
    if (file.is_relative()) file = std::filesystem::path(base_directory) / file;
    if (!LoadBody(file.string(), body.get(), &error)) return reader.Fail("body", error);
  } else if (it->is_object()) {
    if (!ParseBody(*it, "body", base_directory, body.get(), &error)) return reader.Fail("", error);
  } else {
    return reader.Expected("body", expected, *it);
  }
  *out = std::move(body);
  return true;
}

}  // namespace internal
}  // namespace ringlet
