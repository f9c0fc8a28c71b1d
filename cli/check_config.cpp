// `tlsmon check-config FILE`: the effective configuration (defaults filled in, paths
// resolved) on stdout and exit 0, or the error naming file, line and key and exit 1. The
// folders, database and log file are checked as `tlsmon run` checks them at start, but
// nothing is created: a folder that run would create is named in a warning.
#include <iostream>

#include "cli/commands.hpp"
#include "config/config.hpp"
#include "daemon/startup_checks.hpp"

namespace tlsmon {

int run_check_config(const CheckConfigOptions& options) {
    try {
        const Config config = load_config(options.file);
        const std::vector<MissingFolder> missing = check_startup(config);
        for (const auto& line : describe(config)) std::cout << line << '\n';
        if (!can_register(pipeline_config(config).registration)) {
            std::cerr << "tlsmon check-config: warning: " << kNoRegistrationWarning << '\n';
        }
        if (stable_areas_alone(pipeline_config(config).registration)) {
            std::cerr << "tlsmon check-config: warning: " << kStableAreasAloneWarning << '\n';
        }
        for (const auto& problem : notify_file_problems(config.notify))
            std::cerr << "tlsmon check-config: warning: " << problem << '\n';
        for (const auto& m : missing) {
            std::cerr << "tlsmon check-config: warning: " << m.key << ": " << m.path.string()
                      << " does not exist; tlsmon run will create it\n";
        }
    } catch (const Error& e) {
        std::cerr << "tlsmon check-config: " << e.what() << '\n';
        return 1;
    }
    return 0;
}

}  // namespace tlsmon
