#pragma once
// What the site's configuration puts into its database and its campaigns: the zones and the
// alarm rules (stored by the daemon at start and on reload, and by `tlsmon campaign add`),
// and what [campaign] zone_series feeds into the zone series.
#include <optional>
#include <string>

#include "config/config.hpp"
#include "pipeline/campaign_epoch.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

// The zone's definition as stored in zones.definition.
std::string zone_json(const ZoneConfig& zone);
// Every configured zone and alarm rule, inserted or updated (their states stay as stored).
void store_zones_and_rules(EpochDatabase& db, const Config& config);
// The zones with their design normals and the alarm rules; none when [campaign] zone_series
// is off.
std::optional<CampaignFeed> campaign_feed(const Config& config);

}  // namespace tlsmon
