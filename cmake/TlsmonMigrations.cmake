# tlsmon_embed_migrations(target folder function): the numbered migrations folder/NNNN_name.sql
# compiled into `target` as raw strings, returned in order by
# `std::span<const SchemaMigration> function()` (storage/schema_migrations.hpp), so the
# installed binary needs no schema folder. Editing a .sql file re-runs configure.
function(tlsmon_embed_migrations target folder function)
  file(GLOB _migrations CONFIGURE_DEPENDS ${folder}/*.sql)
  list(SORT _migrations)
  set(_entries "")
  set(_seen "")
  foreach(_sql IN LISTS _migrations)
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${_sql})
    get_filename_component(_name ${_sql} NAME_WE)
    if(NOT _name MATCHES "^([0-9]+)_")
      message(FATAL_ERROR "${_sql}: a migration is named NNNN_what.sql")
    endif()
    math(EXPR _version "${CMAKE_MATCH_1}")
    if(_version IN_LIST _seen)
      message(FATAL_ERROR "${_sql}: migration ${_version} exists twice")
    endif()
    list(APPEND _seen ${_version})
    file(READ ${_sql} _text)
    string(APPEND _entries "    {${_version}, \"${_name}\", R\"tlsmon_sql(${_text})tlsmon_sql\"},\n")
  endforeach()
  set(_out ${CMAKE_CURRENT_BINARY_DIR}/${function}_data.cpp)
  file(CONFIGURE OUTPUT ${_out} CONTENT
"// Generated from ${folder}/*.sql by cmake/TlsmonMigrations.cmake; do not edit.
#include \"storage/schema_migrations.hpp\"

namespace tlsmon {

namespace {
const SchemaMigration kMigrations[] = {
@_entries@};
}  // namespace

std::span<const SchemaMigration> ${function}() { return kMigrations; }

}  // namespace tlsmon
" @ONLY)
  target_sources(${target} PRIVATE ${_out})
endfunction()
