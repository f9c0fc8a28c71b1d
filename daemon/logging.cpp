#include "daemon/logging.hpp"

#include <spdlog/sinks/rotating_file_sink.h>
#include <spdlog/sinks/sink.h>
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/sinks/systemd_sink.h>
#include <spdlog/spdlog.h>

#include <cstdlib>
#include <memory>
#include <vector>

#include "core/text_escape.hpp"

namespace tlsmon {

namespace {

// Every sink gets the message with its control characters escaped (core/text_escape.hpp):
// a file name with a newline cannot forge a log record, nor an ESC sequence reach a
// terminal, whichever call site logged it.
class EscapingSink final : public spdlog::sinks::sink {
  public:
    explicit EscapingSink(spdlog::sink_ptr inner) : inner_(std::move(inner)) {}

    void log(const spdlog::details::log_msg& msg) override {
        const std::string_view payload(msg.payload.data(), msg.payload.size());
        const std::string escaped = escape_control_characters(payload);
        if (escaped.size() == payload.size()) {  // nothing escaped
            inner_->log(msg);
            return;
        }
        spdlog::details::log_msg copy = msg;
        copy.payload = spdlog::string_view_t(escaped.data(), escaped.size());
        inner_->log(copy);
    }
    void flush() override { inner_->flush(); }
    void set_pattern(const std::string& pattern) override { inner_->set_pattern(pattern); }
    void set_formatter(std::unique_ptr<spdlog::formatter> formatter) override {
        inner_->set_formatter(std::move(formatter));
    }

  private:
    spdlog::sink_ptr inner_;
};

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
    for (auto& sink : sinks) sink = std::make_shared<EscapingSink>(std::move(sink));
    auto logger = std::make_shared<spdlog::logger>("tlsmon", sinks.begin(), sinks.end());
    logger->set_level(spdlog_level(config.level));
    logger->flush_on(spdlog::level::info);
    spdlog::set_default_logger(logger);
}

}  // namespace tlsmon
