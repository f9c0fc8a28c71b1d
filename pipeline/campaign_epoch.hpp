#pragma once
// A campaign cloud becomes a stored campaign epoch (docs/campaigns.md, "Campaign epochs"):
// identified by the sha256 of its bytes, compared with the station's reference epoch segment
// by segment (campaign_comparison.hpp), and stored with one row per segment in one
// transaction — apart from the station's epochs, so never in its zone series or its alarms.
// `tlsmon campaign add` and the daemon's ingest of an [[instrument]]'s files both come here.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

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

// The file's bytes (read_file_hashed) with their sha256: a campaign already stored is returned
// as it is. Otherwise the reference epoch's scan is read (from the archive when it was moved
// there) and compared. Throws Error when there is no reference epoch yet, its scan is gone,
// the file is no scan or the comparison fails (the clouds do not overlap); StorageError when
// the database refuses.
StoredCampaign add_campaign(EpochDatabase& db, const CampaignSource& source,
                            const HashedBytes& bytes, const CampaignParameters& parameters);

// The segments as stored and as segments.csv has them.
std::vector<CampaignSegmentRow> segment_rows(const CampaignComparison& comparison);
// The campaign's own row (its id not yet known).
CampaignRow campaign_row(const CampaignComparison& comparison, const CampaignParameters& p);

}  // namespace tlsmon
