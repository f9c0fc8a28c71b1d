// ISO-8601 UTC text <-> seconds.
#include <gtest/gtest.h>

#include "core/utc_time.hpp"

namespace tlsmon {
namespace {

TEST(UtcTime, FormatsKnownInstants) {
    EXPECT_EQ(format_utc(0), "1970-01-01T00:00:00Z");
    EXPECT_EQ(format_utc(1772366400), "2026-03-01T12:00:00Z");
    EXPECT_EQ(format_utc(951782400), "2000-02-29T00:00:00Z");  // leap day
    EXPECT_EQ(format_utc(-1), "1969-12-31T23:59:59Z");
    EXPECT_EQ(format_utc(253402300799), "9999-12-31T23:59:59Z");   // the last four-digit year
    EXPECT_EQ(format_utc(253402300800), "10000-01-01T00:00:00Z");  // beyond: printed in full
    EXPECT_EQ(format_utc(-62135596800), "0001-01-01T00:00:00Z");
}

TEST(UtcTime, ParsesTheAcceptedForms) {
    EXPECT_EQ(parse_utc("2026-03-01T12:00:00Z"), 1772366400);
    EXPECT_EQ(parse_utc("2026-03-01T12:00:00"), 1772366400);
    EXPECT_EQ(parse_utc("2026-03-01 12:00"), 1772366400);
    EXPECT_EQ(parse_utc("2026-03-01"), 1772366400 - 12 * 3600);
    EXPECT_EQ(parse_utc("2026-03-01T14:00:00+02:00"), 1772366400);
    EXPECT_EQ(parse_utc("2026-03-01T07:30:00-04:30"), 1772366400);
    for (UtcSeconds t : {0LL, 1772366400LL, 4102444799LL}) EXPECT_EQ(parse_utc(format_utc(t)), t);
}

TEST(UtcTime, RejectsWhatItCannotRead) {
    for (const char* bad : {"", "2026", "2026-02-30", "2026-13-01", "2026-03-01T25:00",
                            "2026-03-01T12:00:00Zjunk", "01.03.2026", "2026-03-01T12"}) {
        try {
            parse_utc(bad);
            ADD_FAILURE() << "accepted '" << bad << "'";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(std::string("'") + bad + "'"), std::string::npos)
                << e.what();
        }
    }
}

}  // namespace
}  // namespace tlsmon
