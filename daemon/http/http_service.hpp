#pragma once
// The daemon's HTTP side (docs/http.md): the dashboard's pages and the JSON API under
// /api/v1/, served by cpp-httplib on its own threads, each request reading the epoch
// database through a read-only connection of its own (WAL: readers never block the
// ingest). Nothing here writes. Live updates: /api/v1/stream, server-sent events, one
// `epoch` event per committed epoch.
#include <filesystem>
#include <memory>
#include <optional>

#include "config/http_config.hpp"
#include "core/utc_time.hpp"
#include "daemon/http/dashboard_api.hpp"

namespace tlsmon {

class HttpService {
  public:
    // Starts listening at once (Error when it cannot: address taken, web root missing).
    HttpService(const HttpConfig& config, const std::filesystem::path& database,
                DashboardSite site);
    ~HttpService();  // stops the server, ends the event streams, joins the threads
    HttpService(const HttpService&) = delete;
    HttpService& operator=(const HttpService&) = delete;

    // An epoch was committed: every open event stream is told.
    void epoch_committed(EpochId epoch);
    // The daemon's main loop is alive (shown as its heartbeat), with the disk's free share.
    void heartbeat(UtcSeconds now, std::optional<double> disk_free_share);

    int port() const;  // the port bound

  private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace tlsmon
