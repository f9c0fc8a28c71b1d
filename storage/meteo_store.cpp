// Meteo sidecar rows (docs/schema.md, "meteo_sidecars").
#include "storage/meteo_store.hpp"

#include <limits>

#include "storage/connection.hpp"
#include "storage/series_reader.hpp"
#include "storage/shared_rows.hpp"

namespace tlsmon {

namespace {

constexpr const char* kMeteoColumns =
    "epoch_id, outcome, file_name, sha256, path, reason, recorded, time, line,"
    " air_temperature_c, pressure_hpa, relative_humidity_pct";

MeteoSidecar read_sidecar(SQLite::Statement& s) {
    MeteoSidecar m;
    m.epoch = optional_int64(s.getColumn(0));
    m.outcome = meteo_outcome_from_string(s.getColumn(1).getString());
    m.file_name = s.getColumn(2).getString();
    m.sha256 = s.getColumn(3).getString();
    m.path = optional_string(s.getColumn(4));
    m.reason = s.getColumn(5).getString();
    m.recorded = s.getColumn(6).getInt64();
    if (!s.getColumn(7).isNull()) {
        m.values = MeteoValues{s.getColumn(7).getInt64(), s.getColumn(8).getInt64(),
                               s.getColumn(9).getDouble(), s.getColumn(10).getDouble(),
                               s.getColumn(11).getDouble()};
    }
    return m;
}

}  // namespace

std::string_view to_string(MeteoOutcome outcome) {
    switch (outcome) {
        case MeteoOutcome::used:
            return "used";
        case MeteoOutcome::rejected:
            return "rejected";
        case MeteoOutcome::unused:
            return "unused";
        case MeteoOutcome::orphan:
            return "orphan";
    }
    return "?";
}

MeteoOutcome meteo_outcome_from_string(std::string_view name) {
    for (auto o :
         {MeteoOutcome::used, MeteoOutcome::rejected, MeteoOutcome::unused, MeteoOutcome::orphan}) {
        if (to_string(o) == name) return o;
    }
    throw StorageError("unknown meteo sidecar outcome '" + std::string(name) + "'");
}

void write_meteo_sidecar(Connection& c, const MeteoSidecar& m) {
    SQLite::Statement s(c.db,
                        "INSERT INTO meteo_sidecars (epoch_id, outcome, file_name, sha256, path,"
                        " reason, recorded, time, line, air_temperature_c, pressure_hpa,"
                        " relative_humidity_pct) VALUES (?,?,?,?,?,?,?,?,?,?,?,?)");
    bind_optional(s, 1, m.epoch);
    s.bind(2, std::string(to_string(m.outcome)));
    s.bind(3, m.file_name);
    s.bind(4, m.sha256);
    bind_optional(s, 5, m.path);
    s.bind(6, m.reason);
    s.bind(7, static_cast<std::int64_t>(now_utc()));
    if (m.values) {
        s.bind(8, static_cast<std::int64_t>(m.values->time));
        s.bind(9, static_cast<std::int64_t>(m.values->line));
        s.bind(10, m.values->air_temperature_c);
        s.bind(11, m.values->pressure_hpa);
        s.bind(12, m.values->relative_humidity_pct);
    } else {
        for (int i = 8; i <= 12; ++i) s.bind(i);
    }
    s.exec();
}

std::optional<MeteoSidecar> MeteoStore::find(const std::string& sha256,
                                             const std::string& file_name) const {
    return guarded(*c_, "reading a meteo sidecar", [&]() -> std::optional<MeteoSidecar> {
        SQLite::Statement s(c_->db, std::string("SELECT ") + kMeteoColumns +
                                        " FROM meteo_sidecars WHERE sha256 = ? AND file_name = ?"
                                        " ORDER BY id DESC LIMIT 1");
        s.bind(1, sha256);
        s.bind(2, file_name);
        if (!s.executeStep()) return std::nullopt;
        return read_sidecar(s);
    });
}

std::vector<MeteoSidecar> MeteoStore::of_epoch(EpochId id) const {
    return guarded(*c_, "reading the meteo sidecars of an epoch", [&] {
        SQLite::Statement s(c_->db, std::string("SELECT ") + kMeteoColumns +
                                        " FROM meteo_sidecars WHERE epoch_id = ? ORDER BY id");
        s.bind(1, id);
        std::vector<MeteoSidecar> out;
        while (s.executeStep()) out.push_back(read_sidecar(s));
        return out;
    });
}

std::vector<EpochMeteo> MeteoStore::used_in_range(const TimeRange& range) const {
    return guarded(*c_, "reading the meteo of a time range", [&] {
        // The epochs of the range by acquisition time (index epochs_by_acquired), each with
        // the row its processing used (index meteo_sidecars_by_epoch).
        SQLite::Statement s(c_->db,
                            "SELECT e.id, e.acquired, m.air_temperature_c, m.pressure_hpa,"
                            " m.relative_humidity_pct FROM epochs e JOIN meteo_sidecars m ON"
                            " m.epoch_id = e.id AND m.outcome = 'used'"
                            " WHERE e.acquired BETWEEN ? AND ? ORDER BY e.acquired, e.id");
        s.bind(1, range.lower());
        s.bind(2, range.upper());
        std::vector<EpochMeteo> out;
        while (s.executeStep()) {
            out.push_back({s.getColumn(0).getInt64(), s.getColumn(1).getInt64(),
                           s.getColumn(2).getDouble(), s.getColumn(3).getDouble(),
                           s.getColumn(4).getDouble()});
        }
        return out;
    });
}

std::optional<Epoch> MeteoStore::scan_epoch(const std::filesystem::path& folder,
                                            const std::string& stem) const {
    return guarded(*c_, "finding the epoch of a meteo sidecar", [&]() -> std::optional<Epoch> {
        // Every file "<folder>/<stem>.<ext>"; "<stem>.x.ptx" has another stem and is skipped.
        // Compared as bytes: substr() of a TEXT counts characters.
        const std::string prefix = (folder / stem).string() + ".";
        SQLite::Statement s(c_->db, std::string("SELECT ") + kEpochColumns +
                                        " FROM epochs WHERE substr(CAST(file_path AS BLOB), 1, ?) ="
                                        " CAST(? AS BLOB)"
                                        " ORDER BY id DESC");
        s.bind(1, static_cast<std::int64_t>(prefix.size()));
        s.bind(2, prefix);
        while (s.executeStep()) {
            Epoch e = read_epoch(s);
            if (std::filesystem::path(e.file_path).stem() == stem) return e;
        }
        return std::nullopt;
    });
}

void MeteoStore::record(const MeteoSidecar& sidecar) {
    if (sidecar.outcome != MeteoOutcome::unused && sidecar.outcome != MeteoOutcome::orphan) {
        throw_storage(*c_, sidecar.file_name +
                               ": a used or rejected sidecar is recorded by its epoch's commit");
    }
    guarded(*c_, "recording a meteo sidecar", [&] { write_meteo_sidecar(*c_, sidecar); });
}

}  // namespace tlsmon
