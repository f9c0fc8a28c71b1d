#pragma once
// The campaign epochs on the dashboard (docs/http.md; docs/campaigns.md): the list over a
// window, one campaign with its segments, and the points it kept, thinned for drawing.
#include <cstddef>
#include <optional>
#include <string>

#include "daemon/http/dashboard_api.hpp"
#include "storage/campaign_store.hpp"

namespace tlsmon {

// `/api/v1/campaigns?from&to`: acquired in the window, oldest first.
Json campaigns_json(const EpochDatabase& db, const TimeRange& range);
// `/api/v1/campaigns/N`: the campaign and its segments; none when there is no campaign N.
std::optional<Json> campaign_json(const EpochDatabase& db, CampaignId id);
// `/api/v1/campaigns/N/points?max=M`: every k-th point it kept, at most `most`, as columns
// (offsets from `origin` in m, rounded to 0.1 mm). None, with the reason in `why`, when there
// is no campaign N or it kept no points.
std::optional<Json> campaign_points_json(const EpochDatabase& db, CampaignId id, std::size_t most,
                                         std::string& why);

}  // namespace tlsmon
