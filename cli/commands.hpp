#pragma once
// Subcommands of the yarnfit front end. Each `add_*` registers a subcommand on the app and
// stores the exit code of its run in `exit_code` (0 success, 2 invalid input, 1 internal).

#include <CLI/CLI.hpp>

#include <filesystem>
#include <functional>
#include <iostream>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "fabrics_db/problems.hpp"
#include "numerics/util/error.hpp"
#include "reports/collection/report_data.hpp"

namespace yarnfit::cli {

inline constexpr int k_exit_ok = 0;
inline constexpr int k_exit_internal = 1;
inline constexpr int k_exit_invalid_input = 2;

void add_db_commands(CLI::App& app, int& exit_code);
void add_shell_commands(CLI::App& app, int& exit_code);
// `shell sim`, registered on the `shell` subcommand by add_shell_commands.
void add_shell_sim_command(CLI::App& shell, int& exit_code);
void add_synth_commands(CLI::App& app, int& exit_code);
// `synth yarn`, registered on the `synth` subcommand (cli/commands_synth.cpp).
void add_synth_yarn_command(CLI::App& synth, int& exit_code);
void add_synth_fabric_command(CLI::App& synth, int& exit_code);
// `yarn sim` and `yarn curve`: periodic yarn tile simulations (SPEC §5).
void add_yarn_commands(CLI::App& app, int& exit_code);
// `yarn fit` (registered on `yarn`) and the whole pipeline `fit` (cli/commands_fit.cpp).
void add_fit_commands(CLI::App& app, CLI::App& yarn, int& exit_code);
// `batch` and `batch status` (cli/commands_batch.cpp).
void add_batch_commands(CLI::App& app, int& exit_code);
// `tile make` (cli/commands_tile.cpp).
void add_tile_commands(CLI::App& app, int& exit_code);
// `report` (cli/commands_report.cpp).
void add_report_command(CLI::App& app, int& exit_code);
// `export` (cli/commands_export.cpp).
void add_export_command(CLI::App& app, int& exit_code);
// `serve user` (cli/commands_serve.cpp): the fitting service's accounts.
void add_serve_commands(CLI::App& app, int& exit_code);
// The exit code of an error that ends a command: 2 for what the user mends in what they gave or
// have (ErrorCategory input, conflict), 1 for the rest (io, solve, system).
inline int exit_code_of(const Error& e) { return e.users_to_mend() ? k_exit_invalid_input : k_exit_internal; }

// Runs `write` (a synth command writing a fabric record into `out`) and turns what it throws
// into the exit code with one line on stderr: invalid settings and an existing record are the
// user's to fix (2), anything else is internal (1).
template <class Write>
int exit_code_of_writing(const std::string& out, Write&& write) {
  try {
    write();
  } catch (const Error& e) {
    std::cerr << out << ": " << e.what() << "\n";
    return exit_code_of(e);
  } catch (const std::exception& e) {
    std::cerr << out << ": " << e.what() << "\n";
    return k_exit_internal;
  }
  return k_exit_ok;
}

// Runs `write`, which writes files into the folder `out`; false after printing
// `out: file: what` when it throws (an internal failure: exit 1).
bool write_files(const std::string& out, const std::function<void()>& write);
// Prints `problems` on stderr, one a line after `prefix` ("tile make: "), their fields as the
// options that set them (cli/option_names.hpp); returns the exit code of invalid input.
int invalid_input(const db::Problems& problems, const std::string& prefix = "");
}  // namespace yarnfit::cli
