#include "daemon/notify/notify_service.hpp"

#include <spdlog/spdlog.h>

namespace tlsmon {

namespace {

std::map<std::string, ChannelSend> make_channels(const NotifyConfig& config,
                                                 const std::string& station) {
    std::map<std::string, ChannelSend> out;
    for (const auto& c : config.channels) {
        try {
            out.emplace(c.name, make_channel(c, station));
        } catch (const std::exception& e) {
            throw Error("notify channel '" + c.name + "': " + e.what());
        }
    }
    return out;
}

}  // namespace

NotifyService::NotifyService(const NotifyConfig& config, std::filesystem::path database,
                             DashboardSite site, std::chrono::milliseconds poll)
    : notifier_(config, site, make_channels(config, site.station)),
      database_(std::move(database)),
      poll_(poll),
      thread_([this] { run(); }) {}

NotifyService::~NotifyService() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
}

void NotifyService::wake() {
    {
        std::lock_guard lock(mutex_);
        woken_ = true;
    }
    cv_.notify_all();
}

void NotifyService::set_disk_free_share(std::optional<double> share) {
    std::lock_guard lock(mutex_);
    disk_ = share;
}

void NotifyService::run() {
    std::optional<EpochDatabase> db;
    std::string last_error;  // logged once until it changes
    for (;;) {
        {
            std::unique_lock lock(mutex_);
            cv_.wait_for(lock, poll_, [this] { return stop_ || woken_; });
            if (stop_) return;
            woken_ = false;
            if (disk_) {
                notifier_.set_disk_free_share(*disk_);
                disk_.reset();
            }
        }
        try {
            if (!db) db.emplace(EpochDatabase::open(database_, EpochDatabase::Mode::read_write));
            notifier_.route(*db, notify_clock(now_utc()));
            notifier_.deliver(*db, now_utc());
            last_error.clear();
        } catch (const std::exception& e) {
            // The database busy, full or gone: the outbox waits; nothing is lost.
            if (e.what() != last_error) spdlog::error("notifications wait: {}", e.what());
            last_error = e.what();
            db.reset();
        }
    }
}

}  // namespace tlsmon
