// USC-HairSalon's .data format: int32 strand count, then per strand an int32 vertex count and
// that many float32 (x, y, z), little-endian (usc_data.h; sources in docs/file-formats.md).
// Bytes are assembled explicitly so the file is the same on any host.
#include "ringlet/usc_data.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "io/strand_readers.h"
#include "ringlet/atomic_file.h"

namespace ringlet {
namespace {

constexpr uint64_t kCountBytes = 4;   // an int32 count
constexpr uint64_t kVertexBytes = 12;  // three float32

inline void Store32(char* p, uint32_t v) {
  p[0] = static_cast<char>(v & 0xff);
  p[1] = static_cast<char>((v >> 8) & 0xff);
  p[2] = static_cast<char>((v >> 16) & 0xff);
  p[3] = static_cast<char>((v >> 24) & 0xff);
}
inline uint32_t Load32(const char* p) {
  const auto* u = reinterpret_cast<const unsigned char*>(p);
  return static_cast<uint32_t>(u[0]) | (static_cast<uint32_t>(u[1]) << 8) |
         (static_cast<uint32_t>(u[2]) << 16) | (static_cast<uint32_t>(u[3]) << 24);
}
inline int32_t LoadInt32(const char* p) { return std::bit_cast<int32_t>(Load32(p)); }
inline float LoadFloat(const char* p) { return std::bit_cast<float>(Load32(p)); }

bool Fail(std::string* error, const std::string& what) {
  if (error) *error = what;
  return false;
}

bool Finite(const Vec3f& x) {
  return std::isfinite(x.x()) && std::isfinite(x.y()) && std::isfinite(x.z());
}

}  // namespace

bool EncodeUscData(const HairCurves& curves, const StrandTargetOptions& options,
                   std::string* bytes, std::string* error) {
  std::string why;
  if (!options.IsValid(&why)) return Fail(error, "strand target options: " + why);
  if (!CheckHairCurves(curves, "curves", &why)) return Fail(error, why);
  constexpr uint64_t kMaxCount = std::numeric_limits<int32_t>::max();
  if (curves.point_counts.size() > kMaxCount) {
    return Fail(error, "curves.point_counts: " + std::to_string(curves.point_counts.size()) +
                           " strands; a .data file holds at most 2^31 - 1");
  }
  for (size_t k = 0; k < curves.point_counts.size(); ++k) {
    if (curves.point_counts[k] > kMaxCount) {
      return Fail(error, "curves.point_counts[" + std::to_string(k) + "]: " +
                             std::to_string(curves.point_counts[k]) +
                             " points; a .data strand holds at most 2^31 - 1");
    }
  }
  // Convert first (a large units_per_metre may overflow float): nothing is written on failure.
  std::vector<Vec3f> file_points(curves.points.size());
  for (size_t i = 0; i < curves.points.size(); ++i) {
    file_points[i] =
        io_internal::FromMetresZUp(curves.points[i], options.units_per_metre, options.up_axis);
    if (!Finite(file_points[i])) {
      return Fail(error, "curves.points[" + std::to_string(i) +
                             "]: not finite in file units (units_per_metre " +
                             std::to_string(options.units_per_metre) + ")");
    }
  }
  std::string& out = *bytes;
  out.assign(kCountBytes * (1 + curves.point_counts.size()) + kVertexBytes * file_points.size(),
             '\0');
  char* p = out.data();
  Store32(p, static_cast<uint32_t>(curves.point_counts.size()));
  p += kCountBytes;
  size_t first = 0;
  for (uint32_t count : curves.point_counts) {
    Store32(p, count);
    p += kCountBytes;
    for (size_t i = first; i < first + count; ++i) {
      for (int c = 0; c < 3; ++c, p += 4) Store32(p, std::bit_cast<uint32_t>(file_points[i][c]));
    }
    first += count;
  }
  return true;
}

bool WriteUscData(const std::string& path, const HairCurves& curves,
                  const StrandTargetOptions& options, bool overwrite, std::string* error) {
  std::string bytes, why;
  if (!EncodeUscData(curves, options, &bytes, &why)) return Fail(error, path + ": " + why);
  return WriteFileAtomically(path, bytes, overwrite, error);
}

bool DecodeUscData(std::string_view bytes, const StrandTargetOptions& options, HairCurves* curves,
                   StrandTargetSummary* summary, std::string* error) {
  std::string why;
  if (!options.IsValid(&why)) return Fail(error, "strand target options: " + why);
  const uint64_t size = bytes.size();
  if (size < kCountBytes) {
    return Fail(error, "header: truncated, expected a 4-byte strand count, got " +
                           std::to_string(size) + " bytes");
  }
  const char* p = bytes.data();
  const int32_t strands = LoadInt32(p);
  // Each strand takes at least its 4-byte vertex count: so the strand count is bounded by the
  // file's size before anything is allocated for it.
  if (strands < 0) {
    return Fail(error, "header: negative strand count " + std::to_string(strands) +
                           " (bytes 0-3 read as a little-endian int32)");
  }
  const uint64_t max_strands = (size - kCountBytes) / kCountBytes;
  if (static_cast<uint64_t>(strands) > max_strands) {
    return Fail(error, "header: " + std::to_string(strands) +
                           " strands announced, but a " + std::to_string(size) +
                           "-byte file holds at most " + std::to_string(max_strands) +
                           " (4 bytes per strand at least)");
  }

  // First pass: the counts against the bytes left, without allocating; count what is kept.
  uint64_t offset = kCountBytes;
  uint64_t kept_strands = 0, kept_points = 0;
  for (int32_t k = 0; k < strands; ++k) {
    if (size - offset < kCountBytes) {
      return Fail(error, "strand " + std::to_string(k) + ": truncated, the vertex count at byte " +
                             std::to_string(offset) + " is missing (file of " +
                             std::to_string(size) + " bytes)");
    }
    const int32_t n = LoadInt32(p + offset);
    offset += kCountBytes;
    if (n < 0) {
      return Fail(error, "strand " + std::to_string(k) + ": negative vertex count " +
                             std::to_string(n));
    }
    const uint64_t need = kVertexBytes * static_cast<uint64_t>(n);
    if (size - offset < need) {
      return Fail(error, "strand " + std::to_string(k) + ": truncated, " + std::to_string(n) +
                             " vertices need " + std::to_string(need) + " bytes from byte " +
                             std::to_string(offset) + ", the file has " +
                             std::to_string(size - offset) + " left");
    }
    offset += need;
    if (n >= 2) {
      ++kept_strands;
      kept_points += static_cast<uint64_t>(n);
    }
  }
  if (offset != size) {
    return Fail(error, "trailing data: " + std::to_string(size - offset) +
                           " bytes after the last strand (which ends at byte " +
                           std::to_string(offset) + ")");
  }
  if (kept_points > std::numeric_limits<uint32_t>::max()) {
    return Fail(error, "points: " + std::to_string(kept_points) +
                           " points; at most 2^32 - 1 are read");
  }

  // Second pass: the strands with hair, converted and checked. Every size below is bounded by
  // the file's (checked above).
  HairCurves out;
  StrandTargetSummary info;
  out.point_counts.reserve(kept_strands);
  out.points.reserve(kept_points);
  info.file_strand_index.reserve(kept_strands);
  offset = kCountBytes;
  for (int32_t k = 0; k < strands; ++k) {
    const int32_t n = LoadInt32(p + offset);
    offset += kCountBytes;
    if (n < 2) {
      ++info.skipped_empty_strands;
      offset += kVertexBytes * static_cast<uint64_t>(n);
      continue;
    }
    for (int32_t i = 0; i < n; ++i, offset += kVertexBytes) {
      const Vec3f x(LoadFloat(p + offset), LoadFloat(p + offset + 4), LoadFloat(p + offset + 8));
      if (!Finite(x)) {
        return Fail(error, "strand " + std::to_string(k) + ", point " + std::to_string(i) +
                               ": expected finite coordinates");
      }
      out.points.push_back(x);
    }
    out.point_counts.push_back(static_cast<uint32_t>(n));
    info.file_strand_index.push_back(static_cast<uint64_t>(k));
  }
  out.widths.assign(out.points.size(), static_cast<float>(options.default_width));
  io_internal::ConvertToMetresZUp(options.units_per_metre, options.up_axis, &out);
  const auto name = [&](size_t k) { return "strand " + std::to_string(info.file_strand_index[k]); };
  if (!io_internal::CheckStrands(out, name, &why)) return Fail(error, why);
  info.metres_per_unit = 1.0 / options.units_per_metre;
  info.up_axis = options.up_axis;
  *curves = std::move(out);
  if (summary) *summary = std::move(info);
  return true;
}

}  // namespace ringlet
