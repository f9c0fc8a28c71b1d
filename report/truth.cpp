#include "report/truth.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/statistics.hpp"

namespace tlsmon::report {

namespace {

using nlohmann::json;

// The value at `key` of `j`, or an Error naming the file and the key.
const json& at(const json& j, const std::string& key, const std::filesystem::path& file,
               const std::string& path) {
    if (!j.is_object() || !j.contains(key)) {
        throw Error(file.string() + ": key '" + path + key +
                    "' missing (not a tlsmon simulator "
                    "truth file?)");
    }
    return j.at(key);
}

double number(const json& j, const std::string& key, const std::filesystem::path& file,
              const std::string& path = "") {
    const json& v = at(j, key, file, path);
    if (!v.is_number()) throw Error(file.string() + ": key '" + path + key + "' is not a number");
    return v.get<double>();
}

Eigen::Vector3d vec3(const json& j, const std::string& key, const std::filesystem::path& file,
                     const std::string& path = "") {
    const json& v = at(j, key, file, path);
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() ||
        !v[2].is_number()) {
        throw Error(file.string() + ": key '" + path + key + "' is not an array of 3 numbers");
    }
    return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
}

Eigen::Affine3d matrix4(const json& j, const std::string& key, const std::filesystem::path& file,
                        const std::string& path) {
    const json& v = at(j, key, file, path);
    Eigen::Matrix4d m;
    if (!v.is_array() || v.size() != 4) {
        throw Error(file.string() + ": key '" + path + key + "' is not a 4x4 matrix");
    }
    for (int r = 0; r < 4; ++r) {
        if (!v[r].is_array() || v[r].size() != 4) {
            throw Error(file.string() + ": key '" + path + key + "' is not a 4x4 matrix");
        }
        for (int c = 0; c < 4; ++c) m(r, c) = v[r][c].get<double>();
    }
    return Eigen::Affine3d(m);
}

TruthEpoch parse(const json& j, const std::filesystem::path& file) {
    TruthEpoch t;
    t.file = file;
    const std::string format = at(j, "format", file, "").get<std::string>();
    if (format.rfind("tlsmon-simulator-truth/", 0) != 0) {
        throw Error(file.string() + ": key 'format' is '" + format +
                    "', not a tlsmon simulator truth file");
    }
    t.epoch = static_cast<int>(number(j, "epoch", file));
    t.time_unix = static_cast<std::int64_t>(number(j, "time_unix", file));
    const json& scanner = at(j, "scanner", file, "");
    t.scanner_position = vec3(scanner, "position", file, "scanner.");
    const json& scan = at(j, "scan", file, "");
    t.missing = scan.value("missing", false);
    if (!t.missing) t.header_to_true = matrix4(scanner, "header_to_true", file, "scanner.");
    const json& pier = at(j, "pier", file, "");
    t.pier = {number(pier, "x0", file, "pier."), number(pier, "x1", file, "pier."),
              number(pier, "y0", file, "pier."), number(pier, "y1", file, "pier."),
              number(pier, "height", file, "pier.")};
    const json& d = at(j, "deformation", file, "");
    t.deformation_enabled = at(d, "enabled", file, "deformation.").get<bool>();
    t.exponent = number(d, "exponent", file, "deformation.");
    t.top_displacement = vec3(d, "top_displacement_m", file, "deformation.");
    for (const json& e : at(j, "events", file, "")) {
        const std::string type = at(e, "type", file, "events[].").get<std::string>();
        if (type == "step") {
            StepEvent s;
            s.since_epoch = static_cast<int>(number(e, "since_epoch", file, "events[step]."));
            s.z_min = number(e, "z_min", file, "events[step].");
            s.z_max = number(e, "z_max", file, "events[step].");
            s.displacement = vec3(e, "displacement", file, "events[step].");
            t.step = s;
        } else if (type == "knocked_target") {
            KnockedTarget k;
            k.since_epoch = static_cast<int>(number(e, "since_epoch", file, "events[knocked]."));
            k.target = at(e, "target", file, "events[knocked].").get<std::string>();
            k.displacement = vec3(e, "displacement", file, "events[knocked].");
            t.knocked = k;
        }
    }
    for (const json& s : at(j, "samples", file, "")) {
        t.samples.push_back({at(s, "name", file, "samples[].").get<std::string>(),
                             vec3(s, "point", file, "samples[]."),
                             vec3(s, "displacement", file, "samples[].")});
    }
    return t;
}

}  // namespace

TruthEpoch read_truth_file(const std::filesystem::path& file) {
    std::ifstream in(file);
    if (!in) throw Error("cannot read " + file.string());
    json j;
    try {
        j = json::parse(in);
    } catch (const json::parse_error& e) {
        throw Error(file.string() + ": byte " + std::to_string(e.byte) + ": not JSON");
    }
    try {
        return parse(j, file);
    } catch (const json::exception& e) {
        throw Error(file.string() + ": " + e.what());
    }
}

std::vector<TruthEpoch> read_truth_folder(const std::filesystem::path& folder) {
    std::vector<TruthEpoch> out;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(folder, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.size() > 11 && name.compare(name.size() - 11, 11, ".truth.json") == 0) {
            out.push_back(read_truth_file(entry.path()));
        }
    }
    if (ec) throw Error("cannot read the truth folder " + folder.string() + ": " + ec.message());
    if (out.empty()) throw Error("no *.truth.json in " + folder.string());
    std::sort(out.begin(), out.end(),
              [](const TruthEpoch& a, const TruthEpoch& b) { return a.epoch < b.epoch; });
    return out;
}

Eigen::Vector3d thermal_displacement(const TruthEpoch& t, const Eigen::Vector3d& p) {
    if (!t.deformation_enabled) return Eigen::Vector3d::Zero();
    const double zeta = std::clamp(p.z() / t.pier.height, 0.0, 1.0);
    const double profile = std::pow(zeta, t.exponent);
    return {t.top_displacement.x() * profile, t.top_displacement.y() * profile,
            t.top_displacement.z() * zeta};
}

Eigen::Vector3d true_displacement(const TruthEpoch& t, const Eigen::Vector3d& p) {
    Eigen::Vector3d u = thermal_displacement(t, p);
    if (t.step && p.z() >= t.step->z_min && p.z() <= t.step->z_max) u += t.step->displacement;
    return u;
}

std::optional<ZoneFace> zone_face(const PierBox& pier, const ZoneBox& box) {
    struct Face {
        const char* name;
        int axis;      // 0: x, 1: y
        double plane;  // coordinate of the face's plane on that axis
        double sign;   // outward
    };
    const Face faces[] = {{"south", 1, pier.y0, -1.0},
                          {"north", 1, pier.y1, +1.0},
                          {"west", 0, pier.x0, -1.0},
                          {"east", 0, pier.x1, +1.0}};
    // A zone around a face is a slab across it: its thin horizontal side is the face's
    // normal (a south-face box may still reach past the corner into the west face's plane).
    const Eigen::Vector3d extent = box.max - box.min;
    const int axis = extent.x() <= extent.y() ? 0 : 1;
    std::optional<ZoneFace> found;
    int count = 0;
    for (const Face& f : faces) {
        if (f.axis != axis || f.plane < box.min[f.axis] || f.plane > box.max[f.axis]) continue;
        const int other = 1 - f.axis;
        const double lo = other == 0 ? pier.x0 : pier.y0, hi = other == 0 ? pier.x1 : pier.y1;
        const double a = std::max(lo, box.min[other]), b = std::min(hi, box.max[other]);
        const double z0 = std::max(0.0, box.min.z()), z1 = std::min(pier.height, box.max.z());
        if (b - a <= 1e-9 || z1 - z0 <= 1e-9) continue;  // touches the face along a line only
        ZoneFace z;
        z.face = f.name;
        z.normal[f.axis] = f.sign;
        z.z_min = z0;
        z.z_max = z1;
        z.centre[f.axis] = f.plane;
        z.centre[other] = 0.5 * (a + b);
        z.centre.z() = 0.5 * (z0 + z1);
        found = z;
        ++count;
    }
    if (count != 1) return std::nullopt;
    return found;
}

ZoneTruth zone_truth(const TruthEpoch& reference, const TruthEpoch& epoch, const ZoneFace& face) {
    // 1 cm steps over the height (at least 201 samples): the field is smooth but for the
    // step's edges, which this resolves to a fraction of a percent of the zone.
    const int n = std::max(201, static_cast<int>((face.z_max - face.z_min) / 0.01) + 1);
    std::vector<double> along, thermal;
    along.reserve(n);
    thermal.reserve(n);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int k = 0; k < n; ++k) {
        Eigen::Vector3d p = face.centre;
        p.z() = face.z_min + (face.z_max - face.z_min) * (k + 0.5) / n;
        const Eigen::Vector3d d = true_displacement(epoch, p) - true_displacement(reference, p);
        sum += d;
        along.push_back(d.dot(face.normal));
        thermal.push_back(
            (thermal_displacement(epoch, p) - thermal_displacement(reference, p)).dot(face.normal));
    }
    ZoneTruth z;
    z.mean_vector = sum / n;
    z.normal_mean = z.mean_vector.dot(face.normal);
    z.normal_median = median(along);
    z.thermal_normal_median = median(thermal);
    return z;
}

}  // namespace tlsmon::report
