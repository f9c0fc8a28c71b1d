// Notifications through real servers (issue 26): a daemon fed the demo's scenario (the
// south face's top band stepped at N/2, so its rule is raised) sends the raise, and the
// acknowledgement an operator makes with `tlsmon alarms ack`, to
//   - an SMTP server (aiosmtpd) that takes mail only after STARTTLS and a login,
//   - a webhook receiver that wants a bearer token and refuses the first POST with 503,
//   - an MQTT broker (Debian's mosquitto) with a password file, watched by mosquitto_sub;
// each message is read where it arrived and compared with the database (read by the
// sqlite3 program); each send and the refused attempt are events. And each client, refused
// (a wrong password or token, nobody listening), says why.
#include <gtest/gtest.h>

#include <set>

#include "daemon/notify/notification_channel.hpp"
#include "tests/support/e2e_scenario.hpp"
#include "tests/support/modbus_client.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon::test::e2e {
namespace {

constexpr const char* kSmtpPassword = "smtp-secret";
constexpr const char* kMqttPassword = "mqtt-secret";
constexpr const char* kToken = "hook-token-7f3a";

int another_port(std::set<int>& taken) {
    int p = free_tcp_port();
    while (taken.count(p)) p = free_tcp_port();
    taken.insert(p);
    return p;
}

// The receivers of tests/daemon/notify_receivers.py and a mosquitto broker, in `dir`.
struct Receivers {
    fs::path dir;
    int smtp = 0, http = 0, mqtt = 0;
    std::unique_ptr<ChildProcess> python, broker, subscriber;

    Receivers(const fs::path& d, std::set<int>& ports, int refuse) : dir(d) {
        fs::create_directories(dir / "received");
        smtp = another_port(ports);
        http = another_port(ports);
        mqtt = another_port(ports);
        const auto r =
            shell("(cd " + quoted(dir.string()) +
                  " && openssl req -x509 -newkey rsa:2048 -nodes -keyout key.pem -out "
                  "cert.pem -days 2 -subj /CN=localhost -addext "
                  "subjectAltName=DNS:localhost,IP:127.0.0.1 && mosquitto_passwd -b -c "
                  "broker-passwords tlsmon " +
                  kMqttPassword + " && mosquitto_passwd -b broker-passwords watcher w) 2>&1");
        EXPECT_EQ(r.status, 0) << r.output;
        python = std::make_unique<ChildProcess>(
            "exec /usr/bin/python3 " +
                quoted(std::string(TLSMON_SOURCE_DIR) + "/tests/daemon/notify_receivers.py") +
                " --smtp-port " + std::to_string(smtp) + " --http-port " + std::to_string(http) +
                " --cert " + quoted((dir / "cert.pem").string()) + " --key " +
                quoted((dir / "key.pem").string()) + " --user tlsmon --password " + kSmtpPassword +
                " --token " + kToken + " --refuse " + std::to_string(refuse) + " --out " +
                quoted((dir / "received").string()),
            dir / "receivers.log");
        write_text(dir / "broker.conf", "listener " + std::to_string(mqtt) +
                                            " 127.0.0.1\nallow_anonymous false\npassword_file " +
                                            (dir / "broker-passwords").string() +
                                            "\npersistence false\nuser root\nlog_dest stdout\n"
                                            "log_type all\n");
        broker = std::make_unique<ChildProcess>(
            // Line-buffered: its log is read while it runs.
            "exec stdbuf -oL mosquitto -c " + quoted((dir / "broker.conf").string()),
            dir / "broker.log");
        EXPECT_TRUE(wait_until(
            [&] { return read_text(dir / "receivers.log").find("ready") != std::string::npos; },
            20))
            << read_text(dir / "receivers.log");
        EXPECT_TRUE(wait_until(
            [&] { return read_text(dir / "broker.log").find("running") != std::string::npos; }, 10))
            << read_text(dir / "broker.log");
        subscriber = std::make_unique<ChildProcess>(
            "exec mosquitto_sub -h 127.0.0.1 -p " + std::to_string(mqtt) +
                " -u watcher -P w -i watcher -q 1 -v -t 'site7/#'",
            dir / "subscribed.txt");
        EXPECT_TRUE(wait_until(
            [&] {
                return read_text(dir / "broker.log").find("Received SUBSCRIBE from watcher") !=
                       std::string::npos;
            },
            10))
            << read_text(dir / "broker.log");
    }

    // The JSON files of `kind` ("mail", "hook") received so far.
    std::vector<json> received(const std::string& kind) const {
        std::vector<std::pair<int, json>> found;
        for (const auto& f : fs::directory_iterator(dir / "received")) {
            const std::string name = f.path().filename().string();
            if (name.rfind(kind + "-", 0) != 0 || f.path().extension() != ".json") continue;
            found.emplace_back(std::stoi(name.substr(kind.size() + 1)),
                               json::parse(read_text(f.path())));
        }
        std::sort(found.begin(), found.end(),
                  [](const auto& a, const auto& b) { return a.first < b.first; });
        std::vector<json> out;
        for (auto& [n, j] : found) out.push_back(std::move(j));
        return out;
    }
    std::string refused() const {
        return fs::exists(dir / "received" / "refused.txt")
                   ? read_text(dir / "received" / "refused.txt")
                   : "";
    }
    // mosquitto_sub -v: "topic payload" per line.
    std::vector<std::pair<std::string, json>> published() const {
        std::vector<std::pair<std::string, json>> out;
        std::istringstream in(read_text(dir / "subscribed.txt"));
        for (std::string line; std::getline(in, line);) {
            const auto space = line.find(' ');
            if (space == std::string::npos) continue;
            out.emplace_back(line.substr(0, space),
                             json::parse(line.substr(space + 1), nullptr, false));
        }
        return out;
    }
};

std::string channels_toml(const Receivers& r, const fs::path& run) {
    write_text(run / "smtp-password", std::string(kSmtpPassword) + "\n");
    write_text(run / "hook-token", std::string(kToken) + "\n");
    write_text(run / "mqtt-password", kMqttPassword);
    return "\n[notify]\nenabled = true\nretry_initial = \"1s\"\nretry_max = \"2s\"\n"
           "dashboard_url = \"http://bridge-7.site:8080/\"\n"
           "[[notify.channel]]\nname = \"office\"\nkind = \"email\"\nurl = \"smtp://localhost:" +
           std::to_string(r.smtp) +
           "\"\nfrom = \"tlsmon@bridge.example\"\nto = [\"engineer@bridge.example\"]\n"
           "username = \"tlsmon\"\npassword_file = \"smtp-password\"\nca_file = " +
           "\"" + (r.dir / "cert.pem").string() + "\"" +
           "\n[[notify.channel]]\nname = \"scada-gateway\"\nkind = \"webhook\"\n"
           "url = \"http://127.0.0.1:" +
           std::to_string(r.http) +
           "/hook\"\ntoken_file = \"hook-token\"\n"
           "[[notify.channel]]\nname = \"site-broker\"\nkind = \"mqtt\"\nurl = "
           "\"mqtt://127.0.0.1:" +
           std::to_string(r.mqtt) +
           "\"\nusername = \"tlsmon\"\npassword_file = \"mqtt-password\"\ntopic = \"site7\"\n"
           "[[notify.route]]\nrules = [\"south_top_*\"]\n"
           "events = [\"raise\", \"escalate\", \"return\", \"clear\", \"ack\"]\n"
           "channels = [\"office\", \"scada-gateway\", \"site-broker\"]\n";
}

TEST(Notify, AlarmReachesMailWebhookAndMqttAndEachSendIsAnEvent) {
    TempDir tmp("notify");
    constexpr int kEpochs = 4;  // the step at epoch 2
    const Scenario s = render_scenario(tmp.path() / "scenario", kEpochs, next_midnight());
    const fs::path run = tmp.path() / "run";
    std::set<int> ports;
    const int modbus_port = another_port(ports);
    Receivers receivers(tmp.path() / "receivers", ports, 1);
    const fs::path config = write_config(s, run, modbus_port, false);
    write_text(config, read_text(config) + channels_toml(receivers, run));
    const fs::path db = run / "tlsmon.sqlite", log = run / "daemon.log";
    DaemonProcess daemon(config, log);
    for (int k = 0; k < kEpochs; ++k) {
        feed(s, k, run / "ingest");
        ASSERT_TRUE(wait_until([&] { return processed(db) == k + 1; }, 120))
            << "epoch " << k << "\n"
            << read_text(log);
    }
    const json raise = sql(db,
                           "SELECT a.id AS id, a.value AS value, a.level AS level, a.epoch_id AS "
                           "epoch FROM alarm_events a JOIN alarm_rules r ON r.id = a.rule_id "
                           "WHERE r.name = '" +
                               std::string(kStepRule) + "' AND a.kind = 'raise'");
    ASSERT_EQ(raise.size(), 1u) << "the step raised its rule once";
    const std::string level = raise.at(0).at("level");

    // The webhook: the first POST refused (503), taken on the retry a second later.
    ASSERT_TRUE(wait_until([&] { return receivers.received("hook").size() >= 1; }, 30))
        << read_text(log) << receivers.refused();
    EXPECT_EQ(receivers.refused(), "hook 503\n");
    const json hook = receivers.received("hook").at(0);
    EXPECT_EQ(hook.at("content_type"), "application/json");
    const json& doc = hook.at("body");
    EXPECT_EQ(doc.at("schema"), "tlsmon-notification/1");
    EXPECT_EQ(doc.at("type"), "alarm");
    EXPECT_EQ(doc.at("station"), sql(db, "SELECT name FROM stations").at(0).at("name"));
    EXPECT_EQ(doc.at("event_id"), raise.at(0).at("id"));
    EXPECT_EQ(doc.at("rule"), kStepRule);
    EXPECT_EQ(doc.at("zone"), kStepZone);
    EXPECT_EQ(doc.at("event"), "raise");
    EXPECT_EQ(doc.at("level"), level);
    EXPECT_EQ(doc.at("value").get<double>(), raise.at(0).at("value").get<double>());
    EXPECT_EQ(doc.at("epoch"), raise.at(0).at("epoch"));
    EXPECT_EQ(doc.at("dashboard"), "http://bridge-7.site:8080/alarms");

    // The mail: over STARTTLS, after the login, with the raise in its subject and text.
    ASSERT_TRUE(wait_until([&] { return receivers.received("mail").size() >= 1; }, 30))
        << read_text(log);
    const json mail = receivers.received("mail").at(0);
    EXPECT_TRUE(mail.at("tls").get<bool>());
    EXPECT_EQ(mail.at("login"), "tlsmon");
    EXPECT_EQ(mail.at("from"), "tlsmon@bridge.example");
    EXPECT_EQ(mail.at("to"), json::array({"engineer@bridge.example"}));
    const std::string text = mail.at("data");
    EXPECT_NE(text.find("Subject: [tlsmon "), std::string::npos) << text;
    EXPECT_NE(text.find(" raise: " + std::string(kStepRule)), std::string::npos) << text;
    EXPECT_NE(text.find("Zone: " + std::string(kStepZone) + "\r\n"), std::string::npos) << text;
    EXPECT_NE(text.find("Content-Type: text/plain; charset=UTF-8"), std::string::npos);

    // MQTT: the same document on site7/alarm/<rule>.
    ASSERT_TRUE(wait_until([&] { return !receivers.published().empty(); }, 30))
        << read_text(receivers.dir / "broker.log");
    const auto [topic, payload] = receivers.published().at(0);
    EXPECT_EQ(topic, "site7/alarm/" + std::string(kStepRule));
    EXPECT_EQ(payload, doc);

    // An operator acknowledges on the command line: the acknowledgement goes out naming them.
    const auto ack = shell(std::string(TLSMON_BINARY) + " alarms ack " + kStepRule + " --config " +
                           quoted(config.string()));
    ASSERT_EQ(ack.status, 0) << ack.output;
    ASSERT_TRUE(wait_until([&] { return receivers.received("hook").size() >= 2; }, 30))
        << read_text(log);
    const json acked = receivers.received("hook").at(1).at("body");
    EXPECT_EQ(acked.at("event"), "ack");
    EXPECT_EQ(acked.at("level"), level) << "an ack carries its alarm's level";
    EXPECT_EQ(acked.at("actor"),
              sql(db, "SELECT actor FROM alarm_events WHERE kind = 'ack'").at(0).at("actor"));
    ASSERT_TRUE(wait_until([&] { return receivers.received("mail").size() >= 2; }, 30));
    EXPECT_NE(receivers.received("mail").at(1).at("data").get<std::string>().find("By: CLI"),
              std::string::npos);
    ASSERT_TRUE(wait_until([&] { return receivers.published().size() >= 2; }, 30));

    // The outbox and the events: six sent, one refused attempt, nothing else.
    const json rows = sql(db, "SELECT channel, status, attempts FROM notifications ORDER BY id");
    ASSERT_EQ(rows.size(), 6u) << rows.dump();
    int attempts = 0;
    for (const auto& r : rows) {
        EXPECT_EQ(r.at("status"), "sent") << r.dump();
        attempts += r.at("attempts").get<int>();
    }
    EXPECT_EQ(attempts, 7);
    EXPECT_EQ(
        sql(db, "SELECT count(*) AS n FROM system_events WHERE kind = 'notify_sent'").at(0).at("n"),
        6);
    const json failed = sql(db, "SELECT message FROM system_events WHERE kind = 'notify_failed'");
    ASSERT_EQ(failed.size(), 1u);
    EXPECT_NE(failed.at(0).at("message").get<std::string>().find(
                  "to channel 'scada-gateway': attempt 1 failed (POST to http://127.0.0.1:" +
                  std::to_string(receivers.http) + "/hook: HTTP 503 (busy, try later))"),
              std::string::npos)
        << failed.dump();
    daemon.signal(SIGTERM);
    EXPECT_EQ(daemon.wait(60), 0) << read_text(log);
}

TEST(Notify, EachRefusedSendSaysWhy) {
    TempDir tmp("notify-refused");
    std::set<int> ports;
    Receivers receivers(tmp.path(), ports, 0);
    write_text(tmp.path() / "wrong", "not-the-password\n");
    Notification n;
    n.id = 1;
    n.subject = "[tlsmon t] test";
    n.body = R"({"schema":"tlsmon-notification/1","type":"alarm","station":"t","event_id":1,)"
             R"("time":"2026-11-29T12:00:00Z","rule":"r","zone":"z","quantity":"q",)"
             R"("event":"raise","level":"alarm","value":null,"unit":"","epoch":null,)"
             R"("actor":"rule","message":"","dashboard":null})";
    const auto error_of = [&](const NotifyChannel& c) -> std::string {
        try {
            make_channel(c, "t")(n);
        } catch (const Error& e) {
            return e.what();
        }
        return "(sent)";
    };
    NotifyChannel mail;
    mail.name = "m";
    mail.kind = ChannelKind::email;
    mail.url = "smtp://localhost:" + std::to_string(receivers.smtp);
    mail.from = "a@b";
    mail.to = {"c@d"};
    mail.username = "tlsmon";
    mail.password_file = tmp.path() / "wrong";
    mail.ca_file = tmp.path() / "cert.pem";
    EXPECT_NE(error_of(mail).find("Login denied"), std::string::npos) << error_of(mail);
    mail.password_file = tmp.path() / "missing";
    EXPECT_NE(error_of(mail).find("cannot read the secret file"), std::string::npos);
    // Without the certificate's issuer the server is not trusted.
    mail.ca_file.clear();
    write_text(tmp.path() / "right", std::string(kSmtpPassword));
    mail.password_file = tmp.path() / "right";
    EXPECT_NE(error_of(mail).find("certificate"), std::string::npos) << error_of(mail);
    mail.ca_file = tmp.path() / "cert.pem";
    EXPECT_EQ(error_of(mail), "(sent)");

    NotifyChannel hook;
    hook.name = "h";
    hook.kind = ChannelKind::webhook;
    hook.url = "http://127.0.0.1:" + std::to_string(receivers.http) + "/hook";
    hook.token_file = tmp.path() / "wrong";
    EXPECT_NE(error_of(hook).find("HTTP 401"), std::string::npos) << error_of(hook);
    hook.url = "http://127.0.0.1:" + std::to_string(another_port(ports)) + "/hook";
    EXPECT_NE(error_of(hook).find("Couldn't connect to server"), std::string::npos)
        << error_of(hook);

    NotifyChannel mqtt;
    mqtt.name = "q";
    mqtt.kind = ChannelKind::mqtt;
    mqtt.url = "mqtt://127.0.0.1:" + std::to_string(receivers.mqtt);
    mqtt.username = "tlsmon";
    mqtt.password_file = tmp.path() / "wrong";
    EXPECT_NE(error_of(mqtt).find("refused the connection"), std::string::npos) << error_of(mqtt);
    mqtt.url = "mqtt://127.0.0.1:" + std::to_string(another_port(ports));
    EXPECT_NE(error_of(mqtt).find("MQTT connect to"), std::string::npos) << error_of(mqtt);
}

}  // namespace
}  // namespace tlsmon::test::e2e
