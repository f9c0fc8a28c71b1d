#include "central/pg_connection.hpp"

#include <libpq-fe.h>

#include <cctype>
#include <fstream>
#include <sstream>

#include "core/redacted_url.hpp"

namespace tlsmon {

std::string read_password_file(const std::filesystem::path& file) {
    std::ifstream in(file);
    if (!in) throw CentralError("central password file " + file.string() + ": cannot be read");
    std::string password;
    std::getline(in, password);
    while (!password.empty() && (password.back() == '\r' || password.back() == ' '))
        password.pop_back();
    if (password.empty())
        throw CentralError("central password file " + file.string() + " is empty");
    return password;
}

namespace {

// libpq's message on one line: its continuation lines ("\n\tIs the server running ...")
// joined with single spaces, for the log and the events.
std::string one_line(const char* message) {
    std::string out;
    bool space = false;
    for (const char* c = message ? message : ""; *c; ++c) {
        if (std::isspace(static_cast<unsigned char>(*c))) {
            space = !out.empty();
            continue;
        }
        if (space) out += ' ';
        space = false;
        out += *c;
    }
    return out;
}

// The server's message of a failed statement: its primary text, and its detail when it has
// one (not the CONTEXT lines, which name the function's own statements).
std::string server_message(const PGresult* r) {
    std::string s = one_line(PQresultErrorField(r, PG_DIAG_MESSAGE_PRIMARY));
    if (s.empty()) return one_line(PQresultErrorMessage(r));
    const char* detail = PQresultErrorField(r, PG_DIAG_MESSAGE_DETAIL);
    if (detail) s += " (" + one_line(detail) + ")";
    return s;
}

// Throws unless `r` succeeded; consumes it either way.
PgResult take(pg_conn* conn, PGresult* r, const std::string& context) {
    struct Clear {
        void operator()(PGresult* p) const { PQclear(p); }
    };
    std::unique_ptr<PGresult, Clear> owned(r);
    if (!r) throw CentralError(context + ": " + one_line(PQerrorMessage(conn)));
    const auto status = PQresultStatus(r);
    if (status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK) {
        const char* state = PQresultErrorField(r, PG_DIAG_SQLSTATE);
        throw CentralError(context + ": " + server_message(r), state ? state : "");
    }
    PgResult out;
    const int columns = PQnfields(r);
    for (int c = 0; c < columns; ++c) out.columns.emplace_back(PQfname(r, c));
    const int rows = PQntuples(r);
    out.rows.reserve(rows);
    for (int i = 0; i < rows; ++i) {
        PgRow row(columns);
        for (int c = 0; c < columns; ++c) {
            if (!PQgetisnull(r, i, c))
                row[c] = std::string(PQgetvalue(r, i, c), PQgetlength(r, i, c));
        }
        out.rows.push_back(std::move(row));
    }
    const char* affected = PQcmdTuples(r);
    out.affected = affected && *affected ? std::stol(affected) : 0;
    return out;
}

}  // namespace

CentralTarget command_target(const std::string& url, const std::filesystem::path& password_file,
                             const std::string& application_name) {
    if (url_has_password(url))
        throw CentralError("the URL " + redacted_url(url) +
                           " holds a password; give it with --password-file or PGPASSFILE");
    CentralTarget t;
    t.url = url;
    t.password_file = password_file;
    t.application_name = application_name;
    return t;
}

PgConnection PgConnection::open(const CentralTarget& t) {
    std::vector<std::string> keys{
        "dbname",     "application_name", "connect_timeout",     "options",
        "keepalives", "keepalives_idle",  "keepalives_interval", "keepalives_count"};
    std::vector<std::string> values{t.url,
                                    t.application_name,
                                    std::to_string(t.connect_timeout_s),
                                    "-c client_min_messages=warning -c statement_timeout=" +
                                        std::to_string(t.statement_timeout_s * 1000),
                                    "1",
                                    "30",
                                    "10",
                                    "3"};
    if (!t.password_file.empty()) {
        keys.emplace_back("password");
        values.push_back(read_password_file(t.password_file));
    }
    if (!t.sslmode.empty()) {
        keys.emplace_back("sslmode");
        values.push_back(t.sslmode);
    }
    if (!t.sslrootcert.empty()) {
        keys.emplace_back("sslrootcert");
        values.push_back(t.sslrootcert.string());
    }
    std::vector<const char*> k, v;
    for (std::size_t i = 0; i < keys.size(); ++i) {
        k.push_back(keys[i].c_str());
        v.push_back(values[i].c_str());
    }
    k.push_back(nullptr);
    v.push_back(nullptr);
    // expand_dbname = 1: the URL's own settings, then the ones after it override.
    pg_conn* c = PQconnectdbParams(k.data(), v.data(), 1);
    PgConnection conn(c);
    if (!c || PQstatus(c) != CONNECTION_OK) {
        throw CentralError("central database " + redacted_url(t.url) + ": " +
                           (c ? one_line(PQerrorMessage(c)) : "out of memory"));
    }
    return conn;
}

void PgConnection::Deleter::operator()(pg_conn* c) const {
    PQfinish(c);
}

PgConnection::PgConnection(PgConnection&&) noexcept = default;
PgConnection& PgConnection::operator=(PgConnection&&) noexcept = default;
PgConnection::~PgConnection() = default;

PgResult PgConnection::exec(const std::string& sql, const std::vector<PgParam>& params) {
    std::vector<const char*> values;
    values.reserve(params.size());
    for (const auto& p : params) values.push_back(p ? p->c_str() : nullptr);
    PGresult* r = PQexecParams(conn_.get(), sql.c_str(), static_cast<int>(params.size()), nullptr,
                               values.data(), nullptr, nullptr, 0);
    return take(conn_.get(), r, describe());
}

void PgConnection::exec_script(const std::string& sql) {
    take(conn_.get(), PQexec(conn_.get(), sql.c_str()), describe());
}

std::string PgConnection::encrypted_password(const std::string& role, const std::string& password) {
    char* hashed = PQencryptPasswordConn(conn_.get(), password.c_str(), role.c_str(), nullptr);
    if (!hashed) throw CentralError(describe() + ": " + one_line(PQerrorMessage(conn_.get())));
    std::string out = hashed;
    PQfreemem(hashed);
    return out;
}

bool PgConnection::ok() const {
    return conn_ && PQstatus(conn_.get()) == CONNECTION_OK;
}

std::string PgConnection::describe() const {
    if (!conn_) return "central database";
    std::ostringstream s;
    s << "central database " << PQuser(conn_.get()) << "@" << PQhost(conn_.get()) << ":"
      << PQport(conn_.get()) << "/" << PQdb(conn_.get());
    return s.str();
}

PgTransaction::PgTransaction(PgConnection& c) : c_(&c) {
    c_->exec("BEGIN");
}

PgTransaction::~PgTransaction() {
    if (done_ || !c_->ok()) return;
    try {
        c_->exec("ROLLBACK");
    } catch (const std::exception&) {
        // The connection is gone; the server rolls back on its own.
    }
}

void PgTransaction::commit() {
    c_->exec("COMMIT");
    done_ = true;
}

std::string quote_identifier(const std::string& name) {
    std::string out = "\"";
    for (char ch : name) out += ch == '"' ? std::string("\"\"") : std::string(1, ch);
    return out + "\"";
}

std::string quote_literal(const std::string& text) {
    std::string out = "'";
    for (char ch : text) out += ch == '\'' ? std::string("''") : std::string(1, ch);
    return out + "'";
}

}  // namespace tlsmon
