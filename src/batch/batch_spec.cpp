// Batch specs (batch.h, docs/batch.md): reading and checking a spec field by field, and
// resolving item k as a pure function of (spec, k).
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "groom/random.h"
#include "io/json_reader.h"
#include "ringlet/atomic_file.h"
#include "ringlet/batch.h"
#include "ringlet/hairstyle_json.h"
#include "ringlet/render_json.h"

namespace ringlet {
namespace {

using internal::Element;
using internal::json;
using internal::Member;
using internal::Reader;
using internal::Show;

// What a varied hairstyle field holds.
enum class FieldType { kNumber, kInteger, kString, kVector, kBool };

struct FieldPath {
  const char* path;
  FieldType type;
};

// The hairstyle fields a spec may vary (docs/batch.md, "parameters"); the hairstyle reader
// checks each value's range.
constexpr FieldPath kFieldPaths[] = {
    {"hair.origin", FieldType::kString},
    {"hair.curl", FieldType::kString},
    {"hair.length", FieldType::kNumber},
    {"hair.length.front", FieldType::kNumber},
    {"hair.length.side", FieldType::kNumber},
    {"hair.length.back", FieldType::kNumber},
    {"hair.length.crown", FieldType::kNumber},
    {"hair.curl_radius", FieldType::kNumber},
    {"hair.curl_pitch", FieldType::kNumber},
    {"hair.curl_spread", FieldType::kNumber},
    {"hair.ellipticity", FieldType::kNumber},
    {"hair.seed", FieldType::kInteger},
    {"comb.tilt", FieldType::kNumber},
    {"comb.direction", FieldType::kVector},
    {"comb.face_sweep", FieldType::kNumber},
    {"comb.curl_inward", FieldType::kBool},
    {"comb.parting.normal", FieldType::kVector},
    {"comb.parting.offset", FieldType::kNumber},
    {"comb.parting.strength", FieldType::kNumber},
    {"masters.count", FieldType::kInteger},
    {"masters.seed", FieldType::kInteger},
    {"masters.segments", FieldType::kInteger},
    {"wisps.strands_per_wisp", FieldType::kInteger},
    {"wisps.points_per_strand", FieldType::kInteger},
    {"wisps.jitter", FieldType::kNumber},
    {"wisps.length_variation", FieldType::kNumber},
    {"wisps.frizz_amplitude", FieldType::kNumber},
    {"wisps.frizz_frequency", FieldType::kNumber},
    {"wisps.tip_scale", FieldType::kNumber},
    {"layers.count", FieldType::kInteger},
    {"layers.thickness", FieldType::kNumber},
    {"scalp.hairline_front", FieldType::kNumber},
    {"scalp.hairline_side", FieldType::kNumber},
    {"scalp.hairline_back", FieldType::kNumber},
    {"render.seed", FieldType::kInteger},
    {"render.hair.eumelanin", FieldType::kNumber},
    {"render.hair.pheomelanin", FieldType::kNumber},
};

// The seeds each item gets of its own (BatchSpec::item_seeds).
constexpr const char* kItemSeedPaths[] = {"masters.seed", "hair.seed", "render.seed"};

constexpr const char* kOperationNames[] = {"curl", "wet", "dry", "cut", "grow"};

// FNV-1a (Fowler, Noll, Vo) of a name: the stream of a parameter depends on its path only, so
// adding a parameter to a spec does not change the values drawn for the others.
std::uint64_t NameHash(const std::string& name) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (const char c : name) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ull;
  }
  return h;
}

// Largest seed a hairstyle accepts: 2^53.
constexpr std::uint64_t kSeedMask = (std::uint64_t{1} << 53) - 1;

bool IsVector3(const json& value) {
  if (!value.is_array() || value.size() != 3) return false;
  for (const json& x : value) {
    if (!x.is_number() || !std::isfinite(x.get<double>())) return false;
  }
  return true;
}

const char* TypeText(FieldType type) {
  switch (type) {
    case FieldType::kNumber:
      return "a finite number";
    case FieldType::kInteger:
      return "an integer";
    case FieldType::kString:
      return "a string";
    case FieldType::kVector:
      return "an array of 3 finite numbers";
    case FieldType::kBool:
      return "true or false";
  }
  return "a value";
}

bool HasType(const json& value, FieldType type) {
  switch (type) {
    case FieldType::kNumber:
      return value.is_number() && std::isfinite(value.get<double>());
    case FieldType::kInteger: {
      std::int64_t i = 0;
      return Reader::ExactInteger(value, &i);
    }
    case FieldType::kString:
      return value.is_string();
    case FieldType::kVector:
      return IsVector3(value);
    case FieldType::kBool:
      return value.is_boolean();
  }
  return false;
}

// Whether value is a distribution object: exactly one member named choice, uniform or normal
// ({"normal": {...}}: a cut plane's "normal" is an array and has an "offset" beside it).
bool IsDistribution(const json& value) {
  if (!value.is_object() || value.size() != 1) return false;
  const std::string& key = value.begin().key();
  if (key == "normal") return value.begin()->is_object();
  return key == "choice" || key == "uniform";
}

// Reads a distribution at path for values of `type`.
bool ParseDistribution(Reader& reader, const json& value, const std::string& path, FieldType type,
                       BatchDistribution* out) {
  const char* expected =
      "a distribution {\"choice\": [...]}, {\"uniform\": [low, high]} or {\"normal\": {\"mean\", "
      "\"sd\", \"min\", \"max\"}}";
  if (!IsDistribution(value)) return reader.Expected(path, expected, value);
  BatchDistribution d;
  d.integer = type == FieldType::kInteger;
  const std::string key = value.begin().key();
  const json& body = *value.begin();
  const std::string member = Member(path, key);
  if (key == "choice") {
    d.kind = BatchDistribution::Kind::kChoice;
    if (!body.is_array() || body.empty() || body.size() > 100000) {
      return reader.Expected(member, "a non-empty array of at most 100000 values", body);
    }
    for (size_t i = 0; i < body.size(); ++i) {
      if (!HasType(body[i], type))
        return reader.Expected(Element(member, i), TypeText(type), body[i]);
      d.choices.push_back(body[i]);
    }
  } else {
    if (type != FieldType::kNumber && type != FieldType::kInteger) {
      return reader.Fail(member, std::string("only \"choice\" can give ") + TypeText(type));
    }
    if (key == "uniform") {
      d.kind = BatchDistribution::Kind::kUniform;
      const char* want = d.integer ? "[low, high]: integers, low <= high"
                                   : "[low, high]: finite numbers, low < high";
      if (!body.is_array() || body.size() != 2 || !HasType(body[0], type) ||
          !HasType(body[1], type)) {
        return reader.Expected(member, want, body);
      }
      d.low = body[0].get<double>();
      d.high = body[1].get<double>();
      if (d.integer ? !(d.low <= d.high) : !(d.low < d.high)) {
        return reader.Expected(member, want, body);
      }
    } else {
      d.kind = BatchDistribution::Kind::kNormal;
      if (!body.is_object()) return reader.Expected(member, "an object {mean, sd, min, max}", body);
      if (!reader.CheckFields(body, member, {"mean", "sd", "min", "max"})) return false;
      const internal::NumberRule any{"a finite number", [](double) { return true; }};
      const internal::NumberRule positive{"a finite number > 0", [](double x) { return x > 0; }};
      if (!reader.ReadNumber(body, member, "mean", any, true, &d.mean) ||
          !reader.ReadNumber(body, member, "sd", positive, true, &d.sd) ||
          !reader.ReadNumber(body, member, "min", any, true, &d.low) ||
          !reader.ReadNumber(body, member, "max", any, true, &d.high)) {
        return false;
      }
      if (!(d.low < d.high)) {
        return reader.Fail(Member(member, "max"), "expected a number > min (" + Show(body["min"]) +
                                                      "), got " + Show(body["max"]));
      }
    }
  }
  *out = std::move(d);
  return true;
}

// Draws from d with rng. A bounded normal is drawn by rejection (up to 1000 draws, then the
// last draw clamped to the bounds, so that every item ends).
json Draw(const BatchDistribution& d, groom::SplitMix64* rng) {
  switch (d.kind) {
    case BatchDistribution::Kind::kChoice: {
      const auto n = static_cast<std::uint64_t>(d.choices.size());
      const auto i = static_cast<size_t>(std::min<double>(
          static_cast<double>(n - 1), std::floor(rng->Uniform() * static_cast<double>(n))));
      return d.choices[i];
    }
    case BatchDistribution::Kind::kUniform: {
      if (d.integer) {
        const double n = d.high - d.low + 1.0;
        const double k = std::min(n - 1.0, std::floor(rng->Uniform() * n));
        return static_cast<std::int64_t>(d.low + k);
      }
      return rng->Uniform(d.low, d.high);
    }
    case BatchDistribution::Kind::kNormal: {
      double x = d.mean;
      for (int attempt = 0; attempt < 1000; ++attempt) {
        x = d.mean + d.sd * rng->Normal();
        if (d.integer) x = std::round(x);
        if (x >= d.low && x <= d.high) break;
      }
      x = std::clamp(x, d.low, d.high);
      if (d.integer) return static_cast<std::int64_t>(std::round(x));
      return x;
    }
  }
  return nullptr;
}

// The test value number `which` of d (ParseBatchSpec's check): the bounds alternately, and the
// choices in turn (the last one repeated).
json TestValue(const BatchDistribution& d, size_t which) {
  if (d.kind == BatchDistribution::Kind::kChoice) {
    return d.choices[std::min(which, d.choices.size() - 1)];
  }
  const double x = which % 2 == 0 ? d.low : d.high;
  if (d.integer) return static_cast<std::int64_t>(x);
  return x;
}

size_t TestValueCount(const BatchDistribution& d) {
  return d.kind == BatchDistribution::Kind::kChoice ? d.choices.size() : 2;
}

// Sets the member at a dot path ("hair.length.front"), creating missing objects and replacing a
// non-object on the way (the hairstyle reader then names what is wrong).
void SetPath(json* document, const std::string& path, const json& value) {
  json* node = document;
  size_t begin = 0;
  while (true) {
    const size_t dot = path.find('.', begin);
    const std::string key = path.substr(begin, dot == std::string::npos ? dot : dot - begin);
    if (!node->is_object()) *node = json::object();
    if (dot == std::string::npos) {
      (*node)[key] = value;
      return;
    }
    node = &(*node)[key];
    begin = dot + 1;
  }
}

// Makes the relative file paths of a base absolute (body file, masters.file).
void AbsolutePaths(json* base, const std::string& directory) {
  namespace fs = std::filesystem;
  const auto absolute = [&](json& value) {
    if (!value.is_string()) return;
    const fs::path p(value.get<std::string>());
    if (p.is_relative()) value = fs::absolute(fs::path(directory) / p).lexically_normal().string();
  };
  if (auto it = base->find("body"); it != base->end()) absolute(*it);
  if (auto m = base->find("masters"); m != base->end() && m->is_object()) {
    if (auto f = m->find("file"); f != m->end()) absolute(*f);
  }
}

// The operation objects of an item or a test: every distribution replaced by value(pointer, d).
template <typename ValueOf>
json ResolveOperation(const BatchOperation& op, const ValueOf& value_of) {
  json body = op.templ;
  for (const auto& [pointer, d] : op.distributions) {
    body[json::json_pointer(pointer)] = value_of(pointer, d);
  }
  return json{{op.name, std::move(body)}};
}

// Collects the distributions inside an operation's object (recursively).
bool CollectDistributions(Reader& reader, const json& value, const std::string& path,
                          const std::string& pointer, BatchOperation* op) {
  if (IsDistribution(value)) {
    // The integer fields of the operations (docs/hairstyle-format.md, "operations").
    const bool integer = pointer.ends_with("/steps") || pointer.ends_with("/max_rounds") ||
                         pointer.ends_with("/samples_per_segment") ||
                         pointer.find("/select/indices") != std::string::npos;
    BatchDistribution d;
    if (!ParseDistribution(reader, value, path, integer ? FieldType::kInteger : FieldType::kNumber,
                           &d)) {
      // Choices of non-numbers ("select" objects, booleans) are allowed in operations.
      if (value.begin().key() != "choice") return false;
      const json& body = *value.begin();
      if (!body.is_array() || body.empty()) {
        return reader.Expected(Member(path, "choice"), "a non-empty array", body);
      }
      d = BatchDistribution{};
      d.choices.assign(body.begin(), body.end());
    }
    op->distributions.emplace_back(pointer, std::move(d));
    return true;
  }
  if (value.is_object()) {
    for (const auto& item : value.items()) {
      if (!CollectDistributions(reader, item.value(), Member(path, item.key()),
                                pointer + "/" + item.key(), op)) {
        return false;
      }
    }
  }
  if (value.is_array()) {
    for (size_t i = 0; i < value.size(); ++i) {
      if (!CollectDistributions(reader, value[i], Element(path, i),
                                pointer + "/" + std::to_string(i), op)) {
        return false;
      }
    }
  }
  return true;
}

bool ParseViews(Reader& reader, const json& document, BatchSpec* spec) {
  const auto it = document.find("views");
  if (it == document.end()) return true;
  const json& views = *it;
  if (views.is_array()) {
    if (views.empty() || views.size() > 1000) {
      return reader.Expected("views", "1 to 1000 camera objects, or {\"orbit\": {...}}", views);
    }
    for (size_t i = 0; i < views.size(); ++i) {
      // Each is a render "camera" object, checked by the render settings reader.
      RenderSettings settings;
      std::string why;
      if (!ParseRenderSettings(json{{"camera", views[i]}}, Element("views", i), &settings, &why)) {
        return reader.Fail("", why);
      }
      spec->views.push_back(views[i]);
    }
    return true;
  }
  if (!views.is_object()) {
    return reader.Expected("views", "an array of camera objects or {\"orbit\": {...}}", views);
  }
  if (!reader.CheckFields(views, "views", {"orbit"})) return false;
  const json* orbit = nullptr;
  if (!internal::OptionalObject(reader, views, "views", "orbit", &orbit)) return false;
  if (orbit == nullptr) return reader.Missing("views.orbit", "an object {count, ...}");
  const std::string path = "views.orbit";
  if (!reader.CheckFields(*orbit, path,
                          {"count", "elevation_degrees", "start_degrees", "fov_degrees"})) {
    return false;
  }
  int count = 4;
  double elevation = 10.0, start = 0.0, fov = 30.0;
  const internal::NumberRule elevation_rule{"a number in (-90, 90) (degrees)",
                                            [](double x) { return x > -90 && x < 90; }};
  const internal::NumberRule any{"a finite number (degrees)", [](double) { return true; }};
  const internal::NumberRule fov_rule{"a number in (0, 180) (degrees)",
                                      [](double x) { return x > 0 && x < 180; }};
  if (!reader.ReadInteger(*orbit, path, "count", 1, 1000, &count) ||
      !reader.ReadNumber(*orbit, path, "elevation_degrees", elevation_rule, false, &elevation) ||
      !reader.ReadNumber(*orbit, path, "start_degrees", any, false, &start) ||
      !reader.ReadNumber(*orbit, path, "fov_degrees", fov_rule, false, &fov)) {
    return false;
  }
  // View i looks at the framed hair from azimuth phi_i = start + 360 i / count degrees about
  // +z, measured from the face (+y) toward +x, and elevation e above the horizon.
  for (int i = 0; i < count; ++i) {
    const double phi = (start + 360.0 * i / count) * M_PI / 180.0;
    const double e = elevation * M_PI / 180.0;
    const json direction = {-std::cos(e) * std::sin(phi), -std::cos(e) * std::cos(phi),
                            -std::sin(e)};
    spec->views.push_back(json{{"view_direction", direction}, {"fov_degrees", fov}});
  }
  return true;
}

bool ParseOutputs(Reader& reader, const json& document, BatchOutputs* outputs) {
  const json* object = nullptr;
  if (!internal::OptionalObject(reader, document, "", "outputs", &object)) return false;
  if (object == nullptr) return true;
  const std::string path = "outputs";
  if (!reader.CheckFields(*object, path, {"formats", "points_per_strand", "images"})) return false;
  if (const auto it = object->find("formats"); it != object->end()) {
    const char* expected = "an array of \"hair\", \"usda\", \"data\" (at least one)";
    if (!it->is_array() || it->empty()) return reader.Expected("outputs.formats", expected, *it);
    outputs->hair = outputs->usda = outputs->data = false;
    for (size_t i = 0; i < it->size(); ++i) {
      const json& f = (*it)[i];
      bool* flag = nullptr;
      if (f == "hair") flag = &outputs->hair;
      if (f == "usda") flag = &outputs->usda;
      if (f == "data") flag = &outputs->data;
      if (flag == nullptr || *flag) {
        return reader.Expected(Element("outputs.formats", i),
                               flag ? "each format once" : "\"hair\", \"usda\" or \"data\"", f);
      }
      *flag = true;
    }
  }
  if (!reader.ReadInteger(*object, path, "points_per_strand", 2, 65536,
                          &outputs->points_per_strand)) {
    return false;
  }
  const json* images = nullptr;
  if (!internal::OptionalObject(reader, *object, path, "images", &images)) return false;
  if (images != nullptr) {
    outputs->images = true;
    const std::string ipath = "outputs.images";
    if (!reader.CheckFields(*images, ipath, {"width", "height", "samples_per_pixel", "labels"}) ||
        !reader.ReadInteger(*images, ipath, "width", 1, 16384, &outputs->width) ||
        !reader.ReadInteger(*images, ipath, "height", 1, 16384, &outputs->height) ||
        !reader.ReadInteger(*images, ipath, "samples_per_pixel", 1, 1 << 20,
                            &outputs->samples_per_pixel) ||
        !reader.ReadBool(*images, ipath, "labels", &outputs->labels)) {
      return false;
    }
    std::string why;
    if (!CheckRenderSize(outputs->width, outputs->height, outputs->samples_per_pixel, &why)) {
      return reader.Fail(ipath, why);
    }
  }
  return true;
}

// The item's hairstyle document: base, parameter values, seeds, operations.
json ItemDocument(const BatchSpec& spec, int base, const json& values, const json& operations,
                  std::uint64_t item_seed) {
  json doc = spec.bases[static_cast<size_t>(base)];
  if (spec.item_seeds) {
    const bool explicit_masters =
        doc.contains("masters") && doc["masters"].is_object() && doc["masters"].contains("file");
    for (const char* path : kItemSeedPaths) {
      if (values.contains(path)) continue;
      if (explicit_masters && std::string(path) == "masters.seed") continue;
      const std::uint64_t seed =
          groom::SplitMix64::Mix(groom::StreamSeed(item_seed, NameHash(path))) & kSeedMask;
      SetPath(&doc, path, seed);
    }
  }
  for (const auto& item : values.items()) SetPath(&doc, item.key(), item.value());
  if (!operations.empty()) {
    json& list = doc["operations"];
    if (!list.is_array()) list = json::array();
    for (const json& op : operations) list.push_back(op);
  }
  return doc;
}

}  // namespace

std::string BatchItemName(std::int64_t index) {
  char name[32];
  std::snprintf(name, sizeof(name), "item-%09lld", static_cast<long long>(index));
  return name;
}

bool ParseBatchSpec(const nlohmann::json& document, const std::string& base_directory,
                    BatchSpec* spec, std::string* error) {
  try {
    Reader reader;
    const auto fail = [&] {
      *error = reader.error();
      return false;
    };
    if (!document.is_object()) {
      reader.Expected("", "a JSON object {\"bases\": [...], \"count\": N, ...}", document);
      return fail();
    }
    if (!reader.CheckFields(document, "",
                            {"description", "bases", "count", "seed", "item_seeds", "parameters",
                             "operations", "views", "outputs"})) {
      return fail();
    }
    BatchSpec s;
    s.directory = base_directory;
    // count: required.
    {
      const auto it = document.find("count");
      std::int64_t count = 0;
      const std::string expected = "an integer between 1 and " + std::to_string(kMaxBatchItems);
      if (it == document.end()) {
        reader.Missing("count", expected);
        return fail();
      }
      if (!Reader::ExactInteger(*it, &count) || count < 1 || count > kMaxBatchItems) {
        reader.Expected("count", expected, *it);
        return fail();
      }
      s.count = count;
    }
    if (!reader.ReadUnsigned(document, "", "seed", internal::kMaxExactInteger, "2^53", &s.seed) ||
        !reader.ReadBool(document, "", "item_seeds", &s.item_seeds)) {
      return fail();
    }
    // bases: file names (relative to the spec) or inline hairstyle objects.
    {
      const auto it = document.find("bases");
      const char* expected = "an array of 1 to 1000 hairstyle file names or objects";
      if (it == document.end()) {
        reader.Missing("bases", expected);
        return fail();
      }
      if (!it->is_array() || it->empty() || it->size() > 1000) {
        reader.Expected("bases", expected, *it);
        return fail();
      }
      for (size_t i = 0; i < it->size(); ++i) {
        const json& b = (*it)[i];
        const std::string path = Element("bases", i);
        json base;
        std::string name = path;
        if (b.is_string()) {
          namespace fs = std::filesystem;
          fs::path file(b.get<std::string>());
          if (file.is_relative()) file = fs::path(base_directory) / file;
          std::string text, why;
          if (!ReadFile(file.string(), &text, &why)) {
            reader.Fail(path, why);
            return fail();
          }
          if (!internal::ParseJsonText(text, &base, &why)) {
            reader.Fail(path, DisplayPath(file.string()) + ": " + why);
            return fail();
          }
          if (!base.is_object()) {
            reader.Fail(path, DisplayPath(file.string()) + ": expected a hairstyle object");
            return fail();
          }
          AbsolutePaths(&base, file.parent_path().string());
          name = b.get<std::string>();
        } else if (b.is_object()) {
          base = b;
          AbsolutePaths(&base, base_directory);
        } else {
          reader.Expected(path, "a hairstyle file name or a hairstyle object", b);
          return fail();
        }
        s.bases.push_back(std::move(base));
        s.base_names.push_back(name);
      }
    }
    // parameters: {"path": distribution}.
    const json* parameters = nullptr;
    if (!internal::OptionalObject(reader, document, "", "parameters", &parameters)) return fail();
    if (parameters != nullptr) {
      for (const auto& item : parameters->items()) {
        const FieldPath* field = nullptr;
        for (const FieldPath& f : kFieldPaths) {
          if (item.key() == f.path) field = &f;
        }
        const std::string path = Member("parameters", item.key());
        if (field == nullptr) {
          std::string known;
          for (const FieldPath& f : kFieldPaths)
            known += (known.empty() ? "" : ", ") + std::string(f.path);
          reader.Fail(path, "not a hairstyle field a batch can vary (fields: " + known + ")");
          return fail();
        }
        BatchParameter p;
        p.path = item.key();
        if (!ParseDistribution(reader, item.value(), path, field->type, &p.distribution)) {
          return fail();
        }
        s.parameters.push_back(std::move(p));
      }
    }
    // operations: [{"NAME": {...}, "probability": p}].
    const json* operations = nullptr;
    if (!reader.ReadArray(document, "", "operations", "an array of operation objects",
                          &operations)) {
      return fail();
    }
    if (operations != nullptr) {
      for (size_t i = 0; i < operations->size(); ++i) {
        const json& o = (*operations)[i];
        const std::string path = Element("operations", i);
        if (!o.is_object()) {
          reader.Expected(path, "an object {\"NAME\": {...}, \"probability\": p}", o);
          return fail();
        }
        BatchOperation op;
        const internal::NumberRule probability{"a number in [0, 1]",
                                               [](double x) { return x >= 0 && x <= 1; }};
        if (!reader.ReadNumber(o, path, "probability", probability, false, &op.probability)) {
          return fail();
        }
        for (const auto& member : o.items()) {
          if (member.key() == "probability") continue;
          bool known = false;
          for (const char* n : kOperationNames) known = known || member.key() == n;
          if (!known || !op.name.empty()) {
            reader.Fail(Member(path, member.key()),
                        known ? "one operation per entry (give another entry)"
                              : "unknown operation (expected \"curl\", \"wet\", \"dry\", "
                                "\"cut\" or \"grow\", and \"probability\")");
            return fail();
          }
          op.name = member.key();
          op.templ = member.value();
        }
        if (op.name.empty()) {
          reader.Missing(path, "an operation: \"curl\", \"wet\", \"dry\", \"cut\" or \"grow\"");
          return fail();
        }
        if (!CollectDistributions(reader, op.templ, Member(path, op.name), "", &op)) return fail();
        s.operations.push_back(std::move(op));
      }
    }
    if (!ParseViews(reader, document, &s) || !ParseOutputs(reader, document, &s.outputs)) {
      return fail();
    }

    // Every base with the distributions at their test values (bounds, choices): a value that
    // no item could use is a spec error now, not a failed item later.
    size_t tests = 2;
    for (const BatchParameter& p : s.parameters) {
      tests = std::max(tests, TestValueCount(p.distribution));
    }
    for (const BatchOperation& op : s.operations) {
      for (const auto& d : op.distributions) tests = std::max(tests, TestValueCount(d.second));
    }
    tests = std::min<size_t>(tests, 64);
    for (size_t b = 0; b < s.bases.size(); ++b) {
      for (size_t t = 0; t < tests; ++t) {
        json values = json::object();
        for (const BatchParameter& p : s.parameters) values[p.path] = TestValue(p.distribution, t);
        json ops = json::array();
        for (const BatchOperation& op : s.operations) {
          ops.push_back(ResolveOperation(
              op, [t](const std::string&, const BatchDistribution& d) { return TestValue(d, t); }));
        }
        const json doc = ItemDocument(s, static_cast<int>(b), values, ops, 0);
        Hairstyle style;
        std::vector<StyleOperation> parsed;
        RenderSettings settings;
        std::string why;
        // The base's body is read by its first test and shared from then on.
        const std::shared_ptr<const Body> body = t == 0 ? nullptr : s.bodies[b];
        if (!ParseHairstyle(doc, base_directory, body, &style, &why) ||
            !ParseStyleOperations(doc, &parsed, &why) || !ParseRenderMember(doc, &settings, &why)) {
          bool choices = false;
          for (const BatchParameter& p : s.parameters) {
            choices = choices || p.distribution.kind == BatchDistribution::Kind::kChoice;
          }
          for (const BatchOperation& op : s.operations) {
            for (const auto& d : op.distributions) {
              choices = choices || d.second.kind == BatchDistribution::Kind::kChoice;
            }
          }
          std::string where;
          if (!s.parameters.empty() || !s.operations.empty()) {
            where = std::string(" with the parameters at their ") +
                    (t % 2 == 0 ? "lowest" : "highest") + " bounds";
            if (choices) {
              where +=
                  " and choice[" + std::to_string(t) + "] of each choice (its last when shorter)";
            }
          }
          const std::string base = Element("bases", b);
          const std::string name =
              s.base_names[b] == base ? base : base + " (" + s.base_names[b] + ")";
          reader.Fail(name + where, why);
          return fail();
        }
        if (t == 0) s.bodies.push_back(style.body);
      }
    }
    *spec = std::move(s);
    return true;
  } catch (const std::exception& e) {
    *error = std::string("unexpected error reading the spec: ") + e.what();
    return false;
  }
}

bool LoadBatchSpec(const std::string& path, BatchSpec* spec, std::string* error) {
  std::string text, why;
  if (!ReadFile(path, &text, &why)) {
    *error = why;
    return false;
  }
  json document;
  if (!internal::ParseJsonText(text, &document, &why)) {
    *error = DisplayPath(path) + ": " + why;
    return false;
  }
  const std::string directory = std::filesystem::path(path).parent_path().string();
  if (!ParseBatchSpec(document, directory.empty() ? "." : directory, spec, &why)) {
    *error = DisplayPath(path) + ": " + why;
    return false;
  }
  spec->path = path;
  return true;
}

BatchItem ResolveBatchItem(const BatchSpec& spec, std::int64_t index) {
  BatchItem item;
  item.index = index;
  item.name = BatchItemName(index);
  const std::uint64_t item_seed = groom::StreamSeed(spec.seed, static_cast<std::uint64_t>(index));
  {
    groom::SplitMix64 rng(groom::StreamSeed(item_seed, NameHash("bases")));
    const double n = static_cast<double>(spec.bases.size());
    item.base = static_cast<int>(std::min(n - 1.0, std::floor(rng.Uniform() * n)));
  }
  json values = json::object();
  for (const BatchParameter& p : spec.parameters) {
    groom::SplitMix64 rng(groom::StreamSeed(item_seed, NameHash("parameters." + p.path)));
    values[p.path] = Draw(p.distribution, &rng);
  }
  json ops = json::array();
  for (size_t j = 0; j < spec.operations.size(); ++j) {
    const BatchOperation& op = spec.operations[j];
    groom::SplitMix64 rng(
        groom::StreamSeed(item_seed, NameHash("operations[" + std::to_string(j) + "]")));
    if (!(rng.Uniform() < op.probability)) continue;
    ops.push_back(ResolveOperation(
        op, [&rng](const std::string&, const BatchDistribution& d) { return Draw(d, &rng); }));
  }
  item.hairstyle = ItemDocument(spec, item.base, values, ops, item_seed);
  item.parameters = json{{"base", item.base},
                         {"base_name", spec.base_names[static_cast<size_t>(item.base)]},
                         {"values", values},
                         {"operations", ops}};
  return item;
}

}  // namespace ringlet
