#pragma once
// Files of an [[instrument]] in the ingest folder (its `pattern`): campaign epochs, never
// station epochs (docs/campaigns.md, "Campaign epochs"). Each is compared with the reference
// epoch after the station's backlog (the reference may come in the same batch), stored with
// its segments, and archived as the station's scans are; a file that cannot be compared goes
// to quarantine with the reason. The same bytes again are known by their sha256.
#include <filesystem>
#include <string>
#include <vector>

#include "daemon/ingest.hpp"
#include "pipeline/campaign_epoch.hpp"

namespace tlsmon {

class CampaignIngest {
  public:
    void take(const std::filesystem::path& file, const InstrumentConfig& instrument);
    // Every file taken, unless there is no reference epoch yet (they wait) or the database
    // refuses (they wait for the retry; returns false).
    bool process(IngestContext& ctx);
    bool waiting() const { return !queue_.empty(); }

  private:
    struct Queued {
        std::filesystem::path file;
        std::string instrument;
    };
    void process_one(IngestContext& ctx, const Queued& queued, CampaignReferences& references);
    std::vector<Queued> queue_;
    bool told_waiting_ = false;  // the wait for a reference epoch was logged
};

}  // namespace tlsmon
