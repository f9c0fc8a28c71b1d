#pragma once
// A campaign cloud becomes a stored campaign epoch (docs/campaigns.md, "Campaign epochs"):
// identified by the sha256 of its bytes, compared with the station's reference epoch segment
// by segment (campaign_comparison.hpp), and stored with one row per segment in one
// transaction — apart from the station's epochs: in its zone series and alarms only under the
// campaigns' own quantities, when configured (CampaignFeed).
// `tlsmon campaign add` and the daemon's ingest of an [[instrument]]'s files both come here.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "alarms/alarm_rule.hpp"
#include "algorithms/zones/zone_shape.hpp"
#include "pipeline/campaign_comparison.hpp"
#include "pipeline/sha256.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

struct CampaignSource {
    std::filesystem::path file;
    std::string instrument;  // its [[instrument]] name and kind (tls, pls, mls)
    std::string kind;
    UtcSeconds acquired = 0;
    // Where the file will be kept (the archive); empty: where it is.
    std::filesystem::path stored_path;
};

struct StoredCampaign {
    bool known = false;  // the same bytes were stored before: not compared again
    CampaignRow row;
    std::optional<CampaignComparison> comparison;  // when compared now
};

// The reference epoch's scan prepared for campaigns (its local planes, segments and planes:
// 20 s for 10 M points), kept for the campaigns that follow while the reference epoch and the
// parameters stay the same. The daemon keeps one for a batch of campaigns, then lets it go
// (it holds the reference's points).
class CampaignReferences {
  public:
    // Throws Error when there is no reference epoch yet or its scan is gone.
    const CampaignReference& get(const EpochDatabase& db, const CampaignParameters& parameters,
                                 EpochId& reference_epoch);
    int prepared() const { return prepared_; }  // how many times it was prepared

  private:
    EpochId epoch_ = 0;
    std::string parameters_;
    std::vector<Eigen::Vector3d> points_;
    std::unique_ptr<CampaignReference> reference_;
    int prepared_ = 0;
};

// What a campaign adds to the zone series ([campaign] zone_series; docs/campaigns.md, "Zone
// series"): a value for each zone with a design normal that `min_points` of its stored points
// fall in, and the alarm rules that watch campaign quantities.
struct CampaignFeed {
    std::vector<ZoneShape> zones;
    int min_points = 30;
    std::vector<AlarmRuleSpec> rules;
};

// What a stored campaign keeps of a comparison besides its rows: the registered points, thinned
// to `spacing` (0: every point), with their segment and C2C vector.
CampaignPoints stored_points(const CampaignComparison& comparison, double spacing,
                             unsigned threads = 0);

// The file's bytes (read_file_hashed) with their sha256: a campaign already stored is returned
// as it is. Otherwise the cloud is compared with the reference epoch's scan (from the archive
// when it was moved there; prepared by `references`) and stored with its points thinned to
// `store_spacing`, with its zone rows and the alarm rows they cause when `feed` is given.
// Throws Error when there is no reference epoch yet, its scan is gone, the
// file is no scan or the comparison fails (the clouds do not overlap); StorageError when the
// database refuses.
StoredCampaign add_campaign(EpochDatabase& db, const CampaignSource& source,
                            const HashedBytes& bytes, const CampaignParameters& parameters,
                            double store_spacing, CampaignReferences& references,
                            const CampaignFeed* feed = nullptr);

// The segments as stored and as segments.csv has them.
std::vector<CampaignSegmentRow> segment_rows(const CampaignComparison& comparison);
// The campaign's own row (its id not yet known).
CampaignRow campaign_row(const CampaignComparison& comparison, const CampaignParameters& p);

}  // namespace tlsmon
