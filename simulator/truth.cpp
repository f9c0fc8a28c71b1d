#include "simulator/truth.hpp"

#include <cmath>
#include <numbers>

#include "simulator/deformation.hpp"
#include "simulator/drift.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/footprint.hpp"
#include "simulator/scene_truth.hpp"
#include "simulator/series.hpp"

namespace tlsmon::sim {

namespace {

constexpr double kArcsecPerRad = 180.0 * 3600.0 / std::numbers::pi;

nlohmann::json vec(const Eigen::Vector3d& v) {
    return {v.x(), v.y(), v.z()};
}

// 4x4 in column-vector form, row by row: p' = M · [x y z 1]ᵀ.
nlohmann::json matrix(const Eigen::Affine3d& a) {
    nlohmann::json rows = nlohmann::json::array();
    const Eigen::Matrix4d m = a.matrix();
    for (int r = 0; r < 4; ++r) rows.push_back({m(r, 0), m(r, 1), m(r, 2), m(r, 3)});
    return rows;
}

}  // namespace

std::vector<SamplePoint> sample_points(const Site& site) {
    const Pier& p = site.pier;
    const double h = p.height;
    const double xc = 0.5 * (p.x0 + p.x1), yc = 0.5 * (p.y0 + p.y1);
    // The faces' middle lines; a round pier's south- and west-most lines.
    const double south = p.round() ? yc - 0.5 * p.diameter : p.y0;
    const double west = p.round() ? xc - 0.5 * p.diameter : p.x0;
    std::vector<SamplePoint> out;
    for (const double z : {5.0, 10.0, 20.0, 30.0, h - 1.0}) {
        if (z <= 0.0 || z > h) continue;
        const std::string tag = "_z" + std::to_string(static_cast<int>(std::lround(z)));
        out.push_back({"south_face" + tag, {xc, south, z}});
        out.push_back({"west_face" + tag, {west, yc, z}});
    }
    out.push_back({"top_centre", {xc, yc, h}});
    return out;
}

PierAxis pier_axis(const Site& site, int epoch, const ThermalBending& bending) {
    // Least squares of u_h(z) = a + b·z over z_k = k·H/N, k = 0..N.
    const Pier& p = site.pier;
    constexpr int kSteps = 200;
    double sz = 0, szz = 0;
    Eigen::Vector2d su = Eigen::Vector2d::Zero(), szu = Eigen::Vector2d::Zero();
    for (int k = 0; k <= kSteps; ++k) {
        const double z = p.height * k / kSteps;
        const Eigen::Vector3d q(p.centre().x(), p.centre().y(), z);
        const Eigen::Vector2d u = pier_displacement(site, q, epoch, bending).head<2>();
        sz += z;
        szz += z * z;
        su += u;
        szu += z * u;
    }
    const double n = kSteps + 1;
    PierAxis axis;
    axis.tilt = (szu - su * sz / n) / (szz - sz * sz / n);
    axis.top = pier_displacement(site, {p.centre().x(), p.centre().y(), p.height}, epoch, bending);
    return axis;
}

nlohmann::json truth_json(const Site& site, int epoch, double hours, std::int64_t acquired_utc,
                          const RenderedScan* rendered) {
    using nlohmann::json;
    json j;
    j["format"] = "tlsmon-simulator-truth/1";
    j["station"] = site.scanner.station;
    j["epoch"] = epoch;
    j["time_utc"] = format_utc(acquired_utc);
    j["time_unix"] = acquired_utc;
    j["hours_since_first_epoch"] = hours;
    j["frame"] = "project: x east, y north, z up, metres, the pier's foot at z = 0";

    const Eigen::Affine3d nominal = nominal_pose(site.scanner);
    json& sc = j["scanner"];
    sc["position"] = vec(site.scanner.position);
    sc["heading_deg"] = site.scanner.heading_deg;
    sc["nominal_pose"] = matrix(nominal);
    if (rendered) {
        const PoseError& e = rendered->pose_error;
        const Eigen::Affine3d E = e.transform();
        sc["pose_error"] = {{"yaw_arcsec", e.yaw * kArcsecPerRad},
                            {"tilt_x_arcsec", e.tilt_x * kArcsecPerRad},
                            {"tilt_y_arcsec", e.tilt_y * kArcsecPerRad},
                            {"translation_m", vec(e.translation)},
                            {"matrix_scanner_frame", matrix(E)}};
        sc["true_pose"] = matrix(nominal * E);
        // p_true = H · p_header for coordinates read through the PTX header pose.
        sc["header_to_true"] = matrix(nominal * E * nominal.inverse());
    }
    const Noise& n = site.noise;
    const bool constant = n.model == Noise::Model::constant;
    j["noise"] = {{"enabled", n.enabled},
                  {"model", constant ? "constant" : "signal"},
                  {"range_sigma", constant ? "a + b * range"
                                           : "signal_a + signal_b * range / sqrt(reflectance * "
                                             "|cos incidence|)"},
                  {"range_a_m", n.range_a},
                  {"range_b_ppm", n.range_b_ppm},
                  {"signal_a_m", n.signal_a},
                  {"signal_b_ppm", n.signal_b_ppm},
                  {"angular_arcsec", n.angular_arcsec},
                  {"intensity_sigma", n.intensity_sigma},
                  {"seed", n.seed}};

    const Beam& b = site.beam;
    j["beam"] = {{"footprint", b.footprint},
                 {"exit_diameter_m", b.exit_diameter},
                 {"divergence_mrad", b.divergence_mrad},
                 {"sub_rays_max", b.footprint ? kSubRays : 1},
                 {"mixed_pixel_spread_m", kMixedPixelSpread}};

    json targets = json::array();
    for (std::size_t i = 0; i < site.targets.size(); ++i) {
        const Target& t = site.targets[i];
        const Eigen::Vector3d c = target_centre(site, i, epoch);
        json tj = {{"name", t.name},
                   {"kind", t.kind == Target::Kind::sphere ? "sphere" : "checkerboard"},
                   {"centre", vec(c)},
                   {"reference_centre", vec(t.centre)},
                   {"displacement", vec(c - t.centre)}};
        if (t.kind == Target::Kind::sphere) {
            tj["radius"] = t.radius;
        } else {
            tj["size"] = t.size;
            Eigen::Vector3d nrm = site.scanner.position - t.centre;
            nrm.z() = 0.0;
            tj["normal"] = vec(nrm.normalized());
        }
        targets.push_back(tj);
    }
    j["targets"] = targets;

    const Pier& p = site.pier;
    j["pier"] = {{"x0", p.x0},
                 {"x1", p.x1},
                 {"y0", p.y0},
                 {"y1", p.y1},
                 {"height", p.height},
                 {"shape", p.round() ? "round" : "box"},
                 {"diameter", p.diameter}};
    const Deck& deck = site.deck;
    j["deck"] = {{"enabled", deck.enabled},
                 {"overhang", deck.overhang},
                 {"half_length", deck.half_length},
                 {"thickness", deck.thickness},
                 {"model", "a box on the pier's top, not deformed"}};

    // ---- Weather, atmosphere and the thermal bending they drive ----
    const EpochConditions cond = epoch_conditions(site, epoch, hours, acquired_utc);
    const Deformation& d = site.deformation;
    const ThermalBending& bend = cond.bending;
    j["deformation"] = {
        {"model", "thermal_bending"},
        {"enabled", d.enabled},
        {"equations",
         "kappa = alpha * dT_lagged / b (b = x1 - x0 for x, y1 - y0 for y; dT_x = T_west - "
         "T_east, dT_y = T_south - T_north); u_h(z) = kappa H^2 / 2 (z/H)^exponent; u_z(z) = "
         "alpha (T_mean - T_ref) z"},
        {"expansion_coefficient_per_k", d.expansion_coefficient},
        {"time_constant_hours", d.time_constant_hours},
        {"exponent", d.exponent},
        {"reference_temperature_c", d.reference_temperature_c},
        {"height_m", p.height},
        {"section_depth_m", {p.section_depth().x(), p.section_depth().y()}},
        {"delta_t_driving_c", {bend.delta_driving.x(), bend.delta_driving.y()}},
        {"delta_t_lagged_c", {bend.delta_lagged.x(), bend.delta_lagged.y()}},
        {"mean_temperature_change_c", bend.mean_change},
        {"curvature_per_m", {bend.curvature.x(), bend.curvature.y()}},
        {"top_displacement_m", vec(bend.top)}};

    const ThermalState& th = cond.thermal;
    const Weather& w = site.weather;
    json faces = json::object();
    for (int f = 0; f < 4; ++f) {
        faces[kFaceNames[f]] = {{"irradiance_w_m2", th.irradiance[f]},
                                {"sol_air_temperature_c", th.sol_air_c[f]},
                                {"temperature_c", th.face_c[f]},
                                {"section_temperature_c", th.section_c[f]}};
    }
    const bool sun_up = th.sunlit_face >= 0;
    const int shaded = sun_up ? (th.sunlit_face ^ 1) : -1;  // the opposite face
    j["weather"] = {
        {"seed", w.seed},
        {"latitude_deg", w.latitude_deg},
        {"longitude_deg", w.longitude_deg},
        {"solar_hour", th.air.sun.solar_hour},
        {"sun_elevation_deg", th.air.sun.elevation_deg},
        {"sun_azimuth_deg", th.air.sun.azimuth_deg},
        {"cloudiness", th.air.cloudiness},
        {"air_temperature_c", th.air.temperature_c},
        {"pressure_hpa", th.air.pressure_hpa},
        {"relative_humidity_pct", th.air.relative_humidity_pct},
        {"dew_point_c", th.air.dew_point_c},
        {"faces", faces},
        {"sunlit_face", sun_up ? json(kFaceNames[th.sunlit_face]) : json(nullptr)},
        {"sunlit_face_temperature_c", sun_up ? json(th.face_c[th.sunlit_face]) : json(nullptr)},
        {"shaded_face", sun_up ? json(kFaceNames[shaded]) : json(nullptr)},
        {"shaded_face_temperature_c", sun_up ? json(th.face_c[shaded]) : json(nullptr)}};

    const Atmosphere& at = site.atmosphere;
    j["atmosphere"] = {{"enabled", at.enabled},
                       {"formula", "IAG 1999 group refractivity (Rueger)"},
                       {"wavelength_nm", at.wavelength_nm},
                       {"scanner_setting",
                        {{"temperature_c", at.scanner_temperature_c},
                         {"pressure_hpa", at.scanner_pressure_hpa},
                         {"relative_humidity_pct", at.scanner_humidity_pct}}},
                       {"group_refractivity_setting", cond.atmosphere.refractivity_setting},
                       {"group_refractivity_true", cond.atmosphere.refractivity_true},
                       {"range_scale", cond.atmosphere.range_scale},
                       {"range_ppm", cond.atmosphere.ppm}};
    // ---- end of weather ----

    json events = json::array();
    const Events& ev = site.events;
    if (ev.step_epoch >= 0 && epoch >= ev.step_epoch) {
        events.push_back({{"type", "step"},
                          {"since_epoch", ev.step_epoch},
                          {"z_min", ev.step_z_min},
                          {"z_max", ev.step_z_max},
                          {"displacement", vec(ev.step_displacement)}});
    }
    if (const Eigen::Vector2d tilt = pier_tilt(site, epoch); tilt.squaredNorm() > 0.0) {
        events.push_back({{"type", "tilt"},
                          {"since_epoch", ev.tilt_epoch},
                          {"tilt_arcsec", {ev.tilt_arcsec.x(), ev.tilt_arcsec.y()}},
                          {"about", {p.centre().x(), p.centre().y(), 0.0}}});
    }
    if (ev.bending_change_epoch >= 0 && epoch >= ev.bending_change_epoch) {
        events.push_back({{"type", "bending_change"},
                          {"since_epoch", ev.bending_change_epoch},
                          {"bending_factor", ev.bending_factor}});
    }
    if (ev.knocked_target >= 0 && ev.knocked_epoch >= 0 && epoch >= ev.knocked_epoch) {
        events.push_back({{"type", "knocked_target"},
                          {"since_epoch", ev.knocked_epoch},
                          {"target", site.targets.at(ev.knocked_target).name},
                          {"displacement", vec(ev.knocked_displacement)}});
    }
    if (ev.station_change_epoch >= 0 && epoch >= ev.station_change_epoch) {
        events.push_back({{"type", "station_change"},
                          {"since_epoch", ev.station_change_epoch},
                          {"shift_m", vec(ev.station_shift)},
                          {"turn_deg", ev.station_turn_deg}});
    }
    if (ev.cut_short_epoch == epoch) {
        events.push_back({{"type", "cut_short"}, {"fraction", ev.cut_short_fraction}});
    }
    for (const int m : ev.missing_epochs) {
        if (m == epoch) events.push_back({{"type", "missing"}});
    }
    j["events"] = events;

    json samples = json::array();
    for (const SamplePoint& s : sample_points(site)) {
        samples.push_back({{"name", s.name},
                           {"point", vec(s.point)},
                           {"displacement", vec(pier_displacement(site, s.point, epoch, bend))}});
    }
    j["samples"] = samples;
    const PierAxis axis = pier_axis(site, epoch, bend);
    j["pier_axis"] = {
        {"definition",
         "the straight line fitted (least squares, uniform in z over 0..height) to the "
         "displaced centre line; tilt = its lean towards +x and +y"},
        {"tilt_arcsec", {axis.tilt.x() * kArcsecPerRad, axis.tilt.y() * kArcsecPerRad}},
        {"top_displacement_m", vec(axis.top)}};

    json& scan = j["scan"];
    const Scanner& s = site.scanner;
    scan["azimuth_min_deg"] = s.azimuth_min_deg;
    scan["azimuth_max_deg"] = s.azimuth_max_deg;
    scan["elevation_min_deg"] = s.elevation_min_deg;
    scan["elevation_max_deg"] = s.elevation_max_deg;
    scan["azimuth_step_deg"] = s.azimuth_step_deg;
    scan["elevation_step_deg"] = s.elevation_step_deg;
    scan["grid"] = "column 0 at azimuth_max, columns clockwise; row 0 at elevation_min, rows up";
    scan["missing"] = rendered == nullptr;
    if (rendered) {
        scan["rows"] = rendered->scan.grid->rows;
        scan["columns"] = rendered->scan.grid->columns;
        scan["points"] = rendered->scan.size();
        scan["mixed_pixels"] = rendered->mixed_pixels;
    }
    scan["details"] = nlohmann::json::array();  // filled by the series (detail_truth)
    // Terrain, target mounts, occluders and vegetation (scene_truth.hpp).
    add_scene_truth(j, site, epoch, hours, rendered);
    return j;
}

nlohmann::json detail_truth(const DetailScan& d, const RenderedScan& rendered) {
    return {{"name", d.name},
            {"scan", rendered.scan.name},
            {"azimuth_min_deg", d.azimuth_min_deg},
            {"azimuth_max_deg", d.azimuth_max_deg},
            {"elevation_min_deg", d.elevation_min_deg},
            {"elevation_max_deg", d.elevation_max_deg},
            {"step_deg", d.step_deg},
            {"rows", rendered.scan.grid->rows},
            {"columns", rendered.scan.grid->columns},
            {"points", rendered.scan.size()},
            {"mixed_pixels", rendered.mixed_pixels}};
}

}  // namespace tlsmon::sim
