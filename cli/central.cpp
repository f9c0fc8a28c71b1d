// `tlsmon central migrate|add-site|rotate-credential URL` (docs/central.md): the central
// database's numbered migrations, and its sites with their roles, done as its owner.
#include <iostream>

#include "central/central_schema.hpp"
#include "central/central_sites.hpp"
#include "cli/commands.hpp"

namespace tlsmon {

int run_central_admin(const CentralAdminOptions& o) {
    return run_reporting_errors("central " + o.action, [&] {
        PgConnection c = PgConnection::open(
            command_target(o.url, o.password_file, "tlsmon central " + o.action));
        if (o.action == "migrate") {
            const auto applied = migrate_central(c);
            std::cout << c.describe() << ": schema version " << central_schema_version(c);
            std::cout << (applied.empty()
                              ? " (already up to date)\n"
                              : ", " + std::to_string(applied.size()) + " migration(s) applied\n");
            return;
        }
        const std::string password = read_password_file(o.site_password_file);
        if (o.action == "add-site") {
            add_site(c, o.name, o.location, password);
            std::cout << "site '" << o.name << "' added; it connects as role " << site_role(o.name)
                      << "\n";
        } else {
            rotate_site_credential(c, o.name, password);
            std::cout << "site '" << o.name << "': password of role " << site_role(o.name)
                      << " replaced\n";
        }
    });
}

}  // namespace tlsmon
