#include "central/central_sites.hpp"

namespace tlsmon {

std::string site_role(const std::string& name) {
    return "tlsmon_site_" + name;
}

void add_site(PgConnection& c, const std::string& name, const std::string& location,
              const std::string& password) {
    const std::string role = site_role(name);
    PgTransaction tx(c);
    // The row first: the table's CHECK refuses a bad name before any role exists.
    c.exec("INSERT INTO tlsmon.sites (name, location, role_name) VALUES ($1, $2, $3)",
           {name, location, role});
    c.exec_script("CREATE ROLE " + quote_identifier(role) + " LOGIN IN ROLE tlsmon_site PASSWORD " +
                  quote_literal(c.encrypted_password(role, password)));
    tx.commit();
}

void rotate_site_credential(PgConnection& c, const std::string& name, const std::string& password) {
    const auto known = c.exec("SELECT role_name FROM tlsmon.sites WHERE name = $1", {name});
    if (known.rows.empty()) throw CentralError("no site '" + name + "' in the central database");
    const std::string role = *known.rows[0][0];
    c.exec_script("ALTER ROLE " + quote_identifier(role) + " PASSWORD " +
                  quote_literal(c.encrypted_password(role, password)));
}

}  // namespace tlsmon
