// The MQTT channel through libmosquitto (MQTT 3.1.1): one connection per notification,
// published at the configured QoS and waited for (QoS 1: the broker's PUBACK; QoS 2: its
// PUBCOMP), then closed. Notifications are rare, so nothing is kept open between them.
#include <mosquitto.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <memory>
#include <mutex>

#include "daemon/notify/notification_channel.hpp"

namespace tlsmon {

namespace {

struct Endpoint {
    std::string host;
    int port = 1883;
    bool tls = false;
};

Endpoint parse_mqtt_url(const std::string& url) {
    Endpoint e;
    std::string rest;
    if (url.rfind("mqtts://", 0) == 0) {
        e.tls = true;
        e.port = 8883;
        rest = url.substr(8);
    } else if (url.rfind("mqtt://", 0) == 0) {
        rest = url.substr(7);
    } else {
        throw Error("not an mqtt:// or mqtts:// URL: " + url);
    }
    rest = rest.substr(0, rest.find('/'));
    const auto colon = rest.rfind(':');
    if (colon != std::string::npos && rest.find(']') == std::string::npos) {
        e.port = std::stoi(rest.substr(colon + 1));
        rest = rest.substr(0, colon);
    }
    if (rest.empty()) throw Error("no host in " + url);
    e.host = rest;
    return e;
}

// What the callbacks learn, read by the waiting loop.
struct Progress {
    int connack = -1;  // CONNACK's return code once it came
    int mid = -1;      // the message id of our PUBLISH
    bool published = false;
};

std::string mosq_error(int rc) {
    return rc == MOSQ_ERR_ERRNO ? std::string(std::strerror(errno)) : mosquitto_strerror(rc);
}

}  // namespace

ChannelSend mqtt_channel(const NotifyChannel& config, const std::string& station) {
    static std::once_flag once;
    std::call_once(once, [] { mosquitto_lib_init(); });
    const Endpoint endpoint = parse_mqtt_url(config.url);
    return [c = config, station, endpoint](const Notification& n) {
        Progress progress;
        const std::string client_id =
            "tlsmon-" + station + "-" + std::to_string(::getpid()) + "-" + std::to_string(n.id);
        std::unique_ptr<mosquitto, decltype(&mosquitto_destroy)> m(
            mosquitto_new(client_id.c_str(), true, &progress), mosquitto_destroy);
        if (!m) throw Error("MQTT: cannot create a client: " + std::string(std::strerror(errno)));
        mosquitto_connect_callback_set(
            m.get(), [](mosquitto*, void* p, int rc) { static_cast<Progress*>(p)->connack = rc; });
        mosquitto_publish_callback_set(m.get(), [](mosquitto*, void* p, int mid) {
            auto* progress = static_cast<Progress*>(p);
            if (mid == progress->mid) progress->published = true;
        });
        std::string password;
        if (!c.username.empty()) {
            if (!c.password_file.empty()) password = read_secret(c.password_file);
            mosquitto_username_pw_set(m.get(), c.username.c_str(),
                                      c.password_file.empty() ? nullptr : password.c_str());
        }
        const std::string where = c.url;
        if (endpoint.tls) {
            const int rc = mosquitto_tls_set(
                m.get(), c.ca_file.empty() ? nullptr : c.ca_file.c_str(),
                c.ca_file.empty() ? "/etc/ssl/certs" : nullptr, nullptr, nullptr, nullptr);
            if (rc != MOSQ_ERR_SUCCESS)
                throw Error("MQTT TLS setup for " + where + ": " + mosq_error(rc));
        }
        const auto deadline =
            std::chrono::steady_clock::now() + std::chrono::duration<double>(c.timeout);
        const auto wait_for = [&](auto done, const char* what) {
            while (!done()) {
                if (std::chrono::steady_clock::now() > deadline)
                    throw Error("MQTT " + where + ": no " + what + " within " +
                                std::to_string(static_cast<int>(c.timeout)) + " s");
                const int rc = mosquitto_loop(m.get(), 100, 1);
                if (progress.connack > 0) break;  // refused: said below, with the reason
                if (rc != MOSQ_ERR_SUCCESS)
                    throw Error("MQTT " + where + ": " + what + ": " + mosq_error(rc));
            }
        };
        int rc = mosquitto_connect(m.get(), endpoint.host.c_str(), endpoint.port, 30);
        if (rc != MOSQ_ERR_SUCCESS) throw Error("MQTT connect to " + where + ": " + mosq_error(rc));
        wait_for([&] { return progress.connack >= 0; }, "CONNACK");
        if (progress.connack != 0)
            throw Error("MQTT " + where +
                        " refused the connection: " + mosquitto_connack_string(progress.connack));
        const std::string topic = mqtt_topic(c.topic, station, n);
        rc = mosquitto_publish(m.get(), &progress.mid, topic.c_str(),
                               static_cast<int>(n.body.size()), n.body.data(), c.qos, c.retain);
        if (rc != MOSQ_ERR_SUCCESS)
            throw Error("MQTT publish on " + topic + " at " + where + ": " + mosq_error(rc));
        // QoS 0 has no acknowledgement: the callback fires once the packet is written.
        wait_for([&] { return progress.published; }, c.qos == 0 ? "write" : "acknowledgement");
        mosquitto_disconnect(m.get());
        mosquitto_loop(m.get(), 100, 1);  // sends the DISCONNECT
    };
}

}  // namespace tlsmon
