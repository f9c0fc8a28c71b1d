#include "central/central_schema.hpp"

#include <string>

namespace tlsmon {

int central_schema_version(PgConnection& c) {
    const auto r = c.exec(
        "SELECT CASE WHEN to_regclass('tlsmon.schema_migrations') IS NULL THEN 0"
        " ELSE (SELECT coalesce(max(version), 0) FROM tlsmon.schema_migrations) END");
    return std::stoi(*r.rows.at(0).at(0));
}

std::vector<int> migrate_central(PgConnection& c) {
    std::vector<int> applied;
    for (const auto& m : central_migrations()) {
        PgTransaction tx(c);
        c.exec("SELECT pg_advisory_xact_lock(hashtext('tlsmon.migrate'))");
        c.exec("CREATE SCHEMA IF NOT EXISTS tlsmon");
        c.exec(
            "CREATE TABLE IF NOT EXISTS tlsmon.schema_migrations (version integer PRIMARY KEY,"
            " name text NOT NULL, applied timestamptz NOT NULL DEFAULT now())");
        const auto done = c.exec("SELECT 1 FROM tlsmon.schema_migrations WHERE version = $1",
                                 {std::to_string(m.version)});
        if (!done.rows.empty()) continue;
        try {
            c.exec_script(m.sql);
        } catch (const CentralError& e) {
            throw CentralError(std::string("central migration ") + m.name + ": " + e.what(),
                               e.sqlstate());
        }
        c.exec("INSERT INTO tlsmon.schema_migrations (version, name) VALUES ($1, $2)",
               {std::to_string(m.version), std::string(m.name)});
        tx.commit();
        applied.push_back(m.version);
    }
    return applied;
}

}  // namespace tlsmon
