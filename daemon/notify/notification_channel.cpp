#include "daemon/notify/notification_channel.hpp"

#include <fstream>
#include <nlohmann/json.hpp>

namespace tlsmon {

ChannelSend make_channel(const NotifyChannel& config, const std::string& station) {
    switch (config.kind) {
        case ChannelKind::email:
            return email_channel(config, station);
        case ChannelKind::webhook:
            return webhook_channel(config);
        case ChannelKind::mqtt:
            return mqtt_channel(config, station);
    }
    throw Error("notify channel '" + config.name + "': unknown kind");
}

std::string read_secret(const std::filesystem::path& file) {
    std::ifstream in(file);
    if (!in) throw Error("cannot read the secret file " + file.string());
    std::string line;
    std::getline(in, line);
    while (!line.empty() && (line.back() == '\r' || line.back() == '\n')) line.pop_back();
    if (line.empty()) throw Error("the secret file " + file.string() + " is empty");
    return line;
}

std::string mqtt_topic(const std::string& prefix, const std::string& station,
                       const Notification& n) {
    std::string base = prefix.empty() ? "tlsmon/" + station : prefix;
    while (!base.empty() && base.back() == '/') base.pop_back();
    const auto doc = nlohmann::json::parse(n.body, nullptr, false);
    const std::string type = doc.is_discarded() ? "" : doc.value("type", "");
    if (type == "summary" || type == "test") return base + "/" + type;
    std::string rule = doc.value("rule", "");
    for (char& c : rule) {
        if (c == '+' || c == '#' || c == '\0') c = '_';
    }
    return base + "/alarm/" + rule;
}

}  // namespace tlsmon
