#pragma once
// A campaign's values in the station's zones (docs/campaigns.md, "Zone series"): what a
// campaign adds to the zone series when [campaign] zone_series is set.
//
// The stored points are the campaign after each segment's own registration, so the SLAM's
// drift — a rigid error per segment, 5–30 mm — is gone, and with it any rigid motion of the
// whole segment: what remains is the surface's change of shape within its segment (a face
// that bulged, spalled or moved against the rest of its segment). Per zone with a design
// normal n, over the stored points of registered segments inside it:
//   d_i = −c_i·n             (c_i the C2C vector from the point to the reference: d > 0 is
//                             the campaign's surface outward of the reference's, as M3C2)
//   value = median(d_i)
//   σ²    = (√(π/2)·σ_d)²/n  (the median's sampling variance for normal errors,
//                             σ_d = 1.4826·MAD; the stored points are one per voxel, each its
//                             own pulse, so their range noise is independent)
//         + Σ_s w_s² (σ_s² + ν_s²)
//                            (w_s the share of the zone's points in segment s; σ_s its
//                             registration error along n at them, from its translation and
//                             rotation σ about its centroid, first order; ν_s what its rigid
//                             registration leaves of a drift that went on while the segment was
//                             seen: the robust spread of the medians of −c·n in its 1 m cells
//                             facing along n, less their sampling variance — a variance
//                             component, as in a one-way random-effects model)
//   LoD95 = 1.96 σ, significant when |value| > LoD95.
#include <vector>

#include "algorithms/zones/zone_shape.hpp"
#include "storage/campaign_store.hpp"

namespace tlsmon {

// Zone rows (quantity kCampaignC2cMedian; uncertainty is the LoD95) for every zone with a
// design normal that at least `min_points` usable points fall in. `segments` are the stored
// campaign's rows: a point counts only when its segment was registered.
std::vector<ZoneResult> campaign_zone_results(const CampaignPoints& points,
                                              const std::vector<CampaignSegmentRow>& segments,
                                              const std::vector<ZoneShape>& zones, int min_points);

}  // namespace tlsmon
