#pragma once
// The notifier's thread in the daemon (docs/notifications.md): routes and delivers
// (daemon/notify/notifier.hpp) every `poll` seconds and at once when woken (an epoch or an
// operator's action committed), through its own connection to the epoch database. Ingest
// never waits for it: a slow or unreachable receiver delays only its own channel.
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <optional>
#include <thread>

#include "daemon/notify/notifier.hpp"

namespace tlsmon {

class NotifyService {
  public:
    // Makes every configured channel (an Error for one that cannot be made, naming it) and
    // starts the thread.
    NotifyService(const NotifyConfig& config, std::filesystem::path database, DashboardSite site,
                  std::chrono::milliseconds poll = std::chrono::seconds(2));
    ~NotifyService();  // finishes the send under way, then joins
    NotifyService(const NotifyService&) = delete;
    NotifyService& operator=(const NotifyService&) = delete;

    void wake();
    void set_disk_free_share(std::optional<double> share);

  private:
    void run();

    Notifier notifier_;
    std::filesystem::path database_;
    std::chrono::milliseconds poll_;
    std::mutex mutex_;
    std::condition_variable cv_;
    bool stop_ = false;
    bool woken_ = false;
    std::optional<std::optional<double>> disk_;  // a new disk share to hand over
    std::thread thread_;
};

}  // namespace tlsmon
