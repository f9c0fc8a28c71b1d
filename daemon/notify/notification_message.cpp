#include "daemon/notify/notification_message.hpp"

#include <cstdio>

namespace tlsmon {

namespace {

bool in_metres(const std::string& quantity) {
    return quantity.size() > 2 && quantity.compare(quantity.size() - 2, 2, "_m") == 0;
}

Json link(const std::string& dashboard_url, const std::string& path) {
    if (dashboard_url.empty()) return nullptr;
    std::string base = dashboard_url;
    while (!base.empty() && base.back() == '/') base.pop_back();
    return base + path;
}

std::string upper(std::string s) {
    for (char& c : s) c = static_cast<char>(c >= 'a' && c <= 'z' ? c - 'a' + 'A' : c);
    return s;
}

std::string text_of(const Json& v) {
    if (v.is_null()) return "";
    if (v.is_string()) return v.get<std::string>();
    return v.dump();
}

}  // namespace

std::string value_text(double value, const std::string& quantity) {
    char buf[64];
    if (quantity.ends_with("height_m")) {
        std::snprintf(buf, sizeof buf, "%.3f m", value);
    } else if (in_metres(quantity)) {
        std::snprintf(buf, sizeof buf, "%.2f mm", value * 1000.0);
    } else {
        std::snprintf(buf, sizeof buf, "%.6g", value);
    }
    return buf;
}

Json alarm_notification(const RoutableAlarmEvent& e, const std::string& station,
                        const std::string& dashboard_url) {
    const AlarmEvent& a = e.event;
    return Json{{"schema", kNotificationSchema},
                {"type", "alarm"},
                {"station", station},
                {"event_id", e.id},
                {"time", format_utc(a.time)},
                {"rule", a.rule},
                {"zone", e.zone},
                {"quantity", e.quantity},
                {"event", a.kind},
                {"level", e.alarm_level},
                {"value", a.value ? Json(*a.value) : Json(nullptr)},
                {"unit", in_metres(e.quantity) ? "m" : ""},
                {"epoch", a.epoch ? Json(*a.epoch) : Json(nullptr)},
                {"actor", a.actor},
                {"message", a.message},
                {"dashboard", link(dashboard_url, "/alarms")}};
}

Json summary_notification(const std::string& station, const std::string& day, UtcSeconds now,
                          Json epochs_24h, Json watched, Json site,
                          const std::string& dashboard_url) {
    for (auto& zone : site["zones"]) {
        for (auto& q : zone["quantities"]) q.erase("spark");
    }
    return Json{{"schema", kNotificationSchema},
                {"type", "summary"},
                {"station", station},
                {"day", day},
                {"time", format_utc(now)},
                {"epochs_24h", std::move(epochs_24h)},
                {"watched", std::move(watched)},
                {"site", std::move(site)},
                {"dashboard", link(dashboard_url, "/")}};
}

Json test_notification(const std::string& station, const std::string& channel, UtcSeconds now) {
    return Json{{"schema", kNotificationSchema},
                {"type", "test"},
                {"station", station},
                {"channel", channel},
                {"time", format_utc(now)},
                {"message", "a test of the channel '" + channel + "', sent by tlsmon notify test"}};
}

std::string notification_subject(const Json& n) {
    const std::string head = "[tlsmon " + n.at("station").get<std::string>() + "] ";
    if (n.at("type") == "test") return head + "test notification";
    if (n.at("type") == "summary") {
        int epochs = 0;
        for (const auto& [status, count] : n.at("epochs_24h").items()) epochs += count.get<int>();
        const int alarms = n.at("site").value("alarms_active", 0);
        return head + "daily summary " + n.at("day").get<std::string>() + ": " +
               std::to_string(epochs) + " epoch" + (epochs == 1 ? "" : "s") + ", " +
               std::to_string(alarms) + " active alarm" + (alarms == 1 ? "" : "s");
    }
    const std::string level = n.at("level").get<std::string>();
    std::string s = head + upper(level.empty() ? "notice" : level) + " " +
                    n.at("event").get<std::string>() + ": " + n.at("rule").get<std::string>();
    const std::string quantity = n.at("quantity");
    if (!n.at("value").is_null() && n.at("zone") != "(system)")
        s += " " + quantity + " = " + value_text(n.at("value").get<double>(), quantity);
    return s;
}

std::string notification_text(const Json& n) {
    std::string out;
    const auto line = [&](const std::string& name, const std::string& value) {
        if (!value.empty()) out += name + ": " + value + "\n";
    };
    line("Station", text_of(n.at("station")));
    if (n.at("type") == "test") {
        line("Channel", text_of(n.at("channel")));
        line("Time", text_of(n.at("time")));
        line("Message", text_of(n.at("message")));
        return out;
    }
    if (n.at("type") == "alarm") {
        line("Rule", text_of(n.at("rule")));
        line("Zone", text_of(n.at("zone")));
        line("Quantity", text_of(n.at("quantity")));
        line("Event", text_of(n.at("event")));
        line("Level", text_of(n.at("level")));
        if (!n.at("value").is_null())
            line("Value", value_text(n.at("value").get<double>(), n.at("quantity")));
        line("Epoch", text_of(n.at("epoch")));
        line("Time", text_of(n.at("time")));
        line("By", text_of(n.at("actor")));
        line("Message", text_of(n.at("message")));
        line("Dashboard", text_of(n.at("dashboard")));
        return out;
    }
    line("Day", text_of(n.at("day")));
    std::string epochs;
    for (const auto& [status, count] : n.at("epochs_24h").items())
        epochs += (epochs.empty() ? "" : ", ") + std::to_string(count.get<int>()) + " " + status;
    line("Epochs in the last 24 h", epochs.empty() ? "none" : epochs);
    const Json& site = n.at("site");
    if (site.contains("disk_free_share") && site.at("disk_free_share").is_number()) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.1f %%", 100.0 * site.at("disk_free_share").get<double>());
        line("Disk free", buf);
    }
    out += "\nActive alarms:\n";
    if (site.at("alarms").empty()) out += "  none\n";
    for (const auto& a : site.at("alarms")) {
        out += "  " + text_of(a.at("rule")) + ": " + text_of(a.at("state")) + " " +
               text_of(a.at("level")) + " since " + text_of(a.at("since")) + "\n";
    }
    const Json& watched = n.at("watched");
    const auto shown = [&](const Json& zone, const std::string& quantity) {
        if (watched.empty()) return true;
        for (const auto& w : watched)
            if (w.at("zone") == zone.at("name") && w.at("quantity") == quantity) return true;
        return false;
    };
    out += watched.empty() ? "\nLatest values:\n"
                           : "\nLatest values of the quantities the alarm rules watch:\n";
    for (const auto& zone : site.at("zones")) {
        for (const auto& q : zone.at("quantities")) {
            if (!shown(zone, q.at("quantity"))) continue;
            const Json& p = q.at("latest");
            const std::string quantity = q.at("quantity");
            std::string v = value_text(p.at("value").get<double>(), quantity);
            if (p.at("lod95").is_number())
                v += " ± " + value_text(p.at("lod95").get<double>(), quantity) + " (LoD95)";
            const std::string at = p.value("acquired", std::string());
            out += "  " + text_of(zone.at("name")) + " " + quantity + ": " + v +
                   (at.empty() ? "" : " at " + at) + "\n";
        }
    }
    if (!n.at("dashboard").is_null()) out += "\nDashboard: " + text_of(n.at("dashboard")) + "\n";
    return out;
}

}  // namespace tlsmon
