#include "pipeline/system_event_log.hpp"

#include <spdlog/spdlog.h>

namespace tlsmon {

namespace {

void log_at(const std::string& level, const std::string& message) {
    if (level == "error") {
        spdlog::error("{}", message);
    } else if (level == "warning") {
        spdlog::warn("{}", message);
    } else {
        spdlog::info("{}", message);
    }
}

}  // namespace

void SystemEventLog::record(EpochDatabase& db, const std::string& level, const std::string& kind,
                            const std::string& message, std::optional<EpochId> epoch) {
    log_at(level, message);
    if (waiting_.size() >= capacity) waiting_.pop_front();
    waiting_.push_back(SystemEvent{now_utc(), level, kind, message, epoch});
    flush(db);
}

void SystemEventLog::flush(EpochDatabase& db) {
    while (!waiting_.empty()) {
        try {
            db.events().record(waiting_.front());
        } catch (const StorageError& e) {
            spdlog::debug("system event kept for later: {}", e.what());
            write_failed(e);
            return;
        }
        wrote();
        waiting_.pop_front();
    }
}

}  // namespace tlsmon
