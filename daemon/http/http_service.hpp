#pragma once
// The daemon's HTTP side (docs/http.md): the dashboard's pages and the JSON API under
// /api/v1/, served by cpp-httplib on its own threads, each request reading the epoch
// database through a read-only connection of its own (WAL: readers never block the
// ingest). Live updates: /api/v1/stream, server-sent events, one `epoch` event per
// committed epoch. Writes only the operators' actions on alarms (through
// the daemon's alarm code, the same path as `tlsmon alarms` and the Modbus coils) and their
// logins, each as an event naming the user.
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "config/http_config.hpp"
#include "core/utc_time.hpp"
#include "daemon/http/dashboard_api.hpp"

namespace tlsmon {

// An operator's action on an alarm rule, as the dashboard asks for it.
struct OperatorAction {
    std::string action;  // "ack", "shelve", "unshelve", "out-of-service", "in-service"
    std::string rule;
    std::optional<UtcSeconds> until;  // shelve
    std::string who;                  // "user alice"
    std::string comment;
};
// Carries it out on a read-write connection; returns the rules changed; Error for an
// unknown rule or an impossible request (the message is shown to the operator).
using AlarmActionHandler =
    std::function<int(EpochDatabase&, const OperatorAction&, UtcSeconds now)>;

class HttpService {
  public:
    // Starts listening at once (Error when it cannot: address taken, web root missing, a
    // malformed users file).
    HttpService(const HttpConfig& config, const std::filesystem::path& database, DashboardSite site,
                AlarmActionHandler actions);
    ~HttpService();  // stops the server, ends the event streams, joins the threads
    HttpService(const HttpService&) = delete;
    HttpService& operator=(const HttpService&) = delete;

    // An epoch was committed: every open event stream is told.
    void epoch_committed(EpochId epoch);
    // The daemon's main loop is alive (shown as its heartbeat), with the disk's free share.
    void heartbeat(UtcSeconds now, std::optional<double> disk_free_share);

  private:
    struct State;
    std::unique_ptr<State> state_;
};

}  // namespace tlsmon
