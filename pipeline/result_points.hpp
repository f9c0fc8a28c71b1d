#pragma once
// The per-point results tlsmon stores, as points with named attributes (formats/las_points.hpp):
// what `tlsmon export` writes as LAS 1.4 or CSV. One builder per kind of stored map, each
// putting the map's positions (from the stage's reference product, or stored beside the
// values) with its arrays; docs/export.md lists every attribute.
#include <string_view>

#include "formats/las_points.hpp"
#include "storage/campaign_store.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

// What an epoch's per-point results can be exported from.
enum class ResultMap { m3c2, pbm3c2, vectors };
std::string_view to_string(ResultMap m);
ResultMap parse_result_map(std::string_view name);  // Error listing the names

// One epoch's map: M3C2 at its core points, PB-M3C2 at its patches' centres, the 3-D vectors
// at their areas' centres (measured areas only). Error naming the epoch when it has none.
LasPoints epoch_result_points(const EpochDatabase& db, EpochId epoch, ResultMap map);

// One campaign's kept points ([campaign] store_spacing) with their segment and C2C vector.
LasPoints campaign_result_points(const EpochDatabase& db, CampaignId campaign);

}  // namespace tlsmon
