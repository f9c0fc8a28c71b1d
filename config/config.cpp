#include "config/config.hpp"

#include <arpa/inet.h>

#include <algorithm>
#include <cctype>
#include <map>
#include <set>

#include "algorithms/keypoints/opencv_features.hpp"
#include "config/alarm_rules.hpp"
#include "config/folder_overlap.hpp"
#include "config/keys.hpp"
#include "formats/coordinate_system.hpp"
#include "pipeline/keypoint_results.hpp"
#include "pipeline/m3c2_stage.hpp"
#include "pipeline/pbm3c2_stage.hpp"
#include "pipeline/primitive_stage.hpp"
#include "pipeline/vector_stage.hpp"
#include "storage/campaign_store.hpp"

namespace tlsmon {

namespace fs = std::filesystem;

namespace {

// Absolute, normal, without a trailing separator ("ingest/" is the folder "ingest").
fs::path resolve(const fs::path& p, const fs::path& base) {
    fs::path r = (p.is_absolute() ? p : base / p).lexically_normal();
    if (!r.has_filename() && r != r.root_path()) r = r.parent_path();
    return r;
}

bool is_sha256(const std::string& s) {
    return s.size() == 64 && std::all_of(s.begin(), s.end(), [](unsigned char c) {
               return std::isdigit(c) || (c >= 'a' && c <= 'f');
           });
}

// Keys of an earlier release that now live in another section.
const std::map<std::string, std::string> kMovedKeys = {
    {"plane_range_sigma_a", "station.range_sigma_a"},
    {"plane_range_sigma_b_ppm", "station.range_sigma_b_ppm"},
    {"plane_angular_sigma_arcsec", "station.angular_sigma_arcsec"},
};

// The rules of each section beyond a single key's type and range (config/keys.cpp), checked
// once the section is read; each names the key it is reported against.

void check_station(TomlFields& t, StationConfig& c) {
    if (c.name.empty() || c.name.find('/') != std::string::npos) {
        t.fail("name", "expected a non-empty station name without '/'");
    }
    if (!c.crs.empty()) {
        try {
            coordinate_system(c.crs);
        } catch (const Error& e) {
            t.fail("crs", e.what());
        }
    }
}

// As the paths are written (resolved, normal); daemon/startup_checks.cpp compares the
// folders again by identity on disk (links, bind mounts).
void check_paths(TomlFields& t, const PathsConfig& c) {
    if (const auto o = folders_overlap(c)) t.fail(o->key, o->what);
}

void check_ingest(TomlFields& t, IngestConfig& c) {
    if (c.extensions.empty()) t.fail("extensions", "expected at least one extension");
    std::set<std::string> seen;
    for (auto& e : c.extensions) {
        if (e.empty() || !std::all_of(e.begin(), e.end(),
                                      [](unsigned char ch) { return std::isalnum(ch) != 0; })) {
            t.fail("extensions", "'" + e + "' is not an extension (letters and digits, no dot)");
        }
        std::transform(e.begin(), e.end(), e.begin(),
                       [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
        if (!seen.insert(e).second) t.fail("extensions", "'" + e + "' is listed twice");
    }
    if (c.max_growing <= c.stable_seconds) {
        t.fail("max_growing", "must be longer than ingest.stable_seconds");
    }
    if (!c.reference_epoch.empty() && !is_sha256(c.reference_epoch) &&
        c.reference_epoch.find('/') != std::string::npos) {
        t.fail("reference_epoch",
               "expected a file name (no folder) or a sha256 of 64 lower-case hex digits");
    }
    if (c.retry_max < c.retry_initial) t.fail("retry_max", "must be >= ingest.retry_initial");
}

// The maps' and the scans' policies have the same tiers (storage/retention_policy.hpp).
void check_tiers(TomlFields& t, const std::string& section, double keep_all_days,
                 double keep_daily_days) {
    if (keep_daily_days < keep_all_days) {
        t.fail("keep_daily_days", "must be >= " + section + ".keep_all_days");
    }
}

bool is_ipv4(const std::string& text) {
    in_addr a{};
    return ::inet_pton(AF_INET, text.c_str(), &a) == 1;
}

// The zone quantities of the stages: all of them, or those the configuration runs.
std::set<std::string> stage_quantities(const Config* runs = nullptr) {
    std::set<std::string> q;
    if (!runs || runs->m3c2.enabled) q.insert(kM3c2Quantities.begin(), kM3c2Quantities.end());
    if (!runs || runs->pbm3c2.enabled) q.insert(kPbM3c2Quantities.begin(), kPbM3c2Quantities.end());
    if (!runs || runs->primitives.enabled)
        q.insert(kPrimitiveQuantities.begin(), kPrimitiveQuantities.end());
    if (!runs || runs->vectors.enabled)
        q.insert(kVectorQuantities.begin(), kVectorQuantities.end());
    if (!runs || runs->keypoints.enabled) {
        q.insert(kKeypointQuantities.begin(), kKeypointQuantities.end());
    }
    if (!runs || runs->registration.uses_planes()) {
        q.insert(kPlaneQuantities.begin(), kPlaneQuantities.end());
    }
    if (!runs || runs->campaign.zone_series) q.insert(kCampaignC2cMedian);
    // The thermal compensation's quantities of those it models (runs: when enabled).
    if (runs && runs->thermal.enabled) {
        for (const std::string& modelled : runs->thermal.quantities) {
            if (!q.contains(modelled)) continue;
            const ThermalQuantities t = thermal_quantities(modelled);
            q.insert({t.predicted, t.compensated, t.drift, t.spread});
        }
    }
    return q;
}

std::string listed(const std::set<std::string>& names) {
    std::string s;
    for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
    return s.empty() ? "none" : s;
}

void check_modbus(TomlFields& t, const ModbusConfig& c) {
    if (!is_ipv4(c.address)) t.fail("address", "'" + c.address + "' is not an IPv4 address");
    for (const auto& a : c.allowlist) {
        if (!is_ipv4(a)) t.fail("allowlist", "'" + a + "' is not an IPv4 address");
    }
    if (c.quantities.empty() || c.quantities.size() > 8) {
        t.fail("quantities", "expected 1 to 8 quantity names (8 slots per zone)");
    }
    std::set<std::string> seen;
    for (const auto& q : c.quantities) {
        if (q.empty()) t.fail("quantities", "expected non-empty quantity names");
        if (!seen.insert(q).second) t.fail("quantities", "'" + q + "' is listed twice");
        // A misspelt name would show NaN for ever.
        if (!stage_quantities().count(q)) {
            t.fail("quantities", "no stage produces '" + q +
                                     "' (quantities: " + listed(stage_quantities()) + ")");
        }
    }
}

void check_http(TomlFields& t, const HttpConfig& c) {
    if (!is_ipv4(c.address)) t.fail("address", "'" + c.address + "' is not an IPv4 address");
    if (c.max_event_streams >= c.threads) {
        t.fail("max_event_streams", "must be less than http.threads (" + std::to_string(c.threads) +
                                        "), or no thread is left for the pages");
    }
    if (c.certificate.empty() != c.private_key.empty()) {
        t.fail(c.certificate.empty() ? "private_key" : "certificate",
               "HTTPS needs both http.certificate and http.private_key");
    }
}

void check_m3c2(TomlFields& t, const M3c2Config& c) {
    std::set<double> seen;
    for (double r : c.normal_radii) {
        if (!seen.insert(r).second) t.fail("normal_radii", "a radius is listed twice");
    }
    if (!c.orient_to_scanner && c.orientation.norm() == 0.0) {
        t.fail("orientation", "the orientation vector must not be zero");
    }
}

void check_keypoints(TomlFields& t, const KeypointConfig& c) {
    keypoints::FeatureParameters f;
    f.detector = c.detector;
    try {
        keypoints::validate(f);  // the detector with the default descriptor
    } catch (const Error& e) {
        t.fail("detector", e.what());
    }
    f.descriptor = c.descriptor;
    try {
        keypoints::validate(f);
    } catch (const Error& e) {
        t.fail("descriptor", e.what());
    }
    static const std::set<std::string> modelled{kKeypointDx,
                                                kKeypointDy,
                                                kKeypointDz,
                                                kKeypointAlongNormal,
                                                kKeypointAlongSurfaceH,
                                                kKeypointAlongSurfaceV};
    std::set<std::string> seen;
    for (const auto& q : c.model_quantities) {
        if (!modelled.count(q)) {
            t.fail("model_quantities",
                   "'" + q +
                       "' is not a keypoint displacement quantity (keypoint_dx_m, "
                       "keypoint_dy_m, keypoint_dz_m, keypoint_along_normal_m, "
                       "keypoint_along_surface_h_m, keypoint_along_surface_v_m)");
        }
        if (!seen.insert(q).second) t.fail("model_quantities", "'" + q + "' is listed twice");
    }
}

void check_section(const std::string& section, TomlFields& t, Config& c) {
    if (section == "station") check_station(t, c.station);
    if (section == "paths") check_paths(t, c.paths);
    if (section == "ingest") check_ingest(t, c.ingest);
    if (section == "retention") {
        check_tiers(t, section, c.retention.keep_all_days, c.retention.keep_daily_days);
    }
    if (section == "archive") {
        check_tiers(t, section, c.archive.keep_all_days, c.archive.keep_daily_days);
    }
    if (section == "modbus") check_modbus(t, c.modbus);
    if (section == "http") check_http(t, c.http);
    if (section == "m3c2") check_m3c2(t, c.m3c2);
    if (section == "keypoints") check_keypoints(t, c.keypoints);
    if (section == "campaign") {
        try {
            validate(campaign_parameters(c.campaign, 0.02));
        } catch (const Error& e) {
            t.fail("min_segment_points", e.what());
        }
    }
    if (section == "registration" &&
        c.registration.global_reject_alpha > c.registration.global_alpha) {
        t.fail("global_reject_alpha", "must be <= registration.global_alpha");
    }
}

// A zone's optional `normal`: three numbers, not all zero; stored with unit length.
void read_zone_normal(TomlFields& t, ZoneConfig& z) {
    if (!t.has("normal")) return;
    std::vector<double> v;
    t.get("normal", v);
    const Eigen::Vector3d n =
        v.size() == 3 ? Eigen::Vector3d(v[0], v[1], v[2]) : Eigen::Vector3d::Zero();
    if (!(n.allFinite() && n.norm() > 0.0)) {
        t.fail("normal", "expected three numbers [x, y, z], not all zero");
    }
    const Eigen::Vector3d u = n.normalized();
    z.normal = std::array<double, 3>{u.x(), u.y(), u.z()};
}

// A [[zone]]: a box (min, max) or a prism (polygon, z), with an optional design normal.
ZoneConfig read_zone(TomlFields& t, const std::set<std::string>& taken) {
    ZoneConfig z;
    if (!t.has("name")) t.fail("name", "every [[zone]] needs a name");
    t.get("name", z.name);
    if (z.name.empty()) t.fail("name", "expected a non-empty zone name");
    if (taken.count(z.name)) t.fail("name", "zone '" + z.name + "' is defined twice");
    read_zone_normal(t, z);
    t.get("no_change", z.no_change);
    t.get("primitive", z.primitive);
    if (!z.primitive.empty()) {
        try {
            primitives::kind_from_string(z.primitive);
        } catch (const Error& e) {
            t.fail("primitive", e.what());
        }
    }
    if (t.has("polygon")) {
        if (t.has("min") || t.has("max")) {
            t.fail("polygon", "a [[zone]] is a box (min, max) or a prism (polygon, z), not both");
        }
        std::vector<std::vector<double>> rows;
        t.get("polygon", rows);
        if (rows.size() < 3) t.fail("polygon", "expected at least 3 vertices [[x, y], ...]");
        for (const auto& r : rows) {
            if (r.size() != 2) t.fail("polygon", "each vertex is [x, y] in metres");
            z.polygon.push_back({r[0], r[1]});
        }
        if (!t.has("z")) t.fail("z", "a prism [[zone]] needs z = [z_min, z_max]");
        std::vector<double> h;
        t.get("z", h);
        if (h.size() != 2 || !(h[0] < h[1]))
            t.fail("z", "expected [z_min, z_max] with z_min < z_max");
        try {
            std::vector<Eigen::Vector2d> outline;
            for (const auto& v : z.polygon) outline.emplace_back(v[0], v[1]);
            const ZoneShape shape = prism_zone(z.name, std::move(outline), h[0], h[1]);
            for (int i = 0; i < 3; ++i) {
                z.min[i] = shape.box.min()[i];
                z.max[i] = shape.box.max()[i];
            }
        } catch (const ConfigError&) {
            throw;
        } catch (const Error& e) {
            t.fail("polygon", e.what());
        }
        t.reject_unknown_keys();
        return z;
    }
    for (const char* key : {"min", "max"}) {
        if (!t.has(key)) {
            t.fail(key,
                   "every [[zone]] needs min = [x, y, z] and max = [x, y, z], or polygon and z");
        }
        std::vector<double> v;
        t.get(key, v);
        if (v.size() != 3) t.fail(key, "expected three numbers [x, y, z] in metres");
        std::copy(v.begin(), v.end(), (std::string(key) == "min" ? z.min : z.max).begin());
    }
    for (int i = 0; i < 3; ++i) {
        if (!(z.min[i] < z.max[i])) t.fail("max", "each coordinate must exceed the one in min");
    }
    t.reject_unknown_keys();
    return z;
}

// Zones with different design normals must not share a volume: a core point there would
// have two normals. Judged on the bounding boxes (a prism's bounds), which may refuse two
// prisms that only come close; touching boxes are allowed.
void check_normal_overlap(TomlFields& t, const std::vector<ZoneConfig>& earlier,
                          const ZoneConfig& z) {
    if (!z.normal) return;
    const Eigen::Vector3d n(z.normal->data());
    for (const auto& e : earlier) {
        if (!e.normal || Eigen::Vector3d(e.normal->data()).dot(n) > 1.0 - 1e-12) continue;
        bool overlap = true;
        for (int i = 0; i < 3; ++i) {
            overlap = overlap && std::max(z.min[i], e.min[i]) < std::min(z.max[i], e.max[i]);
        }
        if (overlap) {
            t.fail("normal", "zone '" + z.name + "' overlaps zone '" + e.name +
                                 "', whose normal differs: a core point cannot have two "
                                 "normals (make the zones meet without overlapping)");
        }
    }
}

constexpr std::array<Named<int>, 3> kAxes{{{0, "x"}, {1, "y"}, {2, "z"}}};

// A [[zone_bands]] table: the bands of a [[zone]] along an axis.
std::vector<ZoneConfig> read_zone_bands(TomlFields& t, const std::vector<ZoneConfig>& zones,
                                        const std::set<std::string>& taken) {
    if (!t.has("zone")) t.fail("zone", "every [[zone_bands]] names the [[zone]] it cuts");
    std::string base_name;
    t.get("zone", base_name);
    const auto base = std::find_if(zones.begin(), zones.end(), [&](const ZoneConfig& z) {
        return z.name == base_name && z.band_of.empty();
    });
    if (base == zones.end()) t.fail("zone", "no [[zone]] named '" + base_name + "'");
    int axis = 2;
    t.get_choice("axis", axis, kAxes);
    if (!t.has("height")) t.fail("height", "every [[zone_bands]] needs the band height in metres");
    double height = 1.0;
    t.get("height", height, 0.01, 1e4);
    double from = base->min[axis], to = base->max[axis];
    t.get("from", from, -1e7, 1e7);
    t.get("to", to, -1e7, 1e7);
    if (!(from < to)) t.fail("to", "must exceed `from`");
    t.reject_unknown_keys();
    std::vector<ZoneConfig> out;
    try {
        for (const ZoneShape& band : bands_of(zone_shape(*base), axis, height, from, to)) {
            if (taken.count(band.name)) t.fail("zone", "zone '" + band.name + "' is defined twice");
            ZoneConfig z = *base;
            z.name = band.name;
            z.band_of = base->name;
            for (int i = 0; i < 3; ++i) {
                z.min[i] = band.box.min()[i];
                z.max[i] = band.box.max()[i];
            }
            out.push_back(std::move(z));
        }
    } catch (const ConfigError&) {
        throw;
    } catch (const Error& e) {
        t.fail("height", e.what());
    }
    return out;
}

TargetConfig read_target(TomlFields& t, const std::set<std::string>& taken) {
    TargetConfig g;
    if (!t.has("name")) t.fail("name", "every [[target]] needs a name");
    t.get("name", g.name);
    if (g.name.empty()) t.fail("name", "expected a non-empty target name");
    if (taken.count(g.name)) t.fail("name", "target '" + g.name + "' is defined twice");
    std::string kind = "sphere";
    t.get_choice("kind", kind, std::vector<std::string>{"sphere", "checkerboard"});
    g.kind = kind == "sphere" ? TargetKind::sphere : TargetKind::checkerboard;
    t.get("radius", g.radius, 0.01, 1.0);
    t.get("size", g.size, 0.05, 5.0);
    std::string mount = "below";
    t.get_choice("mount", mount, std::vector<std::string>{"below", "above", "none"});
    g.mount = mount == "below"   ? Eigen::Vector3d(-Eigen::Vector3d::UnitZ())
              : mount == "above" ? Eigen::Vector3d(Eigen::Vector3d::UnitZ())
                                 : Eigen::Vector3d::Zero();
    t.get("mount_cap_deg", g.mount_cap_deg, 0.0, 80.0);
    const auto vec = [&](const char* key) {
        std::vector<double> v;
        t.get(key, v);
        if (v.size() != 3) t.fail(key, "expected three numbers [x, y, z] in metres");
        return Eigen::Vector3d(v[0], v[1], v[2]);
    };
    if (!t.has("approximate")) {
        t.fail("approximate", "every [[target]] needs approximate = [x, y, z] (project frame)");
    }
    g.approximate = vec("approximate");
    if (t.has("surveyed")) g.surveyed = vec("surveyed");
    t.get("surveyed_sigma", g.surveyed_sigma, 1e-6, 0.1);
    t.reject_unknown_keys();
    return g;
}

StableRegion read_stable_region(TomlFields& t, const std::set<std::string>& taken) {
    StableRegion r;
    if (!t.has("name")) t.fail("name", "every [[stable_region]] needs a name");
    t.get("name", r.name);
    if (r.name.empty()) t.fail("name", "expected a non-empty stable region name");
    if (taken.count(r.name)) t.fail("name", "stable region '" + r.name + "' is defined twice");
    for (const char* key : {"min", "max"}) {
        if (!t.has(key)) {
            t.fail(key, "every [[stable_region]] needs min = [x, y, z] and max = [x, y, z]");
        }
        std::vector<double> v;
        t.get(key, v);
        if (v.size() != 3) t.fail(key, "expected three numbers [x, y, z] in metres");
        (std::string(key) == "min" ? r.min : r.max) = Eigen::Vector3d(v[0], v[1], v[2]);
    }
    for (int i = 0; i < 3; ++i) {
        if (!(r.min[i] < r.max[i])) t.fail("max", "each coordinate must exceed the one in min");
    }
    t.reject_unknown_keys();
    return r;
}

// Relative paths (defaults included) resolve against the configuration's folder.
void resolve_paths(Config& c, const fs::path& base) {
    c.paths.ingest = resolve(c.paths.ingest, base);
    c.paths.archive = resolve(c.paths.archive, base);
    c.paths.quarantine = resolve(c.paths.quarantine, base);
    c.paths.database = resolve(c.paths.database, base);
    if (!c.logging.file.empty()) c.logging.file = resolve(c.logging.file, base);
}

Config parse_table(const toml::table& root, const std::string& source, const fs::path& base) {
    Config c;
    c.file = source;
    TomlFields top(root, source);
    // Zones first: the alarm rules name them.
    std::set<std::string> zone_names;
    for (auto& t : top.array_of_tables("zone")) {
        ZoneConfig z = read_zone(t, zone_names);
        check_normal_overlap(t, c.zones, z);
        zone_names.insert(z.name);
        c.zones.push_back(std::move(z));
    }
    for (auto& t : top.array_of_tables("zone_bands")) {
        for (auto& band : read_zone_bands(t, c.zones, zone_names)) {
            zone_names.insert(band.name);
            c.zones.push_back(std::move(band));
        }
    }
    for (const std::string& section : config_sections()) {
        auto t = top.table(section);
        if (!t) continue;
        for (const ConfigKey& k : config_keys()) {
            if (k.section == section) k.read(*t, c);
        }
        if (section == "paths") resolve_paths(c, base);
        if (section == "http" && !c.http.web_root.empty())
            c.http.web_root = resolve(c.http.web_root, base);
        if (section == "http") {
            for (auto* file : {&c.http.users_file, &c.http.certificate, &c.http.private_key})
                if (!file->empty()) *file = resolve(*file, base);
        }
        check_section(section, *t, c);
        // [m3c2], [keypoints] and [campaign] come before [alarm]: a rule names what their
        // stages write.
        if (section == "alarm") {
            c.alarm.rules = read_alarm_rules(*t, zone_names, stage_quantities(&c));
        }
        if (section == "notify") read_notify_tables(*t, c.notify, base);
        if (section == "central") check_central(*t, c.central, base);
        if (section == "thermal") {
            check_thermal(*t, c.thermal);
            const std::set<std::string> stored = stage_quantities(&c);
            for (const std::string& q : c.thermal.quantities)
                if (c.thermal.enabled && !stored.contains(q))
                    t->fail("quantities", "'" + q +
                                              "' is not a zone quantity of the stages that "
                                              "run; they store: " +
                                              listed(stored));
            for (const std::string& z : c.thermal.zones)
                if (!zone_names.contains(z)) t->fail("zones", "no [[zone]] is named '" + z + "'");
        }
        t->reject_unknown_keys(kMovedKeys);
    }
    resolve_paths(c, base);
    std::set<std::string> target_names;
    for (auto& t : top.array_of_tables("target")) {
        c.registration.targets.push_back(read_target(t, target_names));
        target_names.insert(c.registration.targets.back().name);
    }
    for (auto& t : top.array_of_tables("instrument"))
        c.instruments.push_back(read_instrument(t, c.instruments));
    std::set<std::string> region_names;
    for (auto& t : top.array_of_tables("stable_region")) {
        c.icp.regions.push_back(read_stable_region(t, region_names));
        region_names.insert(c.icp.regions.back().name);
    }
    // The ICP's stable regions leave the check zones out, so their check stays independent
    // of the datum (the planes and the stable areas leave out every zone).
    for (const ZoneConfig& z : c.zones) {
        if (z.no_change && z.band_of.empty())
            c.icp.excluded.push_back(
                {z.name, Eigen::Vector3d(z.min.data()), Eigen::Vector3d(z.max.data())});
    }
    if (c.icp.mode != IcpMode::off && c.icp.regions.empty()) {
        if (auto t = top.table("registration")) {
            t->fail("icp", "needs at least one [[stable_region]] table (ICP runs on them only)");
        }
    }
    top.reject_unknown_keys();
    return c;
}

std::string triple(const std::array<double, 3>& v) {
    std::string s = "[";
    s += toml_number(v[0]) + ", " + toml_number(v[1]) + ", " + toml_number(v[2]) + "]";
    return s;
}

}  // namespace

Config load_config(const fs::path& path) {
    const toml::table root = parse_toml_file(path);
    const fs::path base = fs::absolute(path).parent_path();
    return parse_table(root, path.string(), base);
}

Config parse_config(std::string_view text, const std::string& source_name,
                    const fs::path& base_dir) {
    const toml::table root = parse_toml_string(text, source_name);
    return parse_table(root, source_name, base_dir);
}

std::vector<std::string> describe(const Config& c) {
    std::vector<std::string> l;
    for (const ConfigKey& k : config_keys()) {
        l.push_back(k.section + "." + k.name + " = " + k.value(c));
    }
    for (const auto& z : c.zones) {
        std::string line = "zone " + toml_string(z.name) + ": ";
        if (z.polygon.empty()) {
            line += "min = " + triple(z.min) + ", max = " + triple(z.max);
        } else {
            line += "polygon = [";
            for (std::size_t k = 0; k < z.polygon.size(); ++k) {
                line += (k ? ", [" : "[") + toml_number(z.polygon[k][0]) + ", " +
                        toml_number(z.polygon[k][1]) + "]";
            }
            line += "], z = [" + toml_number(z.min[2]) + ", " + toml_number(z.max[2]) + "]";
        }
        if (z.normal) line += ", normal = " + triple(*z.normal);
        if (z.no_change) line += ", no_change = true";
        if (!z.band_of.empty()) {
            line += " (band of " + toml_string(z.band_of) + ", bounds min = " + triple(z.min) +
                    ", max = " + triple(z.max) + ")";
        }
        l.push_back(line);
    }
    for (const auto& g : c.registration.targets) {
        const auto& a = g.approximate;
        l.push_back("target " + toml_string(g.name) + ": kind = " + to_string(g.kind) +
                    ", approximate = " + triple({a.x(), a.y(), a.z()}) +
                    (g.surveyed ? ", surveyed" : ""));
    }
    for (const auto& r : c.icp.regions) {
        l.push_back("stable_region " + toml_string(r.name) +
                    ": min = " + triple({r.min.x(), r.min.y(), r.min.z()}) +
                    ", max = " + triple({r.max.x(), r.max.y(), r.max.z()}));
    }
    for (const auto& i : c.instruments) l.push_back(describe(i));
    for (const auto& r : c.alarm.rules) l.push_back(describe_alarm_rule(r));
    for (auto& line : describe_notify_tables(c.notify)) l.push_back(std::move(line));
    return l;
}

namespace {

M3c2Config with_zone_shapes(const Config& config) {
    M3c2Config m = config.m3c2;
    m.zones.clear();
    for (const auto& z : config.zones) m.zones.push_back(zone_shape(z));
    return m;
}

RegistrationConfig with_zones(const Config& config) {
    RegistrationConfig r = config.registration;
    r.icp = config.icp;
    r.planes = config.planes;
    r.planes.noise = config.station;
    r.icp.noise = config.station;
    r.stable_areas = config.stable_areas;
    r.zones = with_zone_shapes(config).zones;
    return r;
}

PbM3c2Config pbm3c2_with_zone_shapes(const Config& config) {
    PbM3c2Config p = config.pbm3c2;
    p.segmentation = config.stable_areas;
    p.zones = with_zone_shapes(config).zones;
    return p;
}

VectorConfig vectors_with_zone_shapes(const Config& config) {
    VectorConfig v = config.vectors;
    v.segmentation = config.stable_areas;
    v.zones = with_zone_shapes(config).zones;
    return v;
}

PrimitivesConfig primitives_with_zones(const Config& config) {
    PrimitivesConfig p = config.primitives;
    p.noise = config.station;
    p.zones.clear();
    for (const auto& z : config.zones) {
        if (!z.primitive.empty())
            p.zones.push_back({zone_shape(z), primitives::kind_from_string(z.primitive)});
    }
    return p;
}

KeypointConfig keypoints_with_zone_shapes(const Config& config) {
    KeypointConfig k = config.keypoints;
    k.noise = config.station;
    k.zones.clear();
    for (const auto& z : config.zones) k.zones.push_back(zone_shape(z));
    return k;
}

}  // namespace

ZoneShape zone_shape(const ZoneConfig& z) {
    const Eigen::Vector3d min(z.min[0], z.min[1], z.min[2]), max(z.max[0], z.max[1], z.max[2]);
    ZoneShape s;
    if (z.polygon.empty()) {
        s = box_zone(z.name, min, max);
    } else {
        std::vector<Eigen::Vector2d> polygon;
        for (const auto& v : z.polygon) polygon.emplace_back(v[0], v[1]);
        s = prism_zone(z.name, std::move(polygon), min.z(), max.z());
        // A band of a prism: the polygon with the band's cut of the bounds.
        s.box = Eigen::AlignedBox3d(min, max);
    }
    if (z.normal) s.normal = Eigen::Vector3d(z.normal->data());
    return s;
}

PipelineConfig pipeline_config(const Config& config) {
    return PipelineConfig{.archive = config.paths.archive,
                          .quarantine = config.paths.quarantine,
                          .archive_mode = config.ingest.archive,
                          .reference_epoch = config.ingest.reference_epoch,
                          .coverage = config.coverage,
                          .registration = with_zones(config),
                          .meteo = config.meteo,
                          .m3c2 = with_zone_shapes(config),
                          .pbm3c2 = pbm3c2_with_zone_shapes(config),
                          .primitives = primitives_with_zones(config),
                          .vectors = vectors_with_zone_shapes(config),
                          .keypoints = keypoints_with_zone_shapes(config),
                          .thermal = config.thermal,
                          .zones = with_zone_shapes(config).zones,
                          .stages = {},
                          .alarm_rules = config.alarm.rules};
}

}  // namespace tlsmon
