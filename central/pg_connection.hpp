#pragma once
// A connection to the central PostgreSQL through libpq (the only file that includes it):
// parameters bound, never spliced into SQL; every failure a CentralError with the server's
// SQLSTATE and message. Passwords come from a file or libpq's PGPASSFILE and are never part
// of a message.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/error.hpp"

struct pg_conn;

namespace tlsmon {

class CentralError : public Error {
  public:
    CentralError(const std::string& what, std::string sqlstate = "")
        : Error(what), sqlstate_(std::move(sqlstate)) {}
    // The server's SQLSTATE ("42501" insufficient privilege, "25006" read-only transaction,
    // "53100" disk full ...); "" when the connection itself failed.
    const std::string& sqlstate() const noexcept { return sqlstate_; }

  private:
    std::string sqlstate_;
};

struct CentralTarget {
    std::string url;                      // a libpq URI or key=value string, without a password
    std::filesystem::path password_file;  // "" = none (libpq's PGPASSFILE or ~/.pgpass)
    std::string sslmode;                  // "" = libpq's default or the URL's
    std::filesystem::path sslrootcert;    // "" = libpq's default
    std::string application_name = "tlsmon";
    int connect_timeout_s = 10;
    int statement_timeout_s = 120;  // a hung server fails the batch, not the forwarder
};

// The first line of a password file (trailing blanks dropped); a CentralError when it cannot
// be read or is empty.
std::string read_password_file(const std::filesystem::path& file);

// The target of a command run by hand (`tlsmon central`, `tlsmon fleet`): an Error when the
// URL holds a password, which belongs in `password_file` or PGPASSFILE.
CentralTarget command_target(const std::string& url, const std::filesystem::path& password_file,
                             const std::string& application_name);

using PgParam = std::optional<std::string>;  // nullopt = SQL NULL
using PgRow = std::vector<std::optional<std::string>>;

struct PgResult {
    std::vector<std::string> columns;
    std::vector<PgRow> rows;
    long affected = 0;  // rows an INSERT/UPDATE/DELETE changed
};

class PgConnection {
  public:
    static PgConnection open(const CentralTarget& target);
    PgConnection(PgConnection&&) noexcept;
    PgConnection& operator=(PgConnection&&) noexcept;
    ~PgConnection();

    // One statement with $1.. parameters (text format).
    PgResult exec(const std::string& sql, const std::vector<PgParam>& params = {});
    // Statements without parameters, possibly several (a migration file).
    void exec_script(const std::string& sql);
    // The connection is still usable (after a failure, the caller opens a new one if not).
    bool ok() const;
    // `password` hashed by libpq for `role` as the server stores it (SCRAM-SHA-256), so
    // CREATE/ALTER ROLE never carries it in clear text.
    std::string encrypted_password(const std::string& role, const std::string& password);
    // user@host:port/dbname, for messages.
    std::string describe() const;

  private:
    struct Deleter {
        void operator()(pg_conn* c) const;
    };
    explicit PgConnection(pg_conn* c) : conn_(c) {}
    std::unique_ptr<pg_conn, Deleter> conn_;
};

// BEGIN on construction, ROLLBACK in the destructor unless commit() ran.
class PgTransaction {
  public:
    explicit PgTransaction(PgConnection& c);
    ~PgTransaction();
    PgTransaction(const PgTransaction&) = delete;
    PgTransaction& operator=(const PgTransaction&) = delete;
    void commit();

  private:
    PgConnection* c_;
    bool done_ = false;
};

// A SQL identifier or literal quoted for the server (role names, passwords in CREATE ROLE,
// which takes no parameters).
std::string quote_identifier(const std::string& name);
std::string quote_literal(const std::string& text);

}  // namespace tlsmon
