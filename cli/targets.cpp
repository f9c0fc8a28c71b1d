// `tlsmon targets` and `tlsmon targets resurvey NAME [--by WHO]`: the reference targets as the
// registration last saw them (status in the newest epoch with target observations, whether
// and since when a target is excluded as moved, and why), and the operator's re-survey,
// which clears a target's exclusion so the registration offers it again. The re-survey is
// written in one immediate transaction together with a `target_resurveyed` system event
// naming the actor (storage/registration_store.hpp): safe while the daemon runs.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <map>

#include "cli/commands.hpp"
#include "cli/query_output.hpp"
#include "config/config.hpp"
#include "core/utc_time.hpp"

namespace tlsmon {

namespace {

// Why the excluding epoch excluded the target, from its stored observation.
std::string exclusion_reason(const std::vector<TargetObservation>& observed,
                             const std::string& target) {
    for (const auto& o : observed) {
        if (o.target != target) continue;
        const double moved =
            std::sqrt(o.residual[0] * o.residual[0] + o.residual[1] * o.residual[1] +
                      o.residual[2] * o.residual[2]);
        std::string s = "failed its outlier test";
        if (o.statistic && o.critical) {
            s += fmt::format(" (T {:.1f} > {:.1f})", *o.statistic, *o.critical);
        }
        return s + fmt::format(", apparent movement {:.1f} mm", 1e3 * moved);
    }
    return "moved (no observation stored)";
}

}  // namespace

int run_targets(const ReadOptions& options) {
    return run_reporting_errors("targets", [&] {
        const auto db = open_for_reading(options);
        const auto& store = db.registrations();
        // Per target: its newest exclusion (open or re-surveyed).
        std::map<std::string, TargetExclusion> newest;
        for (const auto& x : store.exclusions()) newest[x.target] = x;
        std::vector<TargetObservation> last;
        std::optional<EpochId> last_epoch = store.last_epoch_with_targets();
        if (last_epoch) last = store.targets_of_epoch(*last_epoch);
        std::vector<std::string> names;
        for (const auto& o : last) names.push_back(o.target);
        for (const auto& [name, x] : newest) {
            if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
        }
        Table t{{"target", "kind", "epoch", "status", "use", "excluded", "excluded_since",
                 "excluded_by_epoch", "why", "resurveyed"},
                {}};
        for (const auto& name : names) {
            std::vector<Cell> row{name};
            const TargetObservation* o = nullptr;
            for (const auto& x : last) {
                if (x.target == name) o = &x;
            }
            row.push_back(o ? Cell(o->kind) : Cell());
            row.push_back(o ? optional_cell(std::optional<std::int64_t>(*last_epoch)) : Cell());
            row.push_back(o ? Cell(o->status) : Cell());
            row.push_back(o ? Cell(o->use) : Cell());
            const auto x = newest.find(name);
            if (x == newest.end()) {
                row.insert(row.end(), {Cell("no"), Cell(), Cell(), Cell(), Cell()});
            } else {
                row.push_back(Cell(x->second.resurveyed ? "no" : "yes"));
                row.push_back(Cell(format_utc(x->second.excluded_acquired)));
                row.push_back(optional_cell(std::optional<std::int64_t>(x->second.epoch)));
                row.push_back(
                    Cell(exclusion_reason(store.targets_of_epoch(x->second.epoch), name)));
                row.push_back(x->second.resurveyed ? Cell(format_utc(*x->second.resurveyed))
                                                   : Cell());
            }
            t.rows.push_back(std::move(row));
        }
        print(std::cout, t, options.format);
    });
}

int run_target_resurvey(const TargetResurveyOptions& o) {
    return run_reporting_errors("targets resurvey", [&] {
        if (o.target.empty()) throw Error("name the target to mark re-surveyed");
        auto db = open_for_writing(o.db, o.config);
        const std::string actor = cli_actor(o.by);
        const int cleared = db.registrations().resurvey(o.target, now_utc(), actor);
        if (cleared == 0) {
            std::string excluded;
            for (const auto& name : db.registrations().excluded_targets()) {
                excluded += (excluded.empty() ? "" : ", ") + name;
            }
            throw Error("target '" + o.target + "' is not excluded (excluded now: " +
                        (excluded.empty() ? "none" : excluded) + ")");
        }
        std::cout << "target " << o.target << " re-surveyed by " << actor
                  << ": offered to the registration again from the next epoch\n";
    });
}

}  // namespace tlsmon
