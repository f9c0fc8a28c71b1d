// `tlsmon run --config FILE [--once]`: the ingest daemon (daemon/ingest_service.hpp).
#include "daemon/commands.hpp"
#include "daemon/ingest_service.hpp"

namespace tlsmon {

void add_run_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("run", "Run the ingest daemon on the configured folders");
    auto options = std::make_shared<RunOptions>();
    auto file = std::make_shared<std::string>();
    cmd->add_option("--config", *file, "TOML configuration file")->required();
    cmd->add_flag("--once", options->once,
                  "Process the files present (once complete) and the backlog, then exit");
    cmd->callback([options, file] {
        options->config_file = *file;
        const int code = run_daemon(*options);
        if (code != 0) throw CLI::RuntimeError(code);
    });
}

}  // namespace tlsmon
