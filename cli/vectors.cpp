// `tlsmon vectors REFERENCE COMPARED ... --out RESULT.csv`: 3-D vectors by local registration
// of quasi-rigid areas between two scan files. The parameters start from a fresh site's
// defaults (pipeline/vector_config.hpp, the segmentation's of [registration]), or from the
// site's with --config; each option given replaces one. With --config the stage itself
// measures (its areas in the site's zones, the site's registration of COMPARED onto
// REFERENCE: cli/file_pair.hpp), so the numbers are those the daemon stored; otherwise the
// areas cover the whole of REFERENCE, one zone "all", in the files' own frame. Writes one CSV
// row per area, prints the parameters used and each zone's rows.
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
#include "pipeline/vector_stage.hpp"

namespace tlsmon {

namespace {

VectorConfig parameters_of(const VectorsOptions& o, const std::optional<Config>& site) {
    VectorConfig p = site ? pipeline_config(*site).vectors : VectorConfig{};
    if (o.window) p.window = *o.window;
    if (o.search_radius) p.search_radius = *o.search_radius;
    if (o.search_depth) p.search_depth = *o.search_depth;
    if (o.block) p.block = *o.block;
    if (o.max_incidence_deg) p.max_incidence_deg = *o.max_incidence_deg;
    if (o.threads) p.threads = *o.threads;
    apply_segmentation_options(p.segmentation, o.voxel, o.seed);
    return p;
}

void write_csv(const std::string& path, const VectorReference& reference,
               const VectorEpoch& epoch) {
    ResultFile f(path);
    // Each area's zones, ';'-joined (a band and its face share areas).
    std::vector<std::string> zones(reference.areas());
    for (std::size_t z = 0; z < reference.zone_names.size(); ++z)
        for (const auto k : reference.zone_areas[z])
            zones[k] += (zones[k].empty() ? "" : ";") + reference.zone_names[z];
    f.write(
        "area,supervoxel,zones,x_m,y_m,z_m,nx,ny,nz,dx_m,dy_m,dz_m,sigma_x_m,sigma_y_m,sigma_z_m,"
        "along_u_m,along_v_m,along_normal_m,sigma_u_m,sigma_v_m,sigma_normal_m,"
        "registration_sigma_m,reference_points,epoch_points,coarse_ncc,gain,iterations,"
        "outcome\n");
    for (std::size_t k = 0; k < reference.areas(); ++k) {
        const auto& frame = reference.frames[k];
        const auto& a = epoch.areas[k];
        const Eigen::Vector3d sigma = a.covariance().diagonal().cwiseSqrt();
        const Eigen::Vector3d local_sigma = a.fit.covariance.diagonal().cwiseSqrt();
        std::vector<std::string> row{std::to_string(k), std::to_string(reference.supervoxel[k]),
                                     zones[k]};
        for (const auto* v : {&frame.origin, &frame.normal, &a.displacement, &sigma,
                              &a.fit.displacement, &local_sigma})
            for (int c = 0; c < 3; ++c) row.push_back(csv_number((*v)(c)));
        row.push_back(csv_number(std::sqrt(a.registration_covariance.trace())));
        row.push_back(std::to_string(a.fit.reference_points));
        row.push_back(std::to_string(a.fit.epoch_points));
        row.push_back(csv_number(a.fit.coarse_correlation));
        row.push_back(csv_number(a.fit.gain));
        row.push_back(std::to_string(a.fit.iterations));
        row.push_back(vectors::outcome_name(a.fit.outcome));
        f.write(csv_line(row));
    }
    f.close();
}

}  // namespace

int run_vectors(const VectorsOptions& o) {
    try {
        const std::optional<Config> site = site_config(o.config);
        VectorConfig p = parameters_of(o, site);
        validate(p);  // before the work, not after it
        Config shown = site.value_or(Config{});
        shown.vectors = p;
        shown.vectors.enabled = true;
        shown.stable_areas.voxel = p.segmentation.voxel;
        shown.stable_areas.seed = p.segmentation.seed;
        std::cout << effective_parameters(shown, "vectors")
                  << "registration.stable_voxel = " << toml_number(p.segmentation.voxel) << "\n"
                  << "registration.stable_seed = " << toml_number(p.segmentation.seed) << "\n";

        const FilePair pair = read_file_pair(o.reference, o.compared, site);
        std::cout << "registration: " << pair.registration << "\n";
        if (p.zones.empty()) p.zones = whole_of(*pair.reference_scans);
        // The stage's reference product and measurement, as the daemon's.
        ReferenceEpoch reference(pair.reference, [&] { return pair.reference_scans; });
        ReferenceCache cache;
        const auto product = VectorStage(p).reference(reference, cache);
        const VectorEpoch epoch = measure_vectors(p, *product, *pair.epoch_scans, pair.outputs);
        write_csv(o.out, *product, epoch);
        std::size_t measured = 0;
        for (const auto& a : epoch.areas) measured += a.fit.measured();
        std::cout << product->areas() << " areas, " << measured << " with a vector -> " << o.out
                  << "\n";
        for (const auto& row : vector_zone_results(p, *product, epoch)) {
            std::cout << row.zone << " " << row.quantity << " = " << csv_number(row.value);
            if (row.uncertainty) std::cout << " (LoD95 " << csv_number(*row.uncertainty) << ")";
            std::cout << " n " << row.n << (row.significant ? " significant" : "") << "\n";
        }
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "tlsmon vectors: " << e.what() << "\n";
        return 1;
    }
}

}  // namespace tlsmon
