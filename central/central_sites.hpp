#pragma once
// Sites of the central database (docs/central.md): each has a login role of its own, a member
// of tlsmon_site, whose row-level security admits only its own rows. Run as the database's
// owner (`tlsmon central add-site|rotate-credential`).
#include <string>

#include "central/pg_connection.hpp"

namespace tlsmon {

// The role of site `name`: "tlsmon_site_<name>".
std::string site_role(const std::string& name);

// Registers a site and creates its role with `password` (hashed by libpq before it is sent).
void add_site(PgConnection& c, const std::string& name, const std::string& location,
              const std::string& password);
// Replaces a site's password; its sessions already open keep running.
void rotate_site_credential(PgConnection& c, const std::string& name, const std::string& password);

}  // namespace tlsmon
