// The keypoint displacement model's rows: written inside an epoch's commit, read by range.
#include "storage/keypoint_models.hpp"

#include <cmath>
#include <limits>
#include <map>

#include "storage/connection.hpp"
#include "storage/series_reader.hpp"
#include "storage/shared_rows.hpp"

namespace tlsmon {

namespace {

constexpr const char* kCoefficientColumns = "a00, a10, a01, a20, a11, a02, a30, a21, a12, a03";

// A model row is whole or it is refused: present exactly when defined, every number finite.
void check_model(Connection& c, EpochId id, const KeypointModelRow& m) {
    const std::string where =
        "epoch " + std::to_string(id) + ", keypoint model of '" + m.quantity + "': ";
    if (m.quantity.empty() || m.variable.empty())
        throw_storage(c, where + "a model needs its quantity and variable");
    const bool complete = m.t_centre && m.t_scale && m.z_centre && m.z_scale && m.coefficients &&
                          m.sum_abs_residuals && m.residual_scale;
    const bool any = m.t_centre || m.t_scale || m.z_centre || m.z_scale || m.coefficients ||
                     m.sum_abs_residuals || m.residual_scale;
    if (m.defined && !complete) throw_storage(c, where + "a defined model needs every figure");
    if (!m.defined && (any || !m.residuals.empty()))
        throw_storage(c, where + "an undefined model has no figures");
    if (!m.defined && m.reason.empty())
        throw_storage(c, where + "an undefined model needs a reason");
    const auto finite = [](const std::optional<double>& v) { return !v || std::isfinite(*v); };
    bool ok = finite(m.t_centre) && finite(m.t_scale) && finite(m.z_centre) && finite(m.z_scale) &&
              finite(m.sum_abs_residuals) && finite(m.residual_scale);
    if (m.coefficients)
        for (double a : *m.coefficients) ok = ok && std::isfinite(a);
    for (const auto& r : m.residuals)
        ok = ok && std::isfinite(r.t) && std::isfinite(r.z) && std::isfinite(r.d) &&
             std::isfinite(r.residual) && !r.zone.empty();
    if (!ok) throw_storage(c, where + "a figure is not finite (or a residual has no zone)");
}

}  // namespace

std::optional<double> KeypointModelRow::at(double t, double z) const {
    if (!defined || !coefficients || !t_centre || !t_scale || !z_centre || !z_scale)
        return std::nullopt;
    const double u = (t - *t_centre) / *t_scale, w = (z - *z_centre) / *z_scale;
    // Terms by total degree, then falling power of u: 00 10 01 20 11 02 30 21 12 03.
    static constexpr int kP[10] = {0, 1, 0, 2, 1, 0, 3, 2, 1, 0};
    static constexpr int kQ[10] = {0, 0, 1, 0, 1, 2, 0, 1, 2, 3};
    double d = 0;
    for (int k = 0; k < 10; ++k) d += (*coefficients)[k] * std::pow(u, kP[k]) * std::pow(w, kQ[k]);
    return d;
}

void write_keypoint_models(Connection& c, EpochId id, const std::vector<KeypointModelRow>& models) {
    if (models.empty()) return;
    for (const auto& m : models) check_model(c, id, m);
    SQLite::Statement s(c.db, std::string("INSERT INTO keypoint_models (epoch_id, quantity,"
                                          " variable, defined, reason, observations, iterations,"
                                          " converged, t_centre, t_scale, z_centre, z_scale, ") +
                                  kCoefficientColumns +
                                  ", sum_abs_residuals, residual_scale)"
                                  " VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
    SQLite::Statement r(c.db,
                        "INSERT INTO keypoint_model_residuals (epoch_id, quantity, zone, t, z,"
                        " d, residual) VALUES (?,?,?,?,?,?,?)");
    for (const auto& m : models) {
        s.reset();
        s.bind(1, id);
        s.bind(2, m.quantity);
        s.bind(3, m.variable);
        s.bind(4, m.defined ? 1 : 0);
        s.bind(5, m.reason);
        s.bind(6, m.observations);
        s.bind(7, m.iterations);
        s.bind(8, m.converged ? 1 : 0);
        bind_optional(s, 9, m.t_centre);
        bind_optional(s, 10, m.t_scale);
        bind_optional(s, 11, m.z_centre);
        bind_optional(s, 12, m.z_scale);
        for (int k = 0; k < 10; ++k)
            bind_optional(
                s, 13 + k,
                m.coefficients ? std::optional<double>((*m.coefficients)[k]) : std::nullopt);
        bind_optional(s, 23, m.sum_abs_residuals);
        bind_optional(s, 24, m.residual_scale);
        s.exec();
        for (const auto& x : m.residuals) {
            r.reset();
            r.bind(1, id);
            r.bind(2, m.quantity);
            r.bind(3, x.zone);
            r.bind(4, x.t);
            r.bind(5, x.z);
            r.bind(6, x.d);
            r.bind(7, x.residual);
            r.exec();
        }
    }
}

namespace {

constexpr const char* kModelSelect =
    "SELECT m.epoch_id, e.acquired, m.quantity, m.variable, m.defined, m.reason,"
    " m.observations, m.iterations, m.converged, m.t_centre, m.t_scale, m.z_centre, m.z_scale,"
    " a00, a10, a01, a20, a11, a02, a30, a21, a12, a03, m.sum_abs_residuals, m.residual_scale"
    " FROM keypoint_models m JOIN epochs e ON e.id = m.epoch_id ";

// The selected fits (kModelSelect + the caller's WHERE and ORDER), each with its residuals.
std::vector<StoredKeypointModel> read_models(Connection& c, SQLite::Statement& s) {
    std::vector<StoredKeypointModel> out;
    while (s.executeStep()) {
        StoredKeypointModel stored;
        stored.epoch = s.getColumn(0).getInt64();
        stored.acquired = s.getColumn(1).getInt64();
        auto& m = stored.model;
        m.quantity = s.getColumn(2).getString();
        m.variable = s.getColumn(3).getString();
        m.defined = s.getColumn(4).getInt() != 0;
        m.reason = s.getColumn(5).getString();
        m.observations = s.getColumn(6).getInt64();
        m.iterations = s.getColumn(7).getInt64();
        m.converged = s.getColumn(8).getInt() != 0;
        m.t_centre = optional_double(s.getColumn(9));
        m.t_scale = optional_double(s.getColumn(10));
        m.z_centre = optional_double(s.getColumn(11));
        m.z_scale = optional_double(s.getColumn(12));
        if (!s.getColumn(13).isNull()) {
            std::array<double, 10> a{};
            for (int k = 0; k < 10; ++k) a[k] = s.getColumn(13 + k).getDouble();
            m.coefficients = a;
        }
        m.sum_abs_residuals = optional_double(s.getColumn(23));
        m.residual_scale = optional_double(s.getColumn(24));
        out.push_back(std::move(stored));
    }
    SQLite::Statement r(c.db,
                        "SELECT zone, t, z, d, residual FROM keypoint_model_residuals"
                        " WHERE epoch_id = ? AND quantity = ? ORDER BY zone");
    for (auto& stored : out) {
        r.reset();
        r.bind(1, stored.epoch);
        r.bind(2, stored.model.quantity);
        while (r.executeStep())
            stored.model.residuals.push_back(
                {r.getColumn(0).getString(), r.getColumn(1).getDouble(), r.getColumn(2).getDouble(),
                 r.getColumn(3).getDouble(), r.getColumn(4).getDouble()});
    }
    return out;
}

}  // namespace

std::vector<StoredKeypointModel> KeypointModelStore::in_range(
    const TimeRange& range, const std::optional<std::string>& quantity) const {
    return guarded(*c_, "reading keypoint models", [&] {
        SQLite::Statement s(c_->db, std::string(kModelSelect) +
                                        "WHERE e.acquired BETWEEN ? AND ?"
                                        " AND (? IS NULL OR m.quantity = ?)"
                                        " ORDER BY e.acquired, e.id, m.quantity");
        s.bind(1, range.lower());
        s.bind(2, range.upper());
        bind_optional(s, 3, quantity);
        bind_optional(s, 4, quantity);
        return read_models(*c_, s);
    });
}

std::optional<StoredKeypointModel> KeypointModelStore::latest_defined(
    const std::string& quantity) const {
    return guarded(*c_, "reading the latest keypoint model", [&] {
        SQLite::Statement s(c_->db, std::string(kModelSelect) +
                                        "WHERE m.quantity = ? AND m.defined = 1"
                                        " ORDER BY e.acquired DESC, e.id DESC LIMIT 1");
        s.bind(1, quantity);
        auto models = read_models(*c_, s);
        return models.empty() ? std::nullopt
                              : std::optional<StoredKeypointModel>(std::move(models.front()));
    });
}

}  // namespace tlsmon
