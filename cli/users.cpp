// `tlsmon users add|remove|list`: the dashboard's users file (daemon/http/users.hpp), named
// by --file or by the configuration's http.users_file. The password is read from the
// terminal without echo, or from standard input with --password-stdin (for scripts).
#include "daemon/http/users.hpp"

#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <iostream>

#include "cli/commands.hpp"
#include "config/config.hpp"
#include "core/error.hpp"

namespace tlsmon {

namespace {

std::filesystem::path users_file(const UsersOptions& o) {
    if (!o.file.empty()) return o.file;
    if (o.config.empty()) throw Error("name the users file: --file FILE or --config SITE.toml");
    const Config c = load_config(o.config);
    if (c.http.users_file.empty())
        throw Error(o.config + " sets no http.users_file: set it, or give --file FILE");
    return c.http.users_file;
}

std::string read_password(bool from_stdin) {
    std::string password;
    if (from_stdin || !::isatty(STDIN_FILENO)) {
        std::getline(std::cin, password);
        return password;
    }
    termios saved{};
    ::tcgetattr(STDIN_FILENO, &saved);
    termios quiet = saved;
    quiet.c_lflag &= ~static_cast<tcflag_t>(ECHO);
    const auto ask = [&](const char* prompt) {
        std::cerr << prompt << std::flush;
        ::tcsetattr(STDIN_FILENO, TCSANOW, &quiet);
        std::string line;
        std::getline(std::cin, line);
        ::tcsetattr(STDIN_FILENO, TCSANOW, &saved);
        std::cerr << '\n';
        return line;
    };
    password = ask("password: ");
    if (ask("again: ") != password) throw Error("the two passwords differ; nothing changed");
    return password;
}

}  // namespace

int run_users(const UsersOptions& o) {
    try {
        const auto file = users_file(o);
        auto users = read_users(file);
        const auto named = std::find_if(users.begin(), users.end(),
                                        [&](const UserEntry& u) { return u.name == o.name; });
        if (o.action == "list") {
            for (const auto& u : users) std::cout << u.name << '\t' << to_string(u.role) << '\n';
            return 0;
        }
        if (o.action == "remove") {
            if (named == users.end()) throw Error("no user '" + o.name + "' in " + file.string());
            users.erase(named);
            write_users(file, users);
            std::cout << "removed " << o.name << " from " << file.string()
                      << " (a session open now lasts until it expires or the daemon restarts)\n";
            return 0;
        }
        const auto role = user_role_from_string(o.role);
        if (!role) throw Error("--role must be viewer, operator or admin, not '" + o.role + "'");
        const UserEntry entry = make_user(o.name, *role, read_password(o.password_stdin));
        const bool is_new = named == users.end();
        if (is_new) {
            users.push_back(entry);
        } else {
            *named = entry;  // a new password or role
        }
        write_users(file, users);
        std::cout << (is_new ? "added " : "changed ") << o.name << " (" << to_string(*role)
                  << ") in " << file.string() << '\n';
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "tlsmon users: " << e.what() << '\n';
        return 1;
    }
}

}  // namespace tlsmon
