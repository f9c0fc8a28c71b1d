#pragma once
// The archive of raw scans in the epoch database (storage/archive_policy.hpp,
// docs/retention.md): which epochs' scan files lie in the archive folder, and what the
// archive policy did to each (table archived_scans). A file is deleted only after the row
// that says so is committed, so a pass killed between the two leaves a row whose file is
// still there; the next pass deletes it (files_to_delete).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/utc_time.hpp"
#include "storage/archive_policy.hpp"
#include "storage/ids.hpp"

namespace tlsmon {

struct Connection;

struct ArchivedScanRecord {
    std::string action;  // "reencoded", "removed" or "not_reencoded"
    UtcSeconds at = 0;
    std::string original_path;
    std::int64_t bytes_before = 0;
    std::int64_t bytes_after = 0;
    std::string sha256_after;  // the re-encoded file's ("" otherwise)
    std::string reason;        // why it was not re-encoded
};

class ArchiveStore {
  public:
    explicit ArchiveStore(Connection& connection) : c_(&connection) {}

    // The plan for the scans of the processed epochs (done or rejected) whose archive_path
    // lies in `folder` and that the policy has not removed, at the newest acquisition time.
    ArchivePlan plan(const std::filesystem::path& folder, const ArchivePolicy& policy) const;

    // Records the removal of `scans` except those protected by now (an operator may have
    // pinned one since the plan), in one immediate transaction with a system event. Returns
    // the scans recorded: the caller deletes their files.
    std::vector<ArchivedScan> record_removed(std::span<const ArchivedScan> scans, UtcSeconds at);

    // Records that `scan`'s file was re-encoded as `written` (its archive_path from now on),
    // in one transaction. The caller deletes the file it replaced.
    void record_reencoded(const ArchivedScan& scan, const std::filesystem::path& written,
                          std::int64_t bytes_after, const std::string& sha256_after, UtcSeconds at);

    // Records that re-encoding `scan` failed (`reason`): its file stays as it was ingested
    // and is not tried again. With a warning event, in one transaction.
    void record_not_reencoded(const ArchivedScan& scan, const std::string& reason, UtcSeconds at);

    // Files a committed row gave up and no epoch holds (a path may be taken again by a later
    // epoch's scan of the same name): those still there are to be deleted.
    std::vector<std::string> files_to_delete() const;

    std::optional<ArchivedScanRecord> record(EpochId epoch) const;

    // Whether an epoch or a campaign holds `path` as its file.
    bool file_in_use(const std::filesystem::path& path) const;

  private:
    Connection* c_;
};

}  // namespace tlsmon
