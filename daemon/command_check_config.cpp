// `tlsmon check-config FILE`: the effective configuration (defaults filled in, paths
// resolved) on stdout and exit 0, or the error naming file, line and key and exit 1.
#include <iostream>

#include "daemon/commands.hpp"
#include "daemon/config.hpp"

namespace tlsmon {

void add_check_config_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("check-config",
                                   "Validate a configuration file and print "
                                   "the effective values");
    auto file = std::make_shared<std::string>();
    cmd->add_option("FILE", *file, "TOML configuration file")->required();
    cmd->callback([file] {
        try {
            const Config config = load_config(*file);
            for (const auto& line : describe(config)) std::cout << line << '\n';
        } catch (const Error& e) {
            std::cerr << "tlsmon check-config: " << e.what() << '\n';
            throw CLI::RuntimeError(1);
        }
    });
}

}  // namespace tlsmon
