// The strand exporters behind one call: `ringlet groom`, `ringlet style` and the studio's Export
// encode strands the same way (.hair, .usda, .obj), chosen by format or by a file's extension.
#pragma once

#include <string>

#include "ringlet/hair_curves.h"
#include "ringlet/hair_file.h"
#include "ringlet/render_json.h"

namespace ringlet {

/// The file formats of exported strands.
enum class StrandFormat {
  kHair,  ///< Cem Yuksel's .hair (hair_file.h), scaled by HairFileOptions::units_per_metre
  kUsda,  ///< USD text, a BasisCurves prim (usd_export.h), metres
  kObj,   ///< Wavefront OBJ polylines (obj_export.h), metres
};

/// The extension of a format without the dot: "hair", "usda", "obj".
const char* StrandFormatExtension(StrandFormat format);

/// The format named by a path's extension (.hair, .usda, .obj; case-sensitive, as the CLI
/// writes them). False with one line naming the path and the expected extensions otherwise.
bool StrandFormatFromPath(const std::string& path, StrandFormat* format, std::string* error);

/// Encodes the strands in a format (EncodeHairFile with `hair_options`, EncodeUsda with the
/// default UsdExportOptions, or EncodeObj). False with the encoder's one-line message.
bool EncodeStrands(const HairCurves& strands, StrandFormat format,
                   const HairFileOptions& hair_options, std::string* bytes, std::string* error);

/// Encodes the strands in the format of the path's extension and writes them atomically
/// (WriteFileAtomically: the file appears complete or not at all; an existing file is replaced
/// only when overwrite is true, and only if it is a regular file). Nothing is written when the
/// encoding fails. Errors are one line starting with the path.
bool ExportStrands(const std::string& path, const HairCurves& strands,
                   const HairFileOptions& hair_options, bool overwrite, std::string* error);

/// A hairstyle's strand file as every front end writes it (`ringlet groom`, `ringlet style` and
/// the studio's Export: one code path, identical bytes): the strands, each given the display
/// colour of the melanins of the hairstyle's "render" settings (SetMelaninColours: the .hair
/// colour array, USD primvars:displayColor, OBJ vertex colours), encoded by EncodeStrands.
/// Strands already coloured so are encoded as they are, others are copied and coloured.
bool EncodeHairstyleStrands(const HairCurves& strands, const RenderSettings& render,
                            StrandFormat format, const HairFileOptions& hair_options,
                            std::string* bytes, std::string* error);

/// ExportStrands of a hairstyle's strands: EncodeHairstyleStrands in the format of the path's
/// extension, written atomically (an existing file only when overwrite). Errors are one line
/// starting with the path.
bool ExportHairstyleStrands(const std::string& path, const HairCurves& strands,
                            const RenderSettings& render, const HairFileOptions& hair_options,
                            bool overwrite, std::string* error);

}  // namespace ringlet
