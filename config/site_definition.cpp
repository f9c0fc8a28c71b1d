#include "config/site_definition.hpp"

#include <nlohmann/json.hpp>

#include "pipeline/alarm_evaluation.hpp"

namespace tlsmon {

std::string zone_json(const ZoneConfig& z) {
    nlohmann::json j{{"type", z.polygon.empty() ? "box" : "prism"}, {"min", z.min}, {"max", z.max}};
    if (!z.polygon.empty()) j["polygon"] = z.polygon;
    if (!z.band_of.empty()) j["band_of"] = z.band_of;
    if (z.normal) j["normal"] = *z.normal;
    if (z.no_change) j["no_change"] = true;
    return j.dump();
}

void store_zones_and_rules(EpochDatabase& db, const Config& config) {
    for (const auto& z : config.zones) db.site().upsert_zone(z.name, zone_json(z));
    store_alarm_rules(db, config.alarm.rules);
}

std::optional<CampaignFeed> campaign_feed(const Config& config) {
    if (!config.campaign.zone_series) return std::nullopt;
    CampaignFeed feed;
    for (const auto& z : config.zones) feed.zones.push_back(zone_shape(z));
    feed.min_points = config.campaign.zone_min_points;
    feed.rules = config.alarm.rules;
    return feed;
}

}  // namespace tlsmon
