#pragma once
// Every key of the configuration file, declared once: where it lives in Config, its type,
// allowed range and meaning. The reader (load_config), the effective configuration logged
// at start (describe) and the reference tables of docs/configuration.md all come from this
// list, so they cannot disagree. The default is the member initialiser in config.hpp.
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "daemon/config.hpp"

namespace tlsmon {

struct ConfigKey {
    std::string section;  // "ingest": the TOML table [ingest]
    std::string name;     // "stable_seconds"
    std::string type;     // as documented: "duration", "integer", "string", "path", ...
    std::string range;    // the allowed values in words, from the same limits the reader uses
    std::string help;     // what the key means
    // Reads the key from its section (absent: the value in `config` stands). Rules that
    // involve other keys are checked in config.cpp once the section is read.
    std::function<void(TomlFields& section, Config& config)> read;
    // The value as TOML text ("10", "\"move\"", "[\"ptx\"]"), as describe() logs it.
    std::function<std::string(const Config& config)> value;
};

// A string and a number as TOML writes them: "a \"b\"", 0.1.
std::string toml_string(const std::string& s);
std::string toml_number(double v);

// In file order: [station], [paths], [ingest], [meteo], [logging], [daemon], [coverage],
// [registration], [m3c2], [modbus], [alarm].
const std::vector<ConfigKey>& config_keys();

// The sections of config_keys(), in that order.
std::vector<std::string> config_sections();

// The Markdown reference table of one section (header, separator, one row per key: key,
// type, default, range, meaning), as docs/configuration.md shows it.
std::string reference_table(const std::string& section);

}  // namespace tlsmon
