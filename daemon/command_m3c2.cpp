// `tlsmon m3c2 REFERENCE COMPARED ... --out RESULT.csv`: M3C2 between two scan files as
// analysts run CloudCompare's or PDAL's, with the same kernel the pipeline uses. Core points
// from --core FILE, or REFERENCE subsampled at --core-spacing, or every point of REFERENCE.
// Writes one CSV row per core point and prints a summary.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "algorithms/m3c2/core_points.hpp"
#include "algorithms/m3c2/reference.hpp"
#include "core/error.hpp"
#include "daemon/commands.hpp"
#include "formats/scan_file.hpp"

namespace tlsmon {

namespace {

struct Cloud {
    std::vector<Eigen::Vector3d> points;
    std::vector<Scan> scans;  // without their points
};

Cloud read_cloud(const std::string& path) {
    Cloud cloud;
    cloud.scans = read_scans(path);
    for (auto& scan : cloud.scans) {
        cloud.points.insert(cloud.points.end(), scan.xyz.begin(), scan.xyz.end());
        std::vector<Eigen::Vector3d>().swap(scan.xyz);
    }
    if (cloud.points.empty()) throw Error(path + ": no points");
    return cloud;
}

m3c2::Orientation orientation_of(const std::string& text, const Cloud& reference,
                                 const std::string& reference_path) {
    if (text == "scanner") {
        const Eigen::Vector3d position = reference.scans.front().scanner_position();
        for (const auto& scan : reference.scans)
            if (scan.scanner_position() != position)
                throw Error("--orient scanner: " + reference_path +
                            " holds scans from several scanner positions");
        return m3c2::Orientation::towards(position);
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
    return m3c2::Orientation::along(vector);
}

// "nan" for NaN whatever its sign bit, else the number with `decimals` decimals.
std::string number(double v, int decimals) {
    if (std::isnan(v)) return "nan";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    return buf;
}

void write_csv(const std::string& path, const m3c2::Reference& reference,
               const std::vector<m3c2::CylinderSide>& compared,
               const std::vector<m3c2::Distance>& distances) {
    std::FILE* f = std::fopen(path.c_str(), "w");
    if (!f) throw Error(path + ": cannot write: " + std::strerror(errno));
    std::fputs("x,y,z,nx,ny,nz,normal_radius,distance,lod,spread1,n1,spread2,n2,significant\n", f);
    for (std::size_t k = 0; k < reference.size(); ++k) {
        const auto& c = reference.core_points()[k];
        const auto& n = reference.normals()[k];
        const auto& s1 = reference.reference_side[k];
        const auto& d = distances[k];
        const std::string row =
            number(c.x(), 6) + ',' + number(c.y(), 6) + ',' + number(c.z(), 6) + ',' +
            number(n.x(), 9) + ',' + number(n.y(), 9) + ',' + number(n.z(), 9) + ',' +
            number(reference.normal_radius[k], 6) + ',' + number(d.distance, 9) + ',' +
            number(d.lod, 9) + ',' + number(s1.spread, 9) + ',' + std::to_string(s1.count) + ',' +
            number(compared[k].spread, 9) + ',' + std::to_string(compared[k].count) + ',' +
            (d.significant ? "1" : "0") + '\n';
        std::fputs(row.c_str(), f);
    }
    const bool failed = std::ferror(f) != 0;
    if (std::fclose(f) != 0 || failed)
        throw Error(path + ": write failed: " + std::strerror(errno));
}

}  // namespace

int run_m3c2(const M3c2Options& o) {
    try {
        const Cloud reference = read_cloud(o.reference);
        std::vector<Eigen::Vector3d> core_points;
        if (!o.core_file.empty())
            core_points = read_cloud(o.core_file).points;
        else if (o.core_spacing)
            core_points = m3c2::subsample(reference.points, *o.core_spacing, o.threads);
        else
            core_points = reference.points;

        const m3c2::NormalParameters normals{o.normal_radii,
                                             orientation_of(o.orient, reference, o.reference)};
        const m3c2::CylinderParameters cylinders{
            o.cylinder_radius, o.max_depth,
            o.median ? m3c2::CylinderStatistic::median : m3c2::CylinderStatistic::mean};
        m3c2::DistanceParameters distance{o.min_points, o.registration_error};
        if (o.max_roughness) distance.max_reference_spread = *o.max_roughness;
        m3c2::validate(distance);  // before the work, not after it

        const m3c2::Reference prepared = m3c2::prepare_reference(
            reference.points, std::move(core_points), normals, cylinders, o.threads);
        const Cloud compared = read_cloud(o.compared);
        const auto side = m3c2::cylinder_sides(prepared.cylinders, compared.points, o.threads);
        const auto d = m3c2::distances(prepared, side, distance);
        write_csv(o.out, prepared, side, d);

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
                  << significant << " significant; mean " << number(mean, 6) << " m, median "
                  << number(median, 6) << " m -> " << o.out << "\n";
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "tlsmon m3c2: " << e.what() << "\n";
        return 1;
    }
}

}  // namespace tlsmon
