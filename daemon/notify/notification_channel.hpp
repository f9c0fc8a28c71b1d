#pragma once
// The channels a notification leaves by (docs/notifications.md): e-mail over SMTP with
// STARTTLS and a webhook (HTTP POST of the JSON document), both through libcurl, and MQTT
// through libmosquitto. A channel is a value: a function that delivers one notification and
// returns once the other side accepted it (the mail server its DATA, the web server a 2xx,
// the broker its PUBACK at QoS 1), or throws an Error saying why not.
#include <functional>
#include <string>

#include "config/notify_config.hpp"
#include "storage/notification_store.hpp"

namespace tlsmon {

using ChannelSend = std::function<void(const Notification&)>;

// The channel of `config`; `station` names the sender (mail's Message-ID, MQTT topic and
// client id). Secrets (password_file, token_file) are read at each send, so a rotated one
// applies without a restart; a missing one is the send's error.
ChannelSend make_channel(const NotifyChannel& config, const std::string& station);

ChannelSend email_channel(const NotifyChannel& config, const std::string& station);
ChannelSend webhook_channel(const NotifyChannel& config);
ChannelSend mqtt_channel(const NotifyChannel& config, const std::string& station);

// The first line of a secret file (a password, a token), without its line end; an Error
// naming the file when it cannot be read or is empty.
std::string read_secret(const std::filesystem::path& file);

// The MQTT topic of a notification: <prefix>/alarm/<rule>, <prefix>/summary or
// <prefix>/test, with the
// characters MQTT reserves (+ # and NUL) in the rule name replaced by '_'.
std::string mqtt_topic(const std::string& prefix, const std::string& station,
                       const Notification& n);

}  // namespace tlsmon
