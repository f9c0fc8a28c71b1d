#include "config/reload.hpp"

#include <algorithm>
#include <set>

namespace tlsmon {

namespace {

template <class T>
std::vector<std::string> names_of(const std::vector<T>& items) {
    std::vector<std::string> names;
    for (const auto& i : items) names.push_back(i.name);
    return names;
}

// The effective lines of one section ("modbus."), as describe() gives them.
std::vector<std::string> section_lines(const Config& c, const std::string& prefix) {
    std::vector<std::string> lines;
    for (const auto& line : describe(c)) {
        if (line.rfind(prefix, 0) == 0) lines.push_back(line);
    }
    return lines;
}

}  // namespace

ReloadChanges compare_for_reload(const Config& current, const Config& fresh) {
    ReloadChanges out;
    struct Kind {
        const char* what;   // "zone"
        const char* table;  // "[[zone]]"
        std::vector<std::string> before, after;
    };
    const Kind kinds[] = {
        {"zone", "[[zone]]", names_of(current.zones), names_of(fresh.zones)},
        {"alarm rule", "[[alarm.rule]]", names_of(current.alarm.rules),
         names_of(fresh.alarm.rules)},
        {"target", "[[target]]", names_of(current.registration.targets),
         names_of(fresh.registration.targets)},
        {"stable region", "[[stable_region]]", names_of(current.icp.regions),
         names_of(fresh.icp.regions)},
    };
    for (const Kind& k : kinds) {
        if (!k.before.empty() && k.after.empty()) {
            out.refused += (out.refused.empty() ? "" : "; ") + std::string("it has no ") + k.table +
                           " table, and the running configuration has " +
                           std::to_string(k.before.size());
        }
        const std::set<std::string> kept(k.after.begin(), k.after.end());
        for (const auto& name : k.before) {
            if (!kept.count(name)) out.removed.push_back(std::string(k.what) + " '" + name + "'");
        }
    }
    out.http = section_lines(current, "http.") != section_lines(fresh, "http.");
    out.notify = section_lines(current, "notify") != section_lines(fresh, "notify");
    out.modbus = section_lines(current, "modbus.") != section_lines(fresh, "modbus.") ||
                 names_of(current.zones) != names_of(fresh.zones);
    return out;
}

}  // namespace tlsmon
