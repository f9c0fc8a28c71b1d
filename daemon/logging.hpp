#pragma once
// Where the daemon's log goes: stderr, or the systemd journal when run by systemd (so each
// line keeps its priority there instead of arriving as plain text), plus an optional
// rotating file. One default spdlog logger; the level comes from the configuration.
#include <string>

#include "config/config.hpp"

namespace tlsmon {

// True when systemd started this process with its output going to the journal
// ($JOURNAL_STREAM, see systemd.exec(5)) or as a unit ($INVOCATION_ID).
bool running_under_systemd();

// Installs the default logger for `config` (replacing any earlier one, e.g. on reload).
// Throws ConfigError when the log file cannot be opened.
void setup_logging(const LoggingConfig& config);

}  // namespace tlsmon
