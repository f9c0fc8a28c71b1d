#pragma once
// A configuration from TOML text, as the daemon reads a file named site.toml in /srv/tlsmon;
// and the error such text gives ("" when it parses), for the configuration tests.
#include <string>

#include "config/config.hpp"

namespace tlsmon::test {

inline Config parse(const std::string& text) {
    return parse_config(text, "site.toml", "/srv/tlsmon");
}

inline std::string error_of(const std::string& text) {
    try {
        parse(text);
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "";
}

}  // namespace tlsmon::test
