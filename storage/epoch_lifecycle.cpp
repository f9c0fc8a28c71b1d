// Epoch rows from discovery to a final status: insert-or-get by sha256, processing order,
// status transitions, crash recovery, the reference epoch, stations.
#include <algorithm>

#include "storage/epoch_database.hpp"
#include "storage/epoch_database_impl.hpp"

namespace tlsmon {

namespace {

bool is_sha256_hex(const std::string& s) {
    return s.size() == 64 && std::all_of(s.begin(), s.end(), [](char c) {
               return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
           });
}

std::string status_of(EpochDatabase::Impl& impl, EpochId id) {
    SQLite::Statement s(impl.db, "SELECT status FROM epochs WHERE id = ?");
    s.bind(1, id);
    if (!s.executeStep()) throw_storage(impl, "no epoch " + std::to_string(id));
    return s.getColumn(0).getString();
}

// processing (or pending: a file found unreadable before it was claimed) -> failed/rejected.
void finish_unprocessed(EpochDatabase::Impl& impl, EpochId id, EpochStatus to,
                        const std::string& reason, const std::optional<std::string>& moved_to) {
    if (reason.empty()) {
        throw_storage(impl, "epoch " + std::to_string(id) + ": a " + std::string(to_string(to)) +
                                " epoch needs a reason");
    }
    guarded(impl, "finishing an epoch", [&] {
        SQLite::Statement s(impl.db,
                            "UPDATE epochs SET status = ?, reason = ?, updated = ?,"
                            " archive_path = coalesce(?, archive_path)"
                            " WHERE id = ? AND status IN ('pending', 'processing')");
        s.bind(1, std::string(to_string(to)));
        s.bind(2, reason);
        s.bind(3, static_cast<std::int64_t>(now_utc()));
        bind_optional(s, 4, moved_to);
        s.bind(5, id);
        if (s.exec() != 1) {
            throw_storage(impl, "epoch " + std::to_string(id) + " cannot become " +
                                    std::string(to_string(to)) + " from status " +
                                    status_of(impl, id));
        }
    });
}

}  // namespace

StationId EpochDatabase::upsert_station(const std::string& name,
                                        const std::array<double, 3>& position) {
    return guarded(*impl_, "upserting a station", [&] {
        SQLite::Statement s(impl_->db,
                            "INSERT INTO stations (name, x, y, z) VALUES (?,?,?,?)"
                            " ON CONFLICT (name) DO UPDATE SET x = excluded.x, y = excluded.y,"
                            " z = excluded.z RETURNING id");
        s.bind(1, name);
        for (int i = 0; i < 3; ++i) s.bind(2 + i, position[i]);
        if (!s.executeStep()) throw_storage(*impl_, "upserting station '" + name + "' gave no id");
        const StationId id = s.getColumn(0).getInt64();
        while (s.executeStep()) {
        }
        return id;
    });
}

std::vector<Station> EpochDatabase::stations() const {
    return guarded(*impl_, "listing stations", [&] {
        SQLite::Statement s(impl_->db, "SELECT id, name, x, y, z FROM stations ORDER BY id");
        std::vector<Station> out;
        while (s.executeStep()) {
            out.push_back({s.getColumn(0).getInt64(),
                           s.getColumn(1).getString(),
                           {s.getColumn(2).getDouble(), s.getColumn(3).getDouble(),
                            s.getColumn(4).getDouble()}});
        }
        return out;
    });
}

EpochInsert EpochDatabase::insert_epoch(const NewEpoch& epoch) {
    if (!is_sha256_hex(epoch.sha256)) {
        throw_storage(*impl_, "epoch " + epoch.file_path.string() +
                                  ": sha256 must be 64 lowercase hex digits, got '" + epoch.sha256 +
                                  "'");
    }
    return guarded(*impl_, "inserting an epoch", [&] {
        const auto now = static_cast<std::int64_t>(now_utc());
        SQLite::Statement s(impl_->db,
                            "INSERT INTO epochs (sha256, acquired, discovered, updated,"
                            " file_path, file_size, station_id, status)"
                            " VALUES (?,?,?,?,?,?,?,'pending') ON CONFLICT (sha256) DO NOTHING");
        s.bind(1, epoch.sha256);
        s.bind(2, static_cast<std::int64_t>(epoch.acquired));
        s.bind(3, now);
        s.bind(4, now);
        s.bind(5, epoch.file_path.string());
        s.bind(6, static_cast<std::int64_t>(epoch.file_size));
        bind_optional(s, 7, epoch.station);
        if (s.exec() == 1) return EpochInsert{impl_->db.getLastInsertRowid(), true};
        SQLite::Statement q(impl_->db, "SELECT id FROM epochs WHERE sha256 = ?");
        q.bind(1, epoch.sha256);
        if (!q.executeStep()) throw_storage(*impl_, "epoch " + epoch.sha256 + " vanished");
        return EpochInsert{q.getColumn(0).getInt64(), false};
    });
}

std::optional<Epoch> EpochDatabase::epoch(EpochId id) const {
    return guarded(*impl_, "reading an epoch", [&]() -> std::optional<Epoch> {
        SQLite::Statement s(impl_->db,
                            std::string("SELECT ") + kEpochColumns + " FROM epochs WHERE id = ?");
        s.bind(1, id);
        if (!s.executeStep()) return std::nullopt;
        return read_epoch(s);
    });
}

std::optional<Epoch> EpochDatabase::epoch_by_sha256(const std::string& sha256) const {
    return guarded(*impl_, "reading an epoch", [&]() -> std::optional<Epoch> {
        SQLite::Statement s(
            impl_->db, std::string("SELECT ") + kEpochColumns + " FROM epochs WHERE sha256 = ?");
        s.bind(1, sha256);
        if (!s.executeStep()) return std::nullopt;
        return read_epoch(s);
    });
}

std::vector<Epoch> EpochDatabase::pending_epochs() const {
    return guarded(*impl_, "listing pending epochs", [&] {
        SQLite::Statement s(impl_->db, std::string("SELECT ") + kEpochColumns +
                                           " FROM epochs WHERE status = 'pending'"
                                           " ORDER BY acquired, id");
        std::vector<Epoch> out;
        while (s.executeStep()) out.push_back(read_epoch(s));
        return out;
    });
}

bool EpochDatabase::claim_epoch(EpochId id) {
    return guarded(*impl_, "claiming an epoch", [&] {
        SQLite::Statement s(impl_->db,
                            "UPDATE epochs SET status = 'processing', updated = ?"
                            " WHERE id = ? AND status = 'pending'");
        s.bind(1, static_cast<std::int64_t>(now_utc()));
        s.bind(2, id);
        return s.exec() == 1;
    });
}

void EpochDatabase::release_epoch(EpochId id) {
    guarded(*impl_, "releasing an epoch", [&] {
        SQLite::Statement s(impl_->db,
                            "UPDATE epochs SET status = 'pending', updated = ?"
                            " WHERE id = ? AND status = 'processing'");
        s.bind(1, static_cast<std::int64_t>(now_utc()));
        s.bind(2, id);
        if (s.exec() != 1) {
            throw_storage(*impl_, "epoch " + std::to_string(id) +
                                      " cannot go back to pending from status " +
                                      status_of(*impl_, id));
        }
    });
}

void EpochDatabase::fail_epoch(EpochId id, const std::string& reason,
                               std::optional<std::string> moved_to) {
    finish_unprocessed(*impl_, id, EpochStatus::failed, reason, moved_to);
}

void EpochDatabase::reject_epoch(EpochId id, const std::string& reason,
                                 std::optional<std::string> moved_to) {
    finish_unprocessed(*impl_, id, EpochStatus::rejected, reason, moved_to);
}

bool EpochDatabase::relocate_epoch(EpochId id, const std::filesystem::path& file) {
    return guarded(*impl_, "relocating an epoch", [&] {
        SQLite::Statement s(impl_->db,
                            "UPDATE epochs SET file_path = ?, status = 'pending', reason = '',"
                            " updated = ? WHERE id = ? AND (status = 'pending' OR"
                            " (status = 'failed' AND archive_path IS NULL))");
        s.bind(1, file.string());
        s.bind(2, static_cast<std::int64_t>(now_utc()));
        s.bind(3, id);
        return s.exec() == 1;
    });
}

std::int64_t EpochDatabase::recover_interrupted() {
    return guarded(*impl_, "recovering interrupted epochs", [&] {
        SQLite::Statement s(impl_->db,
                            "UPDATE epochs SET status = 'pending', updated = ?"
                            " WHERE status = 'processing'");
        s.bind(1, static_cast<std::int64_t>(now_utc()));
        return static_cast<std::int64_t>(s.exec());
    });
}

void EpochDatabase::set_reference_epoch(EpochId id) {
    guarded(*impl_, "setting the reference epoch", [&] {
        SQLite::Transaction tx(impl_->db, SQLite::TransactionBehavior::IMMEDIATE);
        SQLite::Statement q(impl_->db, "SELECT epoch_id FROM reference_epoch");
        if (q.executeStep()) {
            const EpochId current = q.getColumn(0).getInt64();
            if (current == id) return;
            throw_storage(*impl_, "the reference epoch is already " + std::to_string(current) +
                                      "; it cannot become " + std::to_string(id));
        }
        SQLite::Statement s(impl_->db,
                            "INSERT INTO reference_epoch (singleton, epoch_id, set_at)"
                            " VALUES (1, ?, ?)");
        s.bind(1, id);
        s.bind(2, static_cast<std::int64_t>(now_utc()));
        s.exec();
        tx.commit();
    });
}

std::optional<EpochId> EpochDatabase::reference_epoch() const {
    return guarded(*impl_, "reading the reference epoch", [&]() -> std::optional<EpochId> {
        SQLite::Statement q(impl_->db, "SELECT epoch_id FROM reference_epoch");
        if (!q.executeStep()) return std::nullopt;
        return q.getColumn(0).getInt64();
    });
}

}  // namespace tlsmon
