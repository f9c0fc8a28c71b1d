// `tlsmon m3c2 REFERENCE COMPARED ... --out RESULT.csv`: M3C2 between two scan files as
// analysts run CloudCompare's or PDAL's. The parameters start from a fresh site's defaults
// (algorithms/m3c2/parameters.hpp), or from the site's [m3c2] with --config; each option
// given replaces one. With --config and zones, the stage itself measures (its core points in
// the zones, the site's registration of COMPARED onto REFERENCE: cli/file_pair.hpp), so
// the numbers are those the daemon stored; otherwise core points from --core FILE, or
// REFERENCE subsampled at core_spacing, in the files' own frame. Writes one CSV row per core
// point, prints the parameters used and a summary.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "algorithms/m3c2/core_points.hpp"
#include "algorithms/m3c2/reference.hpp"
#include "cli/commands.hpp"
#include "cli/file_pair.hpp"
#include "cli/result_file.hpp"
#include "config/config.hpp"
#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/fixed_decimals.hpp"
#include "formats/scan_file.hpp"
#include "pipeline/m3c2_stage.hpp"

namespace tlsmon {

namespace {

// --orient: "scanner" (towards REFERENCE's scanner) or X,Y,Z, into the parameters.
void set_orientation(const std::string& text, M3c2Config& p) {
    if (text == "scanner") {
        p.orient_to_scanner = true;
        return;
    }
    std::vector<double> v;
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, ',')) {
        char* end = nullptr;
        errno = 0;
        const double x = std::strtod(item.c_str(), &end);
        if (item.empty() || *end != '\0' || errno != 0 || !std::isfinite(x))
            throw Error("--orient: '" + text + "' is neither 'scanner' nor X,Y,Z");
        v.push_back(x);
    }
    if (v.size() != 3) throw Error("--orient: '" + text + "' is neither 'scanner' nor X,Y,Z");
    const Eigen::Vector3d vector(v[0], v[1], v[2]);
    if (vector.norm() == 0.0) throw Error("--orient: the vector must not be zero");
    p.orient_to_scanner = false;
    p.orientation = vector;
}

// The scanner position the normals face: the reference scans' one position.
Eigen::Vector3d scanner_of(const std::vector<Scan>& scans, const std::string& path) {
    const Eigen::Vector3d position = scans.front().scanner_position();
    for (const auto& scan : scans)
        if (scan.scanner_position() != position)
            throw Error("orientation \"scanner\": " + path +
                        " holds scans from several scanner positions; give --orient X,Y,Z");
    return position;
}

void write_csv(const std::string& path, const m3c2::Reference& reference,
               const std::vector<m3c2::CylinderSide>& compared,
               const std::vector<m3c2::Distance>& distances) {
    ResultFile f(path);
    f.write(
        "x_m,y_m,z_m,nx,ny,nz,normal_radius_m,distance_m,lod95_m,spread1_m,n1,spread2_m,n2,"
        "significant\n");
    for (std::size_t k = 0; k < reference.size(); ++k) {
        const auto& c = reference.core_points()[k];
        const auto& n = reference.normals()[k];
        const auto& s1 = reference.reference_side[k];
        const auto& d = distances[k];
        const std::string row = csv_line(std::vector<std::string>{
            csv_number(c.x()), csv_number(c.y()), csv_number(c.z()), csv_number(n.x()),
            csv_number(n.y()), csv_number(n.z()), csv_number(reference.normal_radius[k]),
            csv_number(d.distance), csv_number(d.lod), csv_number(s1.spread),
            std::to_string(s1.count), csv_number(compared[k].spread),
            std::to_string(compared[k].count), d.significant ? "1" : "0"});
        f.write(row);
    }
    f.close();
}

}  // namespace

namespace {

M3c2Config parameters_of(const M3c2Options& o, const std::optional<Config>& site) {
    M3c2Config p = site ? pipeline_config(*site).m3c2 : M3c2Config{};
    if (o.core_spacing) p.core_spacing = *o.core_spacing;
    if (!o.normal_radii.empty()) p.normal_radii = o.normal_radii;
    if (o.cylinder_radius) p.cylinder_radius = *o.cylinder_radius;
    if (o.max_depth) p.max_depth = *o.max_depth;
    if (o.orient) set_orientation(*o.orient, p);
    if (o.registration_error) p.registration_error = *o.registration_error;
    if (o.median) p.statistic = m3c2::CylinderStatistic::median;
    if (o.min_points) p.min_points = *o.min_points;
    if (o.max_roughness) p.max_roughness = *o.max_roughness;
    if (o.stray_distance) p.stray_distance = *o.stray_distance;
    if (o.threads) p.threads = *o.threads;
    return p;
}

}  // namespace

int run_m3c2(const M3c2Options& o) {
    try {
        const std::optional<Config> site = site_config(o.config);
        const M3c2Config p = parameters_of(o, site);
        m3c2::validate(m3c2::distance_parameters(p));  // before the work, not after it
        Config shown = site.value_or(Config{});
        static_cast<m3c2::Parameters&>(shown.m3c2) = p;
        std::cout << effective_parameters(shown, "m3c2");

        const FilePair pair = read_file_pair(o.reference, o.compared, site);
        std::cout << "registration: " << pair.registration << "\n";
        M3c2Reference product;
        if (!p.zones.empty() && o.core_file.empty()) {
            // The stage's own reference product: core points in the zones.
            product = M3c2Stage(p).prepare_reference(*pair.reference_scans);
        } else {
            const M3c2Cloud cloud = m3c2_cloud(*pair.reference_scans, unsigned(p.threads));
            if (cloud.kept() == 0) throw Error(o.reference + ": no points");
            product.scanner = p.orient_to_scanner
                                  ? scanner_of(*pair.reference_scans, o.reference)
                                  : pair.reference_scans->front().scanner_position();
            auto cores = o.core_file.empty() ? m3c2::subsample(cloud.kept_points(), p.core_spacing,
                                                               unsigned(p.threads))
                                             : all_points(read_scans(o.core_file), o.core_file);
            product.reference = m3c2::prepare_reference(
                cloud.points(), std::move(cores), m3c2::normal_parameters(p, product.scanner),
                m3c2::cylinder_parameters(p), unsigned(p.threads), {}, cloud.left_out);
        }
        // The stage's measurement of the epoch against it.
        const M3c2Epoch epoch = measure_m3c2(p, product, *pair.epoch_scans, pair.outputs);
        const m3c2::Reference& prepared = product.reference;
        const auto& d = epoch.distances;
        write_csv(o.out, prepared, epoch.compared, d);
        std::size_t valid = 0, significant = 0;
        std::vector<double> values;
        for (const auto& x : d)
            if (!std::isnan(x.distance)) {
                ++valid;
                significant += x.significant;
                values.push_back(x.distance);
            }
        double mean = std::nan(""), median = std::nan("");
        if (!values.empty()) {
            double sum = 0;
            for (double v : values) sum += v;
            mean = sum / double(values.size());
            median = m3c2::statistic_of(values, m3c2::CylinderStatistic::median).centre;
        }
        std::cout << prepared.size() << " core points, " << valid << " with a distance, "
                  << significant << " significant; mean " << fixed_decimals(mean, 6)
                  << " m, median " << fixed_decimals(median, 6) << " m -> " << o.out << "\n";
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "tlsmon m3c2: " << e.what() << "\n";
        return 1;
    }
}

}  // namespace tlsmon
