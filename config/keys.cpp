#include "config/keys.hpp"

namespace tlsmon {

namespace {

// One section's keys, declared beside its struct, as keys of Config under `section`.
template <class S>
void collect(std::vector<ConfigKey>& out, const std::string& section, S Config::*member,
             const std::vector<SectionKey<S>>& keys) {
    for (const auto& k : keys) {
        out.push_back(
            ConfigKey{{k.name, k.type, k.range, k.help,
                       [member, read = k.read](TomlFields& t, Config& c) { read(t, c.*member); },
                       [member, value = k.value](const Config& c) { return value(c.*member); }},
                      section});
    }
}

std::vector<ConfigKey> collect_keys() {
    std::vector<ConfigKey> keys;
    collect(keys, "station", &Config::station, station_keys());
    collect(keys, "paths", &Config::paths, paths_keys());
    collect(keys, "ingest", &Config::ingest, ingest_keys());
    collect(keys, "meteo", &Config::meteo, meteo_keys());
    collect(keys, "logging", &Config::logging, logging_keys());
    collect(keys, "daemon", &Config::daemon, daemon_keys());
    collect(keys, "coverage", &Config::coverage, coverage_keys());
    collect(keys, "registration", &Config::registration, registration_keys());
    collect(keys, "registration", &Config::icp, icp_keys());
    collect(keys, "registration", &Config::planes, plane_keys());
    collect(keys, "registration", &Config::stable_areas, stable_area_keys());
    collect(keys, "m3c2", &Config::m3c2, m3c2_keys());
    collect(keys, "pbm3c2", &Config::pbm3c2, pbm3c2_keys());
    collect(keys, "primitives", &Config::primitives, primitives_keys());
    collect(keys, "vectors", &Config::vectors, vector_keys());
    collect(keys, "keypoints", &Config::keypoints, keypoint_keys());
    collect(keys, "campaign", &Config::campaign, campaign_keys());
    collect(keys, "thermal", &Config::thermal, thermal_keys());
    collect(keys, "modbus", &Config::modbus, modbus_keys());
    collect(keys, "http", &Config::http, http_keys());
    collect(keys, "alarm", &Config::alarm, alarm_keys());
    collect(keys, "notify", &Config::notify, notify_keys());
    collect(keys, "retention", &Config::retention, retention_keys());
    collect(keys, "archive", &Config::archive, archive_keys());
    collect(keys, "central", &Config::central, central_keys());
    return keys;
}

}  // namespace

const std::vector<ConfigKey>& config_keys() {
    static const std::vector<ConfigKey> keys = collect_keys();
    return keys;
}

std::vector<std::string> config_sections() {
    std::vector<std::string> out;
    for (const auto& k : config_keys()) {
        if (out.empty() || out.back() != k.section) out.push_back(k.section);
    }
    return out;
}

std::string reference_table(const std::string& section) {
    const Config defaults;
    std::string out = "| key | type | default | range | meaning |\n|---|---|---|---|---|\n";
    for (const auto& k : config_keys()) {
        if (k.section != section) continue;
        out += "| `" + k.name + "` | " + k.type + " | `" + k.value(defaults) + "` | " + k.range +
               " | " + k.help + " |\n";
    }
    return out;
}

}  // namespace tlsmon
