#pragma once
// The daemon's main loop (`tlsmon run`): watch the ingest folder, turn complete files into
// epochs, process pending epochs in acquisition-time order, keep systemd informed, reload
// on SIGHUP and stop on SIGTERM/SIGINT. Every wait is a poll() on the watcher's inotify fd
// and the Shutdown eventfd, so a stop request is seen at once between epochs.
#include <filesystem>

namespace tlsmon {

struct RunOptions {
    std::filesystem::path config_file;
    // Process what is there (waiting until files are complete, at most max_growing for a
    // file that keeps growing), then exit.
    bool once = false;
};

// Returns the process exit code: 0 after a clean stop, 1 when it cannot start.
int run_daemon(const RunOptions& options);

}  // namespace tlsmon
