// `tlsmon alarms [history] | ack|shelve|unshelve|out-of-service|in-service RULE`: the alarms
// standing now and their history (read-only, like `tlsmon query`), and the operator's actions,
// written through the database in one immediate transaction each (daemon/alarm_actions.cpp): safe
// while the daemon runs, which waits for the write through its busy timeout and sees it at its next
// epoch.
#include <pwd.h>
#include <unistd.h>

#include <cstdlib>
#include <iostream>

#include "cli/commands.hpp"
#include "cli/query_output.hpp"
#include "config/config.hpp"
#include "core/utc_time.hpp"
#include "daemon/alarm_actions.hpp"
#include "daemon/alarm_shelving.hpp"

namespace tlsmon {

namespace {

Cell time_cell(const std::optional<std::int64_t>& t) {
    return t ? Cell(format_utc(*t)) : Cell();
}

}  // namespace

int run_alarms(const ReadOptions& options) {
    return run_reporting_errors("alarms", [&] {
        const auto db = open_for_reading(options);
        Table t{{"rule", "state", "level", "since", "value", "epoch", "shelved_until"}, {}};
        for (const auto& a : db.alarms().states()) {
            if (a.state == "normal") continue;
            t.rows.push_back({a.rule, a.state, a.level, format_utc(a.since), optional_cell(a.value),
                              optional_cell(a.epoch), time_cell(a.shelved_until)});
        }
        print(std::cout, t, options.format);
    });
}

int run_alarm_history(const AlarmHistoryOptions& o) {
    return run_reporting_errors("alarms history", [&] {
        const auto range = time_range(o.read);
        const auto db = open_for_reading(o.read);
        Table t{
            {"time", "time_base", "rule", "kind", "level", "value", "epoch", "actor", "message"},
            {}};
        for (const auto& e : db.alarms().events(range.from, o.rule)) {
            if (range.to && e.time > *range.to) continue;
            t.rows.push_back({format_utc(e.time),
                              std::string(alarm_event_time_base(e.rule, e.actor)), e.rule, e.kind,
                              e.level, optional_cell(e.value), optional_cell(e.epoch), e.actor,
                              e.message});
        }
        print(std::cout, t, o.read.format);
    });
}

// The Unix user who runs the command (and, under sudo, who called sudo), for the history.
std::string command_user() {
    const passwd* pw = ::getpwuid(::getuid());
    std::string who = "user " + (pw ? std::string(pw->pw_name) : std::to_string(::getuid()));
    if (const char* sudo = std::getenv("SUDO_USER")) who += " (sudo by " + std::string(sudo) + ")";
    return who;
}

int run_alarm_action(const AlarmActionOptions& o) {
    return run_reporting_errors("alarms " + o.action, [&] {
        auto db = open_for_writing(o.db, o.config);
        const UtcSeconds now = now_utc();
        const std::string who = command_user();
        int changed = 0;
        if (o.action == "ack") {
            changed = acknowledge_alarm(db, o.rule, AlarmActor::cli, now, who);
        } else if (o.action == "shelve") {
            if (o.until.empty()) throw Error("shelve needs --until TIME (ISO-8601 UTC)");
            changed = shelve_alarm(db, o.rule, parse_utc(o.until), AlarmActor::cli, now, who);
        } else if (o.action == "unshelve") {
            changed = unshelve_alarm(db, o.rule, AlarmActor::cli, now, who);
        } else if (o.action == "out-of-service") {
            changed = remove_alarm_from_service(db, o.rule, AlarmActor::cli, now, who);
        } else if (o.action == "in-service") {
            changed = return_alarm_to_service(db, o.rule, AlarmActor::cli, now, who);
        } else {
            throw Error("unknown alarm action '" + o.action + "'");
        }
        std::cout << o.action << ": " << changed << (changed == 1 ? " rule" : " rules")
                  << " changed\n";
    });
}

}  // namespace tlsmon
