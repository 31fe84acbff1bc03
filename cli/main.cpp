// yarnfit: calibrates cloth simulation models against physical tests of knitted fabrics.
#include <cstdlib>
#include <exception>
#include <iostream>

#include "cli/commands.hpp"
#include "numerics/util/error.hpp"

#ifndef YARNFIT_VERSION
#define YARNFIT_VERSION "0.0.0"
#endif

int main(int argc, char** argv) {
  using namespace yarnfit::cli;
  // Before OpenMP starts its threads: spinning waits steal the core from the other work on a
  // busy 2-core machine and slow the parallel loops several times over. A user's setting wins.
  ::setenv("OMP_WAIT_POLICY", "passive", 0);
  CLI::App app{
      "yarnfit — fits thin-shell and yarn-level cloth models to stretch and bending tests of "
      "knitted fabrics.\nExit codes: 0 success, 2 invalid input, 1 internal failure."};
  app.set_version_flag("--version", std::string("yarnfit ") + YARNFIT_VERSION);
  app.require_subcommand(1);
  int exit_code = k_exit_ok;
  add_db_commands(app, exit_code);
  add_shell_commands(app, exit_code);
  add_synth_commands(app, exit_code);
  add_synth_yarn_command(*app.get_subcommand("synth"), exit_code);
  add_synth_fabric_command(*app.get_subcommand("synth"), exit_code);
  add_yarn_commands(app, exit_code);
  add_fit_commands(app, *app.get_subcommand("yarn"), exit_code);
  add_batch_commands(app, exit_code);
  add_report_command(app, exit_code);
  add_tile_commands(app, exit_code);
  add_export_command(app, exit_code);
  add_serve_commands(app, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // Help and version exit 0; a bad command line is invalid input.
    return app.exit(e) == 0 ? k_exit_ok : k_exit_invalid_input;
  } catch (const yarnfit::Error& e) {  // one a command did not answer itself: its category says whose it is
    std::cerr << "yarnfit: " << (e.users_to_mend() ? "" : "internal error: ") << e.what() << "\n";
    return exit_code_of(e);
  } catch (const std::exception& e) {
    std::cerr << "yarnfit: internal error: " << e.what() << "\n";
    return k_exit_internal;
  }
  return exit_code;
}
