#include "simulator/scene_file.hpp"

#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "simulator/render.hpp"
#include "simulator/target_layout.hpp"

namespace tlsmon {

namespace {

constexpr double kBig = 1e6;

void get_vector3(TomlFields& f, const std::string& key, Eigen::Vector3d& v, double limit) {
    if (!f.has(key)) return;  // the default stands
    std::vector<double> a;
    f.get(key, a);
    if (a.size() != 3) f.fail(key, "expected [x, y, z]");
    for (const double x : a) {
        if (std::abs(x) > limit) f.fail(key, "value outside ±" + std::to_string(limit));
    }
    v = {a[0], a[1], a[2]};
}

void get_seed(TomlFields& f, const std::string& key, std::uint64_t& seed) {
    std::int64_t s = static_cast<std::int64_t>(seed);
    f.get(key, s, 0, std::numeric_limits<std::int64_t>::max());
    seed = static_cast<std::uint64_t>(s);
}

// A grid over sim::max_scan_cells is refused here, naming `key`, rather than at rendering.
void check_cells(TomlFields& f, const std::string& key, const sim::Scanner& s) {
    const double cells =
        (std::floor((s.azimuth_max_deg - s.azimuth_min_deg) / s.azimuth_step_deg) + 1) *
        (std::floor((s.elevation_max_deg - s.elevation_min_deg) / s.elevation_step_deg) + 1);
    if (cells > static_cast<double>(sim::max_scan_cells)) {
        f.fail(key, "the window and steps give " + std::to_string(cells / 1e6) +
                        " M cells, over the " + std::to_string(sim::max_scan_cells / 1000000) +
                        " M allowed");
    }
}

// [[scanner.detail]]: a window inside the scanner's reach at its own step.
sim::DetailScan read_detail(TomlFields& f, const sim::Scanner& overview) {
    sim::DetailScan d;
    f.get("name", d.name);
    if (d.name.empty() || d.name.find_first_of("/\\ _#") != std::string::npos) {
        f.fail("name", "expected a non-empty name without '/', '\\', ' ', '_' or '#'");
    }
    for (const char* key :
         {"azimuth_min_deg", "azimuth_max_deg", "elevation_min_deg", "elevation_max_deg"}) {
        if (!f.has(key)) f.fail(key, "required: a detail scan has no default window");
    }
    f.get("azimuth_min_deg", d.azimuth_min_deg, -360.0, 360.0);
    f.get("azimuth_max_deg", d.azimuth_max_deg, -360.0, 360.0);
    f.get("elevation_min_deg", d.elevation_min_deg, -90.0, 90.0);
    f.get("elevation_max_deg", d.elevation_max_deg, -90.0, 90.0);
    f.get("step_deg", d.step_deg, 0.001, 10.0);
    if (d.azimuth_max_deg <= d.azimuth_min_deg)
        f.fail("azimuth_max_deg", "must exceed azimuth_min_deg");
    if (d.elevation_max_deg <= d.elevation_min_deg) {
        f.fail("elevation_max_deg", "must exceed elevation_min_deg");
    }
    check_cells(f, "step_deg", sim::detail_scanner(overview, d));
    f.reject_unknown_keys();
    return d;
}

void read_scanner(TomlFields& f, sim::Scanner& s) {
    f.get("station", s.station);
    if (s.station.empty() || s.station.find_first_of("/\\ _") != std::string::npos) {
        f.fail("station", "expected a non-empty name without '/', '\\', ' ' or '_'");
    }
    get_vector3(f, "position", s.position, kBig);
    f.get("heading_deg", s.heading_deg, -360.0, 360.0);
    f.get("azimuth_min_deg", s.azimuth_min_deg, -360.0, 360.0);
    f.get("azimuth_max_deg", s.azimuth_max_deg, -360.0, 360.0);
    f.get("elevation_min_deg", s.elevation_min_deg, -90.0, 90.0);
    f.get("elevation_max_deg", s.elevation_max_deg, -90.0, 90.0);
    f.get("azimuth_step_deg", s.azimuth_step_deg, 0.001, 10.0);
    f.get("elevation_step_deg", s.elevation_step_deg, 0.001, 10.0);
    f.get("max_range", s.max_range, 1.0, 10000.0);
    f.get("min_return", s.min_return, 0.0, 1.0);
    if (s.azimuth_max_deg <= s.azimuth_min_deg)
        f.fail("azimuth_max_deg", "must exceed azimuth_min_deg");
    if (s.elevation_max_deg <= s.elevation_min_deg) {
        f.fail("elevation_max_deg", "must exceed elevation_min_deg");
    }
    check_cells(f, "azimuth_step_deg", s);
    if (f.has("detail")) {
        s.details.clear();
        for (TomlFields& d : f.array_of_tables("detail")) s.details.push_back(read_detail(d, s));
    }
    f.reject_unknown_keys();
}

void read_beam(TomlFields& f, sim::Beam& b) {
    f.get("footprint", b.footprint);
    f.get("exit_diameter", b.exit_diameter, 0.0, 1.0);
    f.get("divergence_mrad", b.divergence_mrad, 0.0, 100.0);
    f.reject_unknown_keys();
}

void read_noise(TomlFields& f, sim::Noise& n) {
    f.get("enabled", n.enabled);
    std::string model = n.model == sim::Noise::Model::constant ? "constant" : "signal";
    f.get_choice("model", model, {"constant", "signal"});
    n.model = model == "constant" ? sim::Noise::Model::constant : sim::Noise::Model::signal;
    f.get("range_a", n.range_a, 0.0, 1.0);
    f.get("range_b_ppm", n.range_b_ppm, 0.0, 10000.0);
    f.get("signal_a", n.signal_a, 0.0, 1.0);
    f.get("signal_b_ppm", n.signal_b_ppm, 0.0, 10000.0);
    f.get("angular_arcsec", n.angular_arcsec, 0.0, 3600.0);
    f.get("intensity_sigma", n.intensity_sigma, 0.0, 1.0);
    get_seed(f, "seed", n.seed);
    f.reject_unknown_keys();
}

void read_drift(TomlFields& f, sim::Drift& d) {
    f.get("enabled", d.enabled);
    f.get("yaw_amplitude_arcsec", d.yaw_amplitude_arcsec, 0.0, 36000.0);
    f.get("yaw_period_hours", d.yaw_period_hours, 0.01, 1e5);
    f.get("yaw_jitter_arcsec", d.yaw_jitter_arcsec, 0.0, 3600.0);
    f.get("tilt_amplitude_arcsec", d.tilt_amplitude_arcsec, 0.0, 3600.0);
    f.get("tilt_jitter_arcsec", d.tilt_jitter_arcsec, 0.0, 3600.0);
    f.get("translation_sigma", d.translation_sigma, 0.0, 1.0);
    f.reject_unknown_keys();
}

void read_pier(TomlFields& f, sim::Pier& p) {
    f.get("x0", p.x0, -kBig, kBig);
    f.get("x1", p.x1, -kBig, kBig);
    f.get("y0", p.y0, -kBig, kBig);
    f.get("y1", p.y1, -kBig, kBig);
    f.get("height", p.height, 0.1, 1000.0);
    f.get("diameter", p.diameter, 0.0, 100.0);
    if (p.x1 <= p.x0) f.fail("x1", "must exceed x0");
    if (p.y1 <= p.y0) f.fail("y1", "must exceed y0");
    if (p.diameter > std::min(p.x1 - p.x0, p.y1 - p.y0))
        f.fail("diameter", "must fit in the box x0..x1, y0..y1 (it stands at its centre)");
    f.reject_unknown_keys();
}

void read_deck(TomlFields& f, sim::Deck& d) {
    f.get("enabled", d.enabled);
    f.get("overhang", d.overhang, 0.0, 1000.0);
    f.get("half_length", d.half_length, 0.0, 10000.0);
    f.get("thickness", d.thickness, 0.01, 100.0);
    f.reject_unknown_keys();
}

sim::Target read_target(TomlFields& f, const sim::Site& site) {
    // Either `centre`, or a set-out place: `distance` (horizontal) or `range` (slant), with
    // `azimuth_deg` and `height` above what the mount stands on (target_layout.hpp).
    sim::TargetPlacement p;
    f.get("name", p.name);
    if (p.name.empty()) f.fail("name", "every target needs a name");
    std::string kind = "sphere";
    f.get_choice("kind", kind, {"sphere", "checkerboard"});
    p.kind = kind == "sphere" ? sim::Target::Kind::sphere : sim::Target::Kind::checkerboard;
    std::string mount = "none";
    f.get_choice("mount", mount, {"none", "mast", "stand", "abutment"});
    p.mount = mount == "mast"       ? sim::Target::Mount::mast
              : mount == "stand"    ? sim::Target::Mount::stand
              : mount == "abutment" ? sim::Target::Mount::abutment
                                    : sim::Target::Mount::none;
    f.get("radius", p.radius, 0.001, 10.0);
    f.get("size", p.size, 0.01, 10.0);
    const bool placed = f.has("distance") || f.has("range");
    if (f.has("centre") == placed) {
        f.fail(placed ? "centre" : "name",
               "give a target either `centre` or `distance`/`range` with `azimuth_deg` and "
               "`height`");
    }
    if (f.has("distance") && f.has("range"))
        f.fail("range", "give `distance` or `range`, not both");
    try {
        if (placed) {
            f.get("distance", p.distance, 0.01, kBig);
            f.get("range", p.range, 0.01, kBig);
            if (!f.has("azimuth_deg")) f.fail("azimuth_deg", "a placed target needs azimuth_deg");
            f.get("azimuth_deg", p.azimuth_deg, -360.0, 360.0);
            f.get("height", p.height, -1000.0, 1000.0);
            f.reject_unknown_keys();
            return sim::place_target(site, p);
        }
        sim::Target t;
        t.name = p.name;
        t.kind = p.kind;
        t.radius = p.radius;
        t.size = p.size;
        t.mount = p.mount;
        get_vector3(f, "centre", t.centre, kBig);
        f.reject_unknown_keys();
        t.base_z = sim::target_base_z(site, t);
        return t;
    } catch (const ConfigError&) {
        throw;
    } catch (const Error& e) {
        f.fail(placed ? "azimuth_deg" : "centre", e.what());
    }
}

// ---- Terrain, stable blocks, occluders and vegetation (docs/simulator.md "Terrain") ----

void get_vector2(TomlFields& f, const std::string& key, Eigen::Vector2d& v) {
    if (!f.has(key)) return;
    std::vector<double> a;
    f.get(key, a);
    if (a.size() != 2) f.fail(key, "expected [x, y]");
    for (const double x : a) {
        if (std::abs(x) > kBig) f.fail(key, "value outside ±1e6");
    }
    v = {a[0], a[1]};
}

void read_terrain(TomlFields& f, sim::Terrain& t) {
    f.get("profile_y", t.profile_y);
    f.get("profile_z", t.profile_z);
    if (f.has("profile_y") != f.has("profile_z")) {
        f.fail(f.has("profile_y") ? "profile_z" : "profile_y",
               "profile_y and profile_z are given together");
    }
    if (t.profile_y.empty() || t.profile_y.size() != t.profile_z.size()) {
        f.fail("profile_z", "expected as many heights as profile_y values (at least one)");
    }
    for (std::size_t k = 1; k < t.profile_y.size(); ++k) {
        if (!(t.profile_y[k] > t.profile_y[k - 1])) f.fail("profile_y", "values must increase");
    }
    for (const double v : t.profile_z) {
        if (std::abs(v) > 1e4) f.fail("profile_z", "value outside ±10000");
    }
    f.get("albedo", t.albedo, 0.0, 1.0);
    f.get("roughness", t.roughness, 0.0, 1.0);
    f.get("roughness_wavelength", t.roughness_wavelength, 0.01, 100.0);
    f.get("creep_from_epoch", t.creep.from_epoch, -1, 1000000);
    get_vector2(f, "creep_centre", t.creep.centre);
    f.get("creep_radius", t.creep.radius, 0.01, 1000.0);
    get_vector3(f, "creep_rate_m", t.creep.rate, 1.0);
    f.reject_unknown_keys();
}

sim::Block read_block(TomlFields& f) {
    sim::Block b;
    f.get("name", b.name);
    if (b.name.empty()) f.fail("name", "every block needs a name");
    std::string kind = "foundation";
    f.get_choice("kind", kind, {"foundation", "abutment", "wall"});
    b.kind = kind == "abutment" ? sim::Block::Kind::abutment
             : kind == "wall"   ? sim::Block::Kind::wall
                                : sim::Block::Kind::foundation;
    if (!f.has("lo") || !f.has("hi")) f.fail("lo", "a block needs corners lo and hi [x, y, z]");
    get_vector3(f, "lo", b.lo, kBig);
    get_vector3(f, "hi", b.hi, kBig);
    if (!(b.hi.array() > b.lo.array()).all()) f.fail("hi", "must exceed lo on every axis");
    f.get("yaw_deg", b.yaw_deg, -360.0, 360.0);
    f.get("albedo", b.albedo, 0.0, 1.0);
    f.get("moves_from_epoch", b.motion.from_epoch, -1, 1000000);
    get_vector3(f, "motion_m", b.motion.translation, 1.0);
    get_vector3(f, "motion_arcsec", b.motion.rotation_arcsec, 36000.0);
    f.reject_unknown_keys();
    return b;
}

sim::Occluder read_occluder(TomlFields& f) {
    sim::Occluder o;
    f.get("name", o.name);
    if (o.name.empty()) f.fail("name", "every occluder needs a name");
    std::string kind = "person";
    f.get_choice("kind", kind, {"person", "vehicle"});
    o.kind = kind == "vehicle" ? sim::Occluder::Kind::vehicle : sim::Occluder::Kind::person;
    if (o.kind == sim::Occluder::Kind::vehicle) {
        o.length = 5.0, o.width = 2.0, o.height = 2.3;
    }
    f.get("probability", o.probability, 0.0, 1.0);
    if (!f.has("path_start") || !f.has("path_end")) {
        f.fail("path_start", "an occluder needs path_start and path_end [x, y]");
    }
    get_vector2(f, "path_start", o.path_start);
    get_vector2(f, "path_end", o.path_end);
    f.get("length", o.length, 0.01, 100.0);
    f.get("width", o.width, 0.01, 100.0);
    f.get("height", o.height, 0.01, 100.0);
    f.get("albedo", o.albedo, 0.0, 1.0);
    f.reject_unknown_keys();
    return o;
}

sim::Vegetation read_vegetation(TomlFields& f) {
    sim::Vegetation v;
    f.get("name", v.name);
    if (v.name.empty()) f.fail("name", "every vegetation patch needs a name");
    if (!f.has("centre")) f.fail("centre", "a vegetation patch needs a centre [x, y]");
    get_vector2(f, "centre", v.centre);
    get_vector3(f, "radii", v.radii, 100.0);
    if (!(v.radii.array() > 0.0).all()) f.fail("radii", "every half-axis must be > 0");
    f.get("leaf_spacing", v.leaf_spacing, 0.01, 1.0);
    f.get("leaf_radius", v.leaf_radius, 0.001, 0.5);
    f.get("density", v.density, 0.0, 1.0);
    f.get("sway", v.sway, 0.0, 0.5);
    f.get("albedo", v.albedo, 0.0, 1.0);
    if (v.leaf_radius + v.sway > 0.5 * v.leaf_spacing) {
        f.fail("leaf_radius", "leaf_radius + sway must not exceed half the leaf_spacing");
    }
    if ((v.radii * 2.0 / v.leaf_spacing).prod() > 5e7) {
        f.fail("leaf_spacing", "more than 50 M voxels: raise leaf_spacing or shrink radii");
    }
    f.reject_unknown_keys();
    return v;
}

void read_occlusion(TomlFields& f, sim::Occlusion& o) {
    get_seed(f, "seed", o.seed);
    f.reject_unknown_keys();
}

// ---- end of terrain and occluders ----

void read_deformation(TomlFields& f, sim::Deformation& d) {
    f.get("enabled", d.enabled);
    f.get("expansion_coefficient", d.expansion_coefficient, -1e-3, 1e-3);
    f.get("time_constant_hours", d.time_constant_hours, 0.01, 100.0);
    f.get("exponent", d.exponent, 0.0, 10.0);
    f.get("reference_temperature_c", d.reference_temperature_c, -80.0, 80.0);
    f.reject_unknown_keys();
}

// ---- Weather, atmosphere and the weather station ----

void read_weather(TomlFields& f, sim::Weather& w) {
    get_seed(f, "seed", w.seed);
    f.get("latitude_deg", w.latitude_deg, -89.0, 89.0);
    f.get("longitude_deg", w.longitude_deg, -180.0, 180.0);
    f.get("mean_temperature_c", w.mean_temperature_c, -60.0, 60.0);
    f.get("day_sigma_c", w.day_sigma_c, 0.0, 30.0);
    f.get("day_correlation", w.day_correlation, 0.0, 0.95);
    f.get("daily_range_c", w.daily_range_c, 0.0, 40.0);
    f.get("max_hour_solar", w.max_hour_solar, 10.0, 20.0);
    f.get("cloudiness_mean", w.cloudiness_mean, 0.0, 1.0);
    f.get("cloudiness_sigma", w.cloudiness_sigma, 0.0, 1.0);
    f.get("pressure_hpa", w.pressure_hpa, 500.0, 1100.0);
    f.get("pressure_sigma_hpa", w.pressure_sigma_hpa, 0.0, 50.0);
    f.get("pressure_tide_hpa", w.pressure_tide_hpa, 0.0, 5.0);
    f.get("absorptance", w.absorptance, 0.0, 1.0);
    f.get("surface_coefficient", w.surface_coefficient, 1.0, 200.0);
    f.get("surface_time_constant_hours", w.surface_time_constant_hours, 0.01, 100.0);
    f.reject_unknown_keys();
}

void read_atmosphere(TomlFields& f, sim::Atmosphere& a) {
    f.get("enabled", a.enabled);
    f.get("wavelength_nm", a.wavelength_nm, 300.0, 2000.0);
    f.get("scanner_temperature_c", a.scanner_temperature_c, -60.0, 60.0);
    f.get("scanner_pressure_hpa", a.scanner_pressure_hpa, 500.0, 1100.0);
    f.get("scanner_humidity_pct", a.scanner_humidity_pct, 0.0, 100.0);
    f.reject_unknown_keys();
}

void read_meteo(TomlFields& f, sim::MeteoStation& m) {
    f.get("enabled", m.enabled);
    f.get("span_minutes", m.span_minutes, 0, 1440);
    f.get("temperature_sigma_c", m.temperature_sigma_c, 0.0, 10.0);
    f.get("pressure_sigma_hpa", m.pressure_sigma_hpa, 0.0, 10.0);
    f.get("humidity_sigma_pct", m.humidity_sigma_pct, 0.0, 10.0);
    f.reject_unknown_keys();
}

// ---- end of weather ----

void read_events(TomlFields& f, sim::Site& site) {
    sim::Events& e = site.events;
    f.get("step_epoch", e.step_epoch, -1, 1000000);
    f.get("step_z_min", e.step_z_min, -kBig, kBig);
    f.get("step_z_max", e.step_z_max, -kBig, kBig);
    get_vector3(f, "step_displacement", e.step_displacement, 100.0);
    f.get("tilt_epoch", e.tilt_epoch, -1, 1000000);
    f.get("bending_change_epoch", e.bending_change_epoch, -1, 1000000);
    f.get("bending_factor", e.bending_factor, 0.0, 10.0);
    if (f.has("tilt_arcsec")) {
        std::vector<double> a;
        f.get("tilt_arcsec", a);
        if (a.size() != 2) f.fail("tilt_arcsec", "expected [towards +x, towards +y]");
        for (const double x : a) {
            if (std::abs(x) > 3600.0) f.fail("tilt_arcsec", "value outside ±3600");
        }
        e.tilt_arcsec = {a[0], a[1]};
    }
    std::string knocked;
    f.get("knocked_target", knocked);
    if (!knocked.empty()) {
        e.knocked_target = -1;
        for (std::size_t i = 0; i < site.targets.size(); ++i) {
            if (site.targets[i].name == knocked) e.knocked_target = static_cast<int>(i);
        }
        if (e.knocked_target < 0) f.fail("knocked_target", "no target named '" + knocked + "'");
    }
    f.get("knocked_epoch", e.knocked_epoch, -1, 1000000);
    get_vector3(f, "knocked_displacement", e.knocked_displacement, 100.0);
    f.get("station_change_epoch", e.station_change_epoch, -1, 1000000);
    get_vector3(f, "station_shift", e.station_shift, 100.0);
    f.get("station_turn_deg", e.station_turn_deg, -180.0, 180.0);
    std::vector<double> missing;
    f.get("missing_epochs", missing);
    if (f.has("missing_epochs")) {
        e.missing_epochs.clear();
        for (const double m : missing) {
            if (m < 0 || m != std::floor(m) || m > 1e6) {
                f.fail("missing_epochs", "expected epoch numbers 0, 1, 2, ...");
            }
            e.missing_epochs.push_back(static_cast<int>(m));
        }
    }
    f.get("cut_short_epoch", e.cut_short_epoch, -1, 1000000);
    f.get("cut_short_fraction", e.cut_short_fraction, 0.0, 1.0);
    f.reject_unknown_keys();
}

void read_texture(TomlFields& f, sim::Texture& t) {
    get_seed(f, "seed", t.seed);
    f.get("albedo", t.albedo, 0.0, 1.0);
    f.get("panel_width", t.panel_width, 0.05, 100.0);
    f.get("panel_height", t.panel_height, 0.05, 100.0);
    f.get("joint_width", t.joint_width, 0.0, 1.0);
    f.get("tie_hole_radius", t.tie_hole_radius, 0.0, 1.0);
    f.get("range_attenuation", t.range_attenuation, 1.0, 1e6);
    f.reject_unknown_keys();
}

sim::Site read_site(const toml::table& doc, const std::string& source,
                    const std::optional<std::string>& preset) {
    TomlFields root(doc, source);
    std::string name = preset.value_or("small");
    if (root.has("preset")) {
        std::string file_preset;
        root.get_choice("preset", file_preset, sim::preset_names());
        if (preset && *preset != file_preset) {
            root.fail("preset",
                      "the file says '" + file_preset + "' but '" + *preset + "' was asked for");
        }
        name = file_preset;
    }
    sim::Site site = sim::preset(name);
    root.get_seconds("cadence", site.cadence_seconds, 1.0, 30.0 * 86400.0);
    if (auto t = root.table("scanner")) read_scanner(*t, site.scanner);
    if (auto t = root.table("beam")) read_beam(*t, site.beam);
    if (auto t = root.table("noise")) read_noise(*t, site.noise);
    if (auto t = root.table("drift")) read_drift(*t, site.drift);
    if (auto t = root.table("pier")) read_pier(*t, site.pier);
    if (auto t = root.table("deck")) read_deck(*t, site.deck);
    // Terrain and blocks before the targets: a placed target stands on them.
    if (auto t = root.table("terrain")) read_terrain(*t, site.terrain);
    if (root.has("block")) {
        site.terrain.blocks.clear();
        for (TomlFields& b : root.array_of_tables("block"))
            site.terrain.blocks.push_back(read_block(b));
    }
    if (auto t = root.table("occlusion")) read_occlusion(*t, site.occlusion);
    if (root.has("occluder")) {
        site.occlusion.occluders.clear();
        for (TomlFields& o : root.array_of_tables("occluder")) {
            site.occlusion.occluders.push_back(read_occluder(o));
        }
    }
    if (root.has("vegetation")) {
        site.occlusion.vegetation.clear();
        for (TomlFields& v : root.array_of_tables("vegetation")) {
            site.occlusion.vegetation.push_back(read_vegetation(v));
        }
    }
    if (root.has("target")) {
        site.targets.clear();
        for (TomlFields& t : root.array_of_tables("target")) {
            site.targets.push_back(read_target(t, site));
        }
        if (site.targets.size() < 4) root.fail("target", "at least 4 targets are needed");
    }
    if (auto t = root.table("deformation")) read_deformation(*t, site.deformation);
    if (auto t = root.table("events")) read_events(*t, site);
    if (auto t = root.table("texture")) read_texture(*t, site.texture);
    if (auto t = root.table("weather")) read_weather(*t, site.weather);
    if (auto t = root.table("atmosphere")) read_atmosphere(*t, site.atmosphere);
    if (auto t = root.table("meteo")) read_meteo(*t, site.meteo);
    root.reject_unknown_keys();
    return site;
}

}  // namespace

sim::Site load_scene_file(const std::filesystem::path& path,
                          const std::optional<std::string>& preset) {
    const toml::table doc = parse_toml_file(path);
    return read_site(doc, path.string(), preset);
}

sim::Site parse_scene_file(std::string_view text, const std::string& source_name,
                           const std::optional<std::string>& preset) {
    const toml::table doc = parse_toml_string(text, source_name);
    return read_site(doc, source_name, preset);
}

}  // namespace tlsmon
