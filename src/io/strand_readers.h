// Shared by the strand-target readers (strand_targets.cpp, usc_data.cpp, usda_curves_reader.cpp,
// obj_polylines.cpp): the conversion to metres and z up, the strand checks, and the text
// readers' entry points. Private to src/io.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "ringlet/hair_curves.h"
#include "ringlet/strand_targets.h"

namespace ringlet::io_internal {

/// Names strand k of the curves being checked in messages ("strand 3", "strand 3 (line 12)").
using StrandName = std::function<std::string(size_t k)>;

/// File coordinates -> metres, z up: divide by units_per_metre, then rotate a y-up file by +90
/// degrees about x, (x, y, z) -> (x, -z, y). In double, rounded once to float (exact for
/// units_per_metre = 1: the rotation only permutes and negates).
inline Vec3f ToMetresZUp(const Vec3f& x, double units_per_metre, StrandTargetOptions::UpAxis up) {
  const double a = static_cast<double>(x.x()) / units_per_metre;
  const double b = static_cast<double>(x.y()) / units_per_metre;
  const double c = static_cast<double>(x.z()) / units_per_metre;
  if (up == StrandTargetOptions::UpAxis::kY) {
    return Vec3f(static_cast<float>(a), static_cast<float>(-c), static_cast<float>(b));
  }
  return Vec3f(static_cast<float>(a), static_cast<float>(b), static_cast<float>(c));
}

/// The inverse of ToMetresZUp: metres, z up -> file units and axes ((x, y, z) -> (x, z, -y)
/// for a y-up file, then multiplied by units_per_metre).
inline Vec3f FromMetresZUp(const Vec3f& x, double units_per_metre,
                           StrandTargetOptions::UpAxis up) {
  const double a = static_cast<double>(x.x()) * units_per_metre;
  const double b = static_cast<double>(x.y()) * units_per_metre;
  const double c = static_cast<double>(x.z()) * units_per_metre;
  if (up == StrandTargetOptions::UpAxis::kY) {
    return Vec3f(static_cast<float>(a), static_cast<float>(c), static_cast<float>(-b));
  }
  return Vec3f(static_cast<float>(a), static_cast<float>(b), static_cast<float>(c));
}

/// Converts curves read in file units and axes in place: points and widths scaled, points and
/// major axes rotated.
void ConvertToMetresZUp(double units_per_metre, StrandTargetOptions::UpAxis up,
                        HairCurves* curves);

/// CheckStrandTargets with strands named by name(k).
bool CheckStrands(const HairCurves& curves, const StrandName& name, std::string* why);

/// Polylines read from a text format, in the file's units and axes, before conversion.
struct TextStrands {
  HairCurves curves;  ///< points, point_counts, widths (per point), colors, major_axes
  /// How to name strand k in messages: label_prefixes[labels[k].prefix] followed by
  /// labels[k].number ("line 12", "</hair> curve 1").
  struct Label {
    uint32_t prefix = 0;
    uint64_t number = 0;
  };
  std::vector<Label> labels;
  std::vector<std::string> label_prefixes;
  /// .usda: the stage's metadata, when authored.
  bool has_meters_per_unit = false;
  double meters_per_unit = 0.01;
  bool has_up_axis = false;
  StrandTargetOptions::UpAxis up_axis = StrandTargetOptions::UpAxis::kY;
  bool has_widths = false;  ///< false: widths still to be filled with the default
};

/// Parses .usda text (the BasisCurves subset of docs/file-formats.md) into *out. Errors are one
/// line, "line N: ..." or "</prim>.attribute: ...".
bool ParseUsdaCurves(std::string_view text, TextStrands* out, std::string* error);

/// Parses OBJ text ('v' and 'l' elements) into *out. Errors are one line, "line N: ...".
bool ParseObjPolylines(std::string_view text, TextStrands* out, std::string* error);

}  // namespace ringlet::io_internal
