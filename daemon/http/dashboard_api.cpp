#include "daemon/http/dashboard_api.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

#include "core/csv.hpp"
#include "daemon/http/series_decimation.hpp"
#include "pipeline/core_point_map.hpp"
#include "pipeline/keypoint_results.hpp"
#include "pipeline/stored_area_vectors.hpp"
#include "pipeline/thermal_config.hpp"
#include "report/data.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

Json time_or_null(const std::optional<UtcSeconds>& t) {
    return t ? Json(format_utc(*t)) : Json(nullptr);
}

namespace {

constexpr UtcSeconds kDay = 86400;
constexpr std::size_t kSparkBuckets = 24;

Json optional_number(const std::optional<double>& v) {
    return v ? Json(*v) : Json(nullptr);
}

// A point of a series; `with_time_text` adds the ISO time beside the Unix seconds (the
// overview's latest values; a long series leaves it out, its CSV has it).
Json point_json(const SeriesPoint& p, bool with_time_text = true) {
    Json j{{"epoch", p.epoch}};
    if (with_time_text) j["acquired"] = format_utc(p.acquired);
    j["t"] = p.acquired;
    j["value"] = p.value;
    j["lod95"] = optional_number(p.uncertainty);
    j["n"] = p.n;
    j["significant"] = p.significant;
    j["datum"] = p.datum;
    j["registration_accepted"] = p.registration_accepted;
    if (p.campaign) j["campaign"] = *p.campaign;
    return j;
}

// The epoch's registration as the overview shows it: method, verdict, targets used and
// left out, s0 and the σ at each zone.
Json registration_summary(const EpochDatabase& db, EpochId id) {
    const auto row = db.registrations().of_epoch(id);
    if (!row) return nullptr;
    std::int64_t used = 0, excluded = 0;
    for (const auto& t : db.registrations().targets_of_epoch(id)) (t.used ? used : excluded)++;
    Json sigmas = Json::array();
    for (const auto& s : db.registrations().zone_sigmas_of_epoch(id))
        sigmas.push_back({{"zone", s.zone}, {"sigma_3d_m", s.max_sigma_3d_m}});
    return Json{{"method", row->method},   {"accepted", row->accepted},
                {"status", row->status},   {"reason", row->reason},
                {"targets_used", used},    {"targets_left_out", excluded},
                {"rms_m", row->rms_m},     {"sigma0", optional_number(row->sigma0)},
                {"sigma_at_zones", sigmas}};
}

Json epoch_summary(const Epoch& e) {
    return Json{{"id", e.id},
                {"acquired", format_utc(e.acquired)},
                {"t", e.acquired},
                {"status", std::string(to_string(e.status))},
                {"reason", e.reason},
                {"file", e.file_path},
                {"archived_as", e.archive_path ? Json(*e.archive_path) : Json(nullptr)},
                {"points", e.point_count ? Json(*e.point_count) : Json(nullptr)},
                {"total_ms", optional_number(e.timings.total_ms)}};
}

Json alarm_state_json(const AlarmState& a, const std::map<std::string, AlarmRule>& rules) {
    const auto rule = rules.find(a.rule);
    return Json{{"rule", a.rule},
                {"zone", rule == rules.end() ? "" : rule->second.zone},
                {"quantity", rule == rules.end() ? "" : rule->second.quantity},
                {"state", a.state},
                {"level", a.level},
                {"since", a.since > 0 ? Json(format_utc(a.since)) : Json(nullptr)},
                {"value", optional_number(a.value)},
                {"epoch", a.epoch ? Json(*a.epoch) : Json(nullptr)},
                {"shelved_until", time_or_null(a.shelved_until)}};
}

std::map<std::string, AlarmRule> rules_by_name(const EpochDatabase& db) {
    std::map<std::string, AlarmRule> out;
    for (auto& r : db.alarms().rules()) out.emplace(r.name, r);
    return out;
}

// Zones in the configuration's order, then any other stored (keypoint bands).
// The keypoint model d(t, z) (docs/keypoints.md, step 7) of the newest defined fit of the
// series' quantity, at the zone's height in that fit (its residual's z), t in hours since
// the reference epoch: sampled over the window clipped to the hours the fit observed (no
// extrapolation). Null when there is none (not a modelled quantity, the zone not a segment
// of the fit, or the window outside it).
Json keypoint_model_json(const EpochDatabase& db, const SeriesView& view) {
    const auto fit = db.keypoint_models().latest_defined(view.request.quantity);
    const auto reference = db.epochs().reference();
    if (!fit || !reference || fit->model.variable != "time_h") return nullptr;
    const auto ref = db.epochs().find(*reference);
    const auto zone = std::find_if(fit->model.residuals.begin(), fit->model.residuals.end(),
                                   [&](const auto& r) { return r.zone == view.request.zone; });
    if (!ref || zone == fit->model.residuals.end()) return nullptr;
    const auto& m = fit->model;
    const double hour = 3600.0, t0 = static_cast<double>(ref->acquired);
    double from = t0 + (*m.t_centre - *m.t_scale) * hour,
           to = t0 + (*m.t_centre + *m.t_scale) * hour;
    const auto& range = view.request.range;
    if (range.from) from = std::max(from, static_cast<double>(*range.from));
    if (range.to) to = std::min(to, static_cast<double>(*range.to));
    if (!(from < to)) return nullptr;
    const std::size_t samples = std::clamp<std::size_t>(view.request.width / 4, 2, 200);
    Json points = Json::array();
    for (std::size_t k = 0; k < samples; ++k) {
        const double t = from + (to - from) * static_cast<double>(k) / double(samples - 1);
        points.push_back({std::llround(t), *m.at((t - t0) / hour, zone->z)});
    }
    return Json{{"epoch", fit->epoch},
                {"acquired", format_utc(fit->acquired)},
                {"zone_height_m", zone->z},
                {"residual_scale", optional_number(m.residual_scale)},
                {"points", points}};
}

// The newest thermal model of the zone quantity `quantity` belongs to (itself, or the base of
// its prediction, residual or health); none when there is none.
std::optional<ThermalModelRow> thermal_model_of(const EpochDatabase& db, const std::string& zone,
                                                const std::string& quantity) {
    std::vector<std::string> candidates{quantity};
    for (const char* suffix :
         {"_thermal_m", "_compensated_m", "_thermal_drift_z", "_thermal_spread_ratio"}) {
        if (quantity.ends_with(suffix))
            candidates.push_back(quantity.substr(0, quantity.size() - std::strlen(suffix)) + "_m");
    }
    for (const auto& c : candidates)
        if (auto m = db.thermal().latest(zone, c)) return m;
    return std::nullopt;
}

// Points of another quantity over the view's window, decimated alike: [[t, value, lod95]…].
Json window_points(const EpochDatabase& db, const SeriesView& view, const std::string& quantity) {
    SeriesRequest r = view.request;
    r.quantity = quantity;
    Json out = Json::array();
    for (const auto& p : series_view(db, r).points)
        out.push_back({p.acquired, p.value, optional_number(p.uncertainty)});
    return out;
}

// The thermal compensation of the series' zone quantity (docs/thermal.md): the newest model,
// the measured, predicted and compensated series over the window, and the runs of epochs it
// did not compensate (no model yet, no meteo) or compensated by extrapolation. Null when the
// quantity has no thermal model.
Json thermal_json(const EpochDatabase& db, const SeriesView& view) {
    const auto& r = view.request;
    const auto m = thermal_model_of(db, r.zone, r.quantity);
    if (!m) return nullptr;
    const std::string& base = m->quantity;
    const ThermalQuantities names = thermal_quantities(base);
    Json runs = Json::array();
    bool extending = false;  // the last run goes on at this epoch
    for (const auto& c : db.thermal().compensations(r.range, r.zone, base)) {
        const std::string quality = to_string(c.row.quality);
        if (c.row.quality == ThermalQuality::compensated) {
            extending = false;
        } else if (extending && runs.back()["quality"] == quality) {
            runs.back()["to"] = c.acquired;
            runs.back()["epochs"] = runs.back()["epochs"].get<std::int64_t>() + 1;
        } else {
            runs.push_back({{"from", c.acquired},
                            {"to", c.acquired},
                            {"quality", quality},
                            {"epochs", 1},
                            {"reason", c.row.reason}});
            extending = true;
        }
    }
    return Json{{"quantity", base},
                {"model",
                 {{"version", m->version},
                  {"epoch", m->epoch},
                  {"training_from", format_utc(m->training_from)},
                  {"training_to", format_utc(m->training_to)},
                  {"surface_lag_h", m->surface_lag_h},
                  {"section_lag_h", m->section_lag_h},
                  {"prediction_sigma", m->prediction_sigma},
                  {"explained_share", m->explained_share}}},
                {"measured", window_points(db, view, base)},
                {"predicted", window_points(db, view, names.predicted)},
                {"compensated", window_points(db, view, names.compensated)},
                {"not_compensated", runs}};
}

std::vector<std::string> zone_order(const EpochDatabase& db, const DashboardSite& site) {
    std::vector<std::string> out = site.zones;
    for (const auto& [name, definition] : db.site().zones()) {
        if (std::find(out.begin(), out.end(), name) == out.end()) out.push_back(name);
    }
    return out;
}

}  // namespace

Json zone_overview(const EpochDatabase& db, const DashboardSite& site) {
    // Each zone quantity's newest value and the day before it (the sparkline: its lowest and
    // highest per 1/24 of the day, at 0.1 µm).
    std::map<std::string, Json> zone_rows;
    for (const auto& v : db.series().latest_values()) {
        const TimeRange day{v.point.acquired - kDay, v.point.acquired};
        const SeriesView last_day = series_view(db, {v.zone, v.quantity, day, kSparkBuckets});
        Json spark = Json::array();
        for (const auto& p : last_day.points)
            spark.push_back({p.acquired, std::round(p.value * 1e7) / 1e7});
        auto& z = zone_rows[v.zone];
        if (z.is_null()) z = Json::array();
        z.push_back({{"quantity", v.quantity}, {"latest", point_json(v.point)}, {"spark", spark}});
    }
    Json zones = Json::array();
    for (const auto& name : zone_order(db, site)) {
        const auto it = zone_rows.find(name);
        zones.push_back(
            {{"name", name}, {"quantities", it == zone_rows.end() ? Json::array() : it->second}});
    }
    return zones;
}

Json site_overview(const EpochDatabase& db, const DashboardSite& site, UtcSeconds now,
                   UtcSeconds heartbeat, Json zones) {
    const StatusSummary s = db.series().status_summary();
    Json epochs = Json::object();
    for (const auto& [status, count] : s.epochs_by_status)
        epochs[std::string(to_string(status))] = count;
    Json last = nullptr;
    if (s.last_done) {
        last = epoch_summary(*s.last_done);
        last["registration"] = registration_summary(db, s.last_done->id);
    }
    const auto rules = rules_by_name(db);
    Json alarms = Json::array();
    for (const auto& a : s.alarm_states) {
        if (a.state != "normal") alarms.push_back(alarm_state_json(a, rules));
    }
    return Json{{"station", site.station},
                {"now", format_utc(now)},
                {"daemon",
                 {{"started", format_utc(site.started)},
                  {"heartbeat", format_utc(heartbeat)},
                  {"heartbeat_age_s", now - heartbeat}}},
                {"database", {{"bytes", s.database_bytes}, {"schema_version", s.schema_version}}},
                {"disk_free_share", optional_number(site.disk_free_share)},
                {"epochs", epochs},
                {"backlog", s.backlog},
                {"oldest_pending", time_or_null(s.oldest_pending)},
                {"reference_epoch", s.reference_epoch ? Json(*s.reference_epoch) : Json(nullptr)},
                {"last_epoch", last},
                {"last_failure", s.last_failure ? epoch_summary(*s.last_failure) : Json(nullptr)},
                {"alarms_active", s.alarms_active},
                {"alarms_unacknowledged", s.alarms_unacknowledged},
                {"alarms", alarms},
                {"zones", std::move(zones)}};
}

Json zone_list(const EpochDatabase& db, const DashboardSite& site) {
    Json out = Json::array();
    std::map<std::string, std::string> definitions;
    for (const auto& [name, definition] : db.site().zones()) definitions[name] = definition;
    for (const auto& name : zone_order(db, site)) {
        const auto d = Json::parse(definitions[name], nullptr, false);
        out.push_back({{"name", name},
                       {"definition", d.is_discarded() ? Json(nullptr) : d},
                       {"quantities", db.series().quantities(name)}});
    }
    return out;
}

SeriesView series_view(const EpochDatabase& db, const SeriesRequest& request) {
    SeriesView v;
    v.request = request;
    auto all = db.series().points(request.zone, request.quantity, request.range);
    v.total = all.size();
    if (all.empty()) return v;
    std::vector<std::int64_t> t(all.size());
    std::vector<double> y(all.size());
    for (std::size_t i = 0; i < all.size(); ++i) {
        t[i] = all[i].acquired;
        y[i] = all[i].value;
    }
    const std::int64_t from = request.range.from.value_or(t.front());
    const std::int64_t to = request.range.to.value_or(t.back());
    for (std::size_t i : min_max_decimation(t, y, from, to, request.width))
        v.points.push_back(all[i]);
    return v;
}

Json series_json(const EpochDatabase& db, const SeriesView& view) {
    const auto& r = view.request;
    Json points = Json::array();
    for (const auto& p : view.points) points.push_back(point_json(p, false));
    Json rules = Json::array();
    Json marks = Json::array();
    for (const auto& rule : db.alarms().rules()) {
        if (rule.zone != r.zone || rule.quantity != r.quantity) continue;
        const auto d = Json::parse(rule.definition_json, nullptr, false);
        rules.push_back({{"name", rule.name},
                         {"enabled", rule.enabled},
                         {"definition", d.is_discarded() ? Json(nullptr) : d}});
        for (const auto& e : db.alarms().events(r.range.from, rule.name)) {
            if (r.range.to && e.time > *r.range.to) continue;
            marks.push_back({{"t", e.time},
                             {"time", format_utc(e.time)},
                             {"rule", rule.name},
                             {"kind", e.kind},
                             {"level", e.level},
                             {"actor", e.actor},
                             {"message", e.message}});
        }
    }
    Json rejected = Json::array();
    for (const auto& e : db.series().epochs_in_range(r.range, EpochStatus::rejected))
        rejected.push_back({{"epoch", e.id}, {"t", e.acquired}, {"reason", e.reason}});
    return Json{{"zone", r.zone},
                {"quantity", r.quantity},
                {"from", time_or_null(r.range.from)},
                {"to", time_or_null(r.range.to)},
                {"width", r.width},
                {"total", view.total},
                {"decimated", view.points.size() < view.total},
                {"points", points},
                {"alarm_rules", rules},
                {"alarm_events", marks},
                {"rejected_epochs", rejected},
                {"model", keypoint_model_json(db, view)},
                {"thermal", thermal_json(db, view)}};
}

Json meteo_json(const EpochDatabase& db, const TimeRange& range, std::size_t width) {
    const auto all = db.meteo().used_in_range(range);
    Json out{{"from", time_or_null(range.from)},
             {"to", time_or_null(range.to)},
             {"width", width},
             {"total", all.size()}};
    std::vector<std::int64_t> t(all.size());
    for (std::size_t i = 0; i < all.size(); ++i) t[i] = all[i].acquired;
    // Each quantity decimated on its own (min/max per pixel, as the series).
    const auto column = [&](double EpochMeteo::*field) {
        Json points = Json::array();
        if (all.empty()) return points;
        std::vector<double> v(all.size());
        for (std::size_t i = 0; i < all.size(); ++i) v[i] = all[i].*field;
        for (std::size_t i : min_max_decimation(t, v, range.from.value_or(t.front()),
                                                range.to.value_or(t.back()), width))
            points.push_back({t[i], v[i]});
        return points;
    };
    out["air_temperature_c"] = column(&EpochMeteo::air_temperature_c);
    out["pressure_hpa"] = column(&EpochMeteo::pressure_hpa);
    return out;
}

std::string series_csv(const SeriesView& view) {
    std::string out = "epoch,acquired,value,lod95,n,significant,datum\n";
    for (const auto& p : view.points) {
        const std::string fields[] = {std::to_string(p.epoch),
                                      format_utc(p.acquired),
                                      csv_number(p.value),
                                      p.uncertainty ? csv_number(*p.uncertainty) : "",
                                      std::to_string(p.n),
                                      p.significant ? "1" : "0",
                                      p.datum};
        append_csv_line(out, fields);
    }
    return out;
}

Json events_json(const EpochDatabase& db, const TimeRange& range,
                 const std::optional<std::string>& kind) {
    Json out = Json::array();
    for (const auto& e : db.series().events(range, kind)) {
        out.push_back({{"time", format_utc(e.time)},
                       {"t", e.time},
                       {"source", e.source},
                       {"level", e.level},
                       {"kind", e.kind},
                       {"message", e.message},
                       {"epoch", e.epoch ? Json(*e.epoch) : Json(nullptr)},
                       {"rule", e.rule},
                       {"actor", e.actor}});
    }
    return out;
}

Json alarms_json(const EpochDatabase& db, const TimeRange& history) {
    const auto rules = rules_by_name(db);
    Json states = Json::array();
    for (const auto& a : db.alarms().states()) states.push_back(alarm_state_json(a, rules));
    Json events = Json::array();
    for (const auto& e : db.alarms().events(history.from)) {
        if (history.to && e.time > *history.to) continue;
        events.push_back({{"time", format_utc(e.time)},
                          {"t", e.time},
                          {"rule", e.rule},
                          {"kind", e.kind},
                          {"level", e.level},
                          {"value", optional_number(e.value)},
                          {"epoch", e.epoch ? Json(*e.epoch) : Json(nullptr)},
                          {"actor", e.actor},
                          {"message", e.message}});
    }
    return Json{{"states", states}, {"events", events}};
}

Json epochs_json(const EpochDatabase& db, const TimeRange& range) {
    Json out = Json::array();
    for (const auto& e : db.series().epochs_in_range(range)) out.push_back(epoch_summary(e));
    return out;
}

std::optional<Json> epoch_json(const EpochDatabase& db, EpochId id) {
    const auto e = db.epochs().find(id);
    if (!e) return std::nullopt;
    Json out = epoch_summary(*e);
    out["registration"] = registration_summary(db, id);
    Json stages = Json::array();
    for (const auto& s : db.series().stages(id)) {
        stages.push_back(
            {{"stage", s.stage}, {"ms", s.ms}, {"rejected", s.rejected}, {"note", s.note}});
    }
    out["stages"] = stages;
    Json targets = Json::array();
    for (const auto& t : db.registrations().targets_of_epoch(id)) {
        targets.push_back({{"target", t.target},
                           {"kind", t.kind},
                           {"status", t.status},
                           {"use", t.use},
                           {"reason", t.reason},
                           {"residual_m", t.residual},
                           {"stable", t.stable},
                           {"statistic", optional_number(t.statistic)},
                           {"critical", optional_number(t.critical)}});
    }
    out["targets"] = targets;
    Json meteo = nullptr;
    for (const auto& m : db.meteo().of_epoch(id)) {
        if (!m.values) continue;
        meteo = {{"time", format_utc(m.values->time)},
                 {"air_temperature_c", m.values->air_temperature_c},
                 {"pressure_hpa", m.values->pressure_hpa},
                 {"relative_humidity_pct", m.values->relative_humidity_pct}};
    }
    out["meteo"] = meteo;
    return out;
}

namespace {

// The epoch's keypoint segment of a zone (docs/keypoints.md, "In the database") in the
// map's frame: the mean vector projected on u and v, where it is drawn (v = the segment's
// height in a wall frame), the method's own LoD95 along the wall (horizontal, vertical).
// Null when the epoch has no defined keypoint vector for the zone.
Json keypoint_vector_json(const EpochDatabase& db, const Epoch& epoch, const std::string& zone,
                          const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
    const auto value = [&](const char* quantity) -> std::optional<SeriesPoint> {
        for (const auto& p : db.series().points(zone, quantity, {epoch.acquired, epoch.acquired}))
            if (p.epoch == epoch.id) return p;
        return std::nullopt;
    };
    const auto dx = value(kKeypointDx), dy = value(kKeypointDy), dz = value(kKeypointDz);
    if (!dx || !dy || !dz) return nullptr;
    const Eigen::Vector3d d(dx->value, dy->value, dz->value);
    const auto h = value(kKeypointAlongSurfaceH), vertical = value(kKeypointAlongSurfaceV);
    const auto height = value(kKeypointHeight);
    const auto lod = [](const std::optional<SeriesPoint>& p) {
        return p ? optional_number(p->uncertainty) : Json(nullptr);
    };
    return Json{{"du_m", u.dot(d)},
                {"dv_m", v.dot(d)},
                {"height_m", height ? Json(height->value) : Json(nullptr)},
                {"lod95_h_m", lod(h)},
                {"lod95_v_m", lod(vertical)},
                {"kept", dx->n},
                {"significant", (h && h->significant) || (vertical && vertical->significant)}};
}

// The epoch's 3-D vectors (docs/vectors.md) of the areas whose centre lies in the zone's
// box, in the map's frame: where each is drawn (u, v of its centre), its components along u,
// v and the third axis w = u × v (along the normal of a wall), and the LoD95 along u and v
// (StoredAreaVector::lod95_along). Null when the epoch has no vectors or the zone is not a
// box.
Json area_vectors_json(const std::vector<StoredAreaVector>& areas,
                       const std::optional<report::ZoneBox>& box, const Eigen::Vector3d& u,
                       const Eigen::Vector3d& v) {
    if (areas.empty() || !box) return nullptr;
    const Eigen::Vector3d w = u.cross(v);
    Json us = Json::array(), vs = Json::array(), du = Json::array(), dv = Json::array(),
         dw = Json::array(), lu = Json::array(), lv = Json::array();
    for (const StoredAreaVector& a : areas) {
        if (!box->contains(a.centre)) continue;
        us.push_back(std::round(u.dot(a.centre) * 1000.0) / 1000.0);
        vs.push_back(std::round(v.dot(a.centre) * 1000.0) / 1000.0);
        du.push_back(u.dot(a.displacement));
        dv.push_back(v.dot(a.displacement));
        dw.push_back(w.dot(a.displacement));
        lu.push_back(a.lod95_along(u));
        lv.push_back(a.lod95_along(v));
    }
    return Json{{"u", us},    {"v", vs},         {"du_m", du},     {"dv_m", dv},
                {"dw_m", dw}, {"lod95_u_m", lu}, {"lod95_v_m", lv}};
}

}  // namespace

Json core_point_map_json(const EpochDatabase& db, EpochId id, bool& absent) {
    absent = false;
    const CorePointMap map = [&] {
        try {
            return read_core_point_map(db, id);
        } catch (const NoCorePointMap&) {
            absent = true;
            throw;
        }
    }();
    const Epoch epoch = *db.epochs().find(id);  // read_core_point_map found it
    const auto& ref = map.reference.reference;
    const std::vector<StoredAreaVector> vectors = read_area_vectors(db, id);
    std::map<std::string, std::optional<report::ZoneBox>> boxes;
    if (!vectors.empty()) {
        for (const auto& [name, definition] : db.site().zones())
            boxes[name] = report::parse_zone_box(definition);
    }
    Json zones = Json::array();
    for (std::size_t z = 0; z < map.reference.zone_names.size(); ++z) {
        const auto& cores = map.reference.zone_cores[z];
        // The wall frame: u horizontal along the wall (up × mean normal), v up; a zone
        // facing up or down (no horizontal normal) is drawn in plan, x and y.
        Eigen::Vector3d n = Eigen::Vector3d::Zero();
        for (auto k : cores) {
            if (ref.normals()[k].allFinite()) n += ref.normals()[k];
        }
        Eigen::Vector3d u = Eigen::Vector3d::UnitZ().cross(n);
        Eigen::Vector3d v = Eigen::Vector3d::UnitZ();
        const bool plan = u.norm() < 0.2 * n.norm() || n.norm() == 0.0;
        if (plan) {
            u = Eigen::Vector3d::UnitX();
            v = Eigen::Vector3d::UnitY();
        }
        u.normalize();
        Json core = Json::array(), us = Json::array(), vs = Json::array(), d = Json::array(),
             lod = Json::array(), n1 = Json::array(), n2 = Json::array(), sig = Json::array();
        for (auto k : cores) {
            if (!std::isfinite(map.distance[k])) continue;
            const Eigen::Vector3d p = ref.core_points()[k];
            core.push_back(k);
            us.push_back(std::round(u.dot(p) * 1000.0) / 1000.0);
            vs.push_back(std::round(v.dot(p) * 1000.0) / 1000.0);
            d.push_back(map.distance[k]);
            lod.push_back(map.lod95[k]);
            n1.push_back(static_cast<std::int64_t>(map.n1[k]));
            n2.push_back(static_cast<std::int64_t>(map.n2[k]));
            sig.push_back(std::abs(map.distance[k]) > map.lod95[k]);
        }
        zones.push_back(
            {{"zone", map.reference.zone_names[z]},
             {"frame", plan ? "plan" : "wall"},
             {"core_points", cores.size()},
             {"core", core},
             {"u", us},
             {"v", vs},
             {"distance_m", d},
             {"lod95_m", lod},
             {"n1", n1},
             {"n2", n2},
             {"significant", sig},
             {"keypoint", keypoint_vector_json(db, epoch, map.reference.zone_names[z], u, v)},
             {"vectors", area_vectors_json(vectors, boxes[map.reference.zone_names[z]], u, v)}});
    }
    return Json{{"epoch", id}, {"core_points", ref.size()}, {"zones", zones}};
}

}  // namespace tlsmon
