// USD text export of hair curves (UsdGeomBasisCurves). The text follows the usda grammar as
// Pixar's own writer emits it: layer metadata in parentheses after "#usda 1.0", attribute
// metadata in parentheses after the value, and time samples as "name.timeSamples = { t: v, }".
#include "ringlet/usd_export.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <span>

#include "io/curves_check.h"
#include "ringlet/atomic_file.h"

namespace ringlet {
namespace {

using io_internal::AppendNumber;

bool Fail(std::string* error, const std::string& what) {
  if (error) *error = what;
  return false;
}

bool IsIdentifier(const std::string& name) {
  if (name.empty()) return false;
  for (size_t i = 0; i < name.size(); ++i) {
    const char c = name[i];
    const bool letter = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_';
    const bool digit = c >= '0' && c <= '9';
    if (!(letter || (digit && i > 0))) return false;
  }
  return true;
}

// "(x, y, z)", formatted in a local buffer and appended once (appending piece by piece costs
// more than the number formatting).
void AppendTuple(std::string* out, const Vec3f& v) {
  char buffer[64];
  char* p = buffer;
  *p++ = '(';
  p = io_internal::WriteNumber(p, v.x());
  *p++ = ',';
  *p++ = ' ';
  p = io_internal::WriteNumber(p, v.y());
  *p++ = ',';
  *p++ = ' ';
  p = io_internal::WriteNumber(p, v.z());
  *p++ = ')';
  out->append(buffer, p);
}

void AppendArray(std::string* out, const std::vector<Vec3f>& values) {
  *out += '[';
  for (size_t i = 0; i < values.size(); ++i) {
    if (i > 0) *out += ", ";
    AppendTuple(out, values[i]);
  }
  *out += ']';
}

template <typename T>
void AppendArray(std::string* out, const std::vector<T>& values) {
  *out += '[';
  for (size_t i = 0; i < values.size(); ++i) {
    if (i > 0) *out += ", ";
    if constexpr (std::is_integral_v<T>) {
      AppendNumber(out, static_cast<long long>(values[i]));
    } else {
      AppendNumber(out, values[i]);
    }
  }
  *out += ']';
}

// UsdGeomCurves::ComputeExtent: bounding box of the points grown by half the largest width on
// every side (as for a point cloud of spheres of that width). Computed in float like USD.
std::vector<Vec3f> Extent(const HairCurves& curves) {
  Vec3f lo = curves.points[0], hi = curves.points[0];
  for (const Vec3f& x : curves.points) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  const float half = *std::max_element(curves.widths.begin(), curves.widths.end()) / 2.0f;
  return {lo - Vec3f::Constant(half), hi + Vec3f::Constant(half)};
}

// One attribute: either a single value or time samples, plus optional metadata.
// value(frame, out) appends the value of a frame.
template <typename ValueOf>
void AppendAttribute(std::string* out, const char* declaration, const char* metadata,
                     bool sampled, size_t frames, int start, const ValueOf& value) {
  if (!sampled) {
    *out += "    ";
    *out += declaration;
    *out += " = ";
    value(0, out);
    if (metadata) {
      *out += " (\n        ";
      *out += metadata;
      *out += "\n    )";
    }
    *out += '\n';
    return;
  }
  if (metadata) {
    *out += "    ";
    *out += declaration;
    *out += " (\n        ";
    *out += metadata;
    *out += "\n    )\n";
  }
  *out += "    ";
  *out += declaration;
  *out += ".timeSamples = {\n";
  for (size_t f = 0; f < frames; ++f) {
    *out += "        ";
    AppendNumber(out, static_cast<long long>(start) + static_cast<long long>(f));
    *out += ": ";
    value(f, out);
    *out += ",\n";
  }
  *out += "    }\n";
}

// The layer metadata and the prim's opening lines, up to its first attribute. first: the frame
// the doc line counts; count: the number of frames of a sequence.
void AppendHeader(std::string* text, const HairCurves& first, bool sequence, size_t count,
                  const UsdExportOptions& options) {
  std::string& out = *text;
  const int start = options.start_time_code;
  out += "#usda 1.0\n(\n";
  out += "    defaultPrim = \"" + options.prim_name + "\"\n";
  out += "    doc = \"ringlet hair curves: ";
  AppendNumber(&out, static_cast<long long>(first.NumStrands()));
  out += " strands, ";
  AppendNumber(&out, static_cast<long long>(first.NumPoints()));
  out += " points";
  if (sequence) {
    out += " in the first of ";
    AppendNumber(&out, static_cast<long long>(count));
    out += " frames";
  }
  out += "; metres, z up; widths are fibre diameters\"\n";
  if (sequence) {
    out += "    endTimeCode = ";
    AppendNumber(&out, static_cast<long long>(start) + static_cast<long long>(count) - 1);
    out += "\n    framesPerSecond = ";
    AppendNumber(&out, options.time_codes_per_second);
    out += '\n';
  }
  out += "    metersPerUnit = 1\n";
  if (sequence) {
    out += "    startTimeCode = ";
    AppendNumber(&out, static_cast<long long>(start));
    out += "\n    timeCodesPerSecond = ";
    AppendNumber(&out, options.time_codes_per_second);
    out += '\n';
  }
  out += "    upAxis = \"Z\"\n)\n\n";
  out += "def BasisCurves \"" + options.prim_name + "\"\n{\n";
  out += "    uniform token type = \"linear\"\n";
  out += "    uniform token wrap = \"nonperiodic\"\n";
}

// The shared writer: one frame gives plain values, several give time samples.
bool Encode(std::span<const HairCurves> frames, bool sequence, const UsdExportOptions& options,
            std::string* text, std::string* error) {
  std::string why;
  if (!options.IsValid(&why)) return Fail(error, "usd export options: " + why);
  if (frames.empty()) return Fail(error, "frames: expected at least one frame, got none");
  for (size_t f = 0; f < frames.size(); ++f) {
    const std::string name = sequence ? "frames[" + std::to_string(f) + "]" : "curves";
    if (!CheckHairCurves(frames[f], name, &why)) return Fail(error, why);
    if (frames[f].colors.empty() != frames[0].colors.empty()) {
      return Fail(error, name + ".colors: expected colours in every frame or in none (frame 0 " +
                             (frames[0].colors.empty() ? "has none)" : "has them)"));
    }
  }
  auto all_equal = [&](auto member) {
    for (const HairCurves& c : frames) {
      if (c.*member != frames[0].*member) return false;
    }
    return true;
  };
  const bool counts_sampled = sequence && !all_equal(&HairCurves::point_counts);
  const bool widths_sampled = sequence && !all_equal(&HairCurves::widths);
  const bool colors_sampled = sequence && !all_equal(&HairCurves::colors);
  const bool with_colors = !frames[0].colors.empty();
  bool any_points = false;
  for (const HairCurves& c : frames) any_points = any_points || !c.points.empty();
  const int start = options.start_time_code;

  // Everything is checked: from here on nothing fails, so write straight into *text (reusing
  // its capacity).
  std::string& out = *text;
  out.clear();
  size_t points = 0;
  for (const HairCurves& c : frames) points += c.points.size();
  out.reserve(64 * points + 1024);  // ~3 numbers of <= 13 characters plus a width per point
  AppendHeader(&out, frames[0], sequence, frames.size(), options);
  const size_t n = frames.size();
  AppendAttribute(&out, "int[] curveVertexCounts", nullptr, counts_sampled, n, start,
                  [&](size_t f, std::string* o) { AppendArray(o, frames[f].point_counts); });
  AppendAttribute(&out, "point3f[] points", nullptr, sequence, n, start,
                  [&](size_t f, std::string* o) { AppendArray(o, frames[f].points); });
  AppendAttribute(&out, "float[] widths", "interpolation = \"vertex\"", widths_sampled, n, start,
                  [&](size_t f, std::string* o) { AppendArray(o, frames[f].widths); });
  if (with_colors) {
    AppendAttribute(&out, "color3f[] primvars:displayColor", "interpolation = \"uniform\"",
                    colors_sampled, n, start,
                    [&](size_t f, std::string* o) { AppendArray(o, frames[f].colors); });
  }
  if (any_points) {
    AppendAttribute(&out, "float3[] extent", nullptr, sequence, n, start,
                    [&](size_t f, std::string* o) {
                      if (frames[f].points.empty()) {
                        *o += "[]";
                      } else {
                        AppendArray(o, Extent(frames[f]));
                      }
                    });
  }
  out += "}\n";
  return true;
}

}  // namespace

bool UsdExportOptions::IsValid(std::string* why) const {
  if (!IsIdentifier(prim_name)) {
    if (why) *why = "prim_name: expected a USD identifier ([A-Za-z_][A-Za-z0-9_]*), got \"" +
                    prim_name + "\"";
    return false;
  }
  if (!std::isfinite(time_codes_per_second) || !(time_codes_per_second > 0.0)) {
    if (why) *why = "time_codes_per_second: expected a finite number > 0";
    return false;
  }
  return true;
}

bool EncodeUsda(const HairCurves& curves, const UsdExportOptions& options, std::string* text,
                std::string* error) {
  return Encode(std::span<const HairCurves>(&curves, 1), false, options, text, error);
}

bool EncodeUsdaSequence(const std::vector<HairCurves>& frames, const UsdExportOptions& options,
                        std::string* text, std::string* error) {
  return Encode(frames, true, options, text, error);
}

namespace {

// Points formatted per block of the parallel writer, and blocks per round handed to the sink
// (a round's text, ~16 x 330 KB, is all the writer holds of a frame).
constexpr size_t kBlockPoints = 8192;
constexpr size_t kRoundBlocks = 16;
// Buffered text handed to the sink once it passes this size.
constexpr size_t kFlushBytes = size_t{1} << 20;

}  // namespace

bool UsdaSequenceWriter::Flush(std::string* error) {
  if (!buffer_.empty()) {
    if (!sink_(buffer_)) failed_ = true;
    buffer_.clear();
  }
  return failed_ ? Fail(error, "cannot write") : true;
}

bool UsdaSequenceWriter::Begin(const HairCurves& first, int frames,
                               const UsdExportOptions& options, FileSink sink,
                               std::string* error) {
  std::string why;
  if (!options.IsValid(&why)) return Fail(error, "usd export options: " + why);
  if (frames < 1) {
    return Fail(error, "frames: expected at least one frame, got " + std::to_string(frames));
  }
  if (!CheckHairCurves(first, "frames[0]", &why)) return Fail(error, why);
  options_ = options;
  sink_ = std::move(sink);
  frames_ = frames;
  appended_ = 0;
  failed_ = false;
  begun_ = true;
  counts_ = first.point_counts;
  widths_ = first.widths;
  colors_ = first.colors;
  extents_.clear();
  extents_.reserve(2 * static_cast<size_t>(frames));
  buffer_.clear();
  // As Encode for a sequence whose counts, widths and colours are the same in every frame:
  // the counts once, then the points' samples.
  AppendHeader(&buffer_, first, true, static_cast<size_t>(frames), options_);
  AppendAttribute(&buffer_, "int[] curveVertexCounts", nullptr, false, 1, 0,
                  [&](size_t, std::string* o) { AppendArray(o, counts_); });
  buffer_ += "    point3f[] points.timeSamples = {\n";
  return Flush(error);
}

bool UsdaSequenceWriter::Append(const HairCurves& frame, std::string* error) {
  if (!begun_) return Fail(error, "frames: Append before Begin");
  if (failed_) return Fail(error, "cannot write");
  const std::string name = "frames[" + std::to_string(appended_) + "]";
  if (appended_ >= frames_) {
    return Fail(error, name + ": more frames than the " + std::to_string(frames_) + " announced");
  }
  std::string why;
  if (!CheckHairCurves(frame, name, &why)) return Fail(error, why);
  auto differs = [&](const char* field) {
    return Fail(error, name + "." + field +
                           ": differ from frame 0's (a streamed sequence writes the curve counts, "
                           "widths and colours once)");
  };
  if (frame.point_counts != counts_) return differs("point_counts");
  if (frame.widths != widths_) return differs("widths");
  if (frame.colors != colors_) return differs("colors");

  buffer_ += "        ";
  AppendNumber(&buffer_, static_cast<long long>(options_.start_time_code) + appended_);
  buffer_ += ": [";
  // AppendArray's text, "(x, y, z), (x, y, z), ...", formatted block by block in parallel.
  const size_t n = frame.points.size();
  const size_t blocks = (n + kBlockPoints - 1) / kBlockPoints;
  blocks_.resize(std::min(blocks, kRoundBlocks));
  for (size_t round = 0; round < blocks; round += kRoundBlocks) {
    const size_t count = std::min(kRoundBlocks, blocks - round);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t b = r.begin(); b != r.end(); ++b) {
        std::string& out = blocks_[b];
        out.clear();
        const size_t begin = (round + b) * kBlockPoints;
        const size_t end = std::min(n, begin + kBlockPoints);
        for (size_t i = begin; i < end; ++i) {
          if (i > 0) out += ", ";
          AppendTuple(&out, frame.points[i]);
        }
      }
    });
    if (!Flush(error)) return false;
    for (size_t b = 0; b < count && !failed_; ++b) {
      if (!sink_(blocks_[b])) failed_ = true;
    }
    if (failed_) return Fail(error, "cannot write");
  }
  buffer_ += "],\n";
  if (!frame.points.empty()) {
    const std::vector<Vec3f> box = Extent(frame);
    extents_.insert(extents_.end(), box.begin(), box.end());
  }
  ++appended_;
  return buffer_.size() < kFlushBytes ? true : Flush(error);
}

bool UsdaSequenceWriter::Finish(std::string* error) {
  if (!begun_) return Fail(error, "frames: Finish before Begin");
  if (failed_) return Fail(error, "cannot write");
  if (appended_ != frames_) {
    return Fail(error, "frames: expected " + std::to_string(frames_) + ", got " +
                           std::to_string(appended_));
  }
  buffer_ += "    }\n";
  AppendAttribute(&buffer_, "float[] widths", "interpolation = \"vertex\"", false, 1, 0,
                  [&](size_t, std::string* o) { AppendArray(o, widths_); });
  if (!colors_.empty()) {
    AppendAttribute(&buffer_, "color3f[] primvars:displayColor", "interpolation = \"uniform\"",
                    false, 1, 0, [&](size_t, std::string* o) { AppendArray(o, colors_); });
  }
  if (!extents_.empty()) {  // the frames have points (all or none: the same counts)
    AppendAttribute(&buffer_, "float3[] extent", nullptr, true, static_cast<size_t>(frames_),
                    options_.start_time_code, [&](size_t f, std::string* o) {
                      AppendArray(o, std::vector<Vec3f>(extents_.begin() + 2 * f,
                                                        extents_.begin() + 2 * f + 2));
                    });
  }
  buffer_ += "}\n";
  begun_ = false;
  return Flush(error);
}

bool WriteUsda(const std::string& path, const HairCurves& curves, const UsdExportOptions& options,
               bool overwrite, std::string* error) {
  std::string text, why;
  if (!EncodeUsda(curves, options, &text, &why)) return Fail(error, path + ": " + why);
  return WriteFileAtomically(path, text, overwrite, error);
}

bool WriteUsdaSequence(const std::string& path, const std::vector<HairCurves>& frames,
                       const UsdExportOptions& options, bool overwrite, std::string* error) {
  std::string text, why;
  if (!EncodeUsdaSequence(frames, options, &text, &why)) return Fail(error, path + ": " + why);
  return WriteFileAtomically(path, text, overwrite, error);
}

}  // namespace ringlet
