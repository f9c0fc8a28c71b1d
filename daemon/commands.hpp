#pragma once
// Each subcommand of the `tlsmon` binary registers itself on the CLI11 app; the file that
// defines add_X_command owns that subcommand's options and behaviour.
#include <CLI/CLI.hpp>

namespace tlsmon {

void add_check_config_command(CLI::App& app);
void add_info_command(CLI::App& app);
void add_run_command(CLI::App& app);
void add_simulate_command(CLI::App& app);
void add_status_command(CLI::App& app);
void add_query_command(CLI::App& app);
void add_events_command(CLI::App& app);

}  // namespace tlsmon
