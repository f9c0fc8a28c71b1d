// `tlsmon archive plan|run --config FILE` (docs/retention.md): the operator's side of the
// archive policy of raw scans. A pass run here is the daemon's own (daemon/archive_pass.hpp):
// its removals are short transactions, and a re-encoding replaces a file only once the E57
// written from it has been read back and compared.
#include <iostream>

#include "cli/commands.hpp"
#include "cli/policy_fields.hpp"
#include "config/config.hpp"
#include "daemon/archive_pass.hpp"

namespace tlsmon {

int run_archive(const RetentionOptions& o) {
    return run_reporting_errors("archive " + o.action, [&] {
        if (o.read.config.empty()) {
            throw Error(
                "--config is needed: the archive folder (paths.archive) and the "
                "[archive] policy are the site's");
        }
        const Config config = load_config(o.read.config);
        const ArchivePolicy& policy = config.archive;
        std::vector<std::pair<std::string, Cell>> fields = {
            {"enabled", policy.enabled},
            {"archive", config.paths.archive.string()},
            {"keep_all_days", policy.keep_all_days},
            {"keep_daily_days", policy.keep_daily_days},
            {"reencode", std::string(policy.reencode == ScanReencoding::e57 ? "e57" : "none")}};
        const auto add_plan = [&](const ArchivePlan& p) {
            fields.insert(fields.end(), {{"scans", p.scans}, {"bytes", p.bytes}});
            const auto tiers = tier_fields(p.tiers);
            fields.insert(fields.end(), tiers.begin(), tiers.end());
        };
        if (o.action == "plan") {
            const auto db = open_for_reading(o.read);
            const ArchivePlan p = db.archive().plan(config.paths.archive, policy);
            add_plan(p);
            fields.insert(fields.end(),
                          {{"to_remove", static_cast<std::int64_t>(p.remove.size())},
                           {"bytes_to_free", p.bytes_to_free},
                           {"to_reencode", static_cast<std::int64_t>(p.reencode.size())}});
            print_fields(std::cout, fields, o.read.format);
            return;
        }
        if (!policy.enabled) {
            throw Error("archive.enabled = false in " + o.read.config + ": nothing is removed");
        }
        auto db = open_for_writing(o.read.db, o.read.config);
        const ArchivePassResult r = run_archive_pass(db, policy, config.paths.archive);
        add_plan(r.plan);
        fields.insert(fields.end(), {{"scans_removed", r.scans_removed},
                                     {"deletions_finished", r.deletions_finished},
                                     {"scans_reencoded", r.scans_reencoded},
                                     {"reencoded_bytes_before", r.reencoded_bytes_before},
                                     {"reencoded_bytes_after", r.reencoded_bytes_after},
                                     {"bytes_freed", r.bytes_freed},
                                     {"errors", static_cast<std::int64_t>(r.errors.size())}});
        print_fields(std::cout, fields, o.read.format);
        for (const auto& e : r.errors) std::cerr << "tlsmon archive run: " << e << "\n";
    });
}

}  // namespace tlsmon
