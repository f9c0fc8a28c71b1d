// The thermal compensation's rows: written inside an epoch's commit, read by zone quantity.
#include "storage/thermal_store.hpp"

#include <cmath>
#include <cstring>
#include <map>
#include <utility>

#include "storage/connection.hpp"
#include "storage/meteo_store.hpp"
#include "storage/series_reader.hpp"
#include "storage/shared_rows.hpp"

namespace tlsmon {

namespace {

constexpr const char* kModelColumns =
    "zone, quantity, version, epoch_id, training_from, training_to, observations, excluded,"
    " surface_lag_h, section_lag_h, terms, coefficients, covariance, trend_origin,"
    " residual_sigma, prediction_sigma, day_mean_sigma, day_spread_max, cv_days,"
    " lag1_autocorrelation, measurement_variance,"
    " explained_share, amplitude_min_c, amplitude_max_c, iterations, converged";

std::string terms_json(const std::vector<std::string>& terms) {
    std::string out = "[";
    for (const auto& t : terms) out += (out.size() > 1 ? ",\"" : "\"") + t + "\"";
    return out + "]";
}

// The names of a JSON array of plain strings (as terms_json writes them).
std::vector<std::string> terms_of(const std::string& json) {
    std::vector<std::string> out;
    std::size_t i = 0;
    while ((i = json.find('"', i)) != std::string::npos) {
        const std::size_t j = json.find('"', i + 1);
        out.push_back(json.substr(i + 1, j - i - 1));
        i = j + 1;
    }
    return out;
}

std::vector<double> doubles_of(const SQLite::Column& c) {
    std::vector<double> out(static_cast<std::size_t>(c.getBytes()) / sizeof(double));
    if (!out.empty()) std::memcpy(out.data(), c.getBlob(), out.size() * sizeof(double));
    return out;
}

ThermalModelRow read_model(SQLite::Statement& s) {
    ThermalModelRow m;
    m.zone = s.getColumn(0).getString();
    m.quantity = s.getColumn(1).getString();
    m.version = s.getColumn(2).getInt64();
    m.epoch = s.getColumn(3).getInt64();
    m.training_from = s.getColumn(4).getInt64();
    m.training_to = s.getColumn(5).getInt64();
    m.observations = s.getColumn(6).getInt64();
    m.excluded = s.getColumn(7).getInt64();
    m.surface_lag_h = s.getColumn(8).getDouble();
    m.section_lag_h = s.getColumn(9).getDouble();
    m.terms = terms_of(s.getColumn(10).getString());
    m.coefficients = doubles_of(s.getColumn(11));
    m.covariance = doubles_of(s.getColumn(12));
    m.trend_origin = s.getColumn(13).getDouble();
    m.residual_sigma = s.getColumn(14).getDouble();
    m.prediction_sigma = s.getColumn(15).getDouble();
    m.day_mean_sigma = s.getColumn(16).getDouble();
    m.day_spread_max = s.getColumn(17).getDouble();
    m.cv_days = s.getColumn(18).getInt64();
    m.lag1_autocorrelation = s.getColumn(19).getDouble();
    m.measurement_variance = s.getColumn(20).getDouble();
    m.explained_share = s.getColumn(21).getDouble();
    m.amplitude_min_c = s.getColumn(22).getDouble();
    m.amplitude_max_c = s.getColumn(23).getDouble();
    m.iterations = s.getColumn(24).getInt64();
    m.converged = s.getColumn(25).getInt() != 0;
    return m;
}

std::optional<double> optional_real(const SQLite::Column& c) {
    if (c.isNull()) return std::nullopt;
    return c.getDouble();
}

// A model row is whole or it is refused: its matrices match its terms, every figure finite.
void check_model(Connection& c, EpochId id, const ThermalModelRow& m) {
    const std::string where =
        "epoch " + std::to_string(id) + ", thermal model of " + m.zone + " " + m.quantity + ": ";
    const std::size_t p = m.terms.size();
    if (m.zone.empty() || m.quantity.empty() || p == 0 || m.coefficients.size() != p ||
        m.covariance.size() != p * p)
        throw_storage(c, where + "a model needs its zone, quantity, terms and their matrices");
    bool finite = std::isfinite(m.residual_sigma) && std::isfinite(m.prediction_sigma) &&
                  std::isfinite(m.day_mean_sigma) && std::isfinite(m.day_spread_max) &&
                  std::isfinite(m.amplitude_min_c) && std::isfinite(m.amplitude_max_c) &&
                  std::isfinite(m.lag1_autocorrelation) && std::isfinite(m.explained_share) &&
                  std::isfinite(m.trend_origin);
    for (const double v : m.coefficients) finite = finite && std::isfinite(v);
    for (const double v : m.covariance) finite = finite && std::isfinite(v);
    if (!finite) throw_storage(c, where + "a figure is not finite");
}

}  // namespace

const char* to_string(ThermalQuality q) {
    switch (q) {
        case ThermalQuality::compensated:
            return "compensated";
        case ThermalQuality::extrapolated:
            return "extrapolated";
        case ThermalQuality::no_meteo:
            return "no_meteo";
        case ThermalQuality::no_model:
            return "no_model";
    }
    return "?";
}

namespace {

ThermalQuality quality_of(const std::string& text) {
    for (const auto q : {ThermalQuality::compensated, ThermalQuality::extrapolated,
                         ThermalQuality::no_meteo, ThermalQuality::no_model})
        if (text == to_string(q)) return q;
    return ThermalQuality::no_model;
}

}  // namespace

void write_thermal_rows(Connection& c, EpochId id, const std::vector<ThermalModelRow>& models,
                        const std::vector<ThermalCompensationRow>& compensations) {
    for (const auto& m : models) {
        check_model(c, id, m);
        // The next version of this zone quantity.
        SQLite::Statement s(c.db, std::string("INSERT INTO thermal_models (") + kModelColumns +
                                      ") SELECT ?1, ?2, coalesce(max(version), 0) + 1, ?3, ?4,"
                                      " ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, ?16,"
                                      " ?17, ?18, ?19, ?20, ?21, ?22, ?23, ?24, ?25 FROM"
                                      " thermal_models"
                                      " WHERE zone = ?1 AND quantity = ?2");
        s.bind(1, m.zone);
        s.bind(2, m.quantity);
        s.bind(3, id);
        s.bind(4, static_cast<std::int64_t>(m.training_from));
        s.bind(5, static_cast<std::int64_t>(m.training_to));
        s.bind(6, m.observations);
        s.bind(7, m.excluded);
        s.bind(8, m.surface_lag_h);
        s.bind(9, m.section_lag_h);
        s.bind(10, terms_json(m.terms));
        s.bind(11, m.coefficients.data(), static_cast<int>(m.coefficients.size() * sizeof(double)));
        s.bind(12, m.covariance.data(), static_cast<int>(m.covariance.size() * sizeof(double)));
        s.bind(13, m.trend_origin);
        s.bind(14, m.residual_sigma);
        s.bind(15, m.prediction_sigma);
        s.bind(16, m.day_mean_sigma);
        s.bind(17, m.day_spread_max);
        s.bind(18, m.cv_days);
        s.bind(19, m.lag1_autocorrelation);
        s.bind(20, m.measurement_variance);
        s.bind(21, m.explained_share);
        s.bind(22, m.amplitude_min_c);
        s.bind(23, m.amplitude_max_c);
        s.bind(24, m.iterations);
        s.bind(25, m.converged ? 1 : 0);
        s.exec();
    }
    for (const auto& r : compensations) {
        // A compensation names the model by version; 0 in the commit is the one fitted in it.
        SQLite::Statement s(
            c.db,
            "INSERT INTO thermal_compensations (epoch_id, zone, quantity, quality, model_version,"
            " reason, air_age_h, daily_amplitude_c, drift_z, spread_ratio, drifted, spread_grew)"
            " VALUES (?1, ?2, ?3, ?4, CASE WHEN ?5 = 0 THEN (SELECT max(version) FROM"
            " thermal_models WHERE zone = ?2 AND quantity = ?3) ELSE ?5 END, ?6, ?7, ?8, ?9, ?10,"
            " ?11, ?12)");
        s.bind(1, id);
        s.bind(2, r.zone);
        s.bind(3, r.quantity);
        s.bind(4, to_string(r.quality));
        bind_optional(s, 5, r.model_version);
        s.bind(6, r.reason);
        bind_optional(s, 7, r.air_age_h);
        bind_optional(s, 8, r.daily_amplitude_c);
        bind_optional(s, 9, r.drift_z);
        bind_optional(s, 10, r.spread_ratio);
        s.bind(11, r.drifted ? 1 : 0);
        s.bind(12, r.spread_grew ? 1 : 0);
        s.exec();
    }
}

std::optional<ThermalModelRow> ThermalStore::latest(const std::string& zone,
                                                    const std::string& quantity) const {
    return guarded(*c_, "reading a thermal model", [&]() -> std::optional<ThermalModelRow> {
        SQLite::Statement s(c_->db, std::string("SELECT ") + kModelColumns +
                                        " FROM thermal_models WHERE zone = ? AND quantity = ?"
                                        " ORDER BY version DESC LIMIT 1");
        s.bind(1, zone);
        s.bind(2, quantity);
        if (!s.executeStep()) return std::nullopt;
        return read_model(s);
    });
}

std::vector<ThermalModelRow> ThermalStore::models(
    const std::optional<std::string>& zone, const std::optional<std::string>& quantity) const {
    return guarded(*c_, "reading the thermal models", [&] {
        SQLite::Statement s(c_->db, std::string("SELECT ") + kModelColumns +
                                        " FROM thermal_models WHERE (?1 IS NULL OR zone = ?1)"
                                        " AND (?2 IS NULL OR quantity = ?2)"
                                        " ORDER BY zone, quantity, version");
        if (zone) s.bind(1, *zone);
        if (quantity) s.bind(2, *quantity);
        std::vector<ThermalModelRow> out;
        while (s.executeStep()) out.push_back(read_model(s));
        return out;
    });
}

namespace {

constexpr const char* kCompensationSelect =
    "SELECT t.epoch_id, e.acquired, t.zone, t.quantity, t.quality, t.model_version, t.reason,"
    " t.air_age_h, t.daily_amplitude_c, t.drift_z, t.spread_ratio, t.drifted, t.spread_grew"
    " FROM thermal_compensations t JOIN epochs e ON e.id = t.epoch_id";

StoredThermalCompensation read_compensation(SQLite::Statement& s) {
    StoredThermalCompensation out;
    out.epoch = s.getColumn(0).getInt64();
    out.acquired = s.getColumn(1).getInt64();
    ThermalCompensationRow& r = out.row;
    r.zone = s.getColumn(2).getString();
    r.quantity = s.getColumn(3).getString();
    r.quality = quality_of(s.getColumn(4).getString());
    if (!s.getColumn(5).isNull()) r.model_version = s.getColumn(5).getInt64();
    r.reason = s.getColumn(6).getString();
    r.air_age_h = optional_real(s.getColumn(7));
    r.daily_amplitude_c = optional_real(s.getColumn(8));
    r.drift_z = optional_real(s.getColumn(9));
    r.spread_ratio = optional_real(s.getColumn(10));
    r.drifted = s.getColumn(11).getInt() != 0;
    r.spread_grew = s.getColumn(12).getInt() != 0;
    return out;
}

}  // namespace

std::vector<StoredThermalCompensation> ThermalStore::compensations(
    const TimeRange& range, const std::optional<std::string>& zone,
    const std::optional<std::string>& quantity) const {
    return guarded(*c_, "reading the thermal compensations", [&] {
        SQLite::Statement s(c_->db, std::string(kCompensationSelect) +
                                        " WHERE e.acquired BETWEEN ?1 AND ?2 AND (?3 IS NULL OR"
                                        " t.zone = ?3) AND (?4 IS NULL OR t.quantity = ?4)"
                                        " ORDER BY e.acquired, e.id, t.zone, t.quantity");
        s.bind(1, range.lower());
        s.bind(2, range.upper());
        if (zone) s.bind(3, *zone);
        if (quantity) s.bind(4, *quantity);
        std::vector<StoredThermalCompensation> out;
        while (s.executeStep()) out.push_back(read_compensation(s));
        return out;
    });
}

std::optional<StoredThermalCompensation> ThermalStore::last_compensation(
    const std::string& zone, const std::string& quantity, UtcSeconds before) const {
    return guarded(*c_, "reading the last thermal compensation",
                   [&]() -> std::optional<StoredThermalCompensation> {
                       SQLite::Statement s(c_->db, std::string(kCompensationSelect) +
                                                       " WHERE t.zone = ? AND t.quantity = ? AND"
                                                       " e.acquired < ? ORDER BY e.acquired DESC,"
                                                       " e.id DESC LIMIT 1");
                       s.bind(1, zone);
                       s.bind(2, quantity);
                       s.bind(3, static_cast<std::int64_t>(before));
                       if (!s.executeStep()) return std::nullopt;
                       return read_compensation(s);
                   });
}

std::vector<AirTemperature> ThermalStore::air(const TimeRange& range) const {
    std::vector<AirTemperature> out;
    for (const EpochMeteo& m : MeteoStore(*c_).used_in_range(range))
        out.push_back({m.acquired, m.air_temperature_c});
    return out;
}

std::set<EpochId> ThermalStore::alarmed_epochs(const std::string& zone, const std::string& quantity,
                                               const TimeRange& range) const {
    return guarded(*c_, "reading the alarmed epochs of a zone", [&] {
        // Each rule on the zone's quantity is raised from a raise (or escalation) until it returns
        // or clears: its rule transitions, by time (acquisition times of their epochs).
        SQLite::Statement s(
            c_->db,
            "SELECT a.rule_id, a.time, a.kind FROM alarm_events a"
            " JOIN alarm_rules r ON r.id = a.rule_id JOIN zones z ON"
            " z.id = r.zone_id WHERE z.name = ? AND r.quantity = ? AND a.time <= ? AND a.kind IN"
            " ('raise', 'escalate', 'return', 'clear') ORDER BY a.time, a.id");
        s.bind(1, zone);
        s.bind(2, quantity);
        s.bind(3, range.upper());
        std::map<std::int64_t, UtcSeconds> raised_since;  // rule -> time raised
        std::vector<std::pair<UtcSeconds, UtcSeconds>> intervals;
        while (s.executeStep()) {
            const std::int64_t rule = s.getColumn(0).getInt64();
            const UtcSeconds t = s.getColumn(1).getInt64();
            const std::string kind = s.getColumn(2).getString();
            if (kind == "raise" || kind == "escalate") {
                raised_since.try_emplace(rule, t);
            } else if (const auto it = raised_since.find(rule); it != raised_since.end()) {
                intervals.emplace_back(it->second, t);
                raised_since.erase(it);
            }
        }
        for (const auto& [rule, since] : raised_since)
            intervals.emplace_back(since, std::numeric_limits<UtcSeconds>::max());
        std::set<EpochId> out;
        if (intervals.empty()) return out;
        SQLite::Statement e(c_->db,
                            "SELECT id, acquired FROM epochs WHERE acquired BETWEEN ? AND ?");
        e.bind(1, range.lower());
        e.bind(2, range.upper());
        while (e.executeStep()) {
            const UtcSeconds t = e.getColumn(1).getInt64();
            for (const auto& [from, to] : intervals)
                if (t >= from && t < to) out.insert(e.getColumn(0).getInt64());
        }
        return out;
    });
}

}  // namespace tlsmon
