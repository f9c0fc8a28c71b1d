#pragma once
// A database as a tlsmon that knew only migration 0001 wrote it, with one epoch.
#include <SQLiteCpp/SQLiteCpp.h>

#include <filesystem>

#include "fake_sha256.hpp"
#include "storage/schema_migrations.hpp"

namespace tlsmon::test {

// The epoch: fake_sha256(7), acquired at 100, file /ingest/a.ptx.
inline void write_schema_1_database(const std::filesystem::path& path) {
    SQLite::Database raw(path.string(), SQLite::OPEN_READWRITE | SQLite::OPEN_CREATE);
    raw.exec(
        "CREATE TABLE schema_migrations (version INTEGER PRIMARY KEY, name TEXT NOT NULL,"
        " applied INTEGER NOT NULL)");
    raw.exec(schema_migrations()[0].sql);
    raw.exec("INSERT INTO schema_migrations VALUES (1, '0001_initial', 0)");
    raw.exec(
        "INSERT INTO epochs (sha256, acquired, discovered, updated, file_path, file_size)"
        " VALUES ('" +
        fake_sha256(7) + "', 100, 100, 100, '/ingest/a.ptx', 1)");
}

}  // namespace tlsmon::test
