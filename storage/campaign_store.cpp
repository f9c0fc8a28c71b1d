// Campaign rows: written in one transaction with their segments, read by sha256, id or range.
#include "storage/campaign_store.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <string_view>

#include "core/error.hpp"
#include "storage/connection.hpp"
#include "storage/series_reader.hpp"
#include "storage/shared_rows.hpp"

namespace tlsmon {

namespace {

constexpr const char* kCampaignColumns =
    "id, sha256, instrument, kind, acquired, added, file_path, file_size, reference_epoch_id,"
    " points, ground_points, global_rx_rad, global_ry_rad, global_rz_rad, global_tx_m,"
    " global_ty_m, global_tz_m, global_pairs, global_rmse_m, segments, registered_segments,"
    " test_statistic, test_dof, test_p, segments_differ, alpha, c2c_mean_m, c2c_sigma_m,"
    " c2c_median_m, c2c_p95_m, c2c_missing, parameters_json, seconds, coarse, coarse_planes,"
    " frame";

constexpr const char* kSegmentColumns =
    "segment, class, cluster, points, voxels, outcome, reference_segment, reference_overlap,"
    " pairs, rank, iterations, converged,"
    " centroid_x_m, centroid_y_m, centroid_z_m, rx_rad, ry_rad, rz_rad, tx_m, ty_m, tz_m,"
    " sigma_rx_rad, sigma_ry_rad, sigma_rz_rad, sigma_tx_m, sigma_ty_m, sigma_tz_m,"
    " cut_fraction, cut_bias_m, rmse_m, test_statistic, test_dof, test_p, c2c_mean_m,"
    " c2c_sigma_m, c2c_median_m, c2c_p95_m, c2c_max_m";

// ",?" for each column of `columns` but the first.
std::string placeholders(std::string_view columns) {
    std::string out;
    for (std::size_t i = 0; i < std::size_t(std::count(columns.begin(), columns.end(), ',')); ++i)
        out += ",?";
    return out;
}

// The segment's optional reals in kSegmentColumns' order from centroid_x_m on (test_dof
// apart), so writing and reading walk one list.
template <class Row>
auto segment_reals(Row& r) {
    return std::array{&r.centroid[0],   &r.centroid[1],   &r.centroid[2],   &r.parameters[0],
                      &r.parameters[1], &r.parameters[2], &r.parameters[3], &r.parameters[4],
                      &r.parameters[5], &r.sigmas[0],     &r.sigmas[1],     &r.sigmas[2],
                      &r.sigmas[3],     &r.sigmas[4],     &r.sigmas[5],     &r.cut_fraction,
                      &r.cut_bias,      &r.rmse,          &r.test_statistic};
}
template <class Row>
auto segment_tail(Row& r) {  // after test_dof
    return std::array{&r.test_p, &r.c2c_mean, &r.c2c_sigma, &r.c2c_median, &r.c2c_p95, &r.c2c_max};
}

void check(const Connection& c, const CampaignRow& r, const std::vector<CampaignSegmentRow>& s) {
    const std::string where = "campaign " + r.sha256.substr(0, 12) + ": ";
    if (r.sha256.size() != 64) throw_storage(c, where + "a sha256 has 64 hex digits");
    bool finite = std::isfinite(r.global_rmse) && std::isfinite(r.seconds);
    for (double v : r.global) finite = finite && std::isfinite(v);
    for (const auto& row : s) {
        auto copy = row;
        for (auto* v : segment_reals(copy)) finite = finite && (!*v || std::isfinite(**v));
        for (auto* v : segment_tail(copy)) finite = finite && (!*v || std::isfinite(**v));
        finite = finite && (!row.reference_overlap || std::isfinite(*row.reference_overlap));
    }
    if (r.frame)
        for (double v : *r.frame) finite = finite && std::isfinite(v);
    if (!finite) throw_storage(c, where + "a figure is not finite");
}

void check(const Connection& c, const CampaignRow& r, const CampaignPoints& p) {
    for (const auto& a : p.arrays)
        if (a.values.size() != p.size())
            throw_storage(c, "campaign " + r.sha256.substr(0, 12) + ": its point array '" +
                                 a.quantity + "' has " + std::to_string(a.values.size()) +
                                 " values, not " + std::to_string(p.size()));
}

CampaignRow read_campaign(SQLite::Statement& q) {
    CampaignRow r;
    int k = 0;
    r.id = q.getColumn(k++).getInt64();
    r.sha256 = q.getColumn(k++).getString();
    r.instrument = q.getColumn(k++).getString();
    r.kind = q.getColumn(k++).getString();
    r.acquired = q.getColumn(k++).getInt64();
    r.added = q.getColumn(k++).getInt64();
    r.file_path = q.getColumn(k++).getString();
    r.file_size = q.getColumn(k++).getInt64();
    r.reference_epoch = q.getColumn(k++).getInt64();
    r.points = q.getColumn(k++).getInt64();
    r.ground_points = q.getColumn(k++).getInt64();
    for (double& v : r.global) v = q.getColumn(k++).getDouble();
    r.global_pairs = q.getColumn(k++).getInt64();
    r.global_rmse = q.getColumn(k++).getDouble();
    r.segments = q.getColumn(k++).getInt64();
    r.registered_segments = q.getColumn(k++).getInt64();
    r.test_statistic = optional_double(q.getColumn(k++));
    r.test_dof = optional_int64(q.getColumn(k++));
    r.test_p = optional_double(q.getColumn(k++));
    if (const auto d = optional_int64(q.getColumn(k++))) r.segments_differ = *d != 0;
    r.alpha = q.getColumn(k++).getDouble();
    r.c2c_mean = optional_double(q.getColumn(k++));
    r.c2c_sigma = optional_double(q.getColumn(k++));
    r.c2c_median = optional_double(q.getColumn(k++));
    r.c2c_p95 = optional_double(q.getColumn(k++));
    r.c2c_missing = q.getColumn(k++).getInt64();
    r.parameters_json = q.getColumn(k++).getString();
    r.seconds = q.getColumn(k++).getDouble();
    r.coarse = q.getColumn(k++).getString();
    r.coarse_planes = optional_int64(q.getColumn(k++));
    const auto frame = q.getColumn(k++);
    if (!frame.isNull()) {
        if (frame.getBytes() != 128)
            throw Error("campaign " + std::to_string(r.id) + ": a frame of " +
                        std::to_string(frame.getBytes()) + " bytes");
        r.frame.emplace();
        std::memcpy(r.frame->data(), frame.getBlob(), 128);
    }
    return r;
}

void check(const Connection& c, const CampaignRow& r, const std::vector<ZoneResult>& zones) {
    for (const auto& z : zones) {
        const std::string where =
            "campaign " + r.sha256.substr(0, 12) + ", zone '" + z.zone + "': ";
        if (!is_campaign_quantity(z.quantity))
            throw_storage(c, where + "'" + z.quantity + "' is not a campaign quantity (" +
                                 std::string(kCampaignQuantityPrefix) + "…)");
        if (!std::isfinite(z.value) || (z.uncertainty && !std::isfinite(*z.uncertainty)))
            throw_storage(c, where + "a figure is not finite");
    }
}

void write_zone_results(Connection& c, CampaignId id, UtcSeconds acquired,
                        const std::vector<ZoneResult>& zones) {
    SQLite::Statement s(c.db,
                        "INSERT INTO campaign_zone_results (zone_id, quantity_id, acquired,"
                        " campaign_id, value, uncertainty, n, significant)"
                        " VALUES (?,?,?,?,?,?,?,?)");
    for (const auto& z : zones) {
        s.reset();
        s.bind(1, zone_id_by_name(c, z.zone));
        s.bind(2, quantity_id(c, z.quantity));
        s.bind(3, acquired);
        s.bind(4, id);
        s.bind(5, z.value);
        bind_optional(s, 6, z.uncertainty);
        s.bind(7, z.n);
        s.bind(8, z.significant ? 1 : 0);
        s.exec();
    }
}

void write_points(Connection& c, CampaignId id, const CampaignPoints& p) {
    SQLite::Statement head(c.db,
                           "INSERT INTO campaign_points (campaign_id, origin_x_m, origin_y_m,"
                           " origin_z_m, spacing_m, count) VALUES (?,?,?,?,?,?)");
    head.bind(1, id);
    for (int k = 0; k < 3; ++k) head.bind(2 + k, p.origin[std::size_t(k)]);
    head.bind(5, p.spacing);
    head.bind(6, std::int64_t(p.size()));
    head.exec();
    SQLite::Statement a(c.db,
                        "INSERT INTO campaign_point_arrays (campaign_id, quantity, count, data)"
                        " VALUES (?,?,?,?)");
    for (const auto& array : p.arrays) {
        a.reset();
        a.bind(1, id);
        a.bind(2, array.quantity);
        a.bind(3, std::int64_t(array.values.size()));
        // bindNoCopy: the vector outlives exec().
        a.bindNoCopy(4, array.values.data(), int(array.values.size() * sizeof(float)));
        a.exec();
    }
}

std::vector<CampaignRow> campaigns_where(const Connection& c, const std::string& where,
                                         const std::function<void(SQLite::Statement&)>& bind) {
    return guarded(c, "reading campaigns", [&] {
        SQLite::Statement q(c.db,
                            std::string("SELECT ") + kCampaignColumns + " FROM campaigns " + where);
        bind(q);
        std::vector<CampaignRow> out;
        while (q.executeStep()) out.push_back(read_campaign(q));
        return out;
    });
}

}  // namespace

CampaignId CampaignStore::add(const CampaignRow& r, const std::vector<CampaignSegmentRow>& rows,
                              const CampaignPoints& points,
                              const std::vector<ZoneResult>& zone_results,
                              const AlarmEvaluation& evaluate) {
    check(*c_, r, rows);
    check(*c_, r, points);
    check(*c_, r, zone_results);
    return guarded(*c_, "storing a campaign", [&] {
        SQLite::Transaction tx(c_->db, SQLite::TransactionBehavior::IMMEDIATE);
        SQLite::Statement insert(c_->db, std::string("INSERT INTO campaigns (") + kCampaignColumns +
                                             ") VALUES (NULL" + placeholders(kCampaignColumns) +
                                             ")");
        int k = 1;
        insert.bind(k++, r.sha256);
        insert.bind(k++, r.instrument);
        insert.bind(k++, r.kind);
        insert.bind(k++, r.acquired);
        insert.bind(k++, r.added);
        insert.bind(k++, r.file_path);
        insert.bind(k++, r.file_size);
        insert.bind(k++, r.reference_epoch);
        insert.bind(k++, r.points);
        insert.bind(k++, r.ground_points);
        for (double v : r.global) insert.bind(k++, v);
        insert.bind(k++, r.global_pairs);
        insert.bind(k++, r.global_rmse);
        insert.bind(k++, r.segments);
        insert.bind(k++, r.registered_segments);
        bind_optional(insert, k++, r.test_statistic);
        bind_optional(insert, k++, r.test_dof);
        bind_optional(insert, k++, r.test_p);
        bind_optional(
            insert, k++,
            r.segments_differ ? std::optional<std::int64_t>(*r.segments_differ) : std::nullopt);
        insert.bind(k++, r.alpha);
        bind_optional(insert, k++, r.c2c_mean);
        bind_optional(insert, k++, r.c2c_sigma);
        bind_optional(insert, k++, r.c2c_median);
        bind_optional(insert, k++, r.c2c_p95);
        insert.bind(k++, r.c2c_missing);
        insert.bind(k++, r.parameters_json);
        insert.bind(k++, r.seconds);
        insert.bind(k++, r.coarse);
        bind_optional(insert, k++, r.coarse_planes);
        if (r.frame)
            insert.bindNoCopy(k++, r.frame->data(), 128);  // r outlives exec()
        else
            insert.bind(k++);
        insert.exec();
        const CampaignId id = c_->db.getLastInsertRowid();
        SQLite::Statement seg(c_->db, std::string("INSERT INTO campaign_segments (campaign_id, ") +
                                          kSegmentColumns + ") VALUES (?,?" +
                                          placeholders(kSegmentColumns) + ")");
        for (auto row : rows) {
            seg.reset();
            k = 1;
            seg.bind(k++, id);
            seg.bind(k++, row.segment);
            seg.bind(k++, row.kind);
            seg.bind(k++, row.cluster);
            seg.bind(k++, row.points);
            seg.bind(k++, row.voxels);
            seg.bind(k++, row.outcome);
            bind_optional(seg, k++, row.reference_segment);
            bind_optional(seg, k++, row.reference_overlap);
            seg.bind(k++, row.pairs);
            seg.bind(k++, row.rank);
            seg.bind(k++, row.iterations);
            seg.bind(k++, row.converged ? 1 : 0);
            for (auto* v : segment_reals(row)) bind_optional(seg, k++, *v);
            bind_optional(seg, k++, row.test_dof);
            for (auto* v : segment_tail(row)) bind_optional(seg, k++, *v);
            seg.exec();
        }
        if (!points.arrays.empty()) write_points(*c_, id, points);
        write_zone_results(*c_, id, r.acquired, zone_results);
        if (evaluate) {
            const AlarmRows alarm_rows = evaluate(id, AlarmStore(*c_), SeriesReader(*c_));
            for (const auto& a : alarm_rows.states) write_alarm_state(*c_, a);
            for (const auto& e : alarm_rows.events) write_alarm_event(*c_, e);
            for (const auto& e : alarm_rows.system_events) write_system_event(*c_, e);
        }
        tx.commit();
        return id;
    });
}

std::optional<CampaignRow> CampaignStore::find(const std::string& sha256) const {
    auto rows =
        campaigns_where(*c_, "WHERE sha256 = ?", [&](SQLite::Statement& q) { q.bind(1, sha256); });
    if (rows.empty()) return std::nullopt;
    return rows.front();
}

std::optional<CampaignRow> CampaignStore::get(CampaignId id) const {
    auto rows = campaigns_where(*c_, "WHERE id = ?", [&](SQLite::Statement& q) { q.bind(1, id); });
    if (rows.empty()) return std::nullopt;
    return rows.front();
}

std::vector<CampaignRow> CampaignStore::in_range(const TimeRange& range) const {
    return campaigns_where(*c_, "WHERE acquired BETWEEN ? AND ? ORDER BY acquired, id",
                           [&](SQLite::Statement& q) {
                               q.bind(1, range.lower());
                               q.bind(2, range.upper());
                           });
}

std::vector<CampaignSegmentRow> CampaignStore::segments(CampaignId id) const {
    return guarded(*c_, "reading a campaign's segments", [&] {
        SQLite::Statement q(c_->db, std::string("SELECT ") + kSegmentColumns +
                                        " FROM campaign_segments WHERE campaign_id = ?"
                                        " ORDER BY segment");
        q.bind(1, id);
        std::vector<CampaignSegmentRow> out;
        while (q.executeStep()) {
            CampaignSegmentRow r;
            int k = 0;
            r.segment = q.getColumn(k++).getInt64();
            r.kind = q.getColumn(k++).getString();
            r.cluster = q.getColumn(k++).getInt64();
            r.points = q.getColumn(k++).getInt64();
            r.voxels = q.getColumn(k++).getInt64();
            r.outcome = q.getColumn(k++).getString();
            r.reference_segment = optional_int64(q.getColumn(k++));
            r.reference_overlap = optional_double(q.getColumn(k++));
            r.pairs = q.getColumn(k++).getInt64();
            r.rank = q.getColumn(k++).getInt64();
            r.iterations = q.getColumn(k++).getInt64();
            r.converged = q.getColumn(k++).getInt() != 0;
            for (auto* v : segment_reals(r)) *v = optional_double(q.getColumn(k++));
            r.test_dof = optional_int64(q.getColumn(k++));
            for (auto* v : segment_tail(r)) *v = optional_double(q.getColumn(k++));
            out.push_back(std::move(r));
        }
        return out;
    });
}

std::optional<CampaignPoints> CampaignStore::points(CampaignId id) const {
    return guarded(*c_, "reading a campaign's points", [&]() -> std::optional<CampaignPoints> {
        SQLite::Statement head(c_->db,
                               "SELECT origin_x_m, origin_y_m, origin_z_m, spacing_m, count"
                               " FROM campaign_points WHERE campaign_id = ?");
        head.bind(1, id);
        if (!head.executeStep()) return std::nullopt;
        CampaignPoints out;
        for (int k = 0; k < 3; ++k) out.origin[std::size_t(k)] = head.getColumn(k).getDouble();
        out.spacing = head.getColumn(3).getDouble();
        const std::int64_t count = head.getColumn(4).getInt64();
        SQLite::Statement q(c_->db,
                            "SELECT quantity, count, data FROM campaign_point_arrays"
                            " WHERE campaign_id = ? ORDER BY rowid");
        q.bind(1, id);
        while (q.executeStep()) {
            CorePointArray a{q.getColumn(0).getString(), {}};
            const auto data = q.getColumn(2);
            if (q.getColumn(1).getInt64() != count || data.getBytes() != count * 4)
                throw_storage(*c_, "campaign " + std::to_string(id) + " point array '" +
                                       a.quantity + "': " + std::to_string(data.getBytes()) +
                                       " bytes for " + std::to_string(count) + " points");
            a.values.resize(std::size_t(count));
            if (count > 0) std::memcpy(a.values.data(), data.getBlob(), std::size_t(count) * 4);
            out.arrays.push_back(std::move(a));
        }
        return out;
    });
}

std::vector<ZoneResult> CampaignStore::zone_results(CampaignId id) const {
    return guarded(*c_, "reading a campaign's zone rows", [&] {
        SQLite::Statement q(c_->db,
                            "SELECT z.name, q.name, r.value, r.uncertainty, r.n, r.significant"
                            " FROM campaign_zone_results r JOIN zones z ON z.id = r.zone_id"
                            " JOIN quantities q ON q.id = r.quantity_id"
                            " WHERE r.campaign_id = ? ORDER BY z.name, q.name");
        q.bind(1, id);
        std::vector<ZoneResult> out;
        while (q.executeStep()) {
            out.push_back(ZoneResult{q.getColumn(0).getString(), q.getColumn(1).getString(),
                                     q.getColumn(2).getDouble(), optional_double(q.getColumn(3)),
                                     q.getColumn(4).getInt64(), q.getColumn(5).getInt() != 0});
        }
        return out;
    });
}

const std::vector<float>* CampaignPoints::array(const std::string& quantity) const {
    for (const auto& a : arrays)
        if (a.quantity == quantity) return &a.values;
    return nullptr;
}

std::array<const std::vector<float>*, 7> CampaignPoints::columns() const {
    std::array<const std::vector<float>*, 7> out{};
    for (std::size_t k = 0; k < out.size(); ++k) {
        out[k] = array(kCampaignPointArrays[k]);
        if (!out[k])
            throw Error(std::string("a campaign's points without their '") +
                        kCampaignPointArrays[k] + "' array");
    }
    return out;
}

}  // namespace tlsmon
