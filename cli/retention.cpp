// `tlsmon epochs pin|unpin|pinned` and `tlsmon retention plan|run` (docs/retention.md): the
// operator's side of the retention policy. A pass run here is the daemon's own
// (daemon/retention_pass.hpp), safe while the daemon runs: every step is one short
// transaction.
#include <iostream>

#include "cli/commands.hpp"
#include "cli/policy_fields.hpp"
#include "config/config.hpp"
#include "core/utc_time.hpp"
#include "daemon/retention_pass.hpp"

namespace tlsmon {

namespace {

// The site's policy with --config, the defaults with --db.
RetentionPolicy policy_of(const ReadOptions& read) {
    return read.config.empty() ? RetentionPolicy{} : load_config(read.config).retention;
}

}  // namespace

int run_epoch_pins(const EpochPinOptions& o) {
    return run_reporting_errors("epochs " + o.action, [&] {
        if (o.action == "pinned") {
            const auto db = open_for_reading(o.read);
            Table t{{"epoch", "acquired", "pinned_at", "pinned_by", "has_maps", "note"}, {}};
            for (const auto& p : db.retention().pins()) {
                t.rows.push_back({p.epoch, format_utc(p.acquired), format_utc(p.pinned_at),
                                  p.pinned_by, p.has_maps, p.note});
            }
            print(std::cout, t, o.read.format);
            return;
        }
        auto db = open_for_writing(o.read.db, o.read.config);
        const std::string actor = cli_actor(o.by);
        const std::string epoch = "epoch " + std::to_string(o.epoch);
        if (o.action == "pin") {
            if (!db.retention().pin(o.epoch, actor, o.note, now_utc())) {
                throw Error(epoch + " is pinned already (tlsmon epochs pinned)");
            }
            std::cout << epoch << " pinned by " << actor;
            if (!db.retention().has_maps(o.epoch)) {
                std::cout << "; it has no per-core-point maps (never made, or thinned before it "
                             "was pinned): its zone series is all there is";
            } else {
                std::cout << ": its maps are kept whatever its age";
            }
            std::cout << "\n";
        } else {
            if (!db.retention().unpin(o.epoch, actor, now_utc())) {
                throw Error(epoch + " is not pinned (tlsmon epochs pinned)");
            }
            std::cout << epoch << " unpinned by " << actor
                      << ": its maps follow the retention policy again\n";
        }
    });
}

int run_retention(const RetentionOptions& o) {
    return run_reporting_errors("retention " + o.action, [&] {
        const RetentionPolicy policy = policy_of(o.read);
        const std::vector<std::pair<std::string, Cell>> policy_fields = {
            {"keep_all_days", policy.keep_all_days}, {"keep_daily_days", policy.keep_daily_days}};
        if (o.action == "plan") {
            const auto db = open_for_reading(o.read);
            const RetentionPlan p = db.retention().plan(policy);
            std::vector<std::pair<std::string, Cell>> fields = {{"enabled", policy.enabled}};
            fields.insert(fields.end(), policy_fields.begin(), policy_fields.end());
            const auto tiers = tier_fields(p);
            fields.insert(fields.end(), tiers.begin(), tiers.end());
            fields.emplace_back("to_thin", static_cast<std::int64_t>(p.thin.size()));
            print_fields(std::cout, fields, o.read.format);
            return;
        }
        if (!policy.enabled) {
            throw Error("retention.enabled = false in " + o.read.config + ": nothing is thinned");
        }
        auto db = open_for_writing(o.read.db, o.read.config);
        const RetentionPassResult r = run_retention_pass(db, policy);
        auto fields = policy_fields;
        fields.insert(fields.end(), {{"series_time", time_cell(r.plan.now)},
                                     {"epochs_thinned", r.epochs_thinned},
                                     {"map_bytes_deleted", r.map_bytes_deleted},
                                     {"size_before", r.size_before},
                                     {"size_after", r.size_after},
                                     {"pages_released", r.pages_released},
                                     {"converted_to_incremental_vacuum", r.converted},
                                     {"vacuum_error", r.vacuum_error}});
        print_fields(std::cout, fields, o.read.format);
    });
}

}  // namespace tlsmon
