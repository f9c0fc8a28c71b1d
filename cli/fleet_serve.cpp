// `tlsmon fleet serve --central URL`: the fleet's page (docs/central.md, "The fleet"): every
// site, every zone quantity's newest value and one zone's series drawn, read from the central
// database with the queries of `tlsmon fleet` and answered as JSON in the rows its
// `--format json` prints. It only reads: connect it with an analyst's (tlsmon_reader) role.
// Until SIGINT or SIGTERM.
#include <httplib.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <functional>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "central/fleet_queries.hpp"
#include "cli/commands.hpp"
#include "cli/fleet_table.hpp"
#include "core/redacted_url.hpp"
#include "daemon/http/web_files.hpp"
#include "daemon/shutdown.hpp"

namespace tlsmon {

namespace {

// A request's parameter that the page must name (a 400 otherwise).
struct BadRequest : std::runtime_error {
    using std::runtime_error::runtime_error;
};

std::string required(const httplib::Request& req, const char* name) {
    const std::string v = req.get_param_value(name);
    if (v.empty()) throw BadRequest(std::string("missing parameter '") + name + "'");
    return v;
}

std::optional<std::int64_t> time_of(const httplib::Request& req, const char* name) {
    const std::string v = req.get_param_value(name);
    if (v.empty()) return std::nullopt;
    try {
        return time_bound(v, now_utc());
    } catch (const std::exception& e) {
        throw BadRequest(std::string("parameter '") + name + "': " + e.what());
    }
}

std::optional<double> number_of(const httplib::Request& req, const char* name) {
    const std::string v = req.get_param_value(name);
    if (v.empty()) return std::nullopt;
    std::size_t used = 0;
    double x = 0;
    try {
        x = std::stod(v, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != v.size() || !std::isfinite(x))
        throw BadRequest(std::string("parameter '") + name + "': not a number: " + v);
    return x;
}

void send_error(httplib::Response& res, int status, const std::string& message) {
    res.status = status;
    res.set_content(nlohmann::json{{"error", message}}.dump(), "application/json");
}

}  // namespace

int serve_fleet(const FleetOptions& o) {
    return run_reporting_errors("fleet serve", [&] {
        const CentralTarget target =
            command_target(o.central, o.password_file, "tlsmon fleet serve");
        const WebFiles web = WebFiles::load(find_web_root(o.web_root));
        SignalThread::block_signals();
        Shutdown shutdown;
        SignalThread signals(shutdown);

        // One connection, one query at a time; opened again after a failure.
        std::mutex mutex;
        std::optional<PgConnection> central;
        const auto rows = [&](const std::function<PgResult(PgConnection&)>& query) {
            std::lock_guard lock(mutex);
            try {
                if (!central || !central->ok()) central.emplace(PgConnection::open(target));
                return query(*central);
            } catch (...) {
                central.reset();
                throw;
            }
        };
        httplib::Server server;
        const auto api = [&](const std::string& path,
                             std::function<PgResult(const httplib::Request&, std::string&)> f) {
            server.Get(path, [&, f](const httplib::Request& req, httplib::Response& res) {
                try {
                    std::string quantity;
                    const PgResult r = f(req, quantity);
                    std::ostringstream out;
                    print(out, fleet_table(r, quantity), OutputFormat::json);
                    res.set_content(out.str(), "application/json");
                } catch (const BadRequest& e) {
                    send_error(res, 400, e.what());
                } catch (const std::exception& e) {
                    spdlog::error("fleet serve {}: {}", req.path, e.what());
                    send_error(res, 503, std::string("the central database: ") + e.what());
                }
            });
        };
        api("/api/v1/fleet/sites", [&](const httplib::Request&, std::string&) {
            return rows([](PgConnection& c) { return fleet_sites(c); });
        });
        api("/api/v1/fleet/status", [&](const httplib::Request& req, std::string&) {
            const LatestFilter filter{number_of(req, "min_abs"), req.get_param_value("site"),
                                      req.get_param_value("quantity")};
            return rows([&](PgConnection& c) { return fleet_latest(c, filter); });
        });
        api("/api/v1/fleet/series", [&](const httplib::Request& req, std::string& quantity) {
            const std::string site = required(req, "site"), zone = required(req, "zone");
            quantity = required(req, "quantity");
            const auto from = time_of(req, "from"), to = time_of(req, "to");
            return rows([&](PgConnection& c) {
                return fleet_series(c, site, zone, quantity, from, to ? *to + 1 : to);
            });
        });
        const auto file = [&](const std::string& name, httplib::Response& res) {
            const WebFile* f = web.find(name);
            if (!f) return send_error(res, 404, "no such file");
            res.set_content(f->body, f->content_type);
        };
        server.Get(
            "/", [&](const httplib::Request&, httplib::Response& res) { file("fleet.html", res); });
        server.Get(R"(/static/(.+))", [&](const httplib::Request& req, httplib::Response& res) {
            file(req.matches[1], res);
        });
        if (!server.bind_to_port(o.address, o.port))
            throw Error("fleet serve: cannot listen on " + o.address + ":" +
                        std::to_string(o.port));
        std::thread stopper([&] {
            while (!shutdown.wait_for(std::chrono::hours(1))) {
            }
            server.stop();
        });
        std::cout << "fleet dashboard on http://" << o.address << ":" << o.port << "/ ("
                  << redacted_url(o.central) << ")" << std::endl;
        server.listen_after_bind();
        shutdown.request_stop();
        stopper.join();
    });
}

}  // namespace tlsmon
