#pragma once
// The campaign epochs and their segments as tables: `tlsmon query campaigns`,
// `tlsmon query campaign-segments` and the segments.csv of `tlsmon campaign compare` print
// the same columns (cli/query_campaigns.cpp).
#include <vector>

#include "cli/query_output.hpp"
#include "storage/campaign_store.hpp"

namespace tlsmon {

Table campaigns_table(const std::vector<CampaignRow>& campaigns);
Table campaign_segments_table(const std::vector<CampaignSegmentRow>& segments);

}  // namespace tlsmon
