// Masters files: explicit master strands (docs/hairstyle-format.md, "Explicit masters").
//
// Every field is checked where it is read (io/json_reader.h) so that an error names the master,
// the field, what was expected and what was found, in one line. Arrays are counted against
// segment_lengths before anything is allocated for them.
#include "ringlet/masters_json.h"

#include <cmath>
#include <nlohmann/json.hpp>

#include "io/json_reader.h"
#include "io/json_writer.h"
#include "ringlet/atomic_file.h"

namespace ringlet {
namespace {

using internal::Element;
using internal::Member;
using internal::NumberRule;
using internal::Reader;
using nlohmann::json;

constexpr NumberRule kPositiveLength{"a finite number > 0 (m)", [](double x) { return x > 0.0; }};
constexpr NumberRule kNonNegativeLength{"a finite number >= 0 (m)",
                                        [](double x) { return x >= 0.0; }};
constexpr NumberRule kPositive{"a finite number > 0", [](double x) { return x > 0.0; }};
constexpr NumberRule kNonNegative{"a finite number >= 0", [](double x) { return x >= 0.0; }};
constexpr NumberRule kPoisson{"a finite number in (-1, 0.5]",
                              [](double x) { return x > -1.0 && x <= 0.5; }};

// Orthonormality of a frame read from decimals: the tolerance of IsValid(StrandModel).
constexpr double kFrameTolerance = 1e-9;

// An array of n triples [kappa1, kappa2, tau] (1/m), counted first.
bool ReadTriples(Reader& reader, const json& object, const std::string& path, const char* key,
                 int n, VecX* out) {
  const std::string expected = "an array of " + std::to_string(n) +
                               " triples [kappa1, kappa2, tau] (1/m), one per segment";
  const json* array = nullptr;
  if (!reader.ReadArray(object, path, key, expected.c_str(), &array)) return false;
  if (!array) return true;
  const std::string field = Member(path, key);
  if (array->size() != static_cast<size_t>(n)) {
    return reader.Fail(field, "has " + std::to_string(array->size()) + " entries, expected " +
                                  std::to_string(n) + " (one triple per segment_lengths entry)");
  }
  VecX values(3 * n);
  for (int i = 0; i < n; ++i) {
    const json& triple = (*array)[static_cast<size_t>(i)];
    const char* triple_expected = "an array of 3 finite numbers [kappa1, kappa2, tau] (1/m)";
    if (!triple.is_array() || triple.size() != 3) {
      return reader.Expected(Element(field, static_cast<size_t>(i)), triple_expected, triple);
    }
    for (int j = 0; j < 3; ++j) {
      const json& x = triple[static_cast<size_t>(j)];
      if (!x.is_number() || !std::isfinite(x.get<double>())) {
        return reader.Expected(Element(field, static_cast<size_t>(i)), triple_expected, triple);
      }
      values(3 * i + j) = x.get<double>();
    }
  }
  *out = std::move(values);
  return true;
}

bool ParseRoot(Reader& reader, const json& master, const std::string& path, ExplicitMaster* m) {
  const char* expected = "an object {\"position\": [x, y, z], \"frame\": {\"n1\", \"n2\", \"t\"}}";
  const auto it = master.find("root");
  if (it == master.end()) return reader.Missing(Member(path, "root"), expected);
  if (!it->is_object()) return reader.Expected(Member(path, "root"), expected, *it);
  const std::string root = Member(path, "root");
  if (!reader.CheckFields(*it, root, {"position", "frame"}) ||
      !reader.ReadVector<3>(*it, root, "position", "m", true, &m->root_position)) {
    return false;
  }
  const char* frame_expected =
      "an object {\"n1\": [...], \"n2\": [...], \"t\": [...]} (unit vectors, n1 x n2 = t)";
  const auto frame = it->find("frame");
  const std::string frame_path = Member(root, "frame");
  if (frame == it->end()) return reader.Missing(frame_path, frame_expected);
  if (!frame->is_object()) return reader.Expected(frame_path, frame_expected, *frame);
  Vec3 n1, n2, t;
  if (!reader.CheckFields(*frame, frame_path, {"n1", "n2", "t"}) ||
      !reader.ReadVector<3>(*frame, frame_path, "n1", "a unit vector", true, &n1) ||
      !reader.ReadVector<3>(*frame, frame_path, "n2", "a unit vector", true, &n2) ||
      !reader.ReadVector<3>(*frame, frame_path, "t", "a unit vector", true, &t)) {
    return false;
  }
  Mat3 q;
  q.col(0) = n1;
  q.col(1) = n2;
  q.col(2) = t;
  if ((q.transpose() * q - Mat3::Identity()).norm() > kFrameTolerance || q.determinant() < 0.0) {
    return reader.Fail(frame_path, "expected n1, n2, t orthonormal and right-handed (n1 x n2 = t) "
                                   "within 1e-9");
  }
  m->root_frame = q;
  return true;
}

bool ParseMaster(Reader& reader, const json& master, const std::string& path, ExplicitMaster* m) {
  if (!master.is_object()) {
    return reader.Expected(path, "an object {\"root\": ..., \"segment_lengths\": [...], ...}",
                           master);
  }
  if (!reader.CheckFields(master, path,
                          {"root", "segment_lengths", "section", "material", "natural_curvature",
                           "rest_curvatures", "curvatures", "layer", "wisp_radius",
                           "clearance", "support_offsets"}) ||
      !ParseRoot(reader, master, path, m)) {
    return false;
  }
  // Segments: counted before they are read.
  const std::string lengths_expected = "an array of 1 to " + std::to_string(kMaxSegments) +
                                       " segment lengths (m, each > 0), root to tip";
  const json* lengths = nullptr;
  if (!reader.ReadArray(master, path, "segment_lengths", lengths_expected.c_str(), &lengths)) {
    return false;
  }
  const std::string lengths_path = Member(path, "segment_lengths");
  if (!lengths) return reader.Missing(lengths_path, lengths_expected);
  if (lengths->empty() || lengths->size() > static_cast<size_t>(kMaxSegments)) {
    return reader.Fail(lengths_path, "has " + std::to_string(lengths->size()) +
                                         " entries, expected 1 to " +
                                         std::to_string(kMaxSegments));
  }
  m->segment_lengths.resize(lengths->size());
  for (size_t i = 0; i < lengths->size(); ++i) {
    const json& x = (*lengths)[i];
    if (!x.is_number() || !std::isfinite(x.get<double>()) || !(x.get<double>() > 0.0)) {
      return reader.Expected(Element(lengths_path, i), kPositiveLength.expected, x);
    }
    m->segment_lengths[i] = x.get<double>();
  }
  const int n = static_cast<int>(m->segment_lengths.size());

  // Section and material (optional: the hair type's).
  const json* object = nullptr;
  if (!internal::OptionalObject(reader, master, path, "section", &object)) return false;
  if (object) {
    const std::string p = Member(path, "section");
    CrossSection section;
    if (!reader.CheckFields(*object, p, {"a", "b"}) ||
        !reader.ReadNumber(*object, p, "a", kPositiveLength, true, &section.a) ||
        !reader.ReadNumber(*object, p, "b", kPositiveLength, true, &section.b)) {
      return false;
    }
    if (section.b > section.a) {
      return reader.Fail(p, "expected a >= b (a is the major semi-axis, along n1)");
    }
    m->section = section;
  }
  if (!internal::OptionalObject(reader, master, path, "material", &object)) return false;
  if (object) {
    const std::string p = Member(path, "material");
    Material material;
    if (!reader.CheckFields(*object, p, {"young_modulus", "poisson_ratio", "density"}) ||
        !reader.ReadNumber(*object, p, "young_modulus",
                           {"a finite number > 0 (Pa)", kPositive.accepts}, true,
                           &material.young_modulus) ||
        !reader.ReadNumber(*object, p, "poisson_ratio", kPoisson, true, &material.poisson_ratio) ||
        !reader.ReadNumber(*object, p, "density",
                           {"a finite number >= 0 (kg/m^3)", kNonNegative.accepts}, true,
                           &material.density)) {
      return false;
    }
    m->material = material;
  }
  if (master.contains("natural_curvature")) {
    Vec3 natural;
    if (!reader.ReadVector<3>(master, path, "natural_curvature", "1/m, [kappa1, kappa2, tau]",
                              true, &natural)) {
      return false;
    }
    m->natural_curvature = natural;
  }
  if (!ReadTriples(reader, master, path, "rest_curvatures", n, &m->rest_curvatures) ||
      !ReadTriples(reader, master, path, "curvatures", n, &m->start_curvatures)) {
    return false;
  }
  int layer = 0;
  bool present = false;
  if (!reader.ReadInteger(master, path, "layer", 0, 63, &layer, &present)) return false;
  if (present) m->layer = layer;
  double value = 0.0;
  if (!reader.ReadNumber(master, path, "wisp_radius", kNonNegativeLength, false, &value,
                         &present)) {
    return false;
  }
  if (present) m->wisp_radius = value;
  if (!reader.ReadNumber(master, path, "clearance", kNonNegativeLength, false, &value, &present)) {
    return false;
  }
  if (present) m->clearance = value;
  // Support offsets: one per contact sample, so at most 64 (the most contact samples per segment
  // a hairstyle takes) per segment; their exact count is checked against the hairstyle's
  // contact samples when the masters are built.
  const json* offsets = nullptr;
  const char* offsets_expected = "an array of finite numbers (m), one per contact sample";
  if (!reader.ReadArray(master, path, "support_offsets", offsets_expected, &offsets)) return false;
  if (offsets) {
    const std::string field = Member(path, "support_offsets");
    if (offsets->size() > static_cast<size_t>(64) * static_cast<size_t>(n)) {
      return reader.Fail(field, "has " + std::to_string(offsets->size()) +
                                    " entries, more than 64 per segment");
    }
    m->support_offsets.reserve(offsets->size());
    for (size_t k = 0; k < offsets->size(); ++k) {
      const json& x = (*offsets)[k];
      if (!x.is_number() || !std::isfinite(x.get<double>())) {
        return reader.Expected(Element(field, k), "a finite number (m)", x);
      }
      m->support_offsets.push_back(x.get<double>());
    }
  }
  return true;
}

bool ParseMastersDocument(Reader& reader, const json& document,
                          std::vector<ExplicitMaster>* out) {
  const char* expected = "a JSON object {\"masters\": [...]} at the top level";
  if (!document.is_object()) return reader.Expected("", expected, document);
  if (!reader.CheckFields(document, "", {"description", "masters", "units"})) return false;
  const std::string array_expected =
      "an array of 1 to " + std::to_string(kMaxMasters) + " master objects";
  const json* array = nullptr;
  if (!reader.ReadArray(document, "", "masters", array_expected.c_str(), &array)) return false;
  if (!array) return reader.Missing("masters", array_expected);
  if (array->empty() || array->size() > static_cast<size_t>(kMaxMasters)) {
    return reader.Fail("masters", "has " + std::to_string(array->size()) +
                                      " entries, expected 1 to " + std::to_string(kMaxMasters));
  }
  for (const char* key : {"description", "units"}) {
    const auto it = document.find(key);
    if (it != document.end() && !(key[0] == 'd' ? it->is_string() : it->is_object())) {
      return reader.Expected(key, key[0] == 'd' ? "a string" : "an object (informative)", *it);
    }
  }
  std::vector<ExplicitMaster> masters(array->size());
  for (size_t i = 0; i < array->size(); ++i) {
    if (!ParseMaster(reader, (*array)[i], Element("masters", i), &masters[i])) return false;
  }
  *out = std::move(masters);
  return true;
}

void AppendVector(const Vec3& v, std::string* out) {
  *out += '[';
  for (int k = 0; k < 3; ++k) {
    if (k) *out += ", ";
    internal::AppendJsonNumber(v(k), out);
  }
  *out += ']';
}

void AppendTriples(const VecX& q, std::string* out) {
  *out += '[';
  for (Eigen::Index i = 0; i < q.size() / 3; ++i) {
    if (i) *out += ", ";
    AppendVector(q.segment<3>(3 * i), out);
  }
  *out += ']';
}

}  // namespace

bool ParseMastersText(const std::string& text, std::vector<ExplicitMaster>* masters,
                      std::string* error) {
  json document;
  if (!internal::ParseJsonText(text, &document, error)) return false;
  Reader reader;
  try {
    if (ParseMastersDocument(reader, document, masters)) return true;
  } catch (const std::exception& e) {
    reader.Fail("", std::string("cannot read the masters: ") + e.what());
  }
  if (error) *error = reader.error();
  return false;
}

bool LoadMastersFile(const std::string& path, std::vector<ExplicitMaster>* masters,
                     std::string* error) {
  std::string text, why;
  if (!ReadFile(path, &text, error)) return false;
  if (!ParseMastersText(text, masters, &why)) {
    if (error) *error = DisplayPath(path) + ": " + why;
    return false;
  }
  return true;
}

std::string MastersToString(const std::vector<ExplicitMaster>& masters) {
  std::string out = "{\n  \"masters\": [";
  for (size_t i = 0; i < masters.size(); ++i) {
    const ExplicitMaster& m = masters[i];
    out += i ? ",\n    {\n" : "\n    {\n";
    out += "      \"root\": {\"position\": ";
    AppendVector(m.root_position, &out);
    out += ", \"frame\": {\"n1\": ";
    AppendVector(m.root_frame.col(0), &out);
    out += ", \"n2\": ";
    AppendVector(m.root_frame.col(1), &out);
    out += ", \"t\": ";
    AppendVector(m.root_frame.col(2), &out);
    out += "}},\n      \"segment_lengths\": [";
    for (size_t k = 0; k < m.segment_lengths.size(); ++k) {
      if (k) out += ", ";
      internal::AppendJsonNumber(m.segment_lengths[k], &out);
    }
    out += "]";
    if (m.section) {
      out += ",\n      \"section\": {\"a\": ";
      internal::AppendJsonNumber(m.section->a, &out);
      out += ", \"b\": ";
      internal::AppendJsonNumber(m.section->b, &out);
      out += "}";
    }
    if (m.material) {
      out += ",\n      \"material\": {\"young_modulus\": ";
      internal::AppendJsonNumber(m.material->young_modulus, &out);
      out += ", \"poisson_ratio\": ";
      internal::AppendJsonNumber(m.material->poisson_ratio, &out);
      out += ", \"density\": ";
      internal::AppendJsonNumber(m.material->density, &out);
      out += "}";
    }
    if (m.natural_curvature) {
      out += ",\n      \"natural_curvature\": ";
      AppendVector(*m.natural_curvature, &out);
    }
    if (m.rest_curvatures.size() != 0) {
      out += ",\n      \"rest_curvatures\": ";
      AppendTriples(m.rest_curvatures, &out);
    }
    if (m.start_curvatures.size() != 0) {
      out += ",\n      \"curvatures\": ";
      AppendTriples(m.start_curvatures, &out);
    }
    if (m.layer) {
      out += ",\n      \"layer\": ";
      internal::AppendJsonInteger(*m.layer, &out);
    }
    if (m.wisp_radius) {
      out += ",\n      \"wisp_radius\": ";
      internal::AppendJsonNumber(*m.wisp_radius, &out);
    }
    if (m.clearance) {
      out += ",\n      \"clearance\": ";
      internal::AppendJsonNumber(*m.clearance, &out);
    }
    if (!m.support_offsets.empty()) {
      out += ",\n      \"support_offsets\": [";
      for (size_t k = 0; k < m.support_offsets.size(); ++k) {
        if (k > 0) out += ", ";
        internal::AppendJsonNumber(m.support_offsets[k], &out);
      }
      out += "]";
    }
    out += "\n    }";
  }
  out += "\n  ],\n  \"units\": {\"root.position\": \"m\", \"segment_lengths\": \"m\", "
         "\"section\": \"m (semi-axes)\", \"material\": \"Pa, -, kg/m^3\", "
         "\"curvatures\": \"1/m, [kappa1, kappa2, tau] in the material frame\", "
         "\"wisp_radius\": \"m\", \"clearance\": \"m\", \"support_offsets\": \"m\"}\n}\n";
  return out;
}

ExplicitMaster ExplicitMasterOf(const StrandModel& m) {
  ExplicitMaster e;
  e.root_position = m.root_position;
  e.root_frame = m.root_frame;
  e.segment_lengths = m.segment_lengths;
  e.section = m.section;
  e.material = m.material;
  e.natural_curvature = m.natural_curvature;
  e.rest_curvatures = m.rest_curvatures;
  e.support_offsets = m.contact.support_offsets;
  return e;
}

std::vector<ExplicitMaster> ExplicitMastersOf(const HairstyleMasters& masters,
                                              const std::vector<VecX>* starts) {
  std::vector<ExplicitMaster> out(masters.models.size());
  for (size_t i = 0; i < out.size(); ++i) {
    ExplicitMaster& e = out[i];
    e = ExplicitMasterOf(masters.models[i]);
    if (starts && i < starts->size()) e.start_curvatures = (*starts)[i];
    if (i < masters.layers.size()) e.layer = masters.layers[i];
    if (i < masters.wisp_radii.size()) e.wisp_radius = masters.wisp_radii[i];
    if (i < masters.contact_radii.size()) e.clearance = masters.contact_radii[i];
  }
  return out;
}

}  // namespace ringlet
