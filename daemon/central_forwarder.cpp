#include "daemon/central_forwarder.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <optional>

#include "central/central_forward.hpp"
#include "core/redacted_url.hpp"
#include "daemon/system_alarm_watch.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

namespace {

CentralTarget target_of(const CentralConfig& c, const std::string& station) {
    CentralTarget t;
    t.url = c.url;
    t.password_file = c.password_file;
    t.sslmode = c.sslmode;
    t.sslrootcert = c.sslrootcert;
    t.application_name = "tlsmon " + station;
    return t;
}

}  // namespace

CentralForwarder::CentralForwarder(CentralConfig config, std::filesystem::path database,
                                   std::string station)
    : config_(std::move(config)),
      database_(std::move(database)),
      station_(std::move(station)),
      thread_([this] { run(); }) {}

CentralForwarder::~CentralForwarder() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    cv_.notify_all();
    thread_.join();
}

void CentralForwarder::wake() {
    {
        std::lock_guard lock(mutex_);
        woken_ = true;
    }
    cv_.notify_all();
}

bool CentralForwarder::wait(std::chrono::duration<double> d, bool wakeable) {
    std::unique_lock lock(mutex_);
    cv_.wait_for(lock, d, [&] { return stop_ || (wakeable && woken_); });
    woken_ = false;
    return !stop_;
}

void CentralForwarder::run() {
    spdlog::info("central forwarding to {}", redacted_url(config_.url));
    std::optional<EpochDatabase> db;
    std::optional<PgConnection> central;
    std::string last_error;  // logged once until it changes
    double backoff = 0;      // seconds; 0 while calls succeed
    // system.central_forward as this thread last set it; unknown at start, when a previous
    // run may have left it raised.
    std::optional<bool> alarmed;
    auto observe = [&](bool failing) {
        SystemObservation seen;
        seen.now = now_utc();
        seen.central_forward_failing = failing;
        observe_system_alarms(*db, SystemAlarmConfig{}, seen);
        alarmed = failing;
    };
    for (bool first = true;; first = false) {
        if (!first && !wait(std::chrono::duration<double>(backoff > 0 ? backoff : config_.poll),
                            backoff == 0))
            return;
        try {
            if (!db) db.emplace(EpochDatabase::open(database_, EpochDatabase::Mode::read_write));
            const std::string source = db->central_outbox().state().database_id;
            for (;;) {
                const auto batch = db->central_outbox().pending(config_.batch_size);
                if (batch.empty()) break;
                if (!central || !central->ok())
                    central.emplace(PgConnection::open(target_of(config_, station_)));
                forward_batch(*central, source, batch);
                db->central_outbox().mark_sent(batch.back().seq, now_utc());
                if (backoff > 0) {
                    spdlog::info("central forwarding works again");
                    db->events().record({now_utc(),
                                         "info",
                                         "central_forward",
                                         "forwarding to the central database works again",
                                         {}});
                    backoff = 0;
                    last_error.clear();
                }
                if (alarmed != false) observe(false);
                std::lock_guard lock(mutex_);
                if (stop_) return;
            }
        } catch (const std::exception& e) {
            // The central database down, full, read-only, or refusing this site; or the site
            // database busy. The outbox keeps every entry; the next call sends them again.
            central.reset();
            const std::string error = e.what();
            const bool new_error = error != last_error;
            if (new_error) spdlog::error("central forwarding waits: {}", error);
            last_error = error;
            backoff =
                backoff == 0 ? config_.retry_initial : std::min(config_.retry_max, 2 * backoff);
            try {
                if (!db) continue;
                const UtcSeconds now = now_utc();
                db->central_outbox().record_failure(error, now);
                if (new_error)
                    db->events().record({now,
                                         "warning",
                                         "central_forward",
                                         "forwarding to the central database fails: " + error +
                                             "; the outbox keeps every entry",
                                         {}});
                const auto since = db->central_outbox().state().failing_since;
                if (alarmed != true && since && now - *since >= config_.alarm_after) observe(true);
            } catch (const std::exception& inner) {
                spdlog::error("central forwarding: cannot record the failure: {}", inner.what());
                db.reset();
            }
        }
    }
}

}  // namespace tlsmon
