// `tlsmon backup DEST`: a consistent copy of the epoch database, taken while the daemon runs
// (storage/database_backup.hpp, docs/backup.md).
#include <chrono>
#include <iostream>

#include "cli/commands.hpp"
#include "storage/database_backup.hpp"

namespace tlsmon {

int run_backup(const BackupOptions& o) {
    return run_reporting_errors("backup", [&] {
        const auto source = database_path(o.read);
        const auto destination = backup_destination(source, o.destination);
        const auto start = std::chrono::steady_clock::now();
        const DatabaseBackup b = backup_database(source, destination);
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        print_fields(std::cout,
                     {{"backup", b.path.string()},
                      {"source", source.string()},
                      {"schema_version", static_cast<std::int64_t>(b.schema_version)},
                      {"epochs", b.epochs},
                      {"bytes", b.bytes},
                      {"seconds", seconds},
                      {"quick_check", std::string("ok")}},
                     o.read.format);
    });
}

}  // namespace tlsmon
