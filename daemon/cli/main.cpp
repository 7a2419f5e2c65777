// rig: the command line of the keratome rig (control, archive, model lab, demo, haptics).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>

#include "archive_commands.hpp"
#include "cli_context.hpp"
#include "control_commands.hpp"
#include "demo_command.hpp"
#include "haptic_command.hpp"
#include "lab_commands.hpp"
#include "model_commands.hpp"
#include "sim_commands.hpp"

static int run_rig(int argc, char** argv) {
  CLI::App app{
      "rig: run incision tests on the keratome rig, analyse them with the model lab, feel them on "
      "the Phantom"};
  app.require_subcommand(1);
  // Global options may come before or after the subcommand (`rig demo --once --format json`):
  // options a subcommand does not know fall through to this parent.
  app.fallthrough();
  rig::cli::CliContext context;
  if (const char* api = std::getenv("RIG_API")) context.api_url = api;
  if (const char* archive = std::getenv("RIG_ARCHIVE")) context.archive_path = archive;
  if (const char* token = std::getenv("RIG_TOKEN_FILE")) context.token_file = token;
  app.add_option("--api", context.api_url, "rigd API (env RIG_API)");
  app.add_option("--token-file", context.token_file, "API token file (env RIG_TOKEN_FILE)");
  app.add_option("--archive", context.archive_path,
                 "archive file for export/import/model (env RIG_ARCHIVE)");
  app.add_option("--format", context.format, "output format")
      ->check(CLI::IsMember({"table", "json"}));
  int exit_code = 0;
  rig::cli::add_control_commands(app, context, exit_code);
  rig::cli::add_archive_commands(app, context, exit_code);
  rig::cli::add_demo_command(app, context, exit_code);
  rig::cli::add_model_commands(app, context, exit_code);
  rig::cli::add_haptic_command(app, context, exit_code);
  rig::cli::add_sim_commands(app, context, exit_code);
  rig::cli::add_lab_archive_commands(app, context, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const std::exception& e) {
    std::cerr << "rig: " << e.what() << "\n";
    return 1;
  }
  return exit_code;
}

// An exception no command caught (a bug, or a resource gone at setup) ends the program with its
// message and status 1, not with std::terminate's abort.
int main(int argc, char** argv) {
  try {
    return run_rig(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rig: error: %s\n", e.what());
  } catch (...) {
    std::fprintf(stderr, "rig: error: an unknown exception\n");
  }
  return 1;
}
