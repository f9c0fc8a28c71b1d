#include "daemon/system_alarm_watch.hpp"

#include <sys/statvfs.h>

#include <algorithm>
#include <map>

#include "pipeline/alarm_rows.hpp"

namespace tlsmon {

void store_system_alarm_rules(EpochDatabase& db) {
    // A rule names a zone; the system rules' zone is this one, which no analysis aggregates
    // into. Stored after the configured zones, so their ids (and Modbus slots) come first.
    db.site().upsert_zone(kSystemZone, "{\"system\": true}");
    for (SystemAlarm a : kSystemAlarms) {
        const std::string level(to_string(system_alarm_level(a)));
        db.alarms().upsert_rule(AlarmRule{0, std::string(rule_name(a)), kSystemZone, "system",
                                          "{\"system\":true,\"level\":\"" + level + "\"}", true});
    }
}

int observe_system_alarms(EpochDatabase& db, const SystemAlarmConfig& config,
                          const SystemObservation& seen) {
    int transitions = 0;
    db.alarms().update([&](const std::vector<AlarmState>& states) {
        std::map<std::string, AlarmState> rows;
        for (const auto& s : states) rows.emplace(s.rule, s);
        std::array<AlarmRuleStatus, kSystemAlarms.size()> status{};
        SystemConditions previous{};
        for (std::size_t i = 0; i < kSystemAlarms.size(); ++i) {
            const auto row = rows.find(std::string(rule_name(kSystemAlarms[i])));
            if (row != rows.end()) status[i] = rule_status(row->second);
            previous[i] = status[i].machine.process != AlarmLevel::none;
        }
        const auto now_active = system_conditions(config, seen, previous);
        AlarmRows out;
        transitions = 0;
        for (std::size_t i = 0; i < kSystemAlarms.size(); ++i) {
            const AlarmLevel level =
                now_active[i] ? system_alarm_level(kSystemAlarms[i]) : AlarmLevel::none;
            const AlarmStep step = on_process(status[i].machine, level, false, seen.now);
            if (step.events.empty() && step.state.process == status[i].machine.process) continue;
            status[i].machine = step.state;
            const std::string name(rule_name(kSystemAlarms[i]));
            out.states.push_back(state_row(name, status[i], std::nullopt, std::nullopt));
            for (const auto& t : step.events) {
                out.events.push_back(event_row(name, t, std::nullopt, std::nullopt));
            }
            transitions += static_cast<int>(step.events.size());
        }
        return out;
    });
    return transitions;
}

std::optional<UtcSeconds> newest_epoch_acquired(const EpochDatabase& db) {
    const StatusSummary s = db.series().status_summary();
    std::optional<UtcSeconds> newest;
    auto take = [&](std::optional<UtcSeconds> t) {
        if (t && (!newest || *t > *newest)) newest = t;
    };
    if (s.last_done) take(s.last_done->acquired);
    if (s.last_failure) take(s.last_failure->acquired);
    for (const auto& e : db.epochs().pending()) take(e.acquired);
    return newest;
}

std::optional<double> disk_free_share(const std::filesystem::path& path) {
    struct statvfs v {};
    if (::statvfs(path.c_str(), &v) != 0 || v.f_blocks == 0) return std::nullopt;
    return static_cast<double>(v.f_bavail) / static_cast<double>(v.f_blocks);
}

}  // namespace tlsmon
