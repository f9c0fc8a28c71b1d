#include "daemon/ingest_campaign.hpp"

#include <spdlog/spdlog.h>

#include "config/site_definition.hpp"
#include "core/error.hpp"
#include "daemon/ingest_files.hpp"
#include "pipeline/campaign_config.hpp"
#include "pipeline/epoch_files.hpp"
#include "storage/storage_error.hpp"

namespace tlsmon {

namespace fs = std::filesystem;

namespace {

std::string summary(const CampaignRow& r) {
    std::string test = !r.segments_differ   ? "not testable"
                       : *r.segments_differ ? "no, they differ"
                                            : "yes";
    const std::string frame =
        r.coarse_planes ? "its frame found on " + std::to_string(*r.coarse_planes) + " planes, "
                        : "";
    return std::to_string(r.points) + " points, " + frame + std::to_string(r.registered_segments) +
           " of " + std::to_string(r.segments) + " segments registered, moved as one: " + test;
}

}  // namespace

void CampaignIngest::take(const fs::path& file, const InstrumentConfig& instrument) {
    for (const auto& q : queue_)
        if (q.file == file) return;
    queue_.push_back({file, instrument.name});
}

bool CampaignIngest::process(IngestContext& ctx) {
    if (queue_.empty()) return true;
    if (!ctx.db.epochs().reference()) {
        if (!told_waiting_)
            ctx.events.record(ctx.db, "info", "campaign",
                              std::to_string(queue_.size()) +
                                  " campaign file(s) wait for the reference epoch (" +
                                  queue_.front().file.string() + " first)");
        told_waiting_ = true;
        return true;
    }
    told_waiting_ = false;
    // The reference prepared once for the batch, and let go with it (it holds its points).
    CampaignReferences references;
    while (!queue_.empty()) {
        try {
            process_one(ctx, queue_.front(), references);
        } catch (const StorageError& e) {
            spdlog::warn("{}: {}; the campaign is tried again later", queue_.front().file.string(),
                         e.what());
            return false;
        }
        queue_.erase(queue_.begin());
    }
    return true;
}

void CampaignIngest::process_one(IngestContext& ctx, const Queued& q,
                                 CampaignReferences& references) {
    const InstrumentConfig* instrument = find_instrument(ctx.config.instruments, q.instrument);
    if (!instrument || !instrument->matches(q.file.filename().string())) {
        ctx.events.record(ctx.db, "warning", "campaign",
                          q.file.string() + ": its [[instrument]] '" + q.instrument +
                              "' is no longer configured for it; left in place");
        return;
    }
    std::error_code ec;
    const auto size = fs::file_size(q.file, ec);
    if (ec) return;  // gone meanwhile: nothing to do
    if (std::int64_t(size) > ctx.config.ingest.max_file_size) {
        quarantine(ctx, q.file, "campaign",
                   "a campaign of " + std::to_string(size) +
                       " bytes, more than "
                       "ingest.max_file_size",
                   std::nullopt);
        return;
    }
    HashedBytes bytes;
    try {
        bytes = read_file_hashed(q.file);
    } catch (const Error& e) {
        ctx.events.record(
            ctx.db, "error", "unreadable",
            q.file.string() + ": a campaign that cannot be read; left in place (" + e.what() + ")");
        return;
    }
    const std::string tag = bytes.sha256.substr(0, 12);
    const bool move = ctx.config.ingest.archive == ArchiveMode::move;
    CampaignSource source;
    source.file = q.file;
    source.instrument = instrument->name;
    source.kind = kind_name(instrument->kind);
    std::string used;
    source.acquired = acquisition_time(q.file, ctx.config.ingest.acquisition_time, used);
    if (move)
        source.stored_path = free_name(ctx.config.paths.archive, q.file.filename().string(), tag);
    const CampaignParameters p = campaign_parameters(ctx.config.campaign, instrument->range_sigma);
    const std::optional<CampaignFeed> feed = campaign_feed(ctx.config);
    StoredCampaign stored;
    try {
        stored = add_campaign(ctx.db, source, bytes, p, ctx.config.campaign.store_spacing,
                              references, feed ? &*feed : nullptr);
    } catch (const StorageError&) {
        throw;
    } catch (const std::exception& e) {
        quarantine(ctx, q.file, tag, std::string("campaign not compared: ") + e.what(),
                   std::nullopt);
        return;
    }
    const fs::path stored_at = stored.row.file_path;
    if (stored.known) {
        // Its stored file gone (a stop between storing and archiving): this copy becomes it.
        // The same file seen again (ingest.archive = "keep", a restart): nothing to say.
        if (move && !fs::exists(stored_at) && stored_at.parent_path() == ctx.config.paths.archive) {
            move_file(q.file, stored_at);
            ctx.events.record(ctx.db, "info", "campaign",
                              q.file.string() + ": campaign " + std::to_string(stored.row.id) +
                                  " archived as " + stored_at.string());
        } else if (q.file != stored_at) {
            ctx.events.record(ctx.db, "info", "duplicate",
                              q.file.string() + " is campaign " + std::to_string(stored.row.id) +
                                  " already (" + stored_at.string() + "); left in place");
        }
        return;
    }
    std::string where;
    if (move) {
        try {
            move_file(q.file, stored_at);
            where = "; archived as " + stored_at.string();
        } catch (const Error& e) {
            where = std::string("; not archived (") + e.what() + "), moved when seen again";
        }
    }
    ctx.events.record(ctx.db, "info", "campaign",
                      "campaign " + std::to_string(stored.row.id) + " of instrument '" +
                          instrument->name + "' from " + q.file.string() + ": " +
                          summary(stored.row) + where);
}

}  // namespace tlsmon
