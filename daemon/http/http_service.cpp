// The only file that includes cpp-httplib (its header costs seconds per file).
#include "daemon/http/http_service.hpp"

#include <httplib.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "daemon/http/calibration_api.hpp"
#include "daemon/http/campaign_api.hpp"
#include "daemon/http/connection_queue.hpp"
#include "daemon/http/sessions.hpp"
#include "daemon/http/users.hpp"
#include "daemon/http/web_files.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

namespace {

constexpr std::size_t kMaxBody = 64 * 1024;  // a login or an alarm action is a few hundred bytes
// A comment line this often: the write after a page was closed fails, so its thread is
// freed within two of these (a closed peer is not seen otherwise until a write).
constexpr int kStreamKeepAliveSeconds = 1;

// A request's parameter that is not what it must be: answered 400 with this text.
struct BadRequest : Error {
    using Error::Error;
};

void send_json(httplib::Response& res, const Json& body, int status = 200) {
    res.status = status;
    res.set_content(body.dump(-1, ' ', false, Json::error_handler_t::replace), "application/json");
}

void send_error(httplib::Response& res, int status, const std::string& message) {
    send_json(res, Json{{"error", message}, {"status", status}}, status);
}

std::optional<UtcSeconds> time_parameter(const httplib::Request& req, const char* name) {
    if (!req.has_param(name)) return std::nullopt;
    const std::string text = req.get_param_value(name);
    if (text.empty()) return std::nullopt;
    // Unix seconds are digits with at most a leading minus; anything else is a date or time
    // ("2026-11-29" is a date, not the number 2026).
    const bool seconds =
        text.find_first_not_of("0123456789", text[0] == '-' ? 1 : 0) == std::string::npos;
    if (seconds && text != "-") {
        try {
            return std::stoll(text);  // Unix seconds
        } catch (const std::exception&) {
        }
    } else {
        try {
            return parse_utc(text);
        } catch (const std::exception&) {
        }
    }
    throw BadRequest(std::string("parameter '") + name + "': expected an ISO 8601 UTC time " +
                     "(2026-11-29T06:00:00Z) or Unix seconds, not '" + text + "'");
}

TimeRange range_parameters(const httplib::Request& req) {
    TimeRange r{time_parameter(req, "from"), time_parameter(req, "to")};
    if (r.from && r.to && *r.from > *r.to) throw BadRequest("'from' is after 'to'");
    return r;
}

std::string required_parameter(const httplib::Request& req, const char* name) {
    const std::string v = req.has_param(name) ? req.get_param_value(name) : "";
    if (v.empty()) throw BadRequest(std::string("parameter '") + name + "' is required");
    return v;
}

std::size_t width_parameter(const httplib::Request& req) {
    if (!req.has_param("width")) return 0;
    const std::string text = req.get_param_value("width");
    if (text.empty() || text.size() > 6 ||
        text.find_first_not_of("0123456789") != std::string::npos)
        throw BadRequest("parameter 'width': expected pixels, 0 to 100000, not '" + text + "'");
    const auto w = std::stoul(text);
    if (w > 100000) throw BadRequest("parameter 'width': at most 100000");
    return w;
}

// `max`: the most points of a campaign drawn, 1 to 1 000 000 (default 100 000).
std::size_t max_points_parameter(const httplib::Request& req) {
    if (!req.has_param("max")) return 100000;
    const std::string text = req.get_param_value("max");
    if (text.empty() || text.size() > 7 ||
        text.find_first_not_of("0123456789") != std::string::npos || std::stoul(text) < 1 ||
        std::stoul(text) > 1000000)
        throw BadRequest("parameter 'max': expected points, 1 to 1000000, not '" + text + "'");
    return std::stoul(text);
}

constexpr const char* kSessionCookie = "tlsmon_session";
constexpr std::size_t kMaxComment = 500;

// The value of cookie `name` in the request's Cookie header ("" when absent).
std::string cookie(const httplib::Request& req, const std::string& name) {
    const std::string header = req.get_header_value("Cookie");
    std::size_t at = 0;
    while (at < header.size()) {
        const auto end = std::min(header.find(';', at), header.size());
        std::string pair = header.substr(at, end - at);
        pair.erase(0, pair.find_first_not_of(' '));
        if (pair.rfind(name + "=", 0) == 0) return pair.substr(name.size() + 1);
        at = end + 1;
    }
    return "";
}

// The JSON object of a POST's body; 400 for anything else.
Json json_body(const httplib::Request& req) {
    Json body = Json::parse(req.body, nullptr, false);
    if (body.is_discarded() || !body.is_object())
        throw BadRequest("the request body is not a JSON object");
    return body;
}

std::string string_field(const Json& body, const char* name, std::size_t max_length) {
    const auto it = body.find(name);
    if (it == body.end() || it->is_null()) return "";
    if (!it->is_string()) throw BadRequest(std::string("'") + name + "' must be a string");
    const std::string v = it->get<std::string>();
    if (v.size() > max_length)
        throw BadRequest(std::string("'") + name + "' is longer than " +
                         std::to_string(max_length) + " characters");
    return v;
}

bool may_act_on_alarms(UserRole role) {
    return role == UserRole::operator_ || role == UserRole::admin;
}

// The paths that take a POST: the login and the operators' actions.
bool takes_post(const std::string& path) {
    return path == "/api/v1/login" || path == "/api/v1/logout" ||
           path.rfind("/api/v1/alarms/", 0) == 0;
}

}  // namespace

struct HttpService::State {
    HttpConfig config;
    std::filesystem::path database;
    DashboardSite site;
    AlarmActionHandler actions;
    Sessions sessions;
    LoginThrottle throttle;
    WebFiles files;
    std::unique_ptr<httplib::Server> server;  // an SSLServer with http.certificate
    std::thread thread;

    std::mutex mutex;  // guards what follows
    std::vector<std::unique_ptr<EpochDatabase>> idle_connections;
    std::condition_variable committed;
    std::uint64_t commits = 0;
    EpochId last_epoch = 0;
    std::string last_change = "epoch";  // what the last of `commits` was: "epoch" or "alarm"
    // The overview's zones as they were after commit number `zones_cached_at`.
    Json zones_cache;
    std::optional<std::uint64_t> zones_cached_at;
    bool stopping = false;
    int streams = 0;
    UtcSeconds heartbeat = 0;

    // The session cookie's attributes: never sent in clear once the server speaks HTTPS.
    std::string cookie_attributes() const {
        return std::string("Path=/; HttpOnly; SameSite=Strict") +
               (config.certificate.empty() ? "" : "; Secure");
    }

    // `read` on a read-only connection of the pool (opened when none is idle); a connection
    // whose read failed is dropped, not reused.
    template <class F>
    auto with_database(F read) {
        std::unique_ptr<EpochDatabase> db;
        {
            std::lock_guard lock(mutex);
            if (!idle_connections.empty()) {
                db = std::move(idle_connections.back());
                idle_connections.pop_back();
            }
        }
        if (!db) {
            db = std::make_unique<EpochDatabase>(
                EpochDatabase::open(database, EpochDatabase::Mode::read_only));
        }
        auto result = read(static_cast<const EpochDatabase&>(*db));
        std::lock_guard lock(mutex);
        idle_connections.push_back(std::move(db));
        return result;
    }

    // `write` on the one read-write connection (opened at the first write, dropped after a
    // storage error); writes are few: logins and the operators' actions.
    std::mutex write_mutex;
    std::unique_ptr<EpochDatabase> writer;
    template <class F>
    auto with_writer(F write) {
        std::lock_guard lock(write_mutex);
        if (!writer) {
            writer = std::make_unique<EpochDatabase>(
                EpochDatabase::open(database, EpochDatabase::Mode::read_write));
        }
        try {
            return write(*writer);
        } catch (const StorageError&) {
            writer.reset();
            throw;
        }
    }
    // An event naming who did what; a failure to store it is logged, not fatal to the answer.
    void audit(const std::string& level, const std::string& kind, const std::string& message) {
        spdlog::info("http {}: {}", kind, message);
        try {
            with_writer([&](EpochDatabase& db) {
                db.events().record({now_utc(), level, kind, message, std::nullopt});
                return 0;
            });
        } catch (const std::exception& e) {
            spdlog::error("http: the event '{}' could not be stored: {}", message, e.what());
        }
    }
    std::optional<Session> session_of(const httplib::Request& req) {
        const std::string token = cookie(req, kSessionCookie);
        return token.empty() ? std::nullopt : sessions.find(token, now_utc());
    }

    void routes();
    void operator_routes();
    void login(const httplib::Request& req, httplib::Response& res);
    void alarm_action(const std::string& action, const httplib::Request& req,
                      httplib::Response& res);
    void page(const std::string& pattern, const std::string& file);
    void api(const std::string& pattern,
             std::function<void(const httplib::Request&, httplib::Response&)> handler);
    void stream(const httplib::Request& req, httplib::Response& res);
};

void HttpService::State::page(const std::string& pattern, const std::string& file) {
    server->Get(pattern, [this, file](const httplib::Request&, httplib::Response& res) {
        const WebFile* f = files.find(file);
        if (!f) return send_error(res, 404, "the dashboard has no " + file);
        res.set_content(f->body, f->content_type);
    });
}

// Every API answer: JSON, 400 with the reason for a bad parameter, 503 when the database
// cannot be read (the daemon's problem is its own; this side only reports it).
void HttpService::State::api(
    const std::string& pattern,
    std::function<void(const httplib::Request&, httplib::Response&)> handler) {
    server->Get(pattern, [this, handler](const httplib::Request& req, httplib::Response& res) {
        if (!config.anonymous_read && !session_of(req))
            return send_error(res, 401, "log in to read (http.anonymous_read = false)");
        try {
            handler(req, res);
        } catch (const BadRequest& e) {
            send_error(res, 400, e.what());
        } catch (const StorageError& e) {
            spdlog::warn("http {}: {}", req.path, e.what());
            send_error(res, 503, std::string("the epoch database cannot be read: ") + e.what());
        }
    });
}

void HttpService::State::routes() {
    page("/", "index.html");
    page(R"(/zones/[^/]+)", "zone.html");
    page(R"(/epochs/\d+)", "epoch.html");
    page("/alarms", "alarms.html");
    page("/events", "events.html");
    page("/calibration", "calibration.html");
    page("/campaigns", "campaigns.html");
    page(R"(/campaigns/\d+)", "campaign.html");
    server->Get(R"(/static/(.+))", [this](const httplib::Request& req, httplib::Response& res) {
        const WebFile* f = files.find(req.matches[1].str());
        if (!f) return send_error(res, 404, "no such file");
        res.set_content(f->body, f->content_type);
        res.set_header("Cache-Control", "max-age=300");
    });
    api("/api/v1/site", [this](const httplib::Request&, httplib::Response& res) {
        UtcSeconds beat;
        DashboardSite s;
        std::uint64_t seen;
        std::optional<Json> zones;
        {
            std::lock_guard lock(mutex);
            beat = heartbeat;
            s = site;
            seen = commits;
            if (zones_cached_at == seen) zones = zones_cache;
        }
        send_json(res, with_database([&](const EpochDatabase& db) {
                      if (!zones) {
                          zones = zone_overview(db, s);
                          std::lock_guard lock(mutex);
                          zones_cache = *zones;
                          zones_cached_at = seen;
                      }
                      return site_overview(db, s, now_utc(), beat, std::move(*zones));
                  }));
    });
    api("/api/v1/zones", [this](const httplib::Request&, httplib::Response& res) {
        send_json(res, with_database([&](const EpochDatabase& db) { return zone_list(db, site); }));
    });
    api("/api/v1/series", [this](const httplib::Request& req, httplib::Response& res) {
        const SeriesRequest r{required_parameter(req, "zone"), required_parameter(req, "quantity"),
                              range_parameters(req), width_parameter(req)};
        const std::string format = req.has_param("format") ? req.get_param_value("format") : "json";
        if (format != "json" && format != "csv")
            throw BadRequest("parameter 'format': expected json or csv, not '" + format + "'");
        with_database([&](const EpochDatabase& db) {
            const SeriesView view = series_view(db, r);
            if (format == "csv") {
                res.set_content(series_csv(view), "text/csv; charset=utf-8");
                res.set_header("Content-Disposition", "attachment; filename=\"series.csv\"");
            } else {
                send_json(res, series_json(db, view));
            }
            return 0;
        });
    });
    api("/api/v1/meteo", [this](const httplib::Request& req, httplib::Response& res) {
        const auto range = range_parameters(req);
        const auto width = width_parameter(req);
        send_json(res, with_database(
                           [&](const EpochDatabase& db) { return meteo_json(db, range, width); }));
    });
    api("/api/v1/events", [this](const httplib::Request& req, httplib::Response& res) {
        const auto range = range_parameters(req);
        std::optional<std::string> kind;
        if (req.has_param("kind") && !req.get_param_value("kind").empty())
            kind = req.get_param_value("kind");
        send_json(res, with_database(
                           [&](const EpochDatabase& db) { return events_json(db, range, kind); }));
    });
    api("/api/v1/alarms", [this](const httplib::Request& req, httplib::Response& res) {
        const auto range = range_parameters(req);
        send_json(res,
                  with_database([&](const EpochDatabase& db) { return alarms_json(db, range); }));
    });
    api("/api/v1/calibration", [this](const httplib::Request& req, httplib::Response& res) {
        const auto range = range_parameters(req);
        send_json(res, with_database(
                           [&](const EpochDatabase& db) { return calibration_json(db, range); }));
    });
    api("/api/v1/epochs", [this](const httplib::Request& req, httplib::Response& res) {
        const auto range = range_parameters(req);
        send_json(res,
                  with_database([&](const EpochDatabase& db) { return epochs_json(db, range); }));
    });
    api(R"(/api/v1/epochs/(\d{1,18}))",
        [this](const httplib::Request& req, httplib::Response& res) {
            const EpochId id = std::stoll(req.matches[1].str());
            const auto body =
                with_database([&](const EpochDatabase& db) { return epoch_json(db, id); });
            if (!body) return send_error(res, 404, "no epoch " + std::to_string(id));
            send_json(res, *body);
        });
    api(R"(/api/v1/epochs/(\d{1,18})/corepoints)",
        [this](const httplib::Request& req, httplib::Response& res) {
            const EpochId id = std::stoll(req.matches[1].str());
            bool absent = false;
            try {
                send_json(res, with_database([&](const EpochDatabase& db) {
                              return core_point_map_json(db, id, absent);
                          }));
            } catch (const Error& e) {
                // A stored map that cannot be put together is the server's fault: 500.
                if (!absent) throw;
                send_error(res, 404, e.what());
            }
        });
    api("/api/v1/campaigns", [this](const httplib::Request& req, httplib::Response& res) {
        const auto range = range_parameters(req);
        send_json(
            res, with_database([&](const EpochDatabase& db) { return campaigns_json(db, range); }));
    });
    api(R"(/api/v1/campaigns/(\d{1,18}))",
        [this](const httplib::Request& req, httplib::Response& res) {
            const CampaignId id = std::stoll(req.matches[1].str());
            const auto body =
                with_database([&](const EpochDatabase& db) { return campaign_json(db, id); });
            if (!body) return send_error(res, 404, "no campaign " + std::to_string(id));
            send_json(res, *body);
        });
    api(R"(/api/v1/campaigns/(\d{1,18})/points)",
        [this](const httplib::Request& req, httplib::Response& res) {
            const CampaignId id = std::stoll(req.matches[1].str());
            const std::size_t most = max_points_parameter(req);
            std::string why;
            const auto body = with_database(
                [&](const EpochDatabase& db) { return campaign_points_json(db, id, most, why); });
            if (!body) return send_error(res, 404, why);
            send_json(res, *body);
        });
    server->Get("/api/v1/stream",
                [this](const httplib::Request& req, httplib::Response& res) { stream(req, res); });
    operator_routes();
}

// Who is logged in ({"user": null} when nobody: not an error for a page that asks): the page
// shows the actions the role allows and sends the CSRF token back with each of them.
void HttpService::State::operator_routes() {
    server->Get("/api/v1/session", [this](const httplib::Request& req, httplib::Response& res) {
        const auto s = session_of(req);
        if (!s) return send_json(res, Json{{"user", nullptr}, {"role", nullptr}});
        send_json(res, Json{{"user", s->user},
                            {"role", std::string(to_string(s->role))},
                            {"csrf", s->csrf},
                            {"expires", format_utc(s->expires)}});
    });
    server->Post("/api/v1/login", [this](const httplib::Request& req, httplib::Response& res) {
        try {
            login(req, res);
        } catch (const BadRequest& e) {
            send_error(res, 400, e.what());
        }
    });
    server->Post("/api/v1/logout", [this](const httplib::Request& req, httplib::Response& res) {
        const auto s = session_of(req);
        if (!s) return send_error(res, 401, "not logged in");
        if (!same_token(req.get_header_value("X-CSRF-Token"), s->csrf))
            return send_error(res, 403, "missing or wrong X-CSRF-Token");
        sessions.close(s->token);
        res.set_header("Set-Cookie",
                       std::string(kSessionCookie) + "=; " + cookie_attributes() + "; Max-Age=0");
        audit("info", "http_logout", "user " + s->user + " logged out from " + req.remote_addr);
        send_json(res, Json{{"user", s->user}, {"logged_out", true}});
    });
    for (const char* action : {"ack", "shelve", "unshelve", "out-of-service", "in-service"}) {
        server->Post(std::string("/api/v1/alarms/") + action,
                     [this, action](const httplib::Request& req, httplib::Response& res) {
                         try {
                             alarm_action(action, req, res);
                         } catch (const BadRequest& e) {
                             send_error(res, 400, e.what());
                         }
                     });
    }
}

// POST /api/v1/login {"user", "password"}: a session cookie (HttpOnly, SameSite=Strict) and
// the CSRF token. Every attempt is an event; a client address with 5 failures in 5 minutes
// is refused (429) without its password being checked until the oldest leaves the window.
void HttpService::State::login(const httplib::Request& req, httplib::Response& res) {
    const UtcSeconds now = now_utc();
    const std::string& from = req.remote_addr;
    if (const UtcSeconds wait = throttle.wait_before_login(from, now)) {
        res.set_header("Retry-After", std::to_string(wait));
        spdlog::warn("http: login from {} refused, too many failures", from);
        return send_error(res, 429,
                          "too many failed logins from " + from + "; try again in " +
                              std::to_string(wait) + " s");
    }
    const Json body = json_body(req);
    const std::string name = string_field(body, "user", 64);
    const std::string password = string_field(body, "password", 1024);
    if (config.users_file.empty())
        return send_error(res, 403, "nobody may log in: http.users_file is not set (read-only)");
    std::vector<UserEntry> users;
    try {
        users = read_users(config.users_file);
    } catch (const Error& e) {
        spdlog::error("http: {}", e.what());
        return send_error(res, 503, "the users file cannot be read; see the daemon's log");
    }
    const auto user = std::find_if(users.begin(), users.end(),
                                   [&](const UserEntry& u) { return u.name == name; });
    // An unknown name costs the same hashing as a known one: the time does not tell names.
    static const UserEntry nobody = make_user("nobody", UserRole::viewer, random_token());
    const bool known = user != users.end();
    const bool matches = password_matches(known ? *user : nobody, password);
    if (!known || !matches) {
        throttle.failed(from, now);
        audit("warning", "http_login", "failed login as '" + name + "' from " + from);
        return send_error(res, 401, "wrong user name or password");
    }
    throttle.succeeded(from);
    const Session s = sessions.open(user->name, user->role, now,
                                    static_cast<UtcSeconds>(config.session_lifetime));
    res.set_header("Set-Cookie", std::string(kSessionCookie) + "=" + s.token + "; " +
                                     cookie_attributes() +
                                     "; Max-Age=" + std::to_string(s.expires - now));
    audit("info", "http_login",
          "user " + s.user + " (" + std::string(to_string(s.role)) + ") logged in from " + from);
    send_json(res, Json{{"user", s.user},
                        {"role", std::string(to_string(s.role))},
                        {"csrf", s.csrf},
                        {"expires", format_utc(s.expires)}});
}

// POST /api/v1/alarms/ACTION {"rule", "comment", "until"}: 401 without a login, 403 for a
// viewer or without the session's X-CSRF-Token, 400 for a bad request or an unknown rule.
void HttpService::State::alarm_action(const std::string& action, const httplib::Request& req,
                                      httplib::Response& res) {
    const auto s = session_of(req);
    if (!s) return send_error(res, 401, "log in as an operator to act on alarms");
    if (!same_token(req.get_header_value("X-CSRF-Token"), s->csrf))
        return send_error(res, 403, "missing or wrong X-CSRF-Token");
    if (!may_act_on_alarms(s->role)) {
        audit("warning", "http_refused",
              "user " + s->user + " (viewer) may not " + action + " alarms; refused");
        return send_error(res, 403,
                          "user " + s->user + " is a viewer: only operators act on alarms");
    }
    const Json body = json_body(req);
    OperatorAction a{action, string_field(body, "rule", 200), std::nullopt, "user " + s->user,
                     string_field(body, "comment", kMaxComment)};
    if (a.rule.empty()) throw BadRequest("'rule' is required (\"*\": every rule)");
    if ((action == "shelve" || action == "out-of-service") && a.comment.empty())
        throw BadRequest("a comment is required to " + action + " an alarm: the reason");
    if (action == "shelve") {
        const std::string until = string_field(body, "until", 40);
        try {
            a.until = parse_utc(until);
        } catch (const std::exception&) {
            throw BadRequest("'until' must be an ISO 8601 UTC time, not '" + until + "'");
        }
    }
    int changed = 0;
    try {
        changed = with_writer([&](EpochDatabase& db) { return actions(db, a, now_utc()); });
    } catch (const StorageError& e) {
        spdlog::error("http {}: {}", req.path, e.what());
        return send_error(res, 503, std::string("not stored: ") + e.what());
    } catch (const Error& e) {  // an unknown rule, a shelve into the past
        return send_error(res, 400, e.what());
    }
    {
        std::lock_guard lock(mutex);
        ++commits;  // open pages refresh: the alarm's state changed
        last_change = "alarm";
    }
    committed.notify_all();
    send_json(res,
              Json{{"action", action}, {"rule", a.rule}, {"changed", changed}, {"by", s->user}});
}

// Server-sent events: `epoch` with {"epoch": N} after each commit, `alarm` after an operator's
// action on an alarm, a comment every second
// (so a client that went away is noticed and its thread freed). Each stream holds one of
// the server's threads, hence the bound (http.max_event_streams).
void HttpService::State::stream(const httplib::Request& req, httplib::Response& res) {
    if (!config.anonymous_read && !session_of(req))
        return send_error(res, 401, "log in to read (http.anonymous_read = false)");
    std::uint64_t seen;
    {
        std::lock_guard lock(mutex);
        if (streams >= config.max_event_streams) {
            res.set_header("Retry-After", "60");
            return send_error(res, 503,
                              "too many live-update streams open (http.max_event_streams)");
        }
        ++streams;
        seen = commits;
    }
    res.set_header("Cache-Control", "no-store");
    res.set_chunked_content_provider(
        "text/event-stream",
        [this, seen, first = true](std::size_t, httplib::DataSink& sink) mutable {
            if (first) {  // at once: the page knows its stream is open
                first = false;
                const std::string hello = "retry: 5000\n: connected\n\n";
                return sink.write(hello.data(), hello.size());
            }
            std::string message;
            {
                std::unique_lock lock(mutex);
                committed.wait_for(lock, std::chrono::seconds(kStreamKeepAliveSeconds),
                                   [&] { return stopping || commits != seen; });
                if (stopping) return false;
                if (commits != seen) {
                    seen = commits;
                    message = "event: " + last_change +
                              "\ndata: {\"epoch\":" + std::to_string(last_epoch) + "}\n\n";
                } else {
                    message = ": alive\n\n";
                }
            }
            return sink.write(message.data(), message.size());
        },
        [this](bool) {
            std::lock_guard lock(mutex);
            --streams;
        });
}

namespace {

// cpp-httplib's task queue on ConnectionQueue: its own ThreadPool queues every accepted
// connection without bound, each holding a file descriptor.
class BoundedTaskQueue : public httplib::TaskQueue {
  public:
    BoundedTaskQueue(std::size_t threads, std::size_t waiting) : queue_(threads, waiting) {}
    void enqueue(std::function<void()> fn) override { queue_.enqueue(std::move(fn)); }
    void shutdown() override { queue_.shutdown(); }

  private:
    ConnectionQueue queue_;
};

}  // namespace

HttpService::HttpService(const HttpConfig& config, const std::filesystem::path& database,
                         DashboardSite site, AlarmActionHandler actions)
    : state_(std::make_unique<State>()) {
    State& s = *state_;
    s.config = config;
    s.database = database;
    s.site = std::move(site);
    s.actions = std::move(actions);
    if (!config.users_file.empty()) {  // a malformed file stops the start, naming the line
        const auto users = read_users(config.users_file);
        spdlog::info("dashboard users: {} in {}", users.size(), config.users_file.string());
    }
    s.heartbeat = now_utc();
    s.files = WebFiles::load(find_web_root(config.web_root));
    if (config.certificate.empty()) {
        s.server = std::make_unique<httplib::Server>();
    } else {  // OpenSSL reads both files now: a wrong one stops the start, named
        auto tls = std::make_unique<httplib::SSLServer>(config.certificate.c_str(),
                                                        config.private_key.c_str());
        if (!tls->is_valid()) {
            throw Error("the HTTPS server cannot use the certificate " +
                        config.certificate.string() + " with the key " +
                        config.private_key.string() +
                        " (missing, unreadable, not PEM, or not a pair)");
        }
        s.server = std::move(tls);
    }
    // http.threads connections served, as many waiting; the rest wait in the kernel
    // (daemon/http/connection_queue.hpp).
    const auto threads = static_cast<std::size_t>(config.threads);
    s.server->new_task_queue = [threads] { return new BoundedTaskQueue(threads, threads); };
    // One request per connection: cpp-httplib gives each connection a thread for as long as
    // it stays open, so a browser's idle kept-alive connection would hold a thread and 16
    // open pages would starve the 17th (measured: p99 3.2 s for 20 pages polling once a
    // second with keep-alive, bench/http_dashboard.cpp). A new TCP connection on the site
    // network costs a fraction of a millisecond.
    s.server->set_keep_alive_max_count(1);
    s.server->set_read_timeout(static_cast<time_t>(config.idle_timeout), 0);
    s.server->set_write_timeout(5, 0);
    s.server->set_payload_max_length(kMaxBody);
    s.server->set_default_headers({{"X-Content-Type-Options", "nosniff"},
                                   {"X-Frame-Options", "DENY"},
                                   {"Referrer-Policy", "no-referrer"},
                                   {"Content-Security-Policy",
                                    "default-src 'self'; style-src 'self' 'unsafe-inline'; "
                                    "img-src 'self' data:; frame-ancestors 'none'"}});
    // Read-only: anything but GET and HEAD is refused before routing, and so is anything
    // but POST on the paths that take one.
    s.server->set_pre_routing_handler([](const httplib::Request& req, httplib::Response& res) {
        const bool post = takes_post(req.path);
        if (post ? req.method == "POST" : (req.method == "GET" || req.method == "HEAD"))
            return httplib::Server::HandlerResponse::Unhandled;
        res.set_header("Allow", post ? "POST" : "GET, HEAD");
        send_error(res, 405, "method " + req.method + " not allowed");
        return httplib::Server::HandlerResponse::Handled;
    });
    s.server->set_error_handler([](const httplib::Request& req, httplib::Response& res) {
        if (!res.body.empty()) return;
        send_error(res, res.status,
                   res.status == 404 ? "no such page: " + req.path
                                     : "request refused (" + std::to_string(res.status) + ")");
    });
    s.server->set_exception_handler(
        [](const httplib::Request& req, httplib::Response& res, std::exception_ptr ep) {
            std::string what = "unknown error";
            try {
                std::rethrow_exception(ep);
            } catch (const std::exception& e) {
                what = e.what();
            } catch (...) {
            }
            spdlog::error("http {} {}: {}", req.method, req.path, what);
            send_error(res, 500, what);
        });
    s.routes();
    if (!s.server->bind_to_port(config.address, config.port)) {
        throw Error("the HTTP server cannot listen on " + config.address + ":" +
                    std::to_string(config.port) + " (address in use, or not this machine's)");
    }
    s.thread = std::thread([&s] { s.server->listen_after_bind(); });
    spdlog::info("dashboard on {}://{}:{}/ ({} files from {})",
                 config.certificate.empty() ? "http" : "https", config.address, config.port,
                 s.files.size(), s.files.root().string());
}

HttpService::~HttpService() {
    {
        std::lock_guard lock(state_->mutex);
        state_->stopping = true;
    }
    state_->committed.notify_all();
    state_->server->stop();
    if (state_->thread.joinable()) state_->thread.join();
}

void HttpService::epoch_committed(EpochId epoch) {
    {
        std::lock_guard lock(state_->mutex);
        ++state_->commits;
        state_->last_epoch = epoch;
        state_->last_change = "epoch";
    }
    state_->committed.notify_all();
}

void HttpService::heartbeat(UtcSeconds now, std::optional<double> disk_free_share) {
    std::lock_guard lock(state_->mutex);
    state_->heartbeat = now;
    state_->site.disk_free_share = disk_free_share;
}

}  // namespace tlsmon
