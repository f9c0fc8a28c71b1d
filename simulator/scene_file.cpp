#include "simulator/scene_file.hpp"

#include <cmath>
#include <limits>

#include "simulator/render.hpp"

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
    const double cells =
        (std::floor((s.azimuth_max_deg - s.azimuth_min_deg) / s.azimuth_step_deg) + 1) *
        (std::floor((s.elevation_max_deg - s.elevation_min_deg) / s.elevation_step_deg) + 1);
    if (cells > static_cast<double>(sim::max_scan_cells)) {
        f.fail("azimuth_step_deg",
               "the window and steps give " + std::to_string(cells / 1e6) + " M cells, over the " +
                   std::to_string(sim::max_scan_cells / 1000000) + " M allowed");
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
    if (p.x1 <= p.x0) f.fail("x1", "must exceed x0");
    if (p.y1 <= p.y0) f.fail("y1", "must exceed y0");
    f.reject_unknown_keys();
}

void read_deck(TomlFields& f, sim::Deck& d) {
    f.get("enabled", d.enabled);
    f.get("overhang", d.overhang, 0.0, 1000.0);
    f.get("half_length", d.half_length, 0.0, 10000.0);
    f.get("thickness", d.thickness, 0.01, 100.0);
    f.reject_unknown_keys();
}

sim::Target read_target(TomlFields& f) {
    sim::Target t;
    f.get("name", t.name);
    if (t.name.empty()) f.fail("name", "every target needs a name");
    std::string kind = "sphere";
    f.get_choice("kind", kind, {"sphere", "checkerboard"});
    t.kind = kind == "sphere" ? sim::Target::Kind::sphere : sim::Target::Kind::checkerboard;
    if (!f.has("centre")) f.fail("centre", "every target needs a centre [x, y, z]");
    get_vector3(f, "centre", t.centre, kBig);
    f.get("radius", t.radius, 0.001, 10.0);
    f.get("size", t.size, 0.01, 10.0);
    f.reject_unknown_keys();
    return t;
}

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
    if (root.has("target")) {
        site.targets.clear();
        for (TomlFields& t : root.array_of_tables("target")) site.targets.push_back(read_target(t));
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
