#include "storage/window_extract.hpp"

#include <SQLiteCpp/SQLiteCpp.h>

#include <string>
#include <vector>

#include "storage/database_backup.hpp"
#include "storage/state_epochs.hpp"
#include "storage/storage_error.hpp"

namespace tlsmon {

namespace fs = std::filesystem;

namespace {

std::string quoted(const std::string& name) {
    return "\"" + name + "\"";
}

void reduce(SQLite::Database& db, const TimeRange& window) {
    db.exec("PRAGMA foreign_keys = OFF");  // children and parents go in one transaction
    SQLite::Transaction tx(db);
    db.exec("CREATE TEMP TABLE kept_epochs (id INTEGER PRIMARY KEY)");
    SQLite::Statement in_window(
        db,
        "INSERT OR IGNORE INTO kept_epochs SELECT id FROM epochs WHERE acquired BETWEEN ? AND ?");
    in_window.bind(1, static_cast<std::int64_t>(window.lower()));
    in_window.bind(2, static_cast<std::int64_t>(window.upper()));
    in_window.exec();
    // The epochs the current state names, wherever they lie in time.
    db.exec("INSERT OR IGNORE INTO kept_epochs " + epochs_named_by_state(db));
    db.exec("CREATE TEMP TABLE kept_campaigns (id INTEGER PRIMARY KEY)");
    SQLite::Statement campaigns(
        db, "INSERT INTO kept_campaigns SELECT id FROM campaigns WHERE acquired BETWEEN ? AND ?");
    campaigns.bind(1, static_cast<std::int64_t>(window.lower()));
    campaigns.bind(2, static_cast<std::int64_t>(window.upper()));
    campaigns.exec();

    // Events of the window; the notifications of its alarm events.
    for (const char* t : {"system_events", "alarm_events"}) {
        SQLite::Statement events(
            db, std::string("DELETE FROM ") + t + " WHERE time NOT BETWEEN ? AND ?");
        events.bind(1, static_cast<std::int64_t>(window.lower()));
        events.bind(2, static_cast<std::int64_t>(window.upper()));
        events.exec();
    }
    db.exec(
        "DELETE FROM notifications WHERE alarm_event_id IS NOT NULL AND alarm_event_id NOT IN"
        " (SELECT id FROM alarm_events)");
    // Every row tied to an epoch or a campaign that is not kept.
    for (const auto& t : tables_with_column(db, "epoch_id")) {
        db.exec("DELETE FROM " + quoted(t) +
                " WHERE epoch_id IS NOT NULL AND epoch_id NOT IN (SELECT id FROM kept_epochs)");
    }
    for (const auto& t : tables_with_column(db, "campaign_id")) {
        db.exec("DELETE FROM " + quoted(t) +
                " WHERE campaign_id NOT IN (SELECT id FROM kept_campaigns)");
    }
    db.exec("DELETE FROM campaigns WHERE id NOT IN (SELECT id FROM kept_campaigns)");
    db.exec("DELETE FROM epochs WHERE id NOT IN (SELECT id FROM kept_epochs)");
    db.exec(
        "DELETE FROM reference_cache WHERE reference_sha256 NOT IN (SELECT sha256 FROM epochs)");
    tx.commit();
    db.exec("PRAGMA foreign_keys = ON");
    SQLite::Statement check(db, "PRAGMA foreign_key_check");
    if (check.executeStep()) {
        throw StorageError("rows of " + check.getColumn(0).getString() + " refer to a row of " +
                           check.getColumn(2).getString() +
                           " outside the window (a table the extract does not know)");
    }
    db.exec("VACUUM");
}

}  // namespace

WindowExtract extract_window(const fs::path& source, const fs::path& destination,
                             const TimeRange& window) {
    const DatabaseBackup copy = backup_database(source, destination);
    try {
        SQLite::Database db(destination.string(), SQLite::OPEN_READWRITE, 5000);
        reduce(db, window);
        WindowExtract e;
        e.path = destination;
        e.schema_version = copy.schema_version;
        e.epochs = db.execAndGet("SELECT count(*) FROM epochs").getInt64();
        e.campaigns = db.execAndGet("SELECT count(*) FROM campaigns").getInt64();
        e.bytes = static_cast<std::int64_t>(fs::file_size(destination));
        return e;
    } catch (const SQLite::Exception& ex) {
        std::error_code ec;
        fs::remove(destination, ec);
        throw StorageError(destination.string() + ": reducing to the window: " + ex.what(),
                           ex.getErrorCode(), ex.getExtendedErrorCode());
    } catch (const StorageError& ex) {
        std::error_code ec;
        fs::remove(destination, ec);
        throw StorageError(destination.string() + ": reducing to the window: " + ex.what(),
                           ex.sqlite_code(), ex.extended_code());
    }
}

}  // namespace tlsmon
