#pragma once
// The central forwarder's thread in the daemon (docs/central.md): sends the outbox to the
// central PostgreSQL in order, in batches, through its own connections to both databases;
// an entry is marked sent only after the central commit. Ingest never waits for it: a slow,
// full or unreachable central database delays only the forward, which retries with a
// doubling back-off and raises system.central_forward when failing for [central]
// alarm_after.
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <thread>

#include "config/central_config.hpp"

namespace tlsmon {

class CentralForwarder {
  public:
    // Starts the thread; the outbox's triggers must be on (CentralOutbox::set_enabled).
    CentralForwarder(CentralConfig config, std::filesystem::path database, std::string station);
    ~CentralForwarder();  // finishes the call under way (bounded by libpq's timeouts), joins
    CentralForwarder(const CentralForwarder&) = delete;
    CentralForwarder& operator=(const CentralForwarder&) = delete;

    void wake();  // an epoch or an operator's action committed

  private:
    void run();
    // Waits `d` or until woken or stopped; false when stopping.
    bool wait(std::chrono::duration<double> d, bool wakeable);

    CentralConfig config_;
    std::filesystem::path database_;
    std::string station_;
    std::mutex mutex_;
    std::condition_variable cv_;
    bool stop_ = false;
    bool woken_ = false;
    std::thread thread_;
};

}  // namespace tlsmon
