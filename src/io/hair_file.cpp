// Cem Yuksel's HAIR format (http://www.cemyuksel.com/research/hairmodels/): a 128-byte header
// and up to five arrays, little-endian. Bytes are assembled explicitly so the file is the same
// on any host.
#include "ringlet/hair_file.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>

#include "io/curves_check.h"
#include "ringlet/atomic_file.h"

namespace ringlet {
namespace {

// Header layout from the specification (byte offsets) and the array bits of the bit field.
constexpr size_t kHeaderSize = 128;
constexpr size_t kOffsetStrandCount = 4;
constexpr size_t kOffsetPointCount = 8;
constexpr size_t kOffsetArrays = 12;
constexpr size_t kOffsetDefaultSegments = 16;
constexpr size_t kOffsetDefaultThickness = 20;
constexpr size_t kOffsetDefaultTransparency = 24;
constexpr size_t kOffsetDefaultColor = 28;
constexpr size_t kOffsetInfo = 40;
constexpr size_t kInfoSize = 88;
constexpr uint32_t kSegmentsBit = 1;
constexpr uint32_t kPointsBit = 2;
constexpr uint32_t kThicknessBit = 4;
constexpr uint32_t kTransparencyBit = 8;
constexpr uint32_t kColorsBit = 16;
constexpr uint32_t kKnownBits =
    kSegmentsBit | kPointsBit | kThicknessBit | kTransparencyBit | kColorsBit;
// A segment count is a uint16, so a strand has at most 65535 segments = 65536 points.
constexpr uint32_t kMaxPointsPerStrand = 65536;

// Little-endian stores and loads, byte by byte (independent of the host's byte order).
inline void Store32(char* p, uint32_t v) {
  p[0] = static_cast<char>(v & 0xff);
  p[1] = static_cast<char>((v >> 8) & 0xff);
  p[2] = static_cast<char>((v >> 16) & 0xff);
  p[3] = static_cast<char>((v >> 24) & 0xff);
}
inline void Store16(char* p, uint16_t v) {
  p[0] = static_cast<char>(v & 0xff);
  p[1] = static_cast<char>((v >> 8) & 0xff);
}
inline void StoreFloat(char* p, float v) { Store32(p, std::bit_cast<uint32_t>(v)); }
inline uint32_t Load32(const char* p) {
  const auto* u = reinterpret_cast<const unsigned char*>(p);
  return static_cast<uint32_t>(u[0]) | (static_cast<uint32_t>(u[1]) << 8) |
         (static_cast<uint32_t>(u[2]) << 16) | (static_cast<uint32_t>(u[3]) << 24);
}
inline uint16_t Load16(const char* p) {
  const auto* u = reinterpret_cast<const unsigned char*>(p);
  return static_cast<uint16_t>(u[0] | (u[1] << 8));
}
inline float LoadFloat(const char* p) { return std::bit_cast<float>(Load32(p)); }

bool Fail(std::string* error, const std::string& what) {
  if (error) *error = what;
  return false;
}

// File value -> metres; with scale 1 the division is exact, so floats round-trip bit for bit.
inline float ToMetres(float v, double units_per_metre) {
  return static_cast<float>(static_cast<double>(v) / units_per_metre);
}
inline float ToFileUnits(float v, double units_per_metre) {
  return static_cast<float>(static_cast<double>(v) * units_per_metre);
}

}  // namespace

std::string DefaultHairInfo(double units_per_metre) {
  // The shortest decimal that reads back as units_per_metre (std::to_chars: no locale).
  char number[32];
  const auto result = std::to_chars(number, number + sizeof(number), units_per_metre);
  std::string text = "ringlet hair curves; " + std::string(number, result.ptr);
  text += units_per_metre == 1.0 ? " unit per metre" : " units per metre";
  if (units_per_metre == 1.0) text += " (metres)";
  if (units_per_metre == 100.0) text += " (centimetres)";
  if (units_per_metre == 1000.0) text += " (millimetres)";
  return text + "; z up; thickness: diameter";
}

bool HairFileOptions::IsValid(std::string* why) const {
  if (!std::isfinite(units_per_metre) || !(units_per_metre > 0.0)) {
    if (why) *why = "units_per_metre: expected a finite number > 0";
    return false;
  }
  if (info.size() > kInfoSize - 1) {
    if (why) {
      *why = "info: expected at most " + std::to_string(kInfoSize - 1) + " characters, got " +
             std::to_string(info.size());
    }
    return false;
  }
  for (size_t i = 0; i < info.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(info[i]);
    if (c < 0x20 || c > 0x7e) {
      if (why) *why = "info: expected printable ASCII, character " + std::to_string(i) + " is not";
      return false;
    }
  }
  return true;
}

bool EncodeHairFile(const HairCurves& curves, const HairFileOptions& options, std::string* bytes,
                    std::string* error) {
  std::string why;
  if (!options.IsValid(&why)) return Fail(error, "hair file options: " + why);
  if (!CheckHairCurves(curves, "curves", &why)) return Fail(error, why);
  const size_t strands = curves.point_counts.size();
  const size_t points = curves.points.size();
  if (strands > std::numeric_limits<uint32_t>::max() ||
      points > std::numeric_limits<uint32_t>::max()) {
    return Fail(error, "curves: more than 2^32-1 strands or points do not fit a .hair header");
  }
  bool same_count = true;
  for (size_t k = 0; k < strands; ++k) {
    if (curves.point_counts[k] > kMaxPointsPerStrand) {
      return Fail(error, "curves.point_counts[" + std::to_string(k) + "]: " +
                             std::to_string(curves.point_counts[k]) +
                             " points; a .hair strand has at most 65535 segments (65536 points)");
    }
    same_count = same_count && curves.point_counts[k] == curves.point_counts[0];
  }
  const bool with_segments = strands > 0 && !same_count;
  const bool with_colors = options.store_colors && !curves.colors.empty();
  const uint32_t arrays = (with_segments ? kSegmentsBit : 0) | kPointsBit |
                          (options.store_thickness ? kThicknessBit : 0) |
                          (with_colors ? kColorsBit : 0);
  const double scale = options.units_per_metre;

  // Defaults: the mean width and mean colour (what a reader uses when an array is absent).
  double mean_width = 0.0;
  for (float w : curves.widths) mean_width += w;
  if (points > 0) mean_width /= static_cast<double>(points);
  Eigen::Vector3d mean_color(1.0, 1.0, 1.0);  // cyHairFile's default colour
  if (!curves.colors.empty()) {
    mean_color.setZero();
    for (const Vec3f& c : curves.colors) mean_color += c.cast<double>();
    mean_color /= static_cast<double>(curves.colors.size());
  }

  const size_t size = kHeaderSize + (with_segments ? 2 * strands : 0) + 12 * points +
                      (options.store_thickness ? 4 * points : 0) + (with_colors ? 12 * points : 0);
  // Everything is checked: from here on nothing fails, so write straight into *bytes (reusing
  // its capacity: first-touching a fresh 50-MB buffer costs more than encoding into it).
  std::string& out = *bytes;
  out.assign(size, '\0');
  char* p = out.data();
  // Header.
  std::memcpy(p, "HAIR", 4);
  Store32(p + kOffsetStrandCount, static_cast<uint32_t>(strands));
  Store32(p + kOffsetPointCount, static_cast<uint32_t>(points));
  Store32(p + kOffsetArrays, arrays);
  Store32(p + kOffsetDefaultSegments,
          strands > 0 && same_count ? curves.point_counts[0] - 1 : 0);
  StoreFloat(p + kOffsetDefaultThickness, static_cast<float>(mean_width * scale));
  StoreFloat(p + kOffsetDefaultTransparency, 0.0f);  // opaque
  for (int c = 0; c < 3; ++c) {
    StoreFloat(p + kOffsetDefaultColor + 4 * c, static_cast<float>(mean_color[c]));
  }
  const std::string info = options.info.empty() ? DefaultHairInfo(scale) : options.info;
  std::memcpy(p + kOffsetInfo, info.data(), std::min(info.size(), kInfoSize - 1));  // rest zero
  p += kHeaderSize;
  // Arrays, in the order of the specification.
  if (with_segments) {
    for (uint32_t count : curves.point_counts) {
      Store16(p, static_cast<uint16_t>(count - 1));
      p += 2;
    }
  }
  for (const Vec3f& x : curves.points) {
    for (int c = 0; c < 3; ++c, p += 4) StoreFloat(p, ToFileUnits(x[c], scale));
  }
  if (options.store_thickness) {
    for (float w : curves.widths) {
      StoreFloat(p, ToFileUnits(w, scale));
      p += 4;
    }
  }
  if (with_colors) {
    for (size_t k = 0; k < strands; ++k) {
      for (uint32_t i = 0; i < curves.point_counts[k]; ++i) {
        for (int c = 0; c < 3; ++c, p += 4) StoreFloat(p, curves.colors[k][c]);
      }
    }
  }
  return true;
}

bool WriteHairFile(const std::string& path, const HairCurves& curves,
                   const HairFileOptions& options, bool overwrite, std::string* error) {
  std::string bytes;
  std::string why;
  if (!EncodeHairFile(curves, options, &bytes, &why)) {
    return Fail(error, DisplayPath(path) + ": " + why);
  }
  return WriteFileAtomically(path, bytes, overwrite, error);
}

bool DecodeHairFile(std::string_view bytes, HairCurves* curves, std::string* error,
                    double units_per_metre) {
  if (!std::isfinite(units_per_metre) || !(units_per_metre > 0.0)) {
    return Fail(error, "units_per_metre: expected a finite number > 0");
  }
  if (bytes.size() < kHeaderSize) {
    return Fail(error, "header: truncated, expected 128 bytes, got " +
                           std::to_string(bytes.size()));
  }
  const char* p = bytes.data();
  if (std::memcmp(p, "HAIR", 4) != 0) {
    return Fail(error, "header.signature: expected \"HAIR\" in bytes 0-3");
  }
  const uint32_t strands = Load32(p + kOffsetStrandCount);
  const uint32_t points = Load32(p + kOffsetPointCount);
  const uint32_t arrays = Load32(p + kOffsetArrays);
  const uint32_t default_segments = Load32(p + kOffsetDefaultSegments);
  const float default_thickness = LoadFloat(p + kOffsetDefaultThickness);
  if ((arrays & ~kKnownBits) != 0) {
    return Fail(error, "header.arrays: reserved bits 5-31 must be 0, got 0x" + [&] {
      char hex[9];
      std::snprintf(hex, sizeof(hex), "%08x", arrays);
      return std::string(hex);
    }());
  }
  if ((arrays & kPointsBit) == 0) {
    return Fail(error, "header.arrays: the points array (bit 1) is missing");
  }
  const bool with_segments = (arrays & kSegmentsBit) != 0;
  const bool with_thickness = (arrays & kThicknessBit) != 0;
  const bool with_transparency = (arrays & kTransparencyBit) != 0;
  const bool with_colors = (arrays & kColorsBit) != 0;

  // Exact size of the arrays present (64-bit: the counts come from the file).
  const uint64_t n = points;
  const uint64_t expected = kHeaderSize + (with_segments ? 2ull * strands : 0) + 12 * n +
                            (with_thickness ? 4 * n : 0) + (with_transparency ? 4 * n : 0) +
                            (with_colors ? 12 * n : 0);
  if (bytes.size() < expected) {
    return Fail(error, "arrays: truncated, header announces " + std::to_string(strands) +
                           " strands and " + std::to_string(points) + " points needing " +
                           std::to_string(expected) + " bytes, got " +
                           std::to_string(bytes.size()));
  }
  if (bytes.size() > expected) {
    return Fail(error, "arrays: " + std::to_string(bytes.size() - expected) +
                           " unexpected bytes after the arrays announced by the header (" +
                           std::to_string(expected) + " bytes)");
  }
  p += kHeaderSize;
  // Every strand has at least 2 points, and the points are in the file (checked above): so a
  // strand count above points / 2 is refused here, before anything is allocated for it, and
  // every allocation below is bounded by the file's size.
  if (strands > points / 2) {
    return Fail(error, "header.strand_count: " + std::to_string(strands) +
                           " strands need at least " + std::to_string(2 * uint64_t{strands}) +
                           " points (2 per strand), but the header announces " +
                           std::to_string(points) + " points");
  }

  HairCurves out;
  out.point_counts.resize(strands);
  uint64_t total = 0;
  if (with_segments) {
    for (uint32_t k = 0; k < strands; ++k, p += 2) {
      const uint16_t segments = Load16(p);
      if (segments == 0) {
        return Fail(error, "segments[" + std::to_string(k) +
                               "]: expected at least 1 segment per strand, got 0");
      }
      out.point_counts[k] = static_cast<uint32_t>(segments) + 1;
      total += out.point_counts[k];
    }
  } else if (strands > 0) {
    // The default is a uint32 (unlike the uint16 array entries); it only has to leave room for
    // the extra point in a uint32 point count.
    if (default_segments == 0 || default_segments == std::numeric_limits<uint32_t>::max()) {
      return Fail(error, "header.default_segments: expected at least 1 segment per strand (no "
                         "segments array), got " + std::to_string(default_segments));
    }
    for (uint32_t k = 0; k < strands; ++k) out.point_counts[k] = default_segments + 1;
    total = static_cast<uint64_t>(strands) * (static_cast<uint64_t>(default_segments) + 1);
  }
  if (total != points) {
    return Fail(error, "header.point_count: " + std::to_string(points) +
                           " points, but the segment counts add up to " + std::to_string(total) +
                           " points");
  }

  out.points.resize(points);
  for (uint32_t i = 0; i < points; ++i) {
    Vec3f x;
    for (int c = 0; c < 3; ++c, p += 4) x[c] = LoadFloat(p);
    if (!std::isfinite(x.x()) || !std::isfinite(x.y()) || !std::isfinite(x.z())) {
      return Fail(error, "points[" + std::to_string(i) + "]: expected finite coordinates");
    }
    for (int c = 0; c < 3; ++c) x[c] = ToMetres(x[c], units_per_metre);
    out.points[i] = x;
  }
  if (with_thickness) {
    out.widths.resize(points);
    for (uint32_t i = 0; i < points; ++i, p += 4) {
      const float t = LoadFloat(p);
      if (!std::isfinite(t) || t < 0.0f) {
        return Fail(error, "thickness[" + std::to_string(i) +
                               "]: expected a finite thickness >= 0");
      }
      out.widths[i] = ToMetres(t, units_per_metre);
    }
  } else {
    if (!std::isfinite(default_thickness) || default_thickness < 0.0f) {
      return Fail(error, "header.default_thickness: expected a finite thickness >= 0 (no "
                         "thickness array)");
    }
    out.widths.assign(points, ToMetres(default_thickness, units_per_metre));
  }
  if (with_transparency) p += 4 * n;  // no place for it in HairCurves
  if (with_colors) {
    out.colors.resize(strands);
    const char* first = p;
    uint64_t start = 0;
    for (uint32_t k = 0; k < strands; ++k) {
      const char* root = first + 12 * start;
      for (int c = 0; c < 3; ++c) out.colors[k][c] = LoadFloat(root + 4 * c);
      if (!std::isfinite(out.colors[k].x()) || !std::isfinite(out.colors[k].y()) ||
          !std::isfinite(out.colors[k].z())) {
        return Fail(error, "colors[" + std::to_string(start) + "]: expected a finite RGB colour");
      }
      start += out.point_counts[k];
    }
  }
  *curves = std::move(out);
  return true;
}

bool ReadHairFile(const std::string& path, HairCurves* curves, std::string* error,
                  double units_per_metre) {
  std::string bytes;
  if (!ReadFile(path, &bytes, error, kMaxHairFileBytes)) return false;
  std::string why;
  if (!DecodeHairFile(bytes, curves, &why, units_per_metre)) {
    return Fail(error, DisplayPath(path) + ": " + why);
  }
  return true;
}

}  // namespace ringlet
