#include "cli/commands.hpp"

namespace tlsmon {

int run_ingest(const RunOptions& options) {
    return run_daemon(options);
}

}  // namespace tlsmon
