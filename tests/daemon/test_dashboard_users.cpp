// The dashboard's users file, password hashes, sessions and login brake
// (daemon/http/users.hpp, sessions.hpp) against known answers.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <fstream>

#include "core/error.hpp"
#include "daemon/http/sessions.hpp"
#include "daemon/http/users.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

TEST(DashboardUsers, Pbkdf2MatchesTheRfc7914TestVector) {
    // PBKDF2-HMAC-SHA256, P = "password", S = "salt", c = 4096, dkLen = 32 (the vector
    // published with RFC 7914's reference implementation, and Python's hashlib).
    const UserEntry u{"x", UserRole::viewer, 4096, "73616c74",
                      "c5e478d59288c841aa530db6845c4c8d962893a001ce4e11a4963873aa98134a"};
    EXPECT_TRUE(password_matches(u, "password"));
    EXPECT_FALSE(password_matches(u, "Password"));
    EXPECT_FALSE(password_matches(u, ""));
}

TEST(DashboardUsers, MadeEntriesCheckTheirOwnPasswordWithAFreshSalt) {
    const UserEntry a = make_user("alice", UserRole::operator_, "correct horse", 1000);
    const UserEntry b = make_user("alice", UserRole::operator_, "correct horse", 1000);
    EXPECT_NE(a.salt_hex, b.salt_hex);
    EXPECT_NE(a.hash_hex, b.hash_hex);
    EXPECT_TRUE(password_matches(a, "correct horse"));
    EXPECT_FALSE(password_matches(a, "correct horse "));
    EXPECT_THROW(make_user("al:ice", UserRole::viewer, "p", 1000), Error);
    EXPECT_THROW(make_user("alice", UserRole::viewer, "", 1000), Error);
}

TEST(DashboardUsers, FileRoundTripsOwnerOnlyAndNamesTheBadLine) {
    test::TempDir dir("users");
    const auto file = dir.path() / "users.txt";
    EXPECT_TRUE(read_users(file).empty());  // none yet
    write_users(file, {make_user("alice", UserRole::operator_, "a", 1000),
                       make_user("bob", UserRole::viewer, "b", 1000)});
    struct stat st {};
    ASSERT_EQ(::stat(file.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0600u);
    const auto users = read_users(file);
    ASSERT_EQ(users.size(), 2u);
    EXPECT_EQ(users[0].name, "alice");
    EXPECT_EQ(users[0].role, UserRole::operator_);
    EXPECT_TRUE(password_matches(users[1], "b"));
    std::ofstream(file, std::ios::app) << "carol:superuser:pbkdf2-sha256:1000:00:00\n";
    try {
        read_users(file);
        FAIL() << "a bad role was read";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("users.txt:4: role 'superuser'"), std::string::npos)
            << e.what();
    }
}

TEST(DashboardSessions, ExpireAndClose) {
    Sessions s;
    const Session a = s.open("alice", UserRole::operator_, 1000, 60);
    EXPECT_EQ(a.token.size(), 64u);
    EXPECT_NE(a.token, a.csrf);
    ASSERT_TRUE(s.find(a.token, 1059));
    EXPECT_EQ(s.find(a.token, 1059)->user, "alice");
    EXPECT_FALSE(s.find(a.token, 1060)) << "expired at 1000 + 60";
    const Session b = s.open("bob", UserRole::viewer, 2000, 60);
    s.close(b.token);
    EXPECT_FALSE(s.find(b.token, 2001));
    EXPECT_FALSE(s.find("", 2001));
}

TEST(DashboardSessions, TokensCompareWholeAndExact) {
    const std::string token = random_token();
    EXPECT_EQ(token.size(), 64u);
    EXPECT_NE(random_token(), token);
    EXPECT_TRUE(same_token(token, token));
    EXPECT_FALSE(same_token(token.substr(0, 63), token));
    EXPECT_FALSE(same_token(token + "0", token));
    EXPECT_FALSE(same_token("", token));
    std::string last = token;
    last.back() = last.back() == '0' ? '1' : '0';
    EXPECT_FALSE(same_token(last, token));
}

TEST(DashboardSessions, FiveFailuresBrakeLoginsForTheRestOfTheWindow) {
    LoginThrottle t;
    for (int k = 0; k < 4; ++k) t.failed("192.0.2.1", 100 + k);
    EXPECT_EQ(t.wait_before_login("192.0.2.1", 110), 0);
    t.failed("192.0.2.1", 110);
    // The oldest failure (t = 100) leaves the 300 s window at 400.
    EXPECT_EQ(t.wait_before_login("192.0.2.1", 111), 289);
    EXPECT_EQ(t.wait_before_login("192.0.2.2", 111), 0) << "per address";
    EXPECT_EQ(t.wait_before_login("192.0.2.1", 400), 0);
    t.failed("192.0.2.1", 401);
    t.succeeded("192.0.2.1");
    EXPECT_EQ(t.wait_before_login("192.0.2.1", 402), 0);
}

}  // namespace
}  // namespace tlsmon
