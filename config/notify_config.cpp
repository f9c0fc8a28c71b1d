#include "config/notify_config.hpp"

#include <array>
#include <regex>
#include <set>

namespace tlsmon {

namespace {

constexpr std::array<Named<ChannelKind>, 3> kChannelKinds{{{ChannelKind::email, "email"},
                                                           {ChannelKind::webhook, "webhook"},
                                                           {ChannelKind::mqtt, "mqtt"}}};
constexpr std::array<Named<StartTls>, 3> kStartTls{
    {{StartTls::required, "required"}, {StartTls::optional, "optional"}, {StartTls::off, "off"}}};
constexpr std::array<Named<AlarmLevel>, 3> kLevels{
    {{AlarmLevel::warning, "warning"}, {AlarmLevel::alert, "alert"}, {AlarmLevel::alarm, "alarm"}}};
const std::set<std::string> kEventKinds{
    "raise", "escalate", "deescalate", "return",         "clear",          "ack",
    "reset", "shelve",   "unshelve",   "shelve_expired", "out_of_service", "in_service"};

// The URL schemes each kind of channel speaks.
bool scheme_fits(ChannelKind kind, const std::string& url) {
    const auto starts = [&](const char* s) { return url.rfind(s, 0) == 0; };
    switch (kind) {
        case ChannelKind::email:
            return starts("smtp://") || starts("smtps://");
        case ChannelKind::webhook:
            return starts("http://") || starts("https://");
        case ChannelKind::mqtt:
            return starts("mqtt://") || starts("mqtts://");
    }
    return false;
}

void resolve_against(std::filesystem::path& p, const std::filesystem::path& base) {
    if (!p.empty() && p.is_relative()) p = base / p;
}

NotifyChannel read_channel(TomlFields& t, const std::set<std::string>& taken,
                           const std::filesystem::path& base) {
    NotifyChannel c;
    for (const char* key : {"name", "kind", "url"}) {
        if (!t.has(key)) t.fail(key, "every [[notify.channel]] needs name, kind and url");
    }
    t.get("name", c.name);
    if (c.name.empty()) t.fail("name", "expected a non-empty channel name");
    if (taken.count(c.name)) t.fail("name", "channel '" + c.name + "' is defined twice");
    t.get_choice("kind", c.kind, kChannelKinds);
    t.get("url", c.url);
    if (!scheme_fits(c.kind, c.url)) {
        const char* schemes = c.kind == ChannelKind::email     ? "smtp:// or smtps://"
                              : c.kind == ChannelKind::webhook ? "http:// or https://"
                                                               : "mqtt:// or mqtts://";
        t.fail("url", "a " + std::string(to_string(c.kind)) + " channel's url begins with " +
                          schemes + " (got '" + c.url + "')");
    }
    if (c.kind == ChannelKind::mqtt) {
        // mqtt(s)://host[:port]: libmosquitto takes the two apart, so they must be there.
        static const std::regex form(R"(mqtts?://[^:/\s]+(:([0-9]{1,5}))?/?)");
        std::smatch m;
        if (!std::regex_match(c.url, m, form) ||
            (m[2].matched && (std::stoi(m[2].str()) < 1 || std::stoi(m[2].str()) > 65535)))
            t.fail("url",
                   "expected mqtt://HOST[:PORT] or mqtts://HOST[:PORT] (got '" + c.url + "')");
    }
    t.get("from", c.from);
    t.get("to", c.to);
    t.get_choice("starttls", c.starttls, kStartTls);
    t.get("username", c.username);
    t.get("password_file", c.password_file);
    t.get("token_file", c.token_file);
    t.get("topic", c.topic);
    t.get("qos", c.qos, 0, 2);
    t.get("retain", c.retain);
    t.get("ca_file", c.ca_file);
    t.get_seconds("timeout", c.timeout, 1, 300);
    if (c.kind == ChannelKind::email) {
        if (c.from.empty()) t.fail("from", "an email channel needs a sender address");
        if (c.to.empty()) t.fail("to", "an email channel needs at least one recipient");
    } else {
        for (const char* key : {"from", "to", "starttls"}) {
            if (t.has(key)) t.fail(key, "only an email channel has this key");
        }
    }
    if (c.kind != ChannelKind::mqtt) {
        for (const char* key : {"topic", "qos", "retain"}) {
            if (t.has(key)) t.fail(key, "only an mqtt channel has this key");
        }
    }
    if (c.kind != ChannelKind::webhook && t.has("token_file"))
        t.fail("token_file", "only a webhook channel has this key");
    if (c.kind == ChannelKind::webhook && (t.has("username") || t.has("password_file")))
        t.fail(t.has("username") ? "username" : "password_file",
               "a webhook authenticates with token_file");
    if (!c.password_file.empty() && c.username.empty())
        t.fail("password_file", "a password needs a username");
    for (auto* p : {&c.password_file, &c.token_file, &c.ca_file}) resolve_against(*p, base);
    t.reject_unknown_keys();
    return c;
}

NotifyRoute read_route(TomlFields& t, const std::set<std::string>& channels) {
    NotifyRoute r;
    if (!t.has("channels")) t.fail("channels", "every [[notify.route]] names its channels");
    t.get("channels", r.channels);
    if (r.channels.empty()) t.fail("channels", "expected at least one channel name");
    for (const auto& c : r.channels) {
        if (!channels.count(c)) t.fail("channels", "no [[notify.channel]] named '" + c + "'");
    }
    t.get("rules", r.rules);
    if (r.rules.empty()) t.fail("rules", "expected at least one rule name or pattern");
    t.get_choice("min_level", r.min_level, kLevels);
    t.get("events", r.events);
    for (const auto& e : r.events) {
        if (!kEventKinds.count(e)) {
            std::string known;
            for (const auto& k : kEventKinds) known += (known.empty() ? "" : ", ") + k;
            t.fail("events", "'" + e + "' is not an alarm event kind (" + known + ")");
        }
    }
    t.reject_unknown_keys();
    return r;
}

std::string quoted_list(const std::vector<std::string>& v) {
    std::string out = "[";
    for (const auto& s : v) out += (out.size() > 1 ? ", " : "") + toml_string(s);
    return out + "]";
}

}  // namespace

std::string_view to_string(ChannelKind k) {
    return name_of(k, kChannelKinds);
}

std::vector<SectionKey<NotifyConfig>> notify_keys() {
    using K = Keys<NotifyConfig>;
    return {
        K::flag(&NotifyConfig::enabled, "enabled",
                "Send alarm events and the daily summary through the [[notify.channel]] tables "
                "their [[notify.route]] tables name (docs/notifications.md)."),
        K::seconds(&NotifyConfig::dedup_window, "dedup_window", 0, 7 * 86400.0, "",
                   "A notification of the same rule, event and level as one sent (or waiting) "
                   "within this long is not sent again; 0: every one."),
        K::text(&NotifyConfig::quiet_hours, "quiet_hours", "`HH:MM-HH:MM` or empty",
                "Daily span of local time (it may pass midnight) in which notifications below "
                "`quiet_min_level` wait until it ends; empty: none."),
        K::choice(&NotifyConfig::quiet_min_level, "quiet_min_level", kLevels,
                  "Level from which a notification is sent during quiet hours as at any time."),
        K::text(&NotifyConfig::daily_summary, "daily_summary", "`HH:MM` or empty",
                "Local time of the daily summary (epochs of the last 24 h, active alarms, each "
                "zone's latest value); empty: none."),
        K::names(&NotifyConfig::summary_channels, "summary_channels", "[[notify.channel]] names",
                 "Where the daily summary goes."),
        K::seconds(&NotifyConfig::retry_initial, "retry_initial", 1, 3600, "",
                   "Wait after a failed send before the next attempt; doubles with each failure."),
        K::seconds(&NotifyConfig::retry_max, "retry_max", 1, 86400, "",
                   "Longest wait between attempts."),
        K::seconds(&NotifyConfig::give_up_after, "give_up_after", 60, 30 * 86400.0, "",
                   "A notification not sent within this long after it was due (at its event, or "
                   "at the end of the quiet hours it waited through) is given up: an error "
                   "event."),
        K::text(&NotifyConfig::dashboard_url, "dashboard_url", "an http(s) URL or empty",
                "The dashboard's address as the recipients reach it, linked from each message; "
                "empty: no link."),
    };
}

void read_notify_tables(TomlFields& notify, NotifyConfig& c, const std::filesystem::path& base) {
    if (!parse_quiet_hours(c.quiet_hours))
        notify.fail("quiet_hours", "expected HH:MM-HH:MM, e.g. \"22:00-06:00\"");
    if (!c.daily_summary.empty() && !parse_time_of_day(c.daily_summary))
        notify.fail("daily_summary", "expected HH:MM, e.g. \"07:00\"");
    if (c.retry_max < c.retry_initial)
        notify.fail("retry_max", "must be at least notify.retry_initial");
    if (!c.dashboard_url.empty() && c.dashboard_url.rfind("http://", 0) != 0 &&
        c.dashboard_url.rfind("https://", 0) != 0)
        notify.fail("dashboard_url", "expected an http:// or https:// URL");
    std::set<std::string> names;
    for (auto& t : notify.array_of_tables("channel")) {
        c.channels.push_back(read_channel(t, names, base));
        names.insert(c.channels.back().name);
    }
    for (auto& t : notify.array_of_tables("route")) c.routes.push_back(read_route(t, names));
    for (const auto& s : c.summary_channels) {
        if (!names.count(s))
            notify.fail("summary_channels", "no [[notify.channel]] named '" + s + "'");
    }
    if (c.enabled && c.routes.empty() && c.summary_channels.empty())
        notify.fail("enabled", "nothing to send: no [[notify.route]] and no summary_channels");
}

std::vector<std::string> describe_notify_tables(const NotifyConfig& c) {
    std::vector<std::string> out;
    for (const auto& ch : c.channels) {
        std::string s = "notify channel " + toml_string(ch.name) +
                        ": kind = " + toml_string(std::string(to_string(ch.kind))) +
                        ", url = " + toml_string(ch.url);
        if (ch.kind == ChannelKind::email)
            s += ", from = " + toml_string(ch.from) + ", to = " + quoted_list(ch.to) +
                 ", starttls = " + toml_string(std::string(name_of(ch.starttls, kStartTls)));
        if (ch.kind == ChannelKind::mqtt)
            s += ", topic = " + toml_string(ch.topic) + ", qos = " + std::to_string(ch.qos) +
                 ", retain = " + (ch.retain ? "true" : "false");
        if (!ch.username.empty()) s += ", username = " + toml_string(ch.username);
        if (!ch.password_file.empty())
            s += ", password_file = " + toml_string(ch.password_file.string());
        if (!ch.token_file.empty()) s += ", token_file = " + toml_string(ch.token_file.string());
        if (!ch.ca_file.empty()) s += ", ca_file = " + toml_string(ch.ca_file.string());
        out.push_back(s + ", timeout = " + toml_number(ch.timeout));
    }
    for (const auto& r : c.routes) {
        out.push_back("notify route: rules = " + quoted_list(r.rules) +
                      ", min_level = " + toml_string(std::string(to_string(r.min_level))) +
                      ", events = " + quoted_list(r.events) +
                      ", channels = " + quoted_list(r.channels));
    }
    return out;
}

}  // namespace tlsmon
