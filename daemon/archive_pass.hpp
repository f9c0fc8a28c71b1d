#pragma once
// One pass of the archive policy (storage/archive_policy.hpp, docs/retention.md) over the
// scan files in `folder` (paths.archive), one pass at a time (a lock file in the folder):
// first the E57 files a killed pass was writing and the deletions an earlier, interrupted pass
// recorded but did not finish; then the plan's removals in batches of `batch_scans` (one
// transaction and event each, the files deleted after the commit); then the re-encodings,
// one scan at a time (written, verified, recorded, the original deleted). `stop` is asked
// between steps. It logs nothing: the caller reports the result.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "storage/epoch_database.hpp"

namespace tlsmon {

struct ArchivePassResult {
    ArchivePlan plan;
    std::int64_t scans_removed = 0;
    std::int64_t deletions_finished = 0;  // files an interrupted pass had recorded
    std::int64_t scans_reencoded = 0;
    std::int64_t reencoded_bytes_before = 0;
    std::int64_t reencoded_bytes_after = 0;
    std::int64_t bytes_freed = 0;     // on disk: the files deleted minus the E57 files written
    std::vector<std::string> errors;  // files not deleted or not re-encoded, and why
    bool stopped = false;
};

ArchivePassResult run_archive_pass(
    EpochDatabase& db, const ArchivePolicy& policy, const std::filesystem::path& folder,
    const std::function<bool()>& stop = [] { return false; });

}  // namespace tlsmon
