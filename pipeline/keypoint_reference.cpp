#include "pipeline/keypoint_reference.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>

#include "core/error.hpp"
#include "core/payload.hpp"

namespace tlsmon {

namespace {

using namespace keypoints;

void put_vector(PayloadWriter& w, const Eigen::Vector3d& v) {
    w.put<double>(v.x());
    w.put<double>(v.y());
    w.put<double>(v.z());
}

Eigen::Vector3d get_vector(PayloadReader& r) {
    Eigen::Vector3d v;
    v.x() = r.get<double>();
    v.y() = r.get<double>();
    v.z() = r.get<double>();
    return v;
}

void put_text(PayloadWriter& w, const std::string& s) {
    w.put_array(std::vector<char>(s.begin(), s.end()));
}

std::string get_text(PayloadReader& r) {
    const auto v = r.get_array<char>();
    return std::string(v.begin(), v.end());
}

void put_scan(PayloadWriter& w, const KeypointScanReference& s) {
    w.put_array(s.features.keypoints);
    w.put<std::uint8_t>(s.features.descriptors.binary ? 1 : 0);
    w.put<std::uint64_t>(s.features.descriptors.length);
    w.put_array(s.features.descriptors.bits);
    w.put_array(s.features.descriptors.values);
    w.put_array(s.positions);
    w.put_array(s.anchor_rows);
    w.put_array(s.anchor_columns);
    w.put_array(s.patches);
    w.put_array(s.polar);
    std::vector<double> flat;
    flat.reserve(3 * s.points.size());
    for (const auto& p : s.points) flat.insert(flat.end(), {p.x(), p.y(), p.z()});
    w.put_array(flat);
    w.put<double>(s.angular_step);
    w.put<std::uint64_t>(s.detected);
}

KeypointScanReference get_scan(PayloadReader& in, int patch_radius) {
    KeypointScanReference s;
    s.features.keypoints = in.get_array<Keypoint>();
    s.features.descriptors.binary = in.get<std::uint8_t>() != 0;
    s.features.descriptors.length = in.get<std::uint64_t>();
    s.features.descriptors.bits = in.get_array<std::uint8_t>();
    s.features.descriptors.values = in.get_array<float>();
    s.positions = in.get_array<AngularPosition>();
    s.anchor_rows = in.get_array<double>();
    s.anchor_columns = in.get_array<double>();
    s.patches = in.get_array<float>();
    s.polar = in.get_array<Polar>();
    const auto flat = in.get_array<double>();
    if (flat.size() % 3 != 0) throw Error("keypoints stage payload: a point without 3 coordinates");
    for (std::size_t i = 0; i < flat.size(); i += 3)
        s.points.emplace_back(flat[i], flat[i + 1], flat[i + 2]);
    s.angular_step = in.get<double>();
    s.detected = in.get<std::uint64_t>();
    const std::size_t n = s.size();
    const auto side = static_cast<std::size_t>(2 * patch_radius + 1);
    if (s.features.descriptors.count() != n || s.positions.size() != n || s.polar.size() != n ||
        s.points.size() != n || s.anchor_rows.size() != n || s.anchor_columns.size() != n ||
        s.patches.size() != (patch_radius > 0 ? n * side * side : 0)) {
        throw Error(
            "keypoints stage payload: keypoints, descriptors and positions differ in number");
    }
    return s;
}

}  // namespace

std::size_t KeypointReference::keypoints() const {
    return std::accumulate(scans.begin(), scans.end(), std::size_t{0},
                           [](std::size_t n, const auto& s) { return n + s.size(); });
}

std::size_t KeypointReference::detected() const {
    return std::accumulate(scans.begin(), scans.end(), std::size_t{0},
                           [](std::size_t n, const auto& s) { return n + s.detected; });
}

std::string KeypointReference::encode() const {
    PayloadWriter w;
    w.put<std::uint32_t>(kFormatVersion);
    w.put<std::int32_t>(patch_radius);
    w.put<double>(prefilter_px);
    w.put<std::uint64_t>(scans.size());
    for (const auto& s : scans) put_scan(w, s);
    put_vector(w, scanner);
    w.put<double>(seconds);
    w.put<std::uint64_t>(zone_names.size());
    for (std::size_t z = 0; z < zone_names.size(); ++z) {
        put_text(w, zone_names[z]);
        const WallFrame& f = walls[z];
        put_vector(w, f.centroid);
        put_vector(w, f.normal);
        put_vector(w, f.horizontal);
        put_vector(w, f.vertical);
        w.put<double>(f.rms);
        w.put<std::uint64_t>(f.points);
        w.put<std::uint8_t>(f.horizontal_surface ? 1 : 0);
        put_text(w, f.undefined_reason);
        const std::vector<float> none;
        const auto& cells = z < wall_cells.size() ? wall_cells[z] : none;
        w.put<std::uint64_t>(cells.size());
        for (const float e : cells) w.put<float>(e);
    }
    return w.take();
}

KeypointReference KeypointReference::decode(std::string_view payload) {
    PayloadReader in(payload);
    if (const auto version = in.get<std::uint32_t>(); version != kFormatVersion) {
        throw Error("keypoints stage payload: format " + std::to_string(version) + ", expected " +
                    std::to_string(kFormatVersion));
    }
    KeypointReference r;
    r.patch_radius = in.get<std::int32_t>();
    if (r.patch_radius < 0) throw Error("keypoints stage payload: a negative patch radius");
    r.prefilter_px = in.get<double>();
    if (!(r.prefilter_px >= 0)) throw Error("keypoints stage payload: a negative prefilter");
    const auto scans = in.get<std::uint64_t>();
    if (scans > payload.size()) throw Error("keypoints stage payload: too many scans");
    for (std::uint64_t s = 0; s < scans; ++s) r.scans.push_back(get_scan(in, r.patch_radius));
    r.scanner = get_vector(in);
    r.seconds = in.get<double>();
    const auto zones = in.get<std::uint64_t>();
    if (zones > payload.size()) throw Error("keypoints stage payload: too many zones");
    for (std::uint64_t z = 0; z < zones; ++z) {
        r.zone_names.push_back(get_text(in));
        WallFrame f;
        f.centroid = get_vector(in);
        f.normal = get_vector(in);
        f.horizontal = get_vector(in);
        f.vertical = get_vector(in);
        f.rms = in.get<double>();
        f.points = in.get<std::uint64_t>();
        f.horizontal_surface = in.get<std::uint8_t>() != 0;
        f.undefined_reason = get_text(in);
        r.walls.push_back(std::move(f));
        const auto cells = in.get<std::uint64_t>();
        if (cells > payload.size()) throw Error("keypoints stage payload: too many wall cells");
        std::vector<float> elevations(cells);
        for (auto& e : elevations) e = in.get<float>();
        r.wall_cells.push_back(std::move(elevations));
    }
    in.finish();
    return r;
}

}  // namespace tlsmon
