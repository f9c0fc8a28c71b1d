#pragma once
// The retention thread of the daemon (docs/retention.md): a pass of the retention policy
// (daemon/retention_pass.hpp) at start and every `interval`, through its own connection to
// the epoch database. Each of its transactions is short, so the ingest waits for at most one
// batch; a shutdown is honoured between transactions.
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <thread>

#include "storage/retention_policy.hpp"

namespace tlsmon {

class RetentionService {
  public:
    RetentionService(const RetentionPolicy& policy, std::filesystem::path database);
    ~RetentionService();  // ends the transaction under way, then joins
    RetentionService(const RetentionService&) = delete;
    RetentionService& operator=(const RetentionService&) = delete;

  private:
    void run();
    bool stopping();

    RetentionPolicy policy_;
    std::filesystem::path database_;
    std::mutex mutex_;
    std::condition_variable cv_;
    bool stop_ = false;
    std::thread thread_;
};

}  // namespace tlsmon
