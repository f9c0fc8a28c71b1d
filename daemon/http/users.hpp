#pragma once
// The dashboard's users file (http.users_file): one line per user,
//   NAME:ROLE:pbkdf2-sha256:ITERATIONS:SALT:HASH
// (salt and hash in hex), made and changed by `tlsmon users`. Passwords are stored only as
// PBKDF2-HMAC-SHA256 (RFC 8018, OpenSSL's PKCS5_PBKDF2_HMAC) with a random 16-byte salt and
// 600,000 iterations (OWASP's 2023 figure for this hash), never in clear.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace tlsmon {

// What a user may do: viewer reads, operator also acts on alarms, admin also (later) on users
// and configuration.
enum class UserRole { viewer, operator_, admin };
std::string_view to_string(UserRole role);
std::optional<UserRole> user_role_from_string(std::string_view text);

struct UserEntry {
    std::string name;
    UserRole role = UserRole::viewer;
    int iterations = 0;
    std::string salt_hex;
    std::string hash_hex;
};

inline constexpr int kPasswordIterations = 600000;

// A new entry for `password` (fresh salt). Error for a name that could not be stored (empty,
// longer than 64, or with characters other than letters, digits, ".", "_", "-").
UserEntry make_user(const std::string& name, UserRole role, const std::string& password,
                    int iterations = kPasswordIterations);
// Whether `password` is the entry's (constant-time comparison of the derived keys).
bool password_matches(const UserEntry& user, const std::string& password);

// Error naming the file and line of a malformed entry; none when the file does not exist.
std::vector<UserEntry> read_users(const std::filesystem::path& file);
// Replaces the file (written aside, then renamed; mode 0600: only its owner reads it).
void write_users(const std::filesystem::path& file, const std::vector<UserEntry>& users);

}  // namespace tlsmon
