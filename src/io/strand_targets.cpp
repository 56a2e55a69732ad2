// Strand targets from files: dispatch by extension, conversion to metres and z up, and the
// strand checks shared by every format (strand_targets.h).
#include "ringlet/strand_targets.h"

#include <charconv>
#include <cmath>
#include <string_view>
#include <utility>

#include "io/strand_readers.h"
#include "ringlet/atomic_file.h"
#include "ringlet/hair_file.h"
#include "ringlet/usc_data.h"

namespace ringlet {
namespace {

bool Fail(std::string* why, const std::string& what) {
  if (why) *why = what;
  return false;
}

std::string Text(const Vec3f& v) {
  std::string s = "(";
  for (int c = 0; c < 3; ++c) {
    char buffer[32];
    const auto result = std::to_chars(buffer, buffer + sizeof(buffer), v[c]);
    s.append(buffer, result.ptr);
    s += c < 2 ? ", " : ")";
  }
  return s;
}

// The extension of path after its last dot, in lower case ("" without one).
std::string Extension(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  for (char& c : ext) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return ext;
}

// .usda and .obj: parse, fill the widths, convert and check.
bool ReadText(const std::string& path, bool usda, const StrandTargetOptions& options,
              HairCurves* curves, StrandTargetSummary* summary, std::string* why) {
  std::string text, error;
  if (!ReadFile(path, &text, why, kMaxStrandTargetFileBytes)) return false;
  io_internal::TextStrands strands;
  const bool parsed = usda ? io_internal::ParseUsdaCurves(text, &strands, &error)
                           : io_internal::ParseObjPolylines(text, &strands, &error);
  if (!parsed) return Fail(why, DisplayPath(path) + ": " + error);
  text = std::string();  // the text is no longer needed: free it before converting

  double units_per_metre = options.units_per_metre;
  StrandTargetOptions::UpAxis up = options.up_axis;
  if (usda && !options.ignore_file_metadata) {
    // The stage's metadata, or USD's fallbacks (UsdGeomGetStageMetersPerUnit: centimetres;
    // UsdGeomGetStageUpAxis: "Y").
    units_per_metre = 1.0 / (strands.has_meters_per_unit ? strands.meters_per_unit : 0.01);
    up = strands.has_up_axis ? strands.up_axis : StrandTargetOptions::UpAxis::kY;
  }
  HairCurves& out = strands.curves;
  io_internal::ConvertToMetresZUp(units_per_metre, up, &out);
  if (!strands.has_widths) {
    out.widths.assign(out.points.size(), static_cast<float>(options.default_width));
  }
  const auto name = [&](size_t k) {
    const io_internal::TextStrands::Label& label = strands.labels[k];
    return "strand " + std::to_string(k) + " (" + strands.label_prefixes[label.prefix] +
           std::to_string(label.number) + ")";
  };
  if (!io_internal::CheckStrands(out, name, &error)) {
    return Fail(why, DisplayPath(path) + ": " + error);
  }
  if (summary) {
    StrandTargetSummary info;
    info.file_strand_index.resize(out.point_counts.size());
    for (size_t k = 0; k < info.file_strand_index.size(); ++k) info.file_strand_index[k] = k;
    info.metres_per_unit = 1.0 / units_per_metre;
    info.up_axis = up;
    *summary = std::move(info);
  }
  *curves = std::move(out);
  return true;
}

}  // namespace

bool StrandTargetOptions::IsValid(std::string* why) const {
  if (!std::isfinite(units_per_metre) || !(units_per_metre > 0.0)) {
    return Fail(why, "units_per_metre: expected a finite number > 0");
  }
  if (up_axis != UpAxis::kZ && up_axis != UpAxis::kY) {
    return Fail(why, "up_axis: expected z or y");
  }
  if (!std::isfinite(default_width) || default_width < 0.0 ||
      static_cast<double>(static_cast<float>(default_width)) > kMaxTargetCoordinate) {
    return Fail(why, "default_width: expected a finite width >= 0 (m)");
  }
  return true;
}

namespace io_internal {

void ConvertToMetresZUp(double units_per_metre, StrandTargetOptions::UpAxis up,
                        HairCurves* curves) {
  if (units_per_metre == 1.0 && up == StrandTargetOptions::UpAxis::kZ) return;
  for (Vec3f& x : curves->points) x = ToMetresZUp(x, units_per_metre, up);
  for (float& w : curves->widths) {
    w = static_cast<float>(static_cast<double>(w) / units_per_metre);
  }
  for (Vec3f& a : curves->major_axes) a = ToMetresZUp(a, 1.0, up);
}

bool CheckStrands(const HairCurves& curves, const StrandName& name, std::string* why) {
  uint64_t total = 0;
  for (uint32_t count : curves.point_counts) total += count;
  if (total != curves.points.size() || curves.widths.size() != curves.points.size() ||
      (!curves.major_axes.empty() && curves.major_axes.size() != curves.points.size()) ||
      (!curves.colors.empty() && curves.colors.size() != curves.point_counts.size())) {
    // Only a caller's mistake can get here (the readers build consistent arrays).
    return CheckHairCurves(curves, "curves", why);
  }
  size_t first = 0;
  for (size_t k = 0; k < curves.point_counts.size(); ++k) {
    const size_t count = curves.point_counts[k];
    if (count < 2) {
      return Fail(why, name(k) + ": expected at least 2 points, got " + std::to_string(count));
    }
    for (size_t i = 0; i < count; ++i) {
      const Vec3f& x = curves.points[first + i];
      for (int c = 0; c < 3; ++c) {
        if (!(std::abs(static_cast<double>(x[c])) <= kMaxTargetCoordinate)) {
          return Fail(why, name(k) + ", point " + std::to_string(i) + ": " +
                               (std::isfinite(x[c]) ? "coordinates " + Text(x) +
                                                          " m beyond the limit of 1e4 m "
                                                          "(check the length unit)"
                                                    : std::string("expected finite coordinates")));
        }
      }
      if (i > 0 && x == curves.points[first + i - 1]) {
        return Fail(why, name(k) + ", point " + std::to_string(i) +
                             ": repeated point (the same as point " + std::to_string(i - 1) +
                             ", " + Text(x) + " m): a zero-length segment has no tangent");
      }
      const float w = curves.widths[first + i];
      if (!std::isfinite(w) || w < 0.0f) {
        return Fail(why, name(k) + ", point " + std::to_string(i) +
                             ": expected a finite width >= 0");
      }
      if (!curves.major_axes.empty()) {
        const Vec3f& a = curves.major_axes[first + i];
        if (!std::isfinite(a.x()) || !std::isfinite(a.y()) || !std::isfinite(a.z()) ||
            !(a.squaredNorm() > 0.0f)) {
          return Fail(why, name(k) + ", point " + std::to_string(i) +
                               ": expected a finite, non-zero major axis");
        }
      }
    }
    first += count;
  }
  for (size_t k = 0; k < curves.colors.size(); ++k) {
    const Vec3f& c = curves.colors[k];
    if (!std::isfinite(c.x()) || !std::isfinite(c.y()) || !std::isfinite(c.z())) {
      return Fail(why, name(k) + ": expected a finite colour");
    }
  }
  return true;
}

}  // namespace io_internal

bool CheckStrandTargets(const HairCurves& curves,
                        const std::vector<std::uint64_t>& file_strand_index, std::string* why) {
  const auto name = [&](size_t k) {
    return "strand " + std::to_string(k < file_strand_index.size() ? file_strand_index[k] : k);
  };
  return io_internal::CheckStrands(curves, name, why);
}

bool ReadStrandTargets(const std::string& path, const StrandTargetOptions& options,
                       HairCurves* curves, std::string* why) {
  return ReadStrandTargets(path, options, curves, nullptr, why);
}

bool ReadStrandTargets(const std::string& path, const StrandTargetOptions& options,
                       HairCurves* curves, StrandTargetSummary* summary, std::string* why) {
  std::string error;
  if (!options.IsValid(&error)) return Fail(why, "strand target options: " + error);
  const std::string ext = Extension(path);
  if (ext == ".usda" || ext == ".obj") {
    return ReadText(path, ext == ".usda", options, curves, summary, why);
  }
  if (ext == ".data") {
    std::string bytes;
    if (!ReadFile(path, &bytes, why, kMaxStrandTargetFileBytes)) return false;
    if (!DecodeUscData(bytes, options, curves, summary, &error)) {
      return Fail(why, DisplayPath(path) + ": " + error);
    }
    return true;
  }
  if (ext == ".hair") {
    // The .hair reader converts the unit; the axes and the strand checks are done here.
    HairCurves out;
    if (!ReadHairFile(path, &out, why, options.units_per_metre)) return false;
    io_internal::ConvertToMetresZUp(1.0, options.up_axis, &out);
    const auto name = [](size_t k) { return "strand " + std::to_string(k); };
    if (!io_internal::CheckStrands(out, name, &error)) {
    return Fail(why, DisplayPath(path) + ": " + error);
  }
    if (summary) {
      StrandTargetSummary info;
      info.file_strand_index.resize(out.point_counts.size());
      for (size_t k = 0; k < info.file_strand_index.size(); ++k) info.file_strand_index[k] = k;
      info.metres_per_unit = 1.0 / options.units_per_metre;
      info.up_axis = options.up_axis;
      *summary = std::move(info);
    }
    *curves = std::move(out);
    return true;
  }
  return Fail(why, path + ": unknown strand file extension \"" + ext +
                       "\" (expected .hair, .data, .usda or .obj)");
}

}  // namespace ringlet
