// `tlsmon pbm3c2 REFERENCE COMPARED ... --out RESULT.csv`: patch-based M3C2 between two scan
// files. The parameters start from a fresh site's defaults (algorithms/patches/parameters.hpp,
// the segmentation's of [registration]), or from the site's with --config; each option given
// replaces one. With --config the stage itself measures (its patches in the site's zones, the
// site's registration of COMPARED onto REFERENCE: cli/file_pair.hpp), so the numbers are those
// the daemon stored; otherwise the patches cover the whole of REFERENCE, one zone "all", in the
// files' own frame. Writes one CSV row per patch, prints the parameters used and each zone's
// rows.
#include <cmath>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "cli/file_pair.hpp"
#include "cli/result_file.hpp"
#include "config/config.hpp"
#include "core/csv.hpp"
#include "core/error.hpp"
#include "pipeline/pbm3c2_stage.hpp"

namespace tlsmon {

namespace {

PbM3c2Config parameters_of(const PbM3c2Options& o, const std::optional<Config>& site) {
    PbM3c2Config p = site ? pipeline_config(*site).pbm3c2 : PbM3c2Config{};
    if (o.search_depth) p.search_depth = *o.search_depth;
    if (o.min_points) p.min_points = *o.min_points;
    if (o.max_roughness) p.max_roughness = *o.max_roughness;
    if (o.max_incidence_deg) p.max_incidence_deg = *o.max_incidence_deg;
    if (o.threads) p.threads = *o.threads;
    apply_segmentation_options(p.segmentation, o.voxel, o.seed);
    return p;
}

const char* outcome_name(patches::PatchOutcome o) {
    switch (o) {
        case patches::PatchOutcome::measured:
            return "measured";
        case patches::PatchOutcome::rough:
            return "not_planar";
        case patches::PatchOutcome::few_reference_points:
            return "few_reference_points";
        case patches::PatchOutcome::few_epoch_points:
            return "few_epoch_points";
        case patches::PatchOutcome::partly_seen:
            return "partly_seen";
    }
    return "?";
}

void write_csv(const std::string& path, const PbM3c2Reference& reference,
               const PbM3c2Epoch& epoch) {
    ResultFile f(path);
    // Each patch's zones, ';'-joined (a band and its face share patches).
    std::vector<std::string> zones(reference.patches.size());
    for (std::size_t z = 0; z < reference.zone_names.size(); ++z)
        for (const auto k : reference.zone_patches[z])
            zones[k] += (zones[k].empty() ? "" : ";") + reference.zone_names[z];
    f.write(
        "patch,supervoxel,zones,x_m,y_m,z_m,nx,ny,nz,distance_m,lod95_m,sigma_m,registration_sigma_"
        "m,"
        "n1,sigma1_m,n2,sigma2_m,significant,outcome,compared\n");
    for (std::size_t k = 0; k < reference.patches.size(); ++k) {
        const auto& frame = reference.patches[k].frame;
        const auto& r = epoch.results[k];
        const Eigen::Vector3d at = reference.measured_at(k, &r);
        const std::string row =
            csv_line(std::vector<std::string>{std::to_string(k),
                                              std::to_string(reference.supervoxel[k]),
                                              zones[k],
                                              csv_number(at.x()),
                                              csv_number(at.y()),
                                              csv_number(at.z()),
                                              csv_number(frame.normal.x()),
                                              csv_number(frame.normal.y()),
                                              csv_number(frame.normal.z()),
                                              csv_number(r.distance.distance),
                                              csv_number(r.distance.lod),
                                              csv_number(r.distance.sigma),
                                              csv_number(epoch.registration_sigma[k]),
                                              std::to_string(r.reference.count),
                                              csv_number(r.reference.sigma),
                                              std::to_string(r.epoch.count),
                                              csv_number(r.epoch.sigma),
                                              r.distance.significant ? "1" : "0",
                                              outcome_name(r.outcome),
                                              r.partial ? "part" : "whole"});
        f.write(row);
    }
    f.close();
}

}  // namespace

int run_pbm3c2(const PbM3c2Options& o) {
    try {
        const std::optional<Config> site = site_config(o.config);
        PbM3c2Config p = parameters_of(o, site);
        patches::validate(p);  // before the work, not after it
        Config shown = site.value_or(Config{});
        static_cast<patches::Parameters&>(shown.pbm3c2) = p;
        shown.pbm3c2.enabled = true;
        shown.stable_areas.voxel = p.segmentation.voxel;
        shown.stable_areas.seed = p.segmentation.seed;
        std::cout << effective_parameters(shown, "pbm3c2")
                  << "registration.stable_voxel = " << toml_number(p.segmentation.voxel) << "\n"
                  << "registration.stable_seed = " << toml_number(p.segmentation.seed) << "\n";

        const FilePair pair = read_file_pair(o.reference, o.compared, site);
        std::cout << "registration: " << pair.registration << "\n";
        if (p.zones.empty()) p.zones = whole_of(*pair.reference_scans);
        // The stage's reference product and measurement, as the daemon's.
        ReferenceEpoch reference(pair.reference, [&] { return pair.reference_scans; });
        ReferenceCache cache;
        const auto product = PbM3c2Stage(p).reference(reference, cache);
        const PbM3c2Epoch epoch = measure_pbm3c2(p, *product, *pair.epoch_scans, pair.outputs);
        write_csv(o.out, *product, epoch);
        std::size_t measured = 0;
        for (const auto& r : epoch.results)
            measured += r.outcome == patches::PatchOutcome::measured;
        std::cout << product->patches.size() << " patches, " << measured << " with a distance -> "
                  << o.out << "\n";
        for (const auto& row : pbm3c2_zone_results(*product, epoch)) {
            std::cout << row.zone << " " << row.quantity << " = " << csv_number(row.value);
            if (row.uncertainty) std::cout << " (LoD95 " << csv_number(*row.uncertainty) << ")";
            std::cout << " n " << row.n << (row.significant ? " significant" : "") << "\n";
        }
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "tlsmon pbm3c2: " << e.what() << "\n";
        return 1;
    }
}

}  // namespace tlsmon
