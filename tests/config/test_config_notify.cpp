// [notify] with its [[notify.channel]] and [[notify.route]] tables: read into NotifyConfig,
// every mistake an error naming the key.
#include <gtest/gtest.h>

#include "config/config.hpp"

namespace tlsmon {
namespace {

const std::string kChannels =
    "[notify]\nenabled = true\nquiet_hours = \"22:00-06:00\"\ndaily_summary = \"07:00\"\n"
    "summary_channels = [\"office\"]\nretry_initial = \"10s\"\n"
    "[[notify.channel]]\nname = \"office\"\nkind = \"email\"\nurl = \"smtp://mail:587\"\n"
    "from = \"tlsmon@site\"\nto = [\"a@b\", \"c@d\"]\nusername = \"u\"\n"
    "password_file = \"secret/smtp\"\n"
    "[[notify.channel]]\nname = \"scada\"\nkind = \"webhook\"\nurl = \"https://gw/hook\"\n"
    "token_file = \"/etc/tlsmon/token\"\n"
    "[[notify.channel]]\nname = \"gateway\"\nkind = \"mqtt\"\nurl = \"mqtt://gw:1883\"\n"
    "qos = 2\ntopic = \"site/7\"\n";

std::string error_of(const std::string& text) {
    try {
        parse_config(text, "site.toml", "/etc/tlsmon");
    } catch (const Error& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(ConfigNotify, ReadsChannelsRoutesAndResolvesSecretFiles) {
    const Config c = parse_config(kChannels +
                                      "[[notify.route]]\nrules = [\"P3*\"]\nmin_level = "
                                      "\"alert\"\nevents = [\"raise\"]\nchannels = [\"office\", "
                                      "\"gateway\"]\n",
                                  "site.toml", "/etc/tlsmon");
    ASSERT_EQ(c.notify.channels.size(), 3u);
    EXPECT_EQ(c.notify.channels[0].kind, ChannelKind::email);
    EXPECT_EQ(c.notify.channels[0].to, (std::vector<std::string>{"a@b", "c@d"}));
    EXPECT_EQ(c.notify.channels[0].password_file, "/etc/tlsmon/secret/smtp");
    EXPECT_EQ(c.notify.channels[0].starttls, StartTls::required);
    EXPECT_EQ(c.notify.channels[1].token_file, "/etc/tlsmon/token");
    EXPECT_EQ(c.notify.channels[2].qos, 2);
    EXPECT_EQ(c.notify.retry_initial, 10.0);
    ASSERT_EQ(c.notify.routes.size(), 1u);
    EXPECT_EQ(c.notify.routes[0].min_level, AlarmLevel::alert);
    EXPECT_EQ(c.notify.routes[0].channels, (std::vector<std::string>{"office", "gateway"}));
    // The effective configuration names the secret files, never their content.
    bool seen = false;
    for (const auto& line : describe(c)) {
        if (line.rfind("notify channel \"office\"", 0) == 0) {
            seen = true;
            EXPECT_NE(line.find("password_file = \"/etc/tlsmon/secret/smtp\""), std::string::npos);
        }
    }
    EXPECT_TRUE(seen);
}

TEST(ConfigNotify, EachMistakeNamesItsKey) {
    const std::string route = "[[notify.route]]\nchannels = [\"office\"]\n";
    EXPECT_NE(error_of(kChannels + "[[notify.route]]\nchannels = [\"pager\"]\n")
                  .find("key 'notify.route[0].channels': no [[notify.channel]] named 'pager'"),
              std::string::npos);
    EXPECT_NE(error_of(kChannels + route +
                       "[[notify.route]]\nchannels = [\"office\"]\nevents = "
                       "[\"rise\"]\n")
                  .find("key 'notify.route[1].events': 'rise' is not an alarm event kind"),
              std::string::npos);
    EXPECT_NE(error_of("[notify]\nquiet_hours = \"22-6\"\n")
                  .find("key 'notify.quiet_hours': expected HH:MM-HH:MM"),
              std::string::npos);
    EXPECT_NE(error_of("[notify]\n[[notify.channel]]\nname = \"x\"\nkind = \"webhook\"\nurl = "
                       "\"smtp://mail\"\n")
                  .find("key 'notify.channel[0].url': a webhook channel's url begins with http://"),
              std::string::npos);
    EXPECT_NE(error_of("[notify]\n[[notify.channel]]\nname = \"x\"\nkind = \"email\"\nurl = "
                       "\"smtp://mail\"\nto = [\"a@b\"]\n")
                  .find("key 'notify.channel[0].from'"),
              std::string::npos);
    EXPECT_NE(error_of("[notify]\n[[notify.channel]]\nname = \"x\"\nkind = \"mqtt\"\nurl = "
                       "\"mqtt://gw\"\ntoken_file = \"t\"\n")
                  .find("key 'notify.channel[0].token_file': only a webhook channel"),
              std::string::npos);
    EXPECT_NE(error_of("[notify]\n[[notify.channel]]\nname = \"x\"\nkind = \"mqtt\"\nurl = "
                       "\"mqtt://gw:18a3\"\n")
                  .find("key 'notify.channel[0].url': expected mqtt://HOST[:PORT]"),
              std::string::npos);
    EXPECT_NE(error_of("[notify]\nenabled = true\n").find("nothing to send"), std::string::npos);
    EXPECT_NE(error_of(kChannels + route +
                       "[[notify.channel]]\nname = \"office\"\nkind = "
                       "\"webhook\"\nurl = \"http://x\"\n")
                  .find("channel 'office' is defined twice"),
              std::string::npos);
    EXPECT_NE(error_of(kChannels + route + "[notify.x]\n").find("notify.x"), std::string::npos);
}

}  // namespace
}  // namespace tlsmon
