// The subcommands of the `ringlet` tool, one file each (pbrt's cmd/): main.cpp only registers
// them and runs the one that was parsed. Only cli/ prints and exits.
#pragma once

#include <cstdio>
#include <functional>
#include <string>

namespace CLI {
class App;
}  // namespace CLI

namespace ringlet {
struct Hairstyle;
struct Groom;
}  // namespace ringlet

namespace ringlet::cli {

/// Exit codes shared by all subcommands.
inline constexpr int kExitSuccess = 0;   ///< everything worked
inline constexpr int kExitBadInput = 1;  ///< bad usage or input; nothing was written
inline constexpr int kExitUnsolved =
    2;  ///< results written, but some did not converge or are unstable

/// A registered subcommand: its CLI11 app, and the action that runs it once the command line has
/// been parsed; the action returns the process exit code.
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

/// `ringlet solve SCENE.json -o RESULT.json`: static equilibrium of every strand of a scene.
Command AddSolveCommand(CLI::App* parent);

/// `ringlet groom HAIRSTYLE.json -o OUTDIR/`: a full head of hair with standard file exports.
Command AddGroomCommand(CLI::App* parent);

/// `ringlet render INPUT -o IMAGE.png`: a hairstyle (groomed first) or a .hair file, rendered.
Command AddRenderCommand(CLI::App* parent);

/// The groom of `ringlet groom`, with its progress bar on stderr unless quiet (shared with
/// `ringlet render`). Returns false with GroomHairstyle's message for invalid input.
bool GroomWithProgress(const Hairstyle& style, int threads, bool quiet, Groom* groom,
                       std::string* error);

/// `ringlet style HAIRSTYLE.json --wet --cut-z Z ... -o OUTDIR/`: styling operations on a groom.
Command AddStyleCommand(CLI::App* parent);

/// `ringlet convert IN OUT`: hair strands from .hair/.data/.usda/.obj to any of them.
Command AddConvertCommand(CLI::App* parent);
/// `ringlet invert TARGET -o OUTDIR/`: rest shapes that hold target strands (inverse statics).
Command AddInvertCommand(CLI::App* parent);

/// `ringlet simulate INPUT -o OUTDIR/ --motion MOTION`: hair in motion (docs/dynamics.md).
Command AddSimulateCommand(CLI::App* parent);

/// `ringlet batch SPEC -o OUTDIR [--shard K/N] [--items A:B]`: a dataset of grooms (batch.h).
Command AddBatchCommand(CLI::App* parent);

/// Prints "ringlet: <kind>: <message>" as exactly one line on stderr: control characters in the
/// message (a newline in a file name, say) are shown as '?'.
inline void PrintDiagnostic(const char* kind, const std::string& message) {
  std::string line = message;
  for (char& c : line) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  }
  std::fprintf(stderr, "ringlet: %s: %s\n", kind, line.c_str());
  std::fflush(stderr);
}

/// One line "ringlet: error: <message>" on stderr.
inline void PrintError(const std::string& message) { PrintDiagnostic("error", message); }

/// One line "ringlet: warning: <message>" on stderr.
inline void PrintWarning(const std::string& message) { PrintDiagnostic("warning", message); }

}  // namespace ringlet::cli
