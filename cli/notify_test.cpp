// `tlsmon notify test --config SITE [--channel NAME]`: a test notification through each
// configured channel (or the one named), at once, with what each receiver answered. Writes
// nothing to the epoch database: the daemon's outbox and events stay as they are.
#include <iostream>

#include "cli/commands.hpp"
#include "config/config.hpp"
#include "daemon/notify/notification_channel.hpp"
#include "daemon/notify/notification_message.hpp"

namespace tlsmon {

int run_notify_test(const NotifyTestOptions& o) {
    try {
        const Config config = load_config(o.config);
        int tried = 0, failed = 0;
        for (const NotifyChannel& c : config.notify.channels) {
            if (!o.channel.empty() && c.name != o.channel) continue;
            ++tried;
            const Json doc = test_notification(config.station.name, c.name, now_utc());
            Notification n;
            n.channel = c.name;
            n.created = n.due = now_utc();
            n.subject = notification_subject(doc);
            n.body = doc.dump();
            try {
                make_channel(c, config.station.name)(n);
                std::cout << c.name << " (" << to_string(c.kind) << ", " << c.url << "): sent\n";
            } catch (const std::exception& e) {
                ++failed;
                std::cout << c.name << " (" << to_string(c.kind) << ", " << c.url
                          << "): FAILED: " << e.what() << "\n";
            }
        }
        if (tried == 0) {
            std::cerr << "tlsmon notify test: "
                      << (o.channel.empty() ? "no [[notify.channel]] in " + o.config
                                            : "no channel named '" + o.channel + "' in " + o.config)
                      << "\n";
            return 2;
        }
        return failed == 0 ? 0 : 1;
    } catch (const std::exception& e) {
        std::cerr << "tlsmon notify test: " << e.what() << "\n";
        return 2;
    }
}

}  // namespace tlsmon
