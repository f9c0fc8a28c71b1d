#include "storage/registration_store.hpp"

#include <cstring>
#include <limits>

#include "storage/connection.hpp"
#include "storage/series_reader.hpp"
#include "storage/shared_rows.hpp"
#include "storage/storage_error.hpp"

namespace tlsmon {

namespace {

std::optional<double> opt(const SQLite::Column& c) {
    if (c.isNull()) return std::nullopt;
    return c.getDouble();
}

}  // namespace

std::set<std::string> RegistrationStore::excluded_targets() const {
    return guarded(*c_, "reading target exclusions", [&] {
        SQLite::Statement s(
            c_->db, "SELECT DISTINCT target FROM target_exclusions WHERE resurveyed IS NULL");
        std::set<std::string> out;
        while (s.executeStep()) out.insert(s.getColumn(0).getString());
        return out;
    });
}

std::map<std::string, int> RegistrationStore::outlier_runs(std::int64_t before, int limit) const {
    return guarded(*c_, "reading the targets' outlier tests", [&] {
        SQLite::Statement s(c_->db,
                            "SELECT o.target, o.use FROM target_observations o JOIN"
                            " (SELECT e.id, e.acquired FROM epochs e JOIN registrations r ON"
                            " r.epoch_id = e.id WHERE e.acquired < ? ORDER BY e.acquired DESC,"
                            " e.id DESC LIMIT ?) n ON n.id = o.epoch_id"
                            " ORDER BY n.acquired DESC, n.id DESC");
        s.bind(1, before);
        s.bind(2, limit);
        std::map<std::string, int> runs;
        std::set<std::string> broken;  // a newer epoch where it did not fail
        while (s.executeStep()) {
            const std::string target = s.getColumn(0).getString();
            if (broken.count(target)) continue;
            if (s.getColumn(1).getString() == "excluded_outlier") {
                ++runs[target];
            } else {
                broken.insert(target);
            }
        }
        return runs;
    });
}

int RegistrationStore::mark_resurveyed(const std::string& target, std::int64_t unix_time) {
    return guarded(*c_, "clearing a target exclusion", [&] {
        SQLite::Statement s(c_->db,
                            "UPDATE target_exclusions SET resurveyed = ? WHERE target = ? AND"
                            " resurveyed IS NULL");
        s.bind(1, unix_time);
        s.bind(2, target);
        return s.exec();
    });
}

int RegistrationStore::resurvey(const std::string& target, std::int64_t unix_time,
                                const std::string& actor) {
    return guarded(*c_, "recording a target re-survey", [&] {
        SQLite::Transaction tx(c_->db, SQLite::TransactionBehavior::IMMEDIATE);
        SQLite::Statement s(c_->db,
                            "UPDATE target_exclusions SET resurveyed = ? WHERE target = ? AND"
                            " resurveyed IS NULL");
        s.bind(1, unix_time);
        s.bind(2, target);
        const int cleared = s.exec();
        if (cleared > 0) {
            write_system_event(*c_, SystemEvent{unix_time, "info", "target_resurveyed",
                                                "target " + target + " re-surveyed by " + actor +
                                                    ": offered to the registration again",
                                                std::nullopt});
        }
        tx.commit();
        return cleared;
    });
}

std::vector<TargetExclusion> RegistrationStore::exclusions() const {
    return guarded(*c_, "reading target exclusions", [&] {
        SQLite::Statement s(c_->db,
                            "SELECT x.target, x.epoch_id, e.acquired, x.resurveyed FROM"
                            " target_exclusions x JOIN epochs e ON e.id = x.epoch_id"
                            " ORDER BY e.acquired, x.epoch_id, x.target");
        std::vector<TargetExclusion> out;
        while (s.executeStep()) {
            TargetExclusion x;
            x.target = s.getColumn(0).getString();
            x.epoch = s.getColumn(1).getInt64();
            x.excluded_acquired = s.getColumn(2).getInt64();
            if (!s.getColumn(3).isNull()) x.resurveyed = s.getColumn(3).getInt64();
            out.push_back(std::move(x));
        }
        return out;
    });
}

std::optional<EpochId> RegistrationStore::last_epoch_with_targets() const {
    return guarded(*c_, "reading target observations", [&]() -> std::optional<EpochId> {
        SQLite::Statement s(c_->db,
                            "SELECT o.epoch_id FROM target_observations o JOIN epochs e ON"
                            " e.id = o.epoch_id ORDER BY e.acquired DESC, o.epoch_id DESC"
                            " LIMIT 1");
        if (!s.executeStep()) return std::nullopt;
        return s.getColumn(0).getInt64();
    });
}

std::optional<std::array<double, 16>> RegistrationStore::last_accepted_transform(
    UtcSeconds acquired) const {
    return guarded(*c_, "reading a registration", [&]() -> std::optional<std::array<double, 16>> {
        SQLite::Statement s(c_->db,
                            "SELECT r.transform FROM registrations r JOIN epochs e ON"
                            " e.id = r.epoch_id WHERE r.accepted = 1 AND e.acquired < ?"
                            " ORDER BY e.acquired DESC, r.epoch_id DESC LIMIT 1");
        s.bind(1, static_cast<std::int64_t>(acquired));
        if (!s.executeStep()) return std::nullopt;
        std::array<double, 16> t{};
        const auto blob = s.getColumn(0);
        if (blob.getBytes() != static_cast<int>(sizeof(t))) return std::nullopt;
        std::memcpy(t.data(), blob.getBlob(), sizeof(t));
        return t;
    });
}

std::vector<std::vector<std::uint8_t>> RegistrationStore::recent_stable_area_states(
    UtcSeconds acquired, EpochId reference_epoch, const std::string& segmentation,
    int count) const {
    return guarded(*c_, "reading stable-area masks", [&] {
        std::vector<std::vector<std::uint8_t>> out;
        SQLite::Statement s(c_->db,
                            "SELECT m.reference_epoch_id, m.segmentation, m.states FROM"
                            " stable_area_masks m JOIN epochs e ON e.id = m.epoch_id"
                            " WHERE e.acquired < ? ORDER BY e.acquired DESC, m.epoch_id DESC"
                            " LIMIT ?");
        s.bind(1, static_cast<std::int64_t>(acquired));
        s.bind(2, count);
        while (s.executeStep()) {
            if (s.getColumn(0).getInt64() != reference_epoch ||
                s.getColumn(1).getString() != segmentation)
                break;
            const auto states = s.getColumn(2);
            const auto* b = static_cast<const std::uint8_t*>(states.getBlob());
            out.emplace_back(b, b + states.getBytes());
        }
        return out;
    });
}

namespace {

constexpr const char* kRegistrationColumns =
    "r.method, r.transform, r.target_count, r.rms_m, r.max_residual_m, r.sigma0, r.accepted,"
    " r.quality_json, r.status, r.reason, r.omega_rad, r.phi_rad, r.kappa_rad, r.tx_m, r.ty_m,"
    " r.tz_m, r.qw, r.qx, r.qy, r.qz, r.sigma_omega_rad, r.sigma_phi_rad, r.sigma_kappa_rad,"
    " r.sigma_tx_m, r.sigma_ty_m, r.sigma_tz_m, r.variance_factor, r.redundancy, r.epoch_id";

// The row the statement stands on, in kRegistrationColumns' order.
RegistrationRow registration_row(const Connection& c, SQLite::Statement& s) {
    RegistrationRow r;
    r.method = s.getColumn(0).getString();
    const auto t = s.getColumn(1);
    if (t.getBytes() != static_cast<int>(sizeof(r.transform))) {
        throw_storage(c, "epoch " + std::to_string(s.getColumn(28).getInt64()) +
                             ": transform has " + std::to_string(t.getBytes()) + " bytes, not 128");
    }
    std::memcpy(r.transform.data(), t.getBlob(), sizeof(r.transform));
    r.target_count = s.getColumn(2).getInt64();
    r.rms_m = s.getColumn(3).getDouble();
    r.max_residual_m = s.getColumn(4).getDouble();
    r.sigma0 = opt(s.getColumn(5));
    r.accepted = s.getColumn(6).getInt() != 0;
    r.quality_json = s.getColumn(7).getString();
    r.status = s.getColumn(8).getString();
    r.reason = s.getColumn(9).getString();
    if (!s.getColumn(10).isNull()) {
        std::array<double, 6> p{}, q{};
        std::array<double, 4> quat{};
        for (int k = 0; k < 6; ++k) p[k] = s.getColumn(10 + k).getDouble();
        for (int k = 0; k < 4; ++k) quat[k] = s.getColumn(16 + k).getDouble();
        for (int k = 0; k < 6; ++k) q[k] = s.getColumn(20 + k).getDouble();
        r.parameters = p;
        r.quaternion = quat;
        r.sigmas = q;
    }
    r.variance_factor = opt(s.getColumn(26));
    if (!s.getColumn(27).isNull()) r.redundancy = s.getColumn(27).getInt64();
    return r;
}

constexpr const char* kTargetColumns =
    "o.target, o.kind, o.measured_x, o.measured_y, o.measured_z, o.residual_x, o.residual_y,"
    " o.residual_z, o.stable, o.used, o.status, o.reason, o.use, o.sigma_x, o.sigma_y,"
    " o.sigma_z, o.statistic, o.critical, o.minimal_detectable_bias_m, o.epoch_id";

TargetObservation target_row(SQLite::Statement& s) {
    TargetObservation t;
    t.target = s.getColumn(0).getString();
    t.kind = s.getColumn(1).getString();
    for (int i = 0; i < 3; ++i) t.measured[i] = s.getColumn(2 + i).getDouble();
    for (int i = 0; i < 3; ++i) t.residual[i] = s.getColumn(5 + i).getDouble();
    t.stable = s.getColumn(8).getInt() != 0;
    t.used = s.getColumn(9).getInt() != 0;
    t.status = s.getColumn(10).getString();
    t.reason = s.getColumn(11).getString();
    t.use = s.getColumn(12).getString();
    if (!s.getColumn(13).isNull()) {
        t.sigma = std::array<double, 3>{s.getColumn(13).getDouble(), s.getColumn(14).getDouble(),
                                        s.getColumn(15).getDouble()};
    }
    t.statistic = opt(s.getColumn(16));
    t.critical = opt(s.getColumn(17));
    t.minimal_detectable_bias_m = opt(s.getColumn(18));
    return t;
}

}  // namespace

std::optional<RegistrationRow> RegistrationStore::of_epoch(EpochId id) const {
    return guarded(*c_, "reading a registration", [&]() -> std::optional<RegistrationRow> {
        SQLite::Statement s(c_->db, std::string("SELECT ") + kRegistrationColumns +
                                        " FROM registrations r WHERE r.epoch_id = ?");
        s.bind(1, id);
        if (!s.executeStep()) return std::nullopt;
        return registration_row(*c_, s);
    });
}

std::vector<TargetObservation> RegistrationStore::targets_of_epoch(EpochId id) const {
    return guarded(*c_, "reading target observations", [&] {
        SQLite::Statement s(c_->db, std::string("SELECT ") + kTargetColumns +
                                        " FROM target_observations o WHERE o.epoch_id = ?"
                                        " ORDER BY o.target");
        s.bind(1, id);
        std::vector<TargetObservation> out;
        while (s.executeStep()) out.push_back(target_row(s));
        return out;
    });
}

RegistrationStore::EpochRegistrations RegistrationStore::in_range(const TimeRange& range) const {
    return guarded(*c_, "reading the registrations of a window", [&] {
        EpochRegistrations out;
        // The rows of the window's epochs, `alias` the table's alias.
        const auto joined = [](const char* alias) {
            return std::string(" JOIN epochs e ON e.id = ") + alias +
                   ".epoch_id WHERE e.acquired BETWEEN ? AND ?";
        };
        SQLite::Statement r(c_->db, std::string("SELECT ") + kRegistrationColumns +
                                        " FROM registrations r" + joined("r"));
        r.bind(1, range.lower());
        r.bind(2, range.upper());
        while (r.executeStep())
            out.registration[r.getColumn(28).getInt64()] = registration_row(*c_, r);
        SQLite::Statement t(c_->db, std::string("SELECT ") + kTargetColumns +
                                        " FROM target_observations o" + joined("o") +
                                        " ORDER BY o.epoch_id, o.target");
        t.bind(1, range.lower());
        t.bind(2, range.upper());
        while (t.executeStep()) out.targets[t.getColumn(19).getInt64()].push_back(target_row(t));
        SQLite::Statement z(c_->db,
                            "SELECT g.zone, g.max_sigma_3d_m, g.epoch_id FROM"
                            " registration_zone_sigmas g" +
                                joined("g") + " ORDER BY g.epoch_id, g.zone");
        z.bind(1, range.lower());
        z.bind(2, range.upper());
        while (z.executeStep())
            out.zone_sigmas[z.getColumn(2).getInt64()].push_back(
                {z.getColumn(0).getString(), z.getColumn(1).getDouble()});
        return out;
    });
}

std::vector<PlaneRow> RegistrationStore::planes_of_epoch(EpochId id) const {
    return guarded(*c_, "reading plane observations", [&] {
        SQLite::Statement s(
            c_->db,
            "SELECT plane, zone, role, normal_x, normal_y, normal_z, centroid_x, centroid_y,"
            " centroid_z, reference_points, epoch_points, tilt_u_rad, tilt_v_rad, shift_m,"
            " sigma_tilt_u_rad, sigma_tilt_v_rad, sigma_shift_m, statistic, critical, significant"
            " FROM plane_observations WHERE epoch_id = ? ORDER BY plane");
        s.bind(1, id);
        std::vector<PlaneRow> out;
        while (s.executeStep()) {
            PlaneRow p;
            p.plane = s.getColumn(0).getInt64();
            if (!s.getColumn(1).isNull()) p.zone = s.getColumn(1).getString();
            p.role = s.getColumn(2).getString();
            for (int k = 0; k < 3; ++k) {
                p.normal[k] = s.getColumn(3 + k).getDouble();
                p.centroid[k] = s.getColumn(6 + k).getDouble();
                p.change[k] = s.getColumn(11 + k).getDouble();
                p.sigma[k] = s.getColumn(14 + k).getDouble();
            }
            p.reference_points = s.getColumn(9).getInt64();
            p.epoch_points = s.getColumn(10).getInt64();
            p.statistic = s.getColumn(17).getDouble();
            p.critical = s.getColumn(18).getDouble();
            p.significant = s.getColumn(19).getInt() != 0;
            out.push_back(std::move(p));
        }
        return out;
    });
}

namespace {

// The inverse of the writer's encoding: little-endian int16 in 0.01 mm, −32768 for none.
std::vector<float> metres_from_hundredths(const SQLite::Column& blob, std::size_t n) {
    std::vector<float> out(n, std::numeric_limits<float>::quiet_NaN());
    if (static_cast<std::size_t>(blob.getBytes()) != 2 * n) {
        throw StorageError("stable-area mask: a blob of " + std::to_string(blob.getBytes()) +
                           " bytes for " + std::to_string(n) + " supervoxels");
    }
    const auto* b = static_cast<const unsigned char*>(blob.getBlob());
    for (std::size_t k = 0; k < n; ++k) {
        const auto q =
            static_cast<std::int16_t>(static_cast<std::uint16_t>(b[2 * k] | (b[2 * k + 1] << 8)));
        if (q != std::numeric_limits<std::int16_t>::min()) out[k] = static_cast<float>(q * 1e-5);
    }
    return out;
}

}  // namespace

std::optional<StableAreaMask> RegistrationStore::stable_areas_of_epoch(EpochId id) const {
    return guarded(*c_, "reading the stable-area mask", [&]() -> std::optional<StableAreaMask> {
        SQLite::Statement s(c_->db,
                            "SELECT reference_epoch_id, segmentation, supervoxels, stable,"
                            " unstable, stable_share, states, changes, lods"
                            " FROM stable_area_masks WHERE epoch_id = ?");
        s.bind(1, id);
        if (!s.executeStep()) return std::nullopt;
        StableAreaMask m;
        m.reference_epoch = s.getColumn(0).getInt64();
        m.segmentation = s.getColumn(1).getString();
        const auto n = static_cast<std::size_t>(s.getColumn(2).getInt64());
        m.stable = s.getColumn(3).getInt64();
        m.unstable = s.getColumn(4).getInt64();
        m.stable_share = s.getColumn(5).getDouble();
        const auto states = s.getColumn(6);
        if (static_cast<std::size_t>(states.getBytes()) != n) {
            throw StorageError("stable-area mask of epoch " + std::to_string(id) + ": " +
                               std::to_string(states.getBytes()) + " states for " +
                               std::to_string(n) + " supervoxels");
        }
        const auto* b = static_cast<const std::uint8_t*>(states.getBlob());
        m.states.assign(b, b + n);
        m.changes = metres_from_hundredths(s.getColumn(7), n);
        m.lods = metres_from_hundredths(s.getColumn(8), n);
        SQLite::Statement v(
            c_->db,
            "SELECT centroid_x, centroid_y, centroid_z, normal_x, normal_y,"
            " normal_z, voxels, roughness_m FROM stable_area_supervoxels"
            " WHERE reference_epoch_id = ? AND segmentation = ? ORDER BY supervoxel");
        v.bind(1, m.reference_epoch);
        v.bind(2, m.segmentation);
        while (v.executeStep()) {
            SupervoxelRow r;
            for (int k = 0; k < 3; ++k) {
                r.centroid[k] = v.getColumn(k).getDouble();
                r.normal[k] = v.getColumn(3 + k).getDouble();
            }
            r.voxels = v.getColumn(6).getInt64();
            r.roughness_m = v.getColumn(7).getDouble();
            m.supervoxels.push_back(r);
        }
        if (m.supervoxels.size() != n) {
            throw StorageError("stable-area mask of epoch " + std::to_string(id) + ": " +
                               std::to_string(m.supervoxels.size()) + " supervoxels stored for " +
                               std::to_string(n));
        }
        return m;
    });
}

std::vector<RegistrationZoneSigma> RegistrationStore::zone_sigmas_of_epoch(EpochId id) const {
    return guarded(*c_, "reading registration zone sigmas", [&] {
        SQLite::Statement s(c_->db,
                            "SELECT zone, max_sigma_3d_m FROM registration_zone_sigmas"
                            " WHERE epoch_id = ? ORDER BY zone");
        s.bind(1, id);
        std::vector<RegistrationZoneSigma> out;
        while (s.executeStep()) {
            out.push_back({s.getColumn(0).getString(), s.getColumn(1).getDouble()});
        }
        return out;
    });
}

}  // namespace tlsmon
