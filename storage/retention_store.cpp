#include "storage/retention_store.hpp"

#include <algorithm>

#include "storage/connection.hpp"
#include "storage/shared_rows.hpp"
#include "storage/state_epochs.hpp"

namespace tlsmon {

bool RetentionStore::pin(EpochId epoch, const std::string& by, const std::string& note,
                         UtcSeconds at) {
    return guarded(*c_, "pinning an epoch", [&] {
        SQLite::Transaction tx(c_->db, SQLite::TransactionBehavior::IMMEDIATE);
        SQLite::Statement exists(c_->db, "SELECT 1 FROM epochs WHERE id = ?");
        exists.bind(1, epoch);
        if (!exists.executeStep()) throw_storage(*c_, "no epoch " + std::to_string(epoch));
        SQLite::Statement s(
            c_->db,
            "INSERT OR IGNORE INTO epoch_pins (epoch_id, pinned_at, pinned_by, note)"
            " VALUES (?, ?, ?, ?)");
        s.bind(1, epoch);
        s.bind(2, at);
        s.bind(3, by);
        s.bind(4, note);
        const bool pinned = s.exec() == 1;
        if (pinned) {
            write_system_event(*c_, {at, "info", "epoch_pinned",
                                     "epoch " + std::to_string(epoch) + " pinned by " + by +
                                         (note.empty() ? "" : ": " + note) +
                                         "; the retention policy keeps its maps",
                                     epoch});
        }
        tx.commit();
        return pinned;
    });
}

bool RetentionStore::unpin(EpochId epoch, const std::string& by, UtcSeconds at) {
    return guarded(*c_, "unpinning an epoch", [&] {
        SQLite::Transaction tx(c_->db, SQLite::TransactionBehavior::IMMEDIATE);
        SQLite::Statement s(c_->db, "DELETE FROM epoch_pins WHERE epoch_id = ?");
        s.bind(1, epoch);
        const bool unpinned = s.exec() == 1;
        if (unpinned) {
            write_system_event(*c_, {at, "info", "epoch_unpinned",
                                     "epoch " + std::to_string(epoch) + " unpinned by " + by +
                                         "; its maps follow the retention policy again",
                                     epoch});
        }
        tx.commit();
        return unpinned;
    });
}

std::vector<EpochPin> RetentionStore::pins() const {
    return guarded(*c_, "reading pinned epochs", [&] {
        SQLite::Statement s(c_->db,
                            "SELECT p.epoch_id, e.acquired, p.pinned_at, p.pinned_by, p.note,"
                            " EXISTS (SELECT 1 FROM core_point_arrays c WHERE c.epoch_id ="
                            " p.epoch_id) FROM epoch_pins p JOIN epochs e ON e.id = p.epoch_id"
                            " ORDER BY e.acquired, p.epoch_id");
        std::vector<EpochPin> out;
        while (s.executeStep()) {
            out.push_back({s.getColumn(0).getInt64(), s.getColumn(1).getInt64(),
                           s.getColumn(2).getInt64(), s.getColumn(3).getString(),
                           s.getColumn(4).getString(), s.getColumn(5).getInt() != 0});
        }
        return out;
    });
}

bool RetentionStore::has_maps(EpochId epoch) const {
    return guarded(*c_, "reading an epoch's maps", [&] {
        SQLite::Statement s(c_->db, "SELECT 1 FROM core_point_arrays WHERE epoch_id = ? LIMIT 1");
        s.bind(1, epoch);
        return s.executeStep();
    });
}

std::optional<UtcSeconds> RetentionStore::maps_thinned_at(EpochId epoch) const {
    return guarded(*c_, "reading thinned maps", [&]() -> std::optional<UtcSeconds> {
        SQLite::Statement s(c_->db, "SELECT thinned_at FROM thinned_maps WHERE epoch_id = ?");
        s.bind(1, epoch);
        if (!s.executeStep()) return std::nullopt;
        return s.getColumn(0).getInt64();
    });
}

RetentionPlan RetentionStore::plan(const RetentionPolicy& policy) const {
    return guarded(*c_, "planning the retention pass", [&] {
        // One read transaction: the epochs, their protection and the clock agree.
        SQLite::Transaction tx(c_->db, SQLite::TransactionBehavior::DEFERRED);
        const auto newest = c_->db.execAndGet("SELECT max(acquired) FROM epochs");
        if (newest.isNull()) return RetentionPlan{};
        SQLite::Statement s(c_->db,
                            "WITH maps AS (SELECT DISTINCT epoch_id AS id FROM core_point_arrays),"
                            " kept AS (" +
                                protected_epochs(c_->db) +
                                ") SELECT e.id, e.acquired, e.id IN kept FROM maps JOIN epochs e"
                                " ON e.id = maps.id");
        std::vector<MapEpoch> epochs;
        while (s.executeStep()) {
            epochs.push_back({s.getColumn(0).getInt64(), s.getColumn(1).getInt64(),
                              s.getColumn(2).getInt() != 0});
        }
        return plan_retention(std::move(epochs), newest.getInt64(), policy);
    });
}

ThinnedBatch RetentionStore::thin(std::span<const EpochId> epochs, UtcSeconds at) {
    return guarded(*c_, "thinning per-core-point maps", [&] {
        ThinnedBatch done;
        if (epochs.empty()) return done;
        SQLite::Transaction tx(c_->db, SQLite::TransactionBehavior::IMMEDIATE);
        const std::string kept = protected_epochs(c_->db);
        SQLite::Statement bytes(c_->db,
                                "SELECT count(*), coalesce(sum(length(data)), 0) FROM"
                                " core_point_arrays WHERE epoch_id = ? AND epoch_id NOT IN (" +
                                    kept + ")");
        SQLite::Statement remove(c_->db,
                                 "DELETE FROM core_point_arrays WHERE epoch_id = ? AND"
                                 " epoch_id NOT IN (" +
                                     kept + ")");
        SQLite::Statement record(c_->db,
                                 "INSERT OR REPLACE INTO thinned_maps (epoch_id, thinned_at, bytes)"
                                 " VALUES (?, ?, ?)");
        EpochId first = 0, last = 0;
        for (const EpochId id : epochs) {
            bytes.bind(1, id);
            bytes.executeStep();
            const bool any = bytes.getColumn(0).getInt64() > 0;
            const std::int64_t epoch_bytes = bytes.getColumn(1).getInt64();
            bytes.reset();
            if (!any) continue;
            remove.bind(1, id);
            remove.exec();
            remove.reset();
            record.bind(1, id);
            record.bind(2, at);
            record.bind(3, epoch_bytes);
            record.exec();
            record.reset();
            done.bytes += epoch_bytes;
            first = done.epochs++ == 0 ? id : std::min(first, id);  // given newest first
            last = std::max(last, id);
        }
        if (done.epochs > 0) {
            write_system_event(*c_, {at, "info", "retention_thinned",
                                     "per-core-point maps of " + std::to_string(done.epochs) +
                                         " epochs thinned by the retention policy (epochs " +
                                         std::to_string(first) + " to " + std::to_string(last) +
                                         "): " + format_mib(done.bytes) +
                                         " of map data; their zone series are kept",
                                     std::nullopt});
        }
        tx.commit();
        return done;
    });
}

bool RetentionStore::incremental_vacuum() const {
    return guarded(*c_, "reading auto_vacuum",
                   [&] { return c_->db.execAndGet("PRAGMA auto_vacuum").getInt() == 2; });
}

void RetentionStore::enable_incremental_vacuum() {
    guarded(*c_, "converting to incremental vacuum", [&] {
        c_->db.exec("PRAGMA auto_vacuum = INCREMENTAL");
        c_->db.exec("VACUUM");
    });
}

std::int64_t RetentionStore::free_pages() const {
    return guarded(*c_, "reading freelist_count",
                   [&] { return c_->db.execAndGet("PRAGMA freelist_count").getInt64(); });
}

std::int64_t RetentionStore::size_bytes() const {
    return guarded(*c_, "reading page_count", [&] {
        return c_->db.execAndGet("PRAGMA page_count").getInt64() *
               c_->db.execAndGet("PRAGMA page_size").getInt64();
    });
}

std::int64_t RetentionStore::release_free_pages(int pages) {
    return guarded(*c_, "incremental vacuum", [&] {
        const std::int64_t before = c_->db.execAndGet("PRAGMA freelist_count").getInt64();
        // The pragma returns no row; stepping it through to the end runs it whole.
        SQLite::Statement s(c_->db, "PRAGMA incremental_vacuum(" + std::to_string(pages) + ")");
        while (s.executeStep()) {
        }
        return before - c_->db.execAndGet("PRAGMA freelist_count").getInt64();
    });
}

}  // namespace tlsmon
