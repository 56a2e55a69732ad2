// The `ringlet` command: a thin dispatcher over its subcommands (one file each, see commands.h).
#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "ringlet/atomic_file.h"
#include "commands.h"

#ifndef RINGLET_VERSION
#define RINGLET_VERSION "unknown"
#endif

int main(int argc, char** argv) {
  using ringlet::cli::Command;
  // An interrupted command leaves no temporary file behind (docs/robustness.md).
  ringlet::RemoveTemporariesOnSignals();
  CLI::App app{
      "ringlet: hair strands as Kirchhoff rods (super-helices), statics by energy "
      "minimization.",
      "ringlet"};
  app.set_version_flag("--version", std::string("ringlet ") + RINGLET_VERSION);
  app.require_subcommand(1);

  // Register every subcommand here; each lives in its own cli/<name>_command.cpp.
  const std::vector<Command> commands = {
      ringlet::cli::AddSolveCommand(&app),
      ringlet::cli::AddGroomCommand(&app),
      ringlet::cli::AddStyleCommand(&app),
      ringlet::cli::AddRenderCommand(&app),
      ringlet::cli::AddConvertCommand(&app),
      ringlet::cli::AddInvertCommand(&app),
      ringlet::cli::AddBatchCommand(&app),
      ringlet::cli::AddSimulateCommand(&app),
  };

  // CLI11 would report an unknown command word as "A subcommand is required": name it instead.
  const auto is_command = [&](const char* word) {
    for (const Command& command : commands) {
      if (command.app->check_name(word)) return true;
    }
    return false;
  };
  if (argc > 1 && argv[1][0] != '-' && !is_command(argv[1])) {
    std::string known;
    for (const Command& command : commands) {
      known += (known.empty() ? "" : ", ") + command.app->get_name();
    }
    ringlet::cli::PrintError(std::string("unknown command '") + argv[1] + "' (commands: " + known +
                             "; see 'ringlet --help')");
    return ringlet::cli::kExitBadInput;
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // One line, like every other error, and the usage exit code rather than CLI11's own.
    std::string hint = "ringlet --help";
    for (const Command& command : commands) {
      if (command.app->parsed()) hint = "ringlet " + command.app->get_name() + " --help";
    }
    ringlet::cli::PrintError(std::string(e.what()) + " (see '" + hint + "')");
    return ringlet::cli::kExitBadInput;
  }

  for (const Command& command : commands) {
    if (!command.app->parsed()) continue;
    const int code = command.run();
    // A summary that could not be written (stdout on a full disk, a closed pipe) is an error,
    // not a silent success.
    if (std::fflush(stdout) != 0 || std::ferror(stdout)) {
      const int error_number = errno;
      ringlet::cli::PrintError(std::string("stdout: cannot write the summary: ") +
                               (error_number != 0 ? std::strerror(error_number) : "write error"));
      return code == ringlet::cli::kExitSuccess ? ringlet::cli::kExitBadInput : code;
    }
    return code;
  }
  return ringlet::cli::kExitBadInput;  // unreachable: a subcommand is required
}
