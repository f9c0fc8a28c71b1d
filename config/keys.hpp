#pragma once
// Every key of the configuration file, collected from the sections' declarations beside
// their structs (core/config_key.hpp: `m3c2_keys()` in pipeline/m3c2_config.cpp, ...): its
// section, type, allowed range and meaning. The reader (load_config), the effective
// configuration logged at start (describe), the one-shot commands' parameter lines and the
// reference tables of docs/configuration.md all come from this list, so they cannot
// disagree. The default is the member initialiser of the section's struct.
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "config/config.hpp"

namespace tlsmon {

// A section's key (core/config_key.hpp) lifted to the whole Config: `read` takes the
// key's TOML table, `value` is what describe() logs.
struct ConfigKey : SectionKey<Config> {
    std::string section;  // "ingest": the TOML table [ingest]
};

// In file order: [station], [paths], [ingest], [meteo], [logging], [daemon], [coverage],
// [registration], [m3c2], [pbm3c2], [primitives], [vectors], [keypoints], [campaign],
// [modbus], [http], [alarm], [notify], [retention].
const std::vector<ConfigKey>& config_keys();

// The sections of config_keys(), in that order.
std::vector<std::string> config_sections();

// The Markdown reference table of one section (header, separator, one row per key: key,
// type, default, range, meaning), as docs/configuration.md shows it.
std::string reference_table(const std::string& section);

}  // namespace tlsmon
