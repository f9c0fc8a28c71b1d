#pragma once
// The [notify] section of the configuration and its [[notify.channel]] and [[notify.route]]
// tables (docs/notifications.md): where alarm events and the daily summary are sent.
//
//   [notify]
//   enabled = true
//   quiet_hours = "22:00-06:00"        # local time; warnings and alerts wait until 06:00
//   daily_summary = "07:00"
//   summary_channels = ["office"]
//
//   [[notify.channel]]
//   name = "office"
//   kind = "email"                     # email | webhook | mqtt
//   url = "smtp://mail.example.org:587"
//   from = "tlsmon@example.org"
//   to = ["bridge-team@example.org"]
//   username = "tlsmon"
//   password_file = "/etc/tlsmon/smtp-password"
//
//   [[notify.route]]
//   rules = ["P3*", "system.*"]
//   min_level = "alert"
//   channels = ["office"]
#include <filesystem>
#include <string>
#include <vector>

#include "alarms/notification_routing.hpp"
#include "core/config_key.hpp"

namespace tlsmon {

enum class ChannelKind { email, webhook, mqtt };
// E-mail over smtp://: STARTTLS required (the default), used when offered, or never.
// smtps:// is TLS from the first byte whatever this says.
enum class StartTls { required, optional, off };

struct NotifyChannel {
    std::string name;
    ChannelKind kind = ChannelKind::webhook;
    std::string url;  // smtp(s)://host:port, http(s)://host/path, mqtt(s)://host:port
    // email
    std::string from;
    std::vector<std::string> to;
    StartTls starttls = StartTls::required;
    // email and mqtt: the login; the password is read from a file, never from this one
    std::string username;
    std::filesystem::path password_file;
    // webhook: "Authorization: Bearer <token>", the token read from a file
    std::filesystem::path token_file;
    // mqtt
    std::string topic;  // prefix; "" = "tlsmon/<station>"
    int qos = 1;
    bool retain = false;
    std::filesystem::path ca_file;  // TLS trust anchors; "" = the system's
    double timeout = 20.0;          // seconds for one attempt
};

struct NotifyConfig {
    bool enabled = false;
    double dedup_window = 3600.0;  // a repeat of rule/kind/level inside it is not sent again
    std::string quiet_hours;       // "22:00-06:00" local time; "" = none
    AlarmLevel quiet_min_level = AlarmLevel::alarm;  // at or above: sent during quiet hours
    std::string daily_summary;                       // "07:00" local time; "" = none
    std::vector<std::string> summary_channels;
    double retry_initial = 30.0;     // back-off after a failed send, doubling ...
    double retry_max = 3600.0;       // ... up to this
    double give_up_after = 86400.0;  // a notification due longer ago than this is given up
    std::string dashboard_url;       // linked from each message; "" = none
    std::vector<NotifyChannel> channels;
    std::vector<NotifyRoute> routes;
};

// The keys of [notify] (core/config_key.hpp); the tables are read by read_notify_tables.
std::vector<SectionKey<NotifyConfig>> notify_keys();

// Reads every [[notify.channel]] and [[notify.route]] of the [notify] table and checks the
// section as a whole (names unique, routes naming channels that exist, times well formed);
// relative paths resolve against `base`. Each mistake is a ConfigError naming the key.
void read_notify_tables(TomlFields& notify, NotifyConfig& c, const std::filesystem::path& base);

// The channel and route tables as lines of the effective configuration (no secrets: the
// password and token files are named, never read here).
std::vector<std::string> describe_notify_tables(const NotifyConfig& c);

std::string_view to_string(ChannelKind k);

}  // namespace tlsmon
