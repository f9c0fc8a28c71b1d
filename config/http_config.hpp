#pragma once
// The [http] section of the configuration: the dashboard and its JSON API, served by the
// daemon (docs/http.md). Plain data; the keys are declared in config/http_config.cpp.
#include <filesystem>
#include <string>

#include "core/config_key.hpp"

namespace tlsmon {

struct HttpConfig {
    bool enabled = false;
    std::string address = "127.0.0.1";  // IPv4 address the server listens on
    int port = 8080;
    int threads = 16;                      // requests served at once (event streams included)
    int max_event_streams = 8;             // open /api/v1/stream connections; each holds a thread
    double idle_timeout = 5.0;             // seconds a connection may wait for its next request
    std::filesystem::path web_root;        // the dashboard's files; "" = installed with tlsmon
    std::filesystem::path users_file;      // who may log in (`tlsmon users`); "" = nobody
    double session_lifetime = 8 * 3600.0;  // seconds a login lasts
    bool anonymous_read = true;            // pages and API readable without a login
    std::filesystem::path certificate;     // TLS: PEM certificate (chain); "" = plain HTTP
    std::filesystem::path private_key;     // TLS: its PEM private key
};

// The keys of [http] (core/config_key.hpp).
std::vector<SectionKey<HttpConfig>> http_keys();

}  // namespace tlsmon
