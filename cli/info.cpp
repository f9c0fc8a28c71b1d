// `tlsmon info FILE...`: what a scanner export holds — format, scans, and per scan the
// points, grid and fill ratio, intensity range (normalised and raw), colour, bounding box,
// scanner pose and acquisition time. Text by default, `--json` for machines. A file that
// cannot be read is reported on stderr and the exit code is 2; the other files are still
// reported.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <iostream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "core/fixed_decimals.hpp"
#include "formats/scan_file.hpp"

namespace tlsmon {

namespace {

struct ScanSummary {
    std::size_t points = 0;
    Eigen::Vector3d box_min = Eigen::Vector3d::Zero();
    Eigen::Vector3d box_max = Eigen::Vector3d::Zero();
    float intensity_min = 0.0f;
    float intensity_max = 0.0f;
    bool is_rotation = false;  // the pose's linear part is a proper rotation
    Eigen::AngleAxisd axis_angle;
};

ScanSummary summarise(const Scan& s) {
    ScanSummary out;
    out.points = s.size();
    if (!s.xyz.empty()) {
        out.box_min = Eigen::Vector3d::Constant(std::numeric_limits<double>::max());
        out.box_max = Eigen::Vector3d::Constant(std::numeric_limits<double>::lowest());
        for (const auto& p : s.xyz) {
            out.box_min = out.box_min.cwiseMin(p);
            out.box_max = out.box_max.cwiseMax(p);
        }
    }
    if (!s.intensity.empty()) {
        const auto [lo, hi] = std::minmax_element(s.intensity.begin(), s.intensity.end());
        out.intensity_min = *lo;
        out.intensity_max = *hi;
    }
    const Eigen::Matrix3d r = s.pose.linear();
    out.is_rotation =
        (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() < 1e-6 &&
        r.determinant() > 0.0;
    if (out.is_rotation) out.axis_angle = Eigen::AngleAxisd(r);
    return out;
}

double raw_intensity(const Scan& s, float normalised) {
    return s.intensity_raw_min + normalised * (s.intensity_raw_max - s.intensity_raw_min);
}

std::string iso_utc(double seconds) {
    const auto t = static_cast<std::time_t>(std::floor(seconds));
    std::tm tm{};
    gmtime_r(&t, &tm);
    char buf[96];
    std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02d:%02d:%06.3fZ", tm.tm_year + 1900,
                  tm.tm_mon + 1, tm.tm_mday, tm.tm_hour, tm.tm_min,
                  tm.tm_sec + (seconds - std::floor(seconds)));
    return buf;
}

std::string vec(const Eigen::Vector3d& v, int decimals) {
    return fixed_decimals(v.x(), decimals) + " " + fixed_decimals(v.y(), decimals) + " " +
           fixed_decimals(v.z(), decimals);
}

nlohmann::json json_vec(const Eigen::Vector3d& v) {
    return {v.x(), v.y(), v.z()};
}

nlohmann::json scan_json(const Scan& s) {
    const ScanSummary m = summarise(s);
    nlohmann::json j;
    j["source"] = s.source;
    j["name"] = s.name;
    j["points"] = m.points;
    if (s.grid) {
        j["grid"] = {
            {"rows", s.grid->rows},
            {"columns", s.grid->columns},
            {"cells", s.grid->cells()},
            {"filled", m.points},
            {"fill_ratio", static_cast<double>(m.points) /
                               static_cast<double>(std::max<std::uint64_t>(s.grid->cells(), 1))}};
    } else {
        j["grid"] = nullptr;
    }
    if (s.intensity.empty()) {
        j["intensity"] = nullptr;
    } else {
        j["intensity"] = {{"min", m.intensity_min},
                          {"max", m.intensity_max},
                          {"raw_min", raw_intensity(s, m.intensity_min)},
                          {"raw_max", raw_intensity(s, m.intensity_max)},
                          {"raw_scale", {s.intensity_raw_min, s.intensity_raw_max}}};
    }
    j["colour"] = !s.rgb.empty();
    if (m.points > 0) {
        j["bounding_box"] = {{"min", json_vec(m.box_min)}, {"max", json_vec(m.box_max)}};
    } else {
        j["bounding_box"] = nullptr;
    }
    const Eigen::Matrix3d r = s.pose.linear();
    nlohmann::json pose;
    pose["position"] = json_vec(s.scanner_position());
    pose["linear"] = {json_vec(r.row(0).transpose()), json_vec(r.row(1).transpose()),
                      json_vec(r.row(2).transpose())};
    pose["is_rotation"] = m.is_rotation;
    if (m.is_rotation) {
        pose["axis"] = json_vec(m.axis_angle.axis());
        pose["angle_deg"] = m.axis_angle.angle() * 180.0 / std::numbers::pi;
    }
    j["pose"] = pose;
    if (s.acquired_utc) {
        j["acquired_utc"] = *s.acquired_utc;
        j["acquired"] = iso_utc(*s.acquired_utc);
    } else {
        j["acquired_utc"] = nullptr;
    }
    return j;
}

void print_scan(std::ostream& out, const Scan& s, std::size_t k) {
    const ScanSummary m = summarise(s);
    out << "  scan " << k + 1 << ": " << s.source;
    if (!s.name.empty()) out << " \"" << s.name << "\"";
    out << "\n    points: " << m.points << "\n";
    if (s.grid) {
        const auto cells = s.grid->cells();
        out << "    grid: " << s.grid->rows << " rows x " << s.grid->columns << " columns, "
            << m.points << " of " << cells << " cells filled ("
            << fixed_decimals(100.0 * static_cast<double>(m.points) /
                                  static_cast<double>(std::max<std::uint64_t>(cells, 1)),
                              1)
            << " %)\n";
    } else {
        out << "    grid: none (unstructured)\n";
    }
    if (s.intensity.empty()) {
        out << "    intensity: none\n";
    } else {
        out << "    intensity: " << fixed_decimals(m.intensity_min, 6) << " .. "
            << fixed_decimals(m.intensity_max, 6) << " (raw "
            << fixed_decimals(raw_intensity(s, m.intensity_min), 6) << " .. "
            << fixed_decimals(raw_intensity(s, m.intensity_max), 6) << " on the raw scale "
            << s.intensity_raw_min << " .. " << s.intensity_raw_max << ")\n";
    }
    out << "    colour: " << (s.rgb.empty() ? "no" : "yes") << "\n";
    if (m.points > 0) {
        out << "    bounding box: min " << vec(m.box_min, 4) << ", max " << vec(m.box_max, 4)
            << "\n";
    }
    out << "    scanner position: " << vec(s.scanner_position(), 4) << "\n";
    const Eigen::Matrix3d r = s.pose.linear();
    out << "    rotation: [" << vec(r.row(0).transpose(), 6) << "; " << vec(r.row(1).transpose(), 6)
        << "; " << vec(r.row(2).transpose(), 6) << "]";
    if (m.is_rotation) {
        out << ", axis " << vec(m.axis_angle.axis(), 6) << " angle "
            << fixed_decimals(m.axis_angle.angle() * 180.0 / std::numbers::pi, 4) << " deg\n";
    } else {
        out << " (not a pure rotation: scale or shear)\n";
    }
    out << "    acquired: " << (s.acquired_utc ? iso_utc(*s.acquired_utc) : "unknown") << "\n";
}

// Reports every file; returns false when at least one could not be read.
bool report(const InfoOptions& o) {
    bool all_read = true;
    nlohmann::json report = nlohmann::json::array();
    for (const auto& file : o.files) {
        try {
            const ScanFormat format = detect_format(file);
            const std::vector<Scan> scans = read_scans(file);
            if (o.json) {
                nlohmann::json j = {{"file", file}, {"format", to_string(format)}};
                j["scans"] = nlohmann::json::array();
                for (const Scan& s : scans) j["scans"].push_back(scan_json(s));
                report.push_back(j);
            } else {
                std::cout << file << "\n  format: " << to_string(format)
                          << "\n  scans: " << scans.size() << "\n";
                for (std::size_t k = 0; k < scans.size(); ++k) print_scan(std::cout, scans[k], k);
            }
        } catch (const std::exception& e) {
            all_read = false;
            std::cerr << "tlsmon info: " << e.what() << "\n";
            if (o.json) report.push_back({{"file", file}, {"error", e.what()}});
        }
    }
    if (o.json) std::cout << report.dump(2) << "\n";
    return all_read;
}

}  // namespace

int run_info(const InfoOptions& options) {
    return report(options) ? 0 : 2;
}

}  // namespace tlsmon
