#pragma once
// [[instrument]]: a scanner other than the station whose clouds arrive now and then as
// campaigns — a personal (pls) or mobile (mls) laser scanner walked or driven along the
// structure, or a second TLS set up for a day (docs/campaigns.md, "Campaign epochs"). Its
// clouds are compared with the station's reference segment by segment and stored as campaign
// epochs, apart from the station's series and its alarms.
#include <string>
#include <vector>

#include "core/toml_fields.hpp"

namespace tlsmon {

enum class InstrumentKind { tls, pls, mls };
const char* kind_name(InstrumentKind kind);

struct InstrumentConfig {
    std::string name;
    InstrumentKind kind = InstrumentKind::pls;
    // m, 1σ of a point along its pulse: bounds the bias of each segment's own cut (the
    // campaign comparison's range_sigma). A SLAM scanner's data sheet gives 1–3 cm.
    double range_sigma = 0.02;
    // A glob (fnmatch(3)) of its files' names in the ingest folder, e.g. "pls_*.ply"; empty:
    // its clouds come only through `tlsmon campaign add`.
    std::string pattern;

    bool matches(const std::string& file_name) const;
};

// The first instrument whose pattern matches the file's name (no folder), or none.
const InstrumentConfig* instrument_for(const std::vector<InstrumentConfig>& instruments,
                                       const std::string& file_name);

// The instrument of that name, or none.
const InstrumentConfig* find_instrument(const std::vector<InstrumentConfig>& instruments,
                                        const std::string& name);
// The same, or an Error naming the configured ones (`file`: the configuration's path).
const InstrumentConfig& instrument_named(const std::vector<InstrumentConfig>& instruments,
                                         const std::string& name, const std::string& file);

// One [[instrument]] table; `taken` holds the names read before it.
InstrumentConfig read_instrument(TomlFields& table, const std::vector<InstrumentConfig>& taken);
// "instrument "pls": kind = pls, range_sigma = 0.02, pattern = "pls_*.ply"".
std::string describe(const InstrumentConfig& instrument);

}  // namespace tlsmon
