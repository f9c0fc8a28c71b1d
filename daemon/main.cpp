// tlsmon: unattended deformation monitoring with a terrestrial laser scanner.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

#include "daemon/commands.hpp"

int main(int argc, char** argv) {
    CLI::App app{"tlsmon: unattended deformation monitoring with a terrestrial laser scanner"};
    app.set_version_flag("--version", std::string("tlsmon ") + TLSMON_VERSION);
    app.require_subcommand(1);
    // Subcommands (one file each under daemon/):
    tlsmon::add_check_config_command(app);
    tlsmon::add_info_command(app);
    tlsmon::add_run_command(app);
    tlsmon::add_simulate_command(app);
    tlsmon::add_status_command(app);
    tlsmon::add_query_command(app);
    tlsmon::add_events_command(app);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    return 0;
}
