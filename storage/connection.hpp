#pragma once
// Private to storage/: the one SQLite connection behind an EpochDatabase and the helpers the
// stores share. Nothing outside storage/ includes this (only storage/ knows SQL).
#include <SQLiteCpp/SQLiteCpp.h>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>

#include "storage/epoch_database.hpp"

namespace tlsmon {

struct Connection {
    Connection(std::filesystem::path p, EpochDatabase::Mode m, SQLite::Database d)
        : path(std::move(p)), mode(m), db(std::move(d)) {}
    std::filesystem::path path;
    EpochDatabase::Mode mode;
    SQLite::Database db;
    int version = 0;  // schema version, read at open
};

// Runs `f`, turning an SQLite failure into a StorageError that names the database file and
// what was being done (the SQL context), with SQLite's result codes kept.
template <class F>
auto guarded(const Connection& c, const char* context, F&& f) {
    try {
        return f();
    } catch (const SQLite::Exception& e) {
        throw StorageError(c.path.string() + ": " + context + ": " + e.what(), e.getErrorCode(),
                           e.getExtendedErrorCode());
    }
}

[[noreturn]] void throw_storage(const Connection& c, const std::string& what);

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

}  // namespace tlsmon
