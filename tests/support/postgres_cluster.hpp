#pragma once
// A throw-away PostgreSQL 15 cluster for the central database's tests: initdb into a scratch
// folder, the server on a free port of 127.0.0.1 (password logins by SCRAM over TCP, trust on
// its own Unix socket for the test's psql), stopped and removed with the object. As root the
// server runs as the `postgres` user (initdb refuses root), which the Debian package creates.
// With `tls`, the server also speaks TLS with a certificate for localhost and 127.0.0.1
// signed by a test CA (ca_certificate()); other_ca_certificate() signed nothing of it.
#include <stdexcept>
#include <string>

#include "tests/support/daemon_harness.hpp"
#include "tests/support/modbus_client.hpp"
#include "tests/support/text_file.hpp"

namespace tlsmon::test {

inline const std::string kPostgresBin = "/usr/lib/postgresql/15/bin/";

class PostgresCluster {
  public:
    explicit PostgresCluster(bool tls = false) : dir_("pg"), port_(free_tcp_port()) {
        const fs::path data = dir_ / "data";
        fs::create_directories(data);
        write_text(dir_ / "admin.pw", "admin-secret\n");
        if (tls) make_certificates();
        if (::geteuid() == 0) {
            as_ = "runuser -u postgres -- ";
            shell("chown -R postgres " + dir_.path().string());
        }
        run(as_ + kPostgresBin + "initdb -D " + data.string() +
            " -U postgres --auth-local=trust --auth-host=scram-sha-256 --pwfile=" +
            (dir_ / "admin.pw").string() + " -E UTF8 --no-sync");
        start();
        psql("CREATE DATABASE tlsmon", "postgres");
    }
    ~PostgresCluster() {
        shell(as_ + kPostgresBin + "pg_ctl -D " + (dir_ / "data").string() + " -m immediate stop");
    }
    PostgresCluster(const PostgresCluster&) = delete;
    PostgresCluster& operator=(const PostgresCluster&) = delete;

    void start() {
        run(as_ + kPostgresBin + "pg_ctl -D " + (dir_ / "data").string() + " -l " +
            (dir_ / "server.log").string() + " -w -o \"-p " + std::to_string(port_) +
            " -c listen_addresses=127.0.0.1 -c unix_socket_directories=" + dir_.path().string() +
            " -c fsync=off -c max_connections=40" + tls_options_ + "\" start");
    }
    // `fast`: sessions are ended, the server shuts down cleanly (a maintenance stop).
    void stop() {
        run(as_ + kPostgresBin + "pg_ctl -D " + (dir_ / "data").string() + " -m fast -w stop");
    }

    int port() const { return port_; }
    // libpq URI of `user` over TCP (the password comes from a file).
    std::string url(const std::string& user, const std::string& db = "tlsmon") const {
        return "postgresql://" + user + "@127.0.0.1:" + std::to_string(port_) + "/" + db;
    }
    fs::path admin_password_file() const { return dir_ / "admin.pw"; }
    fs::path ca_certificate() const { return dir_ / "ca.crt"; }
    fs::path other_ca_certificate() const { return dir_ / "other-ca.crt"; }
    fs::path folder() const { return dir_.path(); }

    // `sql` through psql as the superuser on the Unix socket: rows as lines, fields by '|'.
    // Throws with psql's message when it fails.
    std::string psql(const std::string& sql, const std::string& db = "tlsmon") const {
        const auto r =
            shell("psql -X -q -At -v ON_ERROR_STOP=1 -h " + dir_.path().string() + " -p " +
                  std::to_string(port_) + " -U postgres -d " + db + " -c " + shell_quoted(sql));
        if (r.status != 0) throw std::runtime_error("psql: " + r.output + "\nfor: " + sql);
        return r.output;
    }
    // The same as `user` over TCP with `password_file`; returns status and output (a refusal
    // is what some tests expect).
    CommandResult psql_as(const std::string& user, const fs::path& password_file,
                          const std::string& sql) const {
        return shell("PGPASSWORD=\"$(cat " + password_file.string() + ")\" psql -X -q -At -v " +
                     "ON_ERROR_STOP=1 " + shell_quoted(url(user)) + " -c " + shell_quoted(sql));
    }

    static std::string shell_quoted(const std::string& s) {
        std::string out = "'";
        for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
        return out + "'";
    }

  private:
    void make_certificates() {
        const std::string d = dir_.path().string();
        write_text(dir_ / "san.ext", "subjectAltName=DNS:localhost,IP:127.0.0.1\n");
        run("cd " + d +
            " && openssl req -x509 -newkey rsa:2048 -nodes -keyout ca.key -out ca.crt -days 2"
            " -subj /CN=tlsmon-test-ca 2>&1"
            " && openssl req -x509 -newkey rsa:2048 -nodes -keyout other-ca.key -out"
            " other-ca.crt -days 2 -subj /CN=tlsmon-other-ca 2>&1"
            " && openssl req -newkey rsa:2048 -nodes -keyout server.key -out server.csr"
            " -subj /CN=localhost 2>&1"
            " && openssl x509 -req -in server.csr -CA ca.crt -CAkey ca.key -CAcreateserial"
            " -out server.crt -days 2 -extfile san.ext 2>&1 && chmod 600 server.key");
        tls_options_ =
            " -c ssl=on -c ssl_cert_file=" + d + "/server.crt -c ssl_key_file=" + d + "/server.key";
    }

    void run(const std::string& command) const {
        const auto r = shell(command);
        if (r.status != 0) throw std::runtime_error(command + ": " + r.output);
    }

    TempDir dir_;
    int port_;
    std::string as_;
    std::string tls_options_;
};

}  // namespace tlsmon::test
