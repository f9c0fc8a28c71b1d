#include "storage/archive_store.hpp"

#include <algorithm>

#include "storage/connection.hpp"
#include "storage/shared_rows.hpp"
#include "storage/state_epochs.hpp"

namespace fs = std::filesystem;

namespace tlsmon {

namespace {

// The row of a scan the pass kept: its re-encoding (`detail` the new sha256_after) or why
// there was none (`detail` the reason).
void record_kept_scan(SQLite::Database& db, const ArchivedScan& scan, const char* action,
                      UtcSeconds at, std::int64_t bytes_after, const char* detail_column,
                      const std::string& detail) {
    SQLite::Statement record(db, std::string("INSERT INTO archived_scans (epoch_id, action, at,"
                                             " original_path, bytes_before, bytes_after, ") +
                                     detail_column + ") VALUES (?, ?, ?, ?, ?, ?, ?)");
    record.bind(1, scan.id);
    record.bind(2, action);
    record.bind(3, at);
    record.bind(4, scan.path);
    record.bind(5, scan.bytes);
    record.bind(6, bytes_after);
    record.bind(7, detail);
    record.exec();
}

}  // namespace

ArchivePlan ArchiveStore::plan(const fs::path& folder, const ArchivePolicy& policy) const {
    return guarded(*c_, "planning the archive pass", [&] {
        // One read transaction: the scans, their protection and the clock agree.
        SQLite::Transaction tx(c_->db, SQLite::TransactionBehavior::DEFERRED);
        const auto newest = c_->db.execAndGet("SELECT max(acquired) FROM epochs");
        if (newest.isNull()) return ArchivePlan{};
        SQLite::Statement s(
            c_->db, "WITH kept AS (" + protected_epochs(c_->db) + "), named AS (" +
                        epochs_named_by_state(c_->db) +
                        ") SELECT e.id, e.acquired, e.archive_path, e.sha256,"
                        " coalesce(a.bytes_after, e.file_size), e.id IN kept, e.id IN named,"
                        " a.action IS 'not_reencoded'"
                        " FROM epochs e LEFT JOIN archived_scans a ON a.epoch_id = e.id"
                        " WHERE e.archive_path IS NOT NULL AND e.status IN ('done', 'rejected')"
                        " AND a.action IS NOT 'removed'");
        const fs::path archive = folder.lexically_normal();
        std::vector<ArchivedScan> scans;
        while (s.executeStep()) {
            ArchivedScan scan{s.getColumn(0).getInt64(),    s.getColumn(1).getInt64(),
                              s.getColumn(2).getString(),   s.getColumn(3).getString(),
                              s.getColumn(4).getInt64(),    s.getColumn(5).getInt() != 0,
                              s.getColumn(6).getInt() != 0, s.getColumn(7).getInt() != 0};
            // The archive's own files only: a failed epoch's archive_path is in quarantine.
            if (fs::path(scan.path).parent_path().lexically_normal() == archive) {
                scans.push_back(std::move(scan));
            }
        }
        return plan_archive(std::move(scans), newest.getInt64(), policy);
    });
}

std::vector<ArchivedScan> ArchiveStore::record_removed(std::span<const ArchivedScan> scans,
                                                       UtcSeconds at) {
    return guarded(*c_, "recording removed scans", [&] {
        std::vector<ArchivedScan> done;
        if (scans.empty()) return done;
        SQLite::Transaction tx(c_->db, SQLite::TransactionBehavior::IMMEDIATE);
        SQLite::Statement kept(c_->db, "SELECT ? IN (" + protected_epochs(c_->db) + ")");
        SQLite::Statement record(
            c_->db,
            "INSERT OR REPLACE INTO archived_scans (epoch_id, action, at, original_path,"
            " bytes_before, bytes_after, sha256_after) VALUES (?, 'removed', ?, ?, ?, 0, NULL)");
        std::int64_t bytes = 0;
        for (const auto& scan : scans) {
            kept.bind(1, scan.id);
            kept.executeStep();
            const bool is_protected = kept.getColumn(0).getInt() != 0;
            kept.reset();
            if (is_protected) continue;
            record.bind(1, scan.id);
            record.bind(2, at);
            record.bind(3, scan.path);
            record.bind(4, scan.bytes);
            record.exec();
            record.reset();
            bytes += scan.bytes;
            done.push_back(scan);
        }
        if (!done.empty()) {
            write_system_event(
                *c_, {at, "info", "archive_thinned",
                      "scans of " + std::to_string(done.size()) +
                          " epochs removed from the archive by the archive policy (epochs " +
                          std::to_string(std::min(done.front().id, done.back().id)) + " to " +
                          std::to_string(std::max(done.front().id, done.back().id)) +
                          "): " + format_mib(bytes) + " freed; their results are kept",
                      std::nullopt});
        }
        tx.commit();
        return done;
    });
}

void ArchiveStore::record_reencoded(const ArchivedScan& scan, const fs::path& written,
                                    std::int64_t bytes_after, const std::string& sha256_after,
                                    UtcSeconds at) {
    guarded(*c_, "recording a re-encoded scan", [&] {
        SQLite::Transaction tx(c_->db, SQLite::TransactionBehavior::IMMEDIATE);
        record_kept_scan(c_->db, scan, "reencoded", at, bytes_after, "sha256_after", sha256_after);
        SQLite::Statement move(c_->db, "UPDATE epochs SET archive_path = ? WHERE id = ?");
        move.bind(1, written.string());
        move.bind(2, scan.id);
        move.exec();
        tx.commit();
    });
}

void ArchiveStore::record_not_reencoded(const ArchivedScan& scan, const std::string& reason,
                                        UtcSeconds at) {
    guarded(*c_, "recording a scan not re-encoded", [&] {
        SQLite::Transaction tx(c_->db, SQLite::TransactionBehavior::IMMEDIATE);
        record_kept_scan(c_->db, scan, "not_reencoded", at, scan.bytes, "reason", reason);
        write_system_event(*c_, {at, "warning", "archive_not_reencoded",
                                 "the scan of epoch " + std::to_string(scan.id) +
                                     " is kept as it was ingested: " + reason,
                                 scan.id});
        tx.commit();
    });
}

std::vector<std::string> ArchiveStore::files_to_delete() const {
    return guarded(*c_, "reading the archive's deletions", [&] {
        SQLite::Statement s(
            c_->db,
            "SELECT a.original_path FROM archived_scans a JOIN epochs e ON e.id ="
            " a.epoch_id WHERE (a.action = 'removed' OR (a.action = 'reencoded' AND"
            " a.original_path <> e.archive_path)) AND NOT EXISTS (SELECT 1 FROM epochs o WHERE"
            " o.archive_path = a.original_path AND o.id <> a.epoch_id)"
            " ORDER BY a.epoch_id");
        std::vector<std::string> out;
        while (s.executeStep()) out.push_back(s.getColumn(0).getString());
        return out;
    });
}

std::optional<ArchivedScanRecord> ArchiveStore::record(EpochId epoch) const {
    return guarded(*c_, "reading an archived scan", [&]() -> std::optional<ArchivedScanRecord> {
        SQLite::Statement s(
            c_->db,
            "SELECT action, at, original_path, bytes_before, bytes_after,"
            " coalesce(sha256_after, ''), reason FROM archived_scans WHERE epoch_id = ?");
        s.bind(1, epoch);
        if (!s.executeStep()) return std::nullopt;
        return ArchivedScanRecord{s.getColumn(0).getString(), s.getColumn(1).getInt64(),
                                  s.getColumn(2).getString(), s.getColumn(3).getInt64(),
                                  s.getColumn(4).getInt64(),  s.getColumn(5).getString(),
                                  s.getColumn(6).getString()};
    });
}

bool ArchiveStore::file_in_use(const fs::path& path) const {
    return guarded(*c_, "reading the archive's files", [&] {
        SQLite::Statement s(c_->db,
                            "SELECT EXISTS (SELECT 1 FROM epochs WHERE archive_path = ?1 OR"
                            " file_path = ?1) OR EXISTS (SELECT 1 FROM campaigns WHERE file_path"
                            " = ?1)");
        s.bind(1, path.string());
        s.executeStep();
        return s.getColumn(0).getInt() != 0;
    });
}

}  // namespace tlsmon
