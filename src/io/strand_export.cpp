// The strand exporters behind one call (strand_export.h).
#include "ringlet/strand_export.h"

#include <filesystem>

#include "ringlet/atomic_file.h"
#include "ringlet/render_json.h"
#include "ringlet/obj_export.h"
#include "ringlet/usd_export.h"

namespace ringlet {

const char* StrandFormatExtension(StrandFormat format) {
  switch (format) {
    case StrandFormat::kHair:
      return "hair";
    case StrandFormat::kUsda:
      return "usda";
    case StrandFormat::kObj:
      return "obj";
  }
  return "";
}

bool StrandFormatFromPath(const std::string& path, StrandFormat* format, std::string* error) {
  const std::string extension = std::filesystem::path(path).extension().string();
  for (StrandFormat f : {StrandFormat::kHair, StrandFormat::kUsda, StrandFormat::kObj}) {
    if (extension == std::string(".") + StrandFormatExtension(f)) {
      *format = f;
      return true;
    }
  }
  if (error) {
    *error = path + ": expected a file name ending in .hair, .usda or .obj, got \"" + extension +
             "\"";
  }
  return false;
}

bool EncodeStrands(const HairCurves& strands, StrandFormat format,
                   const HairFileOptions& hair_options, std::string* bytes, std::string* error) {
  switch (format) {
    case StrandFormat::kHair:
      return EncodeHairFile(strands, hair_options, bytes, error);
    case StrandFormat::kUsda:
      return EncodeUsda(strands, UsdExportOptions{}, bytes, error);
    case StrandFormat::kObj:
      return EncodeObj(strands, bytes, error);
  }
  if (error) *error = "format: unknown";
  return false;
}

namespace {

// Checks the path and options, encodes with `encode` (bytes, why) and writes atomically.
template <typename Encode>
bool WriteEncoded(const std::string& path, const HairFileOptions& hair_options, bool overwrite,
                  const Encode& encode, std::string* error) {
  StrandFormat format;
  if (!StrandFormatFromPath(path, &format, error)) return false;
  std::string why;
  if (!hair_options.IsValid(&why)) {
    if (error) *error = path + ": " + why;
    return false;
  }
  // Checked before the (seconds-long) encoding, and again by the atomic write.
  if (!CheckReplaceable(path, overwrite, error)) return false;
  std::string bytes;
  if (!encode(format, &bytes, &why)) {
    if (error) *error = path + ": " + why;
    return false;
  }
  return WriteFileAtomically(path, bytes, overwrite, error);
}

// Whether every strand already has the colour SetMelaninColours gives it.
bool HasMelaninColours(const HairCurves& strands, const RenderSettings& render) {
  HairCurves probe;
  probe.point_counts.resize(1);
  SetMelaninColours(render, &probe);
  if (strands.colors.size() != strands.point_counts.size()) return false;
  for (const Vec3f& c : strands.colors) {
    if (c != probe.colors[0]) return false;
  }
  return true;
}

}  // namespace

bool ExportStrands(const std::string& path, const HairCurves& strands,
                   const HairFileOptions& hair_options, bool overwrite, std::string* error) {
  return WriteEncoded(
      path, hair_options, overwrite,
      [&](StrandFormat format, std::string* bytes, std::string* why) {
        return EncodeStrands(strands, format, hair_options, bytes, why);
      },
      error);
}

bool EncodeHairstyleStrands(const HairCurves& strands, const RenderSettings& render,
                            StrandFormat format, const HairFileOptions& hair_options,
                            std::string* bytes, std::string* error) {
  if (HasMelaninColours(strands, render)) {
    return EncodeStrands(strands, format, hair_options, bytes, error);
  }
  HairCurves coloured = strands;
  SetMelaninColours(render, &coloured);
  return EncodeStrands(coloured, format, hair_options, bytes, error);
}

bool ExportHairstyleStrands(const std::string& path, const HairCurves& strands,
                            const RenderSettings& render, const HairFileOptions& hair_options,
                            bool overwrite, std::string* error) {
  return WriteEncoded(
      path, hair_options, overwrite,
      [&](StrandFormat format, std::string* bytes, std::string* why) {
        return EncodeHairstyleStrands(strands, render, format, hair_options, bytes, why);
      },
      error);
}

}  // namespace ringlet
