#pragma once
// What a notification says (docs/notifications.md): one JSON document per alarm event or
// daily summary, which a webhook receives as its body and an MQTT subscriber as its
// payload, and from which an e-mail's subject and text are written.
#include <nlohmann/json.hpp>
#include <string>

#include "core/utc_time.hpp"
#include "storage/notification_store.hpp"

namespace tlsmon {

using Json = nlohmann::ordered_json;

inline constexpr const char* kNotificationSchema = "tlsmon-notification/1";

// {"schema", "type": "alarm", "station", "event_id", "time", "rule", "zone", "quantity",
//  "event", "level", "value", "unit", "epoch", "actor", "message", "dashboard"}.
Json alarm_notification(const RoutableAlarmEvent& e, const std::string& station,
                        const std::string& dashboard_url);
// {"schema", "type": "summary", "station", "day", "time", "epochs_24h": {status: count},
//  "watched": [{"rule", "zone", "quantity"}] (the structure's alarm rules),
//  "site": the dashboard's /api/v1/site document without the sparklines, "dashboard"}.
Json summary_notification(const std::string& station, const std::string& day, UtcSeconds now,
                          Json epochs_24h, Json watched, Json site,
                          const std::string& dashboard_url);

// {"schema", "type": "test", "station", "channel", "time", "message"}: `tlsmon notify test`.
Json test_notification(const std::string& station, const std::string& channel, UtcSeconds now);

// "[tlsmon bridge-7] ALARM raise: P3 top m3c2_median_m = 25.10 mm" or
// "[tlsmon bridge-7] daily summary 2026-11-29: 96 epochs, 1 active alarm".
std::string notification_subject(const Json& n);
// The e-mail's text: one "Name: value" line per field; the summary's active alarms, and the
// latest values of the quantities its rules watch (every quantity when no rule does).
std::string notification_text(const Json& n);

// A zone value for people: displacements (quantities in metres) in mm to 0.01, heights in m,
// others as they are.
std::string value_text(double value, const std::string& quantity);

}  // namespace tlsmon
