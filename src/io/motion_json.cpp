// Motion files (motion_json.h; docs/dynamics.md, "Motion files"). Every field is checked where it
// is read (io/json_reader.h), so that an error names the field in one line. Angles are degrees in
// the file and radians in MotionKeyframe.
#include "ringlet/motion_json.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <vector>

#include "io/json_reader.h"
#include "ringlet/atomic_file.h"

namespace ringlet {
namespace {

using nlohmann::json;
using internal::Element;
using internal::Member;
using internal::NumberRule;
using internal::Reader;

constexpr NumberRule kTimeRule{"a finite number >= 0 (s)", [](double x) { return x >= 0.0; }};
constexpr NumberRule kAngleRule{"a finite number (degrees)", [](double) { return true; }};
// Most keyframes of a motion file: far more than any hand-made motion needs, and a bound on the
// work of reading one.
constexpr size_t kMaxKeyframes = 100000;

bool ParseMotionDocument(const json& document, const Vec3& default_pivot, HeadMotion* motion,
                         std::string* error) {
  Reader reader;
  auto fail = [&] {
    *error = reader.error();
    return false;
  };
  if (!document.is_object()) {
    reader.Expected("", "a JSON object with \"keyframes\"", document);
    return fail();
  }
  if (!reader.CheckFields(document, "", {"description", "pivot", "keyframes"})) return fail();
  const auto description = document.find("description");
  if (description != document.end() && !description->is_string()) {
    reader.Expected("description", "a string", *description);
    return fail();
  }
  Vec3 pivot = default_pivot;
  if (!reader.ReadVector<3>(document, "", "pivot", "m", false, &pivot)) return fail();
  const auto keys = document.find("keyframes");
  if (keys == document.end()) {
    reader.Missing("keyframes", "an array of keyframes {\"time\": s, ...}");
    return fail();
  }
  if (!keys->is_array() || keys->empty() || keys->size() > kMaxKeyframes) {
    reader.Expected("keyframes",
                    "an array of 1 to " + std::to_string(kMaxKeyframes) + " keyframes", *keys);
    return fail();
  }
  std::vector<MotionKeyframe> keyframes;
  keyframes.reserve(keys->size());
  for (size_t k = 0; k < keys->size(); ++k) {
    const json& item = (*keys)[k];
    const std::string path = Element("keyframes", k);
    if (!item.is_object()) {
      reader.Expected(path, "an object {\"time\": s, \"translation\", \"axis\", \"angle\"}", item);
      return fail();
    }
    if (!reader.CheckFields(item, path, {"time", "translation", "axis", "angle"})) return fail();
    MotionKeyframe key;
    if (!reader.ReadNumber(item, path, "time", kTimeRule, true, &key.time)) return fail();
    if (k > 0 && !(key.time > keyframes.back().time)) {
      reader.Expected(Member(path, "time"), "a time after the previous keyframe's (s)",
                      item.at("time"));
      return fail();
    }
    if (!reader.ReadVector<3>(item, path, "translation", "m", false, &key.translation)) {
      return fail();
    }
    if (!reader.ReadVector<3>(item, path, "axis", "a direction", false, &key.axis)) return fail();
    if (!(key.axis.norm() > 0.0) || !std::isfinite(key.axis.norm())) {
      reader.Expected(Member(path, "axis"), "a non-zero direction [x, y, z]", item.at("axis"));
      return fail();
    }
    double degrees = 0.0;
    if (!reader.ReadNumber(item, path, "angle", kAngleRule, false, &degrees)) return fail();
    key.angle = degrees * M_PI / 180.0;
    keyframes.push_back(key);
  }
  // What is left to check (consecutive orientations less than 179 degrees apart) is checked by
  // HeadMotion::Keyframes, whose message names the keyframe and field the same way.
  try {
    *motion = HeadMotion::Keyframes(std::move(keyframes), pivot);
  } catch (const std::invalid_argument& e) {
    *error = e.what();
    return false;
  }
  return true;
}

}  // namespace

bool ParseMotionText(const std::string& text, const Vec3& default_pivot, HeadMotion* motion,
                     std::string* error) {
  json document;
  return internal::ParseJsonText(text, &document, error) &&
         ParseMotionDocument(document, default_pivot, motion, error);
}

bool LoadMotion(const std::string& path, const Vec3& default_pivot, HeadMotion* motion,
                std::string* error) {
  std::string text, why;
  if (!ReadFile(path, &text, error)) return false;
  if (!ParseMotionText(text, default_pivot, motion, &why)) {
    *error = DisplayPath(path) + ": " + why;
    return false;
  }
  return true;
}

}  // namespace ringlet
