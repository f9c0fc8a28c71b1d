// Epoch rows from discovery to a final status: insert-or-get by sha256, processing order,
// status transitions, crash recovery, the reference epoch.
#include "storage/epochs.hpp"

#include <algorithm>

#include "storage/connection.hpp"
#include "storage/shared_rows.hpp"

namespace tlsmon {

namespace {

bool is_sha256_hex(const std::string& s) {
    return s.size() == 64 && std::all_of(s.begin(), s.end(), [](char c) {
               return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
           });
}

std::string status_of(Connection& c, EpochId id) {
    SQLite::Statement s(c.db, "SELECT status FROM epochs WHERE id = ?");
    s.bind(1, id);
    if (!s.executeStep()) throw_storage(c, "no epoch " + std::to_string(id));
    return s.getColumn(0).getString();
}

// processing (or pending: a file found unreadable before it was claimed) -> failed/rejected.
void finish_unprocessed(Connection& c, EpochId id, EpochStatus to, const std::string& reason,
                        const std::optional<std::string>& moved_to) {
    if (reason.empty()) {
        throw_storage(c, "epoch " + std::to_string(id) + ": a " + std::string(to_string(to)) +
                             " epoch needs a reason");
    }
    guarded(c, "finishing an epoch", [&] {
        SQLite::Statement s(c.db,
                            "UPDATE epochs SET status = ?, reason = ?, updated = ?,"
                            " archive_path = coalesce(?, archive_path)"
                            " WHERE id = ? AND status IN ('pending', 'processing')");
        s.bind(1, std::string(to_string(to)));
        s.bind(2, reason);
        s.bind(3, static_cast<std::int64_t>(now_utc()));
        bind_optional(s, 4, moved_to);
        s.bind(5, id);
        if (s.exec() != 1) {
            throw_storage(c, "epoch " + std::to_string(id) + " cannot become " +
                                 std::string(to_string(to)) + " from status " + status_of(c, id));
        }
    });
}

}  // namespace

std::string_view to_string(EpochStatus status) {
    switch (status) {
        case EpochStatus::pending:
            return "pending";
        case EpochStatus::processing:
            return "processing";
        case EpochStatus::done:
            return "done";
        case EpochStatus::failed:
            return "failed";
        case EpochStatus::rejected:
            return "rejected";
    }
    return "?";
}

EpochStatus epoch_status_from_string(std::string_view name) {
    for (auto s : {EpochStatus::pending, EpochStatus::processing, EpochStatus::done,
                   EpochStatus::failed, EpochStatus::rejected}) {
        if (to_string(s) == name) return s;
    }
    throw StorageError("unknown epoch status '" + std::string(name) + "'");
}

EpochInsert Epochs::insert(const NewEpoch& epoch) {
    if (!is_sha256_hex(epoch.sha256)) {
        throw_storage(*c_, "epoch " + epoch.file_path.string() +
                               ": sha256 must be 64 lowercase hex digits, got '" + epoch.sha256 +
                               "'");
    }
    return guarded(*c_, "inserting an epoch", [&] {
        const auto now = static_cast<std::int64_t>(now_utc());
        SQLite::Statement s(c_->db,
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
        if (s.exec() == 1) return EpochInsert{c_->db.getLastInsertRowid(), true};
        SQLite::Statement q(c_->db, "SELECT id FROM epochs WHERE sha256 = ?");
        q.bind(1, epoch.sha256);
        if (!q.executeStep()) throw_storage(*c_, "epoch " + epoch.sha256 + " vanished");
        return EpochInsert{q.getColumn(0).getInt64(), false};
    });
}

std::optional<Epoch> Epochs::find(EpochId id) const {
    return guarded(*c_, "reading an epoch", [&]() -> std::optional<Epoch> {
        SQLite::Statement s(c_->db,
                            std::string("SELECT ") + kEpochColumns + " FROM epochs WHERE id = ?");
        s.bind(1, id);
        if (!s.executeStep()) return std::nullopt;
        return read_epoch(s);
    });
}

std::optional<Epoch> Epochs::find_by_sha256(const std::string& sha256) const {
    return guarded(*c_, "reading an epoch", [&]() -> std::optional<Epoch> {
        SQLite::Statement s(
            c_->db, std::string("SELECT ") + kEpochColumns + " FROM epochs WHERE sha256 = ?");
        s.bind(1, sha256);
        if (!s.executeStep()) return std::nullopt;
        return read_epoch(s);
    });
}

std::optional<Epoch> Epochs::find_by_file(const std::filesystem::path& file) const {
    return guarded(*c_, "reading an epoch", [&]() -> std::optional<Epoch> {
        SQLite::Statement s(c_->db,
                            std::string("SELECT ") + kEpochColumns +
                                " FROM epochs WHERE file_path = ? ORDER BY id DESC LIMIT 1");
        s.bind(1, file.string());
        if (!s.executeStep()) return std::nullopt;
        return read_epoch(s);
    });
}

std::vector<Epoch> Epochs::pending() const {
    return guarded(*c_, "listing pending epochs", [&] {
        SQLite::Statement s(c_->db, std::string("SELECT ") + kEpochColumns +
                                        " FROM epochs WHERE status = 'pending'"
                                        " ORDER BY acquired, id");
        std::vector<Epoch> out;
        while (s.executeStep()) out.push_back(read_epoch(s));
        return out;
    });
}

bool Epochs::claim(EpochId id) {
    return guarded(*c_, "claiming an epoch", [&] {
        SQLite::Statement s(c_->db,
                            "UPDATE epochs SET status = 'processing', updated = ?"
                            " WHERE id = ? AND status = 'pending'");
        s.bind(1, static_cast<std::int64_t>(now_utc()));
        s.bind(2, id);
        return s.exec() == 1;
    });
}

void Epochs::release(EpochId id) {
    guarded(*c_, "releasing an epoch", [&] {
        SQLite::Statement s(c_->db,
                            "UPDATE epochs SET status = 'pending', updated = ?"
                            " WHERE id = ? AND status = 'processing'");
        s.bind(1, static_cast<std::int64_t>(now_utc()));
        s.bind(2, id);
        if (s.exec() != 1) {
            throw_storage(*c_, "epoch " + std::to_string(id) +
                                   " cannot go back to pending from status " + status_of(*c_, id));
        }
    });
}

void Epochs::fail(EpochId id, const std::string& reason, std::optional<std::string> moved_to) {
    finish_unprocessed(*c_, id, EpochStatus::failed, reason, moved_to);
}

void Epochs::reject(EpochId id, const std::string& reason, std::optional<std::string> moved_to) {
    finish_unprocessed(*c_, id, EpochStatus::rejected, reason, moved_to);
}

bool Epochs::relocate(EpochId id, const std::filesystem::path& file) {
    return guarded(*c_, "relocating an epoch", [&] {
        SQLite::Statement s(c_->db,
                            "UPDATE epochs SET file_path = ?, status = 'pending', reason = '',"
                            " updated = ? WHERE id = ? AND (status = 'pending' OR"
                            " (status = 'failed' AND archive_path IS NULL))");
        s.bind(1, file.string());
        s.bind(2, static_cast<std::int64_t>(now_utc()));
        s.bind(3, id);
        return s.exec() == 1;
    });
}

std::int64_t Epochs::recover_interrupted() {
    return guarded(*c_, "recovering interrupted epochs", [&] {
        SQLite::Statement s(c_->db,
                            "UPDATE epochs SET status = 'pending', updated = ?"
                            " WHERE status = 'processing'");
        s.bind(1, static_cast<std::int64_t>(now_utc()));
        return static_cast<std::int64_t>(s.exec());
    });
}

void Epochs::set_reference(EpochId id) {
    guarded(*c_, "setting the reference epoch", [&] {
        SQLite::Transaction tx(c_->db, SQLite::TransactionBehavior::IMMEDIATE);
        SQLite::Statement q(c_->db, "SELECT epoch_id FROM reference_epoch");
        if (q.executeStep()) {
            const EpochId current = q.getColumn(0).getInt64();
            if (current == id) return;
            throw_storage(*c_, "the reference epoch is already " + std::to_string(current) +
                                   "; it cannot become " + std::to_string(id));
        }
        SQLite::Statement s(c_->db,
                            "INSERT INTO reference_epoch (singleton, epoch_id, set_at)"
                            " VALUES (1, ?, ?)");
        s.bind(1, id);
        s.bind(2, static_cast<std::int64_t>(now_utc()));
        s.exec();
        tx.commit();
    });
}

std::optional<EpochId> Epochs::reference() const {
    return guarded(*c_, "reading the reference epoch", [&]() -> std::optional<EpochId> {
        SQLite::Statement q(c_->db, "SELECT epoch_id FROM reference_epoch");
        if (!q.executeStep()) return std::nullopt;
        return q.getColumn(0).getInt64();
    });
}

}  // namespace tlsmon
