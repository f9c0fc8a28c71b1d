#include "report/data.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>

namespace tlsmon::report {

std::optional<ZoneBox> parse_zone_box(const std::string& definition_json) {
    const nlohmann::json j = nlohmann::json::parse(definition_json, nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("min") || !j.contains("max")) {
        return std::nullopt;
    }
    if (j.contains("type") && j["type"] != "box") return std::nullopt;
    const auto v3 = [](const nlohmann::json& a) -> std::optional<Eigen::Vector3d> {
        if (!a.is_array() || a.size() != 3) return std::nullopt;
        for (const auto& x : a) {
            if (!x.is_number()) return std::nullopt;
        }
        return Eigen::Vector3d(a[0].get<double>(), a[1].get<double>(), a[2].get<double>());
    };
    const auto lo = v3(j["min"]), hi = v3(j["max"]);
    if (!lo || !hi) return std::nullopt;
    return ZoneBox{*lo, *hi};
}

bool parse_zone_no_change(const std::string& definition_json) {
    const nlohmann::json j = nlohmann::json::parse(definition_json, nullptr, false);
    if (!j.is_object() || !j.contains("no_change")) return false;
    const auto& v = j["no_change"];
    return v.is_boolean() && v.get<bool>();
}

RunData read_run(const EpochDatabase& db, const TimeRange& window, ZoneSeries series) {
    RunData r;
    r.database = db.path();
    r.reference = db.epochs().reference();
    std::vector<Epoch> epochs = db.series().epochs_in_range(window);
    if (r.reference && std::none_of(epochs.begin(), epochs.end(),
                                    [&](const Epoch& e) { return e.id == *r.reference; })) {
        if (auto e = db.epochs().find(*r.reference)) epochs.insert(epochs.begin(), *e);
    }
    auto registrations = db.registrations().in_range(window);
    for (const Epoch& e : epochs) {
        RunEpoch re;
        re.epoch = e;
        if (e.acquired >= window.lower() && e.acquired <= window.upper()) {
            if (auto it = registrations.registration.find(e.id);
                it != registrations.registration.end())
                re.registration = std::move(it->second);
            re.targets = std::move(registrations.targets[e.id]);
            re.zone_sigmas = std::move(registrations.zone_sigmas[e.id]);
        } else {  // the reference epoch, outside the window
            re.registration = db.registrations().of_epoch(e.id);
            re.targets = db.registrations().targets_of_epoch(e.id);
            re.zone_sigmas = db.registrations().zone_sigmas_of_epoch(e.id);
        }
        r.epochs.push_back(std::move(re));
    }
    const auto definitions = db.site().zones();
    for (const auto& [id, name] : db.site().zone_ids()) {
        RunZone z;
        z.id = id;
        z.name = name;
        for (const auto& [n, definition] : definitions) {
            if (n != name) continue;
            z.box = parse_zone_box(definition);
            z.no_change = parse_zone_no_change(definition);
        }
        if (series == ZoneSeries::all || z.no_change) {
            for (const std::string& q : db.series().quantities(name))
                z.series[q] = db.series().points(name, q, window);
        }
        if (!z.box && z.series.empty()) continue;  // e.g. the system alarms' own zone
        r.zones.push_back(std::move(z));
    }
    for (const AlarmRule& rule : db.alarms().rules()) {
        if (rule.name.rfind("system.", 0) != 0) r.rules.push_back(rule);
    }
    for (const AlarmEvent& e : db.alarms().events(window.from)) {
        if (e.time > window.upper()) break;  // by time
        if (e.rule.rfind("system.", 0) != 0) r.alarm_events.push_back(e);
    }
    r.campaigns = db.campaigns().in_range(window);
    return r;
}

RunData read_run(const std::filesystem::path& database, const TimeRange& window,
                 ZoneSeries series) {
    const EpochDatabase db = EpochDatabase::open(database, EpochDatabase::Mode::read_only);
    return read_run(db, window, series);
}

}  // namespace tlsmon::report
