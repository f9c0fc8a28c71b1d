// `tlsmon query planes --epoch N`: the reference's planes that the registration on planes
// matched in one epoch (docs/schema.md, "plane_observations"): where each is, whether it
// carried the datum, was left out as moved by the congruence test, or lies in a zone, and its
// change under the epoch's transformation — the tilt of its normal towards the plane's long
// axis u and towards v = n × u (arc seconds), the shift along its normal (mm) — with σ and
// the test statistic T against χ²(3, 1 − α).
#include <iostream>

#include "cli/commands.hpp"
#include "cli/query_output.hpp"

namespace tlsmon {

namespace {

constexpr double kArcsecPerRad = 180.0 * 3600.0 / 3.141592653589793;

}  // namespace

int run_query_planes(const PlanesQueryOptions& o) {
    return run_reporting_errors("query planes", [&] {
        const auto db = open_for_reading(o.read);
        const auto epoch = db.epochs().find(o.epoch);
        if (!epoch)
            throw Error("no epoch " + std::to_string(o.epoch) + " in " + db.path().string());
        Table t{{"plane",
                 "zone",
                 "role",
                 "normal_x",
                 "normal_y",
                 "normal_z",
                 "centroid_x_m",
                 "centroid_y_m",
                 "centroid_z_m",
                 "reference_points",
                 "epoch_points",
                 "tilt_u_arcsec",
                 "sigma_tilt_u_arcsec",
                 "tilt_v_arcsec",
                 "sigma_tilt_v_arcsec",
                 "shift_mm",
                 "sigma_shift_mm",
                 "statistic",
                 "critical",
                 "significant"},
                {}};
        for (const auto& p : db.registrations().planes_of_epoch(o.epoch)) {
            t.rows.push_back({p.plane,
                              p.zone.empty() ? Cell() : Cell(p.zone),
                              p.role,
                              p.normal[0],
                              p.normal[1],
                              p.normal[2],
                              p.centroid[0],
                              p.centroid[1],
                              p.centroid[2],
                              p.reference_points,
                              p.epoch_points,
                              p.change[0] * kArcsecPerRad,
                              p.sigma[0] * kArcsecPerRad,
                              p.change[1] * kArcsecPerRad,
                              p.sigma[1] * kArcsecPerRad,
                              1e3 * p.change[2],
                              1e3 * p.sigma[2],
                              p.statistic,
                              p.critical,
                              p.significant});
        }
        if (t.rows.empty() && o.read.format != OutputFormat::json) {
            std::cerr << "epoch " << o.epoch << " (" << to_string(epoch->status)
                      << ") has no plane observations: the registration on planes did not "
                         "register it (registration.method, docs/registration.md)\n";
        }
        print(std::cout, t, o.read.format);
    });
}

}  // namespace tlsmon
