#include "daemon/http/users.hpp"

#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/rand.h>
#include <sys/stat.h>

#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "core/hex.hpp"

namespace tlsmon {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kSaltBytes = 16;
constexpr std::size_t kKeyBytes = 32;

// PBKDF2-HMAC-SHA256 (RFC 8018, section 5.2).
std::vector<unsigned char> derive(const std::string& password,
                                  const std::vector<unsigned char>& salt, int iterations) {
    std::vector<unsigned char> key(kKeyBytes);
    if (PKCS5_PBKDF2_HMAC(password.data(), static_cast<int>(password.size()), salt.data(),
                          static_cast<int>(salt.size()), iterations, EVP_sha256(),
                          static_cast<int>(key.size()), key.data()) != 1) {
        throw Error("PBKDF2 failed (OpenSSL)");
    }
    return key;
}

bool valid_name(const std::string& name) {
    if (name.empty() || name.size() > 64) return false;
    for (char c : name) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                        (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-';
        if (!ok) return false;
    }
    return true;
}

}  // namespace

std::string_view to_string(UserRole role) {
    switch (role) {
        case UserRole::viewer:
            return "viewer";
        case UserRole::operator_:
            return "operator";
        case UserRole::admin:
            return "admin";
    }
    return "viewer";
}

std::optional<UserRole> user_role_from_string(std::string_view text) {
    for (auto r : {UserRole::viewer, UserRole::operator_, UserRole::admin}) {
        if (to_string(r) == text) return r;
    }
    return std::nullopt;
}

UserEntry make_user(const std::string& name, UserRole role, const std::string& password,
                    int iterations) {
    if (!valid_name(name)) {
        throw Error("user name '" + name +
                    "': 1 to 64 letters, digits, '.', '_' or '-' (it is stored in a ':' file)");
    }
    if (password.empty()) throw Error("an empty password is not accepted");
    std::vector<unsigned char> salt(kSaltBytes);
    if (RAND_bytes(salt.data(), static_cast<int>(salt.size())) != 1)
        throw Error("no random bytes for the salt (OpenSSL)");
    const auto key = derive(password, salt, iterations);
    return UserEntry{name, role, iterations, to_hex(salt), to_hex(key)};
}

bool password_matches(const UserEntry& user, const std::string& password) {
    const auto salt = from_hex(user.salt_hex);
    const auto stored = from_hex(user.hash_hex);
    if (!salt || salt->empty() || !stored || stored->size() != kKeyBytes || user.iterations < 1)
        return false;
    const auto key = derive(password, *salt, user.iterations);
    return CRYPTO_memcmp(key.data(), stored->data(), kKeyBytes) == 0;
}

std::vector<UserEntry> read_users(const fs::path& file) {
    std::vector<UserEntry> users;
    std::ifstream in(file);
    if (!in) {
        if (!fs::exists(file)) return users;
        throw Error("cannot read the users file " + file.string());
    }
    std::string line;
    int number = 0;
    while (std::getline(in, line)) {
        ++number;
        if (line.empty() || line[0] == '#') continue;
        std::vector<std::string> f;
        std::stringstream s(line);
        for (std::string part; std::getline(s, part, ':');) f.push_back(part);
        const auto bad = [&](const std::string& what) {
            return Error(file.string() + ":" + std::to_string(number) + ": " + what +
                         " (expected NAME:ROLE:pbkdf2-sha256:ITERATIONS:SALT:HASH; made by "
                         "`tlsmon users add`)");
        };
        if (f.size() != 6) throw bad("6 fields separated by ':'");
        const auto role = user_role_from_string(f[1]);
        if (!role) throw bad("role '" + f[1] + "' is not viewer, operator or admin");
        if (f[2] != "pbkdf2-sha256") throw bad("unknown hash '" + f[2] + "'");
        UserEntry u{f[0], *role, 0, f[4], f[5]};
        try {
            u.iterations = std::stoi(f[3]);
        } catch (const std::exception&) {
            throw bad("iterations '" + f[3] + "' is not a number");
        }
        if (!valid_name(u.name)) throw bad("user name '" + u.name + "'");
        for (const auto& other : users) {
            if (other.name == u.name) throw bad("user '" + u.name + "' is listed twice");
        }
        users.push_back(u);
    }
    return users;
}

void write_users(const fs::path& file, const std::vector<UserEntry>& users) {
    const fs::path aside = file.string() + ".new";
    {
        const mode_t old = ::umask(077);
        std::ofstream out(aside, std::ios::trunc);
        ::umask(old);
        if (!out) throw Error("cannot write " + aside.string());
        out << "# tlsmon dashboard users (tlsmon users): "
               "NAME:ROLE:pbkdf2-sha256:ITERATIONS:SALT:HASH\n";
        for (const auto& u : users) {
            out << u.name << ':' << to_string(u.role) << ":pbkdf2-sha256:" << u.iterations << ':'
                << u.salt_hex << ':' << u.hash_hex << '\n';
        }
        out.close();
        if (!out) throw Error("cannot write " + aside.string());
    }
    fs::permissions(aside, fs::perms::owner_read | fs::perms::owner_write);
    fs::rename(aside, file);
}

}  // namespace tlsmon
