// The numbered migrations of schema/, applied in order, and the schema version checks.
#include "storage/migrations.hpp"

#include "storage/schema_migrations.hpp"

namespace tlsmon {

int applied_version(Connection& c) {
    return guarded(c, "reading schema_migrations", [&] {
        if (!c.db.tableExists("schema_migrations")) return 0;
        return c.db.execAndGet("SELECT coalesce(max(version), 0) FROM schema_migrations").getInt();
    });
}

void check_not_newer(Connection& c, int version) {
    const int latest = EpochDatabase::latest_schema_version();
    if (version > latest) {
        throw_storage(c, "database schema version " + std::to_string(version) +
                             " is newer than this tlsmon knows (" + std::to_string(latest) +
                             "); use the tlsmon that wrote it or a newer one");
    }
}

// Each migration in its own IMMEDIATE transaction, re-checking the version under the write
// lock so two processes starting at once do not apply a migration twice.
// Nothing is written (no write lock taken) when the file is already up to date, so a
// restart does not wait for another writer.
void migrate(Connection& c, int applied) {
    if (applied >= EpochDatabase::latest_schema_version()) return;
    guarded(c, "creating schema_migrations", [&] {
        c.db.exec(
            "CREATE TABLE IF NOT EXISTS schema_migrations ("
            " version INTEGER PRIMARY KEY, name TEXT NOT NULL, applied INTEGER NOT NULL)");
    });
    for (const auto& m : schema_migrations()) {
        if (m.version <= applied) continue;
        const std::string context = std::string("applying migration ") + m.name;
        guarded(c, context.c_str(), [&] {
            SQLite::Transaction tx(c.db, SQLite::TransactionBehavior::IMMEDIATE);
            SQLite::Statement done(c.db, "SELECT 1 FROM schema_migrations WHERE version = ?");
            done.bind(1, m.version);
            if (done.executeStep()) return;
            c.db.exec(m.sql);
            SQLite::Statement record(
                c.db, "INSERT INTO schema_migrations (version, name, applied) VALUES (?,?,?)");
            record.bind(1, m.version);
            record.bind(2, m.name);
            record.bind(3, static_cast<std::int64_t>(now_utc()));
            record.exec();
            tx.commit();
        });
    }
}

}  // namespace tlsmon
