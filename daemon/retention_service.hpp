#pragma once
// The retention thread of the daemon (docs/retention.md): a pass of the retention policy of
// the maps (daemon/retention_pass.hpp) and one of the archive policy of the scans
// (daemon/archive_pass.hpp), each when enabled, at start and every `retention.interval`,
// through its own connection to the epoch database. Each of its transactions is short, so the
// ingest waits for at most one batch; a shutdown is honoured between transactions.
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <thread>

#include "storage/archive_policy.hpp"
#include "storage/epoch_database.hpp"
#include "storage/retention_policy.hpp"

namespace tlsmon {

class RetentionService {
  public:
    RetentionService(const RetentionPolicy& maps, const ArchivePolicy& archive,
                     std::filesystem::path archive_folder, std::filesystem::path database);
    ~RetentionService();  // ends the transaction under way, then joins
    RetentionService(const RetentionService&) = delete;
    RetentionService& operator=(const RetentionService&) = delete;

  private:
    void run();
    bool stopping();
    void thin_maps(EpochDatabase& db);
    void thin_archive(EpochDatabase& db);

    RetentionPolicy policy_;
    ArchivePolicy archive_;
    std::filesystem::path archive_folder_;
    std::filesystem::path database_;
    std::mutex mutex_;
    std::condition_variable cv_;
    bool stop_ = false;
    std::thread thread_;
};

}  // namespace tlsmon
