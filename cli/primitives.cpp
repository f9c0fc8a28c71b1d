// `tlsmon primitives REFERENCE COMPARED --config SITE --out RESULT.csv`: the primitives the
// site's zones name (docs/primitives.md), fitted in both files and their change tested, as
// the daemon's stage does (its reference product, the site's registration of COMPARED onto
// REFERENCE: cli/file_pair.hpp), so the numbers are those the daemon stores. Without
// --config: one zone "box" (--box) holding one primitive (--kind), in the files' own frame.
// Prints the parameters used, each zone's two fits and its rows; writes the rows as CSV.
#include <cmath>
#include <iostream>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "cli/file_pair.hpp"
#include "cli/result_file.hpp"
#include "config/config.hpp"
#include "core/csv.hpp"
#include "core/error.hpp"
#include "pipeline/primitive_stage.hpp"

namespace tlsmon {

namespace {

PrimitivesConfig parameters_of(const PrimitivesOptions& o, const std::optional<Config>& site) {
    PrimitivesConfig p = site ? pipeline_config(*site).primitives : PrimitivesConfig{};
    if (o.band) p.band = *o.band;
    if (o.max_incidence_deg) p.max_incidence_deg = *o.max_incidence_deg;
    if (o.alpha) p.alpha = *o.alpha;
    if (o.threads) p.threads = *o.threads;
    if (!o.box.empty()) {
        if (o.box.size() != 6 ||
            !(o.box[0] < o.box[3] && o.box[1] < o.box[4] && o.box[2] < o.box[5]))
            throw Error("--box: expected x_min y_min z_min x_max y_max z_max, each min < max");
        p.zones = {{box_zone("box", {o.box[0], o.box[1], o.box[2]}, {o.box[3], o.box[4], o.box[5]}),
                    primitives::kind_from_string(o.kind)}};
    }
    if (p.zones.empty())
        throw Error(site
                        ? "the site's [[zone]] tables name no primitive (primitive = \"cylinder\", "
                          "...); or give --box and --kind"
                        : "give --config (zones naming a primitive) or --box and --kind");
    return p;
}

std::string describe(const primitives::Fit& f) {
    if (f.status != primitives::FitStatus::fitted) return primitives::to_string(f.status);
    const auto& p = f.primitive;
    const Eigen::Vector3d at = p.point(), d = p.direction();
    std::string s = std::string(primitives::to_string(p.kind)) + " at (" + csv_number(at.x()) +
                    ", " + csv_number(at.y()) + ", " + csv_number(at.z()) + ")";
    if (p.kind != primitives::Kind::sphere)
        s += " direction (" + csv_number(d.x()) + ", " + csv_number(d.y()) + ", " +
             csv_number(d.z()) + ")";
    if (p.kind != primitives::Kind::plane) s += " radius " + csv_number(p.radius());
    return s + ", " + std::to_string(f.used) + " points, s0 " + csv_number(f.s0) + ", rms " +
           csv_number(f.rms) + " m";
}

void write_csv(const std::string& path, const std::vector<ZoneResult>& rows) {
    ResultFile f(path);
    f.write("zone,quantity,value,lod,n,significant\n");
    for (const auto& r : rows) {
        const std::string line =
            csv_line(std::vector<std::string>{r.zone, r.quantity, csv_number(r.value),
                                              r.uncertainty ? csv_number(*r.uncertainty) : "",
                                              std::to_string(r.n), r.significant ? "1" : "0"});
        f.write(line);
    }
    f.close();
}

}  // namespace

int run_primitives(const PrimitivesOptions& o) {
    try {
        const std::optional<Config> site = site_config(o.config);
        const PrimitivesConfig p = parameters_of(o, site);
        Config shown = site.value_or(Config{});
        shown.primitives = p;
        std::cout << effective_parameters(shown, "primitives");
        const FilePair pair = read_file_pair(o.reference, o.compared, site);
        std::cout << "registration: " << pair.registration << "\n";
        ReferenceEpoch reference(pair.reference, [&] { return pair.reference_scans; });
        ReferenceCache cache;
        const auto product = PrimitivesStage(p).reference(reference, cache);
        const PrimitiveEpoch epoch =
            measure_primitives(p, *product, *pair.epoch_scans, pair.outputs);
        for (std::size_t k = 0; k < epoch.fits.size(); ++k) {
            const auto& e = product->entries[k];
            std::cout << e.zone << ": reference "
                      << (e.refused.empty() ? describe(e.fit) : e.refused) << "\n"
                      << e.zone << ": compared " << describe(epoch.fits[k]) << "\n";
        }
        const auto rows = primitive_zone_results(p, *product, epoch);
        for (const auto& row : rows) {
            std::cout << row.zone << " " << row.quantity << " = " << csv_number(row.value);
            if (row.uncertainty) std::cout << " (LoD " << csv_number(*row.uncertainty) << ")";
            std::cout << (row.significant ? " significant" : "") << "\n";
        }
        write_csv(o.out, rows);
        std::cout << rows.size() << " rows -> " << o.out << "\n";
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "tlsmon primitives: " << e.what() << "\n";
        return 1;
    }
}

}  // namespace tlsmon
