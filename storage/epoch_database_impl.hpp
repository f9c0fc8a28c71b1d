#pragma once
// Private to storage/: the connection behind EpochDatabase and the helpers its files share.
#include <SQLiteCpp/SQLiteCpp.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>

#include "storage/epoch_database.hpp"

namespace tlsmon {

struct EpochDatabase::Impl {
    Impl(std::filesystem::path p, Mode m, SQLite::Database d)
        : path(std::move(p)), mode(m), db(std::move(d)) {}
    std::filesystem::path path;
    Mode mode;
    SQLite::Database db;
    int version = 0;
};

// Runs `f`, turning an SQLite failure into a StorageError that names the database file and
// what was being done (the SQL context), with SQLite's result codes kept.
template <class F>
auto guarded(const EpochDatabase::Impl& impl, const char* context, F&& f) {
    try {
        return f();
    } catch (const SQLite::Exception& e) {
        throw StorageError(impl.path.string() + ": " + context + ": " + e.what(), e.getErrorCode(),
                           e.getExtendedErrorCode());
    }
}

[[noreturn]] void throw_storage(const EpochDatabase::Impl& impl, const std::string& what);

inline void bind_optional(SQLite::Statement& s, int index, const std::optional<double>& v) {
    if (v) {
        s.bind(index, *v);
    } else {
        s.bind(index);
    }
}
inline void bind_optional(SQLite::Statement& s, int index, const std::optional<std::int64_t>& v) {
    if (v) {
        s.bind(index, *v);
    } else {
        s.bind(index);
    }
}
inline void bind_optional(SQLite::Statement& s, int index, const std::optional<std::string>& v) {
    if (v) {
        s.bind(index, *v);
    } else {
        s.bind(index);
    }
}
inline std::optional<double> optional_double(const SQLite::Column& c) {
    return c.isNull() ? std::nullopt : std::optional<double>(c.getDouble());
}
inline std::optional<std::int64_t> optional_int64(const SQLite::Column& c) {
    return c.isNull() ? std::nullopt : std::optional<std::int64_t>(c.getInt64());
}
inline std::optional<std::string> optional_string(const SQLite::Column& c) {
    return c.isNull() ? std::nullopt : std::optional<std::string>(c.getString());
}

// Lookups by name; an unknown name is a StorageError naming it.
ZoneId zone_id_by_name(EpochDatabase::Impl& impl, const std::string& zone);
AlarmRuleId rule_id_by_name(EpochDatabase::Impl& impl, const std::string& rule);
// Single-row writes shared by commit_epoch and the stand-alone calls (no transaction here).
void write_alarm_state(EpochDatabase::Impl& impl, const AlarmState& state);
void write_alarm_event(EpochDatabase::Impl& impl, const AlarmEvent& event);
void write_system_event(EpochDatabase::Impl& impl, const SystemEvent& event);

// The columns of an epoch row in the order read_epoch expects.
extern const char* const kEpochColumns;
Epoch read_epoch(SQLite::Statement& s);

}  // namespace tlsmon
