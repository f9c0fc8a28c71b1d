#include "storage/state_epochs.hpp"

namespace tlsmon {

std::vector<std::string> tables_with_column(SQLite::Database& db, const std::string& column) {
    SQLite::Statement s(db,
                        "SELECT m.name FROM sqlite_master m, pragma_table_info(m.name) p"
                        " WHERE m.type = 'table' AND p.name = ? ORDER BY m.name");
    s.bind(1, column);
    std::vector<std::string> out;
    while (s.executeStep()) out.push_back(s.getColumn(0).getString());
    return out;
}

std::string epochs_named_by_state(SQLite::Database& db) {
    std::string sql = "SELECT epoch_id FROM reference_epoch";
    for (const auto& t : tables_with_column(db, "reference_epoch_id")) {
        sql += " UNION SELECT reference_epoch_id FROM \"" + t +
               "\" WHERE reference_epoch_id IS NOT NULL";
    }
    for (const char* t : {"alarm_states", "target_exclusions"}) {
        sql += std::string(" UNION SELECT epoch_id FROM ") + t + " WHERE epoch_id IS NOT NULL";
    }
    return sql;
}

std::string protected_epochs(SQLite::Database& db) {
    return epochs_named_by_state(db) +
           " UNION SELECT epoch_id FROM alarm_events WHERE epoch_id IS NOT NULL"
           " UNION SELECT epoch_id FROM epoch_pins";
}

}  // namespace tlsmon
