// Read functions for `tlsmon status|query|events` and the HTTP API.
#include "storage/series_reader.hpp"

#include <algorithm>
#include <cstring>
#include <functional>
#include <limits>
#include <tuple>

#include "storage/alarm_store.hpp"
#include "storage/campaign_store.hpp"
#include "storage/connection.hpp"
#include "storage/shared_rows.hpp"

namespace tlsmon {

namespace {

std::optional<Epoch> first_epoch(Connection& c, const std::string& where_order) {
    SQLite::Statement s(
        c.db, std::string("SELECT ") + kEpochColumns + " FROM epochs " + where_order + " LIMIT 1");
    if (!s.executeStep()) return std::nullopt;
    return read_epoch(s);
}

std::int64_t file_bytes(const std::filesystem::path& p) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(p, ec);
    return ec ? 0 : static_cast<std::int64_t>(size);
}

}  // namespace

std::int64_t SeriesReader::database_bytes() const {
    return file_bytes(c_->path) + file_bytes(c_->path.string() + "-wal");
}

StatusSummary SeriesReader::status_summary() const {
    StatusSummary out;
    guarded(*c_, "reading the status summary", [&] {
        for (auto s : {EpochStatus::pending, EpochStatus::processing, EpochStatus::done,
                       EpochStatus::failed, EpochStatus::rejected}) {
            out.epochs_by_status[s] = 0;
        }
        // One read transaction: every figure from the same snapshot.
        SQLite::Transaction tx(c_->db, SQLite::TransactionBehavior::DEFERRED);
        // Kept by triggers (0012_epoch_status_counts.sql): one page, not the whole index.
        SQLite::Statement counts(c_->db, "SELECT status, n FROM epoch_status_counts");
        while (counts.executeStep()) {
            out.epochs_by_status[epoch_status_from_string(counts.getColumn(0).getString())] =
                counts.getColumn(1).getInt64();
        }
        out.backlog = out.epochs_by_status[EpochStatus::pending] +
                      out.epochs_by_status[EpochStatus::processing];
        out.last_done = first_epoch(*c_, "WHERE status = 'done' ORDER BY acquired DESC, id DESC");
        out.last_failure = first_epoch(
            *c_, "WHERE status IN ('failed', 'rejected') ORDER BY updated DESC, id DESC");
        SQLite::Statement oldest(c_->db,
                                 "SELECT min(acquired) FROM epochs WHERE status = 'pending'");
        if (oldest.executeStep()) out.oldest_pending = optional_int64(oldest.getColumn(0));
        out.reference_epoch = Epochs(*c_).reference();
        out.alarm_states = AlarmStore(*c_).states();
        for (const auto& a : out.alarm_states) {
            if (a.state != "normal") ++out.alarms_active;
            if (a.state == "unack" || a.state == "rtn_unack") ++out.alarms_unacknowledged;
        }
    });
    out.database_bytes = database_bytes();
    out.schema_version = c_->version;
    return out;
}

std::vector<Epoch> SeriesReader::epochs_in_range(const TimeRange& range,
                                                 std::optional<EpochStatus> status) const {
    return guarded(*c_, "listing epochs", [&] {
        // With a status: the index epochs_by_status (status, acquired, id).
        SQLite::Statement s(c_->db, std::string("SELECT ") + kEpochColumns +
                                        " FROM epochs WHERE acquired BETWEEN ? AND ?" +
                                        (status ? " AND status = ?" : "") +
                                        " ORDER BY acquired, id");
        s.bind(1, range.lower());
        s.bind(2, range.upper());
        if (status) s.bind(3, std::string(to_string(*status)));
        std::vector<Epoch> out;
        while (s.executeStep()) out.push_back(read_epoch(s));
        return out;
    });
}

std::vector<SeriesPoint> SeriesReader::points(const std::string& zone, const std::string& quantity,
                                              const TimeRange& range) const {
    std::vector<SeriesPoint> out;
    for_each_point(zone, quantity, range, [&](const SeriesPoint& p) { out.push_back(p); });
    return out;
}

void SeriesReader::for_each_point(const std::string& zone, const std::string& quantity,
                                  const TimeRange& range,
                                  const std::function<void(const SeriesPoint&)>& visit) const {
    if (is_campaign_quantity(quantity))
        return for_each_campaign_point(zone, quantity, range, visit);
    guarded(*c_, "reading a time series", [&] {
        // One range scan of the key (zone_id, quantity_id, acquired, epoch_id); the datum
        // from the covering index of 0013_registrations_datum.sql, not the large rows.
        SQLite::Statement s(c_->db,
                            "SELECT r.epoch_id, r.acquired, r.value, r.uncertainty, r.n,"
                            " r.significant, coalesce(g.method, 'unregistered'),"
                            " coalesce(g.accepted, 0)"
                            " FROM zone_results r LEFT JOIN registrations g"
                            " INDEXED BY registrations_datum ON g.epoch_id = r.epoch_id"
                            " WHERE r.zone_id = (SELECT id FROM zones WHERE name = ?)"
                            " AND r.quantity_id = (SELECT id FROM quantities WHERE name = ?)"
                            " AND r.acquired BETWEEN ? AND ?"
                            " ORDER BY r.acquired, r.epoch_id");
        s.bind(1, zone);
        s.bind(2, quantity);
        s.bind(3, range.lower());
        s.bind(4, range.upper());
        SeriesPoint p;
        while (s.executeStep()) {
            p.epoch = s.getColumn(0).getInt64();
            p.acquired = s.getColumn(1).getInt64();
            p.value = s.getColumn(2).getDouble();
            p.uncertainty = optional_double(s.getColumn(3));
            p.n = s.getColumn(4).getInt64();
            p.significant = s.getColumn(5).getInt() != 0;
            p.datum = s.getColumn(6).getText();
            p.registration_accepted = s.getColumn(7).getInt() != 0;
            visit(p);
        }
    });
}

void SeriesReader::for_each_campaign_point(
    const std::string& zone, const std::string& quantity, const TimeRange& range,
    const std::function<void(const SeriesPoint&)>& visit) const {
    guarded(*c_, "reading a campaign series", [&] {
        // One range scan of the key (zone_id, quantity_id, acquired, campaign_id); only
        // registered segments' points make a campaign's zone value, so it is accepted.
        SQLite::Statement s(c_->db,
                            "SELECT r.campaign_id, r.acquired, r.value, r.uncertainty, r.n,"
                            " r.significant FROM campaign_zone_results r"
                            " WHERE r.zone_id = (SELECT id FROM zones WHERE name = ?)"
                            " AND r.quantity_id = (SELECT id FROM quantities WHERE name = ?)"
                            " AND r.acquired BETWEEN ? AND ?"
                            " ORDER BY r.acquired, r.campaign_id");
        s.bind(1, zone);
        s.bind(2, quantity);
        s.bind(3, range.lower());
        s.bind(4, range.upper());
        SeriesPoint p;
        p.datum = "campaign";
        p.registration_accepted = true;
        while (s.executeStep()) {
            p.campaign = s.getColumn(0).getInt64();
            p.acquired = s.getColumn(1).getInt64();
            p.value = s.getColumn(2).getDouble();
            p.uncertainty = optional_double(s.getColumn(3));
            p.n = s.getColumn(4).getInt64();
            p.significant = s.getColumn(5).getInt() != 0;
            visit(p);
        }
    });
}

std::vector<EpochZoneValue> SeriesReader::epoch_zone_values(EpochId id) const {
    return guarded(*c_, "reading an epoch's zone values", [&] {
        // One seek per zone quantity at the epoch's key (zone_id, quantity_id, acquired,
        // epoch_id); CROSS JOIN keeps that loop order, as in latest_values.
        SQLite::Statement s(c_->db,
                            "SELECT z.name, z.definition, q.name, r.value, r.uncertainty, r.n,"
                            " r.significant FROM epochs e CROSS JOIN zones z"
                            " CROSS JOIN quantities q CROSS JOIN zone_results r"
                            " WHERE e.id = ? AND r.zone_id = z.id AND r.quantity_id = q.id"
                            " AND r.acquired = e.acquired AND r.epoch_id = e.id"
                            " ORDER BY z.name, q.name");
        s.bind(1, id);
        std::vector<EpochZoneValue> out;
        while (s.executeStep()) {
            out.push_back({s.getColumn(0).getString(), s.getColumn(1).getString(),
                           s.getColumn(2).getString(), s.getColumn(3).getDouble(),
                           optional_double(s.getColumn(4)), s.getColumn(5).getInt64(),
                           s.getColumn(6).getInt() != 0});
        }
        return out;
    });
}

std::vector<LatestValue> SeriesReader::latest_values() const {
    return guarded(*c_, "reading the latest values", [&] {
        // Per zone quantity, one seek to the end of its key (zone_id, quantity_id, acquired,
        // epoch_id); CROSS JOIN keeps zones x quantities the outer loops (SQLite's planner
        // otherwise scans every row of zone_results).
        SQLite::Statement s(c_->db,
                            "SELECT z.name, q.name, r.epoch_id, r.acquired, r.value, r.uncertainty,"
                            " r.n, r.significant, coalesce(g.method, 'unregistered'),"
                            " coalesce(g.accepted, 0)"
                            " FROM zones z CROSS JOIN quantities q CROSS JOIN zone_results r"
                            " LEFT JOIN registrations g INDEXED BY registrations_datum"
                            " ON g.epoch_id = r.epoch_id"
                            " WHERE r.zone_id = z.id AND r.quantity_id = q.id"
                            " AND (r.acquired, r.epoch_id) = (SELECT r2.acquired, r2.epoch_id"
                            "  FROM zone_results r2 WHERE r2.zone_id = z.id AND r2.quantity_id ="
                            "  q.id ORDER BY r2.acquired DESC, r2.epoch_id DESC LIMIT 1)"
                            " ORDER BY z.name, q.name");
        std::vector<LatestValue> out;
        while (s.executeStep()) {
            out.push_back({s.getColumn(0).getString(), s.getColumn(1).getString(),
                           SeriesPoint{s.getColumn(2).getInt64(), s.getColumn(3).getInt64(),
                                       s.getColumn(4).getDouble(), optional_double(s.getColumn(5)),
                                       s.getColumn(6).getInt64(), s.getColumn(7).getInt() != 0,
                                       s.getColumn(8).getString(), s.getColumn(9).getInt() != 0,
                                       std::nullopt}});
        }
        // The campaigns' own quantities: few rows, one query.
        SQLite::Statement c(c_->db,
                            "SELECT z.name, q.name, r.campaign_id, r.acquired, r.value,"
                            " r.uncertainty, r.n, r.significant"
                            " FROM campaign_zone_results r JOIN zones z ON z.id = r.zone_id"
                            " JOIN quantities q ON q.id = r.quantity_id"
                            " WHERE (r.acquired, r.campaign_id) = (SELECT r2.acquired,"
                            "  r2.campaign_id FROM campaign_zone_results r2 WHERE r2.zone_id ="
                            "  r.zone_id AND r2.quantity_id = r.quantity_id"
                            "  ORDER BY r2.acquired DESC, r2.campaign_id DESC LIMIT 1)");
        while (c.executeStep()) {
            SeriesPoint p{0,
                          c.getColumn(3).getInt64(),
                          c.getColumn(4).getDouble(),
                          optional_double(c.getColumn(5)),
                          c.getColumn(6).getInt64(),
                          c.getColumn(7).getInt() != 0,
                          "campaign",
                          true,
                          c.getColumn(2).getInt64()};
            out.push_back({c.getColumn(0).getString(), c.getColumn(1).getString(), p});
        }
        std::stable_sort(out.begin(), out.end(), [](const LatestValue& a, const LatestValue& b) {
            return std::tie(a.zone, a.quantity) < std::tie(b.zone, b.quantity);
        });
        return out;
    });
}

std::vector<std::string> SeriesReader::quantities(const std::string& zone) const {
    return guarded(*c_, "listing quantities", [&] {
        SQLite::Statement s(c_->db,
                            "SELECT q.name FROM quantities q WHERE EXISTS (SELECT 1"
                            " FROM zone_results r WHERE r.zone_id ="
                            " (SELECT id FROM zones WHERE name = ?1) AND r.quantity_id = q.id)"
                            " OR EXISTS (SELECT 1 FROM campaign_zone_results r WHERE r.zone_id ="
                            " (SELECT id FROM zones WHERE name = ?1) AND r.quantity_id = q.id)"
                            " ORDER BY q.name");
        s.bind(1, zone);
        std::vector<std::string> out;
        while (s.executeStep()) out.push_back(s.getColumn(0).getString());
        return out;
    });
}

std::vector<EventRow> SeriesReader::events(const TimeRange& range,
                                           const std::optional<std::string>& kind) const {
    return guarded(*c_, "listing events", [&] {
        SQLite::Statement s(
            c_->db,
            "SELECT time, 'system' AS source, level, kind, message, epoch_id, '' AS rule, id,"
            " '' AS actor"
            " FROM system_events WHERE time BETWEEN ?1 AND ?2 AND (?3 IS NULL OR kind = ?3)"
            " UNION ALL"
            " SELECT a.time, 'alarm', a.level, a.kind, a.message, a.epoch_id, r.name, a.id,"
            " a.actor"
            " FROM alarm_events a JOIN alarm_rules r ON r.id = a.rule_id"
            " WHERE a.time BETWEEN ?1 AND ?2 AND (?3 IS NULL OR a.kind = ?3)"
            " ORDER BY 1, 2 DESC, 8");
        s.bind(1, range.lower());
        s.bind(2, range.upper());
        bind_optional(s, 3, kind);
        std::vector<EventRow> out;
        while (s.executeStep()) {
            out.push_back({s.getColumn(0).getInt64(), s.getColumn(1).getString(),
                           s.getColumn(2).getString(), s.getColumn(3).getString(),
                           s.getColumn(4).getString(), optional_int64(s.getColumn(5)),
                           s.getColumn(6).getString(), s.getColumn(8).getString()});
        }
        return out;
    });
}

std::optional<CorePointArray> SeriesReader::core_point_array(EpochId id,
                                                             const std::string& quantity) const {
    return guarded(*c_, "reading a core point array", [&]() -> std::optional<CorePointArray> {
        SQLite::Statement s(c_->db,
                            "SELECT count, data FROM core_point_arrays"
                            " WHERE epoch_id = ? AND quantity = ?");
        s.bind(1, id);
        s.bind(2, quantity);
        if (!s.executeStep()) return std::nullopt;
        const auto count = s.getColumn(0).getInt64();
        const auto data = s.getColumn(1);
        if (count < 0 || data.getBytes() != count * static_cast<std::int64_t>(sizeof(float))) {
            throw_storage(*c_, "epoch " + std::to_string(id) + " core point array '" + quantity +
                                   "': " + std::to_string(data.getBytes()) + " bytes for " +
                                   std::to_string(count) + " values");
        }
        CorePointArray out{quantity, std::vector<float>(static_cast<std::size_t>(count))};
        if (count > 0) std::memcpy(out.values.data(), data.getBlob(), data.getBytes());
        return out;
    });
}

std::vector<StageRun> SeriesReader::stages(EpochId id) const {
    return guarded(*c_, "reading the stages of an epoch", [&] {
        SQLite::Statement s(c_->db,
                            "SELECT stage, ms, rejected, note FROM epoch_stages WHERE epoch_id = ?"
                            " ORDER BY position");
        s.bind(1, id);
        std::vector<StageRun> out;
        while (s.executeStep()) {
            out.push_back({s.getColumn(0).getString(), s.getColumn(1).getDouble(),
                           s.getColumn(2).getString(), s.getColumn(3).getString()});
        }
        return out;
    });
}

}  // namespace tlsmon
