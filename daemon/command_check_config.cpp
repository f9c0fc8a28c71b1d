// `tlsmon check-config FILE`: the effective configuration (defaults filled in, paths
// resolved) on stdout and exit 0, or the error naming file, line and key and exit 1.
#include <iostream>

#include "daemon/commands.hpp"
#include "daemon/config.hpp"

namespace tlsmon {

int run_check_config(const CheckConfigOptions& options) {
    try {
        const Config config = load_config(options.file);
        for (const auto& line : describe(config)) std::cout << line << '\n';
    } catch (const Error& e) {
        std::cerr << "tlsmon check-config: " << e.what() << '\n';
        return 1;
    }
    return 0;
}

}  // namespace tlsmon
