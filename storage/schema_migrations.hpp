#pragma once
// The numbered SQL migrations of schema/, embedded at build time (storage/CMakeLists.txt).
#include <span>

namespace tlsmon {

struct SchemaMigration {
    int version;       // NNNN of schema/NNNN_name.sql
    const char* name;  // file name without .sql
    const char* sql;   // the whole file
};

// In ascending version order.
std::span<const SchemaMigration> schema_migrations();

}  // namespace tlsmon
