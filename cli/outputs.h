// The output directory and output options of `ringlet groom` and `ringlet style` (one code for
// both): --formats, --hair-units-per-metre, --force, --render with --spp/--width/--height. The
// directory is checked before any work and written only after every file has been encoded, each
// file atomically.
#pragma once

#include <chrono>
#include <functional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "ringlet/body.h"
#include "ringlet/hair_curves.h"
#include "ringlet/hair_file.h"
#include "ringlet/render_json.h"

namespace CLI {
class App;
}  // namespace CLI

namespace ringlet::cli {

/// Wall time since start (s).
double SecondsSince(std::chrono::steady_clock::time_point start);

/// The directory may exist (it is created otherwise) but none of the named files may, unless
/// force: nothing the user had is overwritten silently. A path that is not a directory is an
/// error even with force. On failure *error gets one line.
bool CheckOutputDirectory(const std::string& directory, const std::vector<std::string>& names,
                          bool force, std::string* error);

/// Creates the directory if needed and writes the (name, contents) into it as one output
/// (WriteFilesAtomically): all files or, after a failure while writing, none; a failure while
/// renaming names the files written and missing. On failure *error gets one line.
bool WriteOutputFiles(const std::string& directory,
                      const std::vector<std::pair<std::string, std::string>>& files, bool force,
                      std::string* error);

/// The strand files of a groom or styled head, by format name (--formats).
struct OutputFile {
  const char* format;
  const char* name;
};
inline constexpr OutputFile kStrandOutputs[] = {
    {"hair", "strands.hair"},   // Cem Yuksel's binary hair format
    {"usda", "strands.usda"},   // USD text, BasisCurves
    {"obj", "strands.obj"},     // OBJ line segments
    {"body", "body.obj"},       // the body as a triangle mesh (OBJ), for other tools
    {"json", "masters.json"},   // the solved master strands and the summary
};

/// The image of --render, next to the other files.
inline constexpr const char* kRenderName = "render.png";

/// The output options shared by `groom` and `style` (AddOutputOptions registers them).
struct OutputOptions {
  std::string formats = "hair,usda,obj,body,json";  ///< --formats
  double hair_units_per_metre = 1.0;          ///< --hair-units-per-metre
  bool force = false;                         ///< --force
  bool render = false;                        ///< --render: also render.png
  int spp = 0;                                ///< --spp, --width, --height: 0 = the file's
  int width = 0;
  int height = 0;
  int denoise = -1;       ///< --denoise (1) / --no-denoise (0); -1 = the file's
  double clamp = -1.0;    ///< --clamp; < 0 = the file's
};

/// Registers --formats, --hair-units-per-metre, --force, --render, --spp, --width, --height,
/// --denoise / --no-denoise and --clamp on app; `what` names what --render draws ("the groom", "the styled hair").
void AddOutputOptions(CLI::App* app, OutputOptions* options, const std::string& what);

/// Checks the options before any work: the format names ("hair,usda" -> {"hair", "usda"};
/// unknown names are an error naming the valid ones), the .hair unit, and --spp, --width,
/// --height, --(no-)denoise, --clamp only with --render. On failure *error gets one line naming the option.
bool CheckOutputOptions(const OutputOptions& options, std::set<std::string>* formats,
                        HairFileOptions* hair_options, std::string* error);

/// The render settings with the --spp, --width and --height overrides applied.
void ApplyRenderOverrides(const OutputOptions& options, RenderSettings* settings);

/// The names of the strand files in `formats`, in kStrandOutputs order.
std::vector<std::string> StrandOutputNames(const std::set<std::string>& formats);

/// Encodes the strand files in `formats` (strands.hair, .usda, .obj by the library's
/// EncodeHairstyleStrands with the hairstyle's render settings: the studio's Export writes the
/// same bytes; body.obj from body, masters_json makes masters.json) and appends (name,
/// contents) to files. On failure *error gets one line starting with the file name.
bool EncodeStrandOutputs(const HairCurves& strands, const RenderSettings& render,
                         const std::set<std::string>& formats,
                         const HairFileOptions& hair_options, const Body* body,
                         const std::function<std::string()>& masters_json,
                         std::vector<std::pair<std::string, std::string>>* files,
                         std::string* error);

}  // namespace ringlet::cli
