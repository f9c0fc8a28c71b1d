#include "daemon/logging.hpp"

#include <spdlog/sinks/rotating_file_sink.h>
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/sinks/systemd_sink.h>
#include <spdlog/spdlog.h>

#include <cstdlib>
#include <memory>
#include <vector>

namespace tlsmon {

namespace {

spdlog::level::level_enum spdlog_level(LogLevel level) {
    switch (level) {
        case LogLevel::trace:
            return spdlog::level::trace;
        case LogLevel::debug:
            return spdlog::level::debug;
        case LogLevel::info:
            return spdlog::level::info;
        case LogLevel::warn:
            return spdlog::level::warn;
        case LogLevel::error:
            return spdlog::level::err;
        case LogLevel::critical:
            return spdlog::level::critical;
        case LogLevel::off:
            return spdlog::level::off;
    }
    return spdlog::level::info;
}

}  // namespace

bool running_under_systemd() {
    const char* stream = std::getenv("JOURNAL_STREAM");
    const char* invocation = std::getenv("INVOCATION_ID");
    return (stream && *stream) || (invocation && *invocation);
}

void setup_logging(const LoggingConfig& config) {
    std::vector<spdlog::sink_ptr> sinks;
    const bool journal = config.journald == JournaldMode::on ||
                         (config.journald == JournaldMode::automatic && running_under_systemd());
    if (journal) {
        // The journal stamps time and priority itself; the message stays plain.
        sinks.push_back(std::make_shared<spdlog::sinks::systemd_sink_mt>("tlsmon"));
    } else {
        auto err = std::make_shared<spdlog::sinks::stderr_sink_mt>();
        err->set_pattern("%Y-%m-%dT%H:%M:%S.%e%z %^%l%$ %v");
        sinks.push_back(err);
    }
    if (!config.file.empty()) {
        try {
            auto file = std::make_shared<spdlog::sinks::rotating_file_sink_mt>(
                config.file.string(), static_cast<std::size_t>(config.max_size),
                static_cast<std::size_t>(config.max_files));
            file->set_pattern("%Y-%m-%dT%H:%M:%S.%e%z %l %v");
            sinks.push_back(file);
        } catch (const spdlog::spdlog_ex& e) {
            throw ConfigError("logging.file '" + config.file.string() +
                              "' cannot be opened: " + e.what());
        }
    }
    auto logger = std::make_shared<spdlog::logger>("tlsmon", sinks.begin(), sinks.end());
    logger->set_level(spdlog_level(config.level));
    logger->flush_on(spdlog::level::info);
    spdlog::set_default_logger(logger);
}

}  // namespace tlsmon
