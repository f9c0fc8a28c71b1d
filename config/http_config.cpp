#include "config/http_config.hpp"

namespace tlsmon {

std::vector<SectionKey<HttpConfig>> http_keys() {
    using K = Keys<HttpConfig>;
    return {
        K::flag(&HttpConfig::enabled, "enabled",
                "Serve the dashboard and its JSON API (docs/http.md)."),
        K::text(&HttpConfig::address, "address", "an IPv4 address",
                "Address the server listens on; `0.0.0.0`: every interface (the site network)."),
        K::integer(&HttpConfig::port, "port", 1, 65535, "", "TCP port."),
        K::integer(&HttpConfig::threads, "threads", 2, 64, "",
                   "Connections served at once; as many more wait for a free thread, and further "
                   "ones wait in the kernel, holding no descriptor of the daemon."),
        K::integer(&HttpConfig::max_event_streams, "max_event_streams", 0, 63, "",
                   "Open live-update streams (`/api/v1/stream`, one per open page), less than "
                   "`threads`: each holds a thread, so a further one is refused (503) and its page "
                   "refreshes every 30 s instead."),
        K::seconds(&HttpConfig::idle_timeout, "idle_timeout", 1, 300, "",
                   "A connection that has not sent its whole request within this long is closed."),
        K::optional_path(&HttpConfig::web_root, "web_root",
                         "Folder of the dashboard's files; empty: the files installed with tlsmon "
                         "(`share/tlsmon/web` beside its `bin/`, or `web/` beside the program in a "
                         "build tree)."),
        K::optional_path(&HttpConfig::users_file, "users_file",
                         "Who may log in, with their role (viewer, operator, admin) and password "
                         "hash, made by `tlsmon users add`; empty: nobody, the dashboard is "
                         "read-only (docs/http.md)."),
        K::seconds(&HttpConfig::session_lifetime, "session_lifetime", 300, 7 * 86400.0, "",
                   "How long a login lasts."),
        K::flag(&HttpConfig::anonymous_read, "anonymous_read",
                "Whether the pages' data may be read without a login; `false`: a viewer's "
                "login at least."),
        K::optional_path(&HttpConfig::certificate, "certificate",
                         "PEM certificate (with its chain) for HTTPS; empty: plain HTTP. Set "
                         "together with `private_key`; the session cookie is then `Secure`."),
        K::optional_path(&HttpConfig::private_key, "private_key",
                         "PEM private key of `certificate` (readable by the daemon's user only)."),
    };
}

}  // namespace tlsmon
