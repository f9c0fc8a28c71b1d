// The meteo sidecar parser on small texts written here: the values must come back exactly
// as written, whatever the column order, and every malformed case must name its line.
#include <gtest/gtest.h>

#include <string>

#include "formats/format_error.hpp"
#include "formats/meteo_csv.hpp"

namespace tlsmon {
namespace {

const std::filesystem::path kFile = "ingest/pier_20260601T060000Z.meteo.csv";
constexpr std::int64_t k0555 = 1780293300;  // 2026-06-01T05:55:00Z
constexpr std::int64_t k0600 = 1780293600;  // 2026-06-01T06:00:00Z

std::string error_of(const std::string& text) {
    try {
        parse_meteo_csv(text, kFile);
    } catch (const FormatError& e) {
        return e.what();
    }
    return "(no error)";
}

TEST(MeteoCsv, GoodFileGivesEachRowExactly) {
    const auto rows = parse_meteo_csv(
        "time_utc,air_temperature_c,pressure_hpa,relative_humidity_pct\n"
        "2026-06-01T05:55:00Z,14.2,1012.3,78.0\n"
        "2026-06-01T05:56:00Z,14.3,1012.2,77.9\n"
        "2026-06-01T06:00:00Z,-3.5,988.0,100.0\n",
        kFile);
    ASSERT_EQ(rows.size(), 3u);
    EXPECT_EQ(rows[0].time_utc, k0555);
    EXPECT_EQ(rows[0].air_temperature_c, 14.2);
    EXPECT_EQ(rows[0].pressure_hpa, 1012.3);
    EXPECT_EQ(rows[0].relative_humidity_pct, 78.0);
    EXPECT_EQ(rows[0].line, 2u);
    EXPECT_EQ(rows[1].time_utc, k0555 + 60);
    EXPECT_EQ(rows[2].time_utc, k0600);
    EXPECT_EQ(rows[2].air_temperature_c, -3.5);
    EXPECT_EQ(rows[2].pressure_hpa, 988.0);
    EXPECT_EQ(rows[2].relative_humidity_pct, 100.0);
    EXPECT_EQ(rows[2].line, 4u);
}

TEST(MeteoCsv, ColumnsInAnotherOrderWithAnExtraColumnCommentsAndCrLf) {
    const auto rows = parse_meteo_csv(
        "\xEF\xBB\xBF# station WS-12, pier P3\r\n"
        "# logged every minute\r\n"
        "\r\n"
        "pressure_hpa, wind_speed_ms ,relative_humidity_pct,time_utc,air_temperature_c\r\n"
        "# a comment between rows\r\n"
        "1012.3, 3.1 ,78.0,2026-06-01T05:55:00Z,+14.2\r\n"
        "1001.9,,55.5,2026-06-01T06:00:00Z,21.0\r\n",
        kFile);
    ASSERT_EQ(rows.size(), 2u);
    EXPECT_EQ(rows[0].time_utc, k0555);
    EXPECT_EQ(rows[0].air_temperature_c, 14.2);
    EXPECT_EQ(rows[0].pressure_hpa, 1012.3);
    EXPECT_EQ(rows[0].relative_humidity_pct, 78.0);
    EXPECT_EQ(rows[0].line, 6u);
    // The extra column may be empty: it is not read.
    EXPECT_EQ(rows[1].pressure_hpa, 1001.9);
    EXPECT_EQ(rows[1].relative_humidity_pct, 55.5);
    EXPECT_EQ(rows[1].air_temperature_c, 21.0);
    EXPECT_EQ(rows[1].line, 7u);
}

TEST(MeteoCsv, EachMalformedCaseNamesFileAndLine) {
    const std::string header = "time_utc,air_temperature_c,pressure_hpa,relative_humidity_pct\n";
    const std::string f = kFile.string();
    struct Case {
        std::string text;
        std::string expected;  // the start of the message
    };
    const Case cases[] = {
        {"# only a comment\ntime,temperature,pressure,humidity\n2026-06-01T05:55:00Z,1,1000,1\n",
         f + ":2: the header has no column 'time_utc'"},
        {"time_utc,air_temperature_c,pressure_hpa\n", f + ":1: the header has no column "
                                                          "'relative_humidity_pct'"},
        {"time_utc,air_temperature_c,pressure_hpa,relative_humidity_pct,time_utc\n",
         f + ":1: header names column 'time_utc' twice"},
        {"time_utc,,air_temperature_c,pressure_hpa,relative_humidity_pct\n",
         f + ":1: header column 2 has no name"},
        {header + "2026-06-01T05:55:00Z,14.2,1012.3,78.0\n2026-06-01T05:56:00Z,14.2,,78.0\n",
         f + ":3: column 'pressure_hpa': empty value"},
        {header + "2026-06-01T05:55:00Z,14.2,1012.3,78.0\n\n2026-06-01T05:56:00Z,14,2,1012.3,78\n",
         f + ":4: the row has 5 fields, the header on line 1 names 4"},
        {header + "2026-06-01T05:55:00Z,14.2,1012.3\n",
         f + ":2: the row has 3 fields, the header on line 1 names 4"},
        {header + "2026-06-01T05:55:00Z,14.2,1O12.3,78.0\n",
         f + ":2: column 'pressure_hpa': not a number: '1O12.3'"},
        {header + "2026-06-01T05:55:00Z,14,2,1012.3,78.0\n",
         f + ":2: the row has 5 fields"},  // a decimal comma
        {header + "2026-06-01T05:55:00Z,nan,1012.3,78.0\n",
         f + ":2: column 'air_temperature_c': not a number: 'nan'"},
        {header + "2026-06-01T05:55:00Z,-999,1012.3,78.0\n",
         f + ":2: column 'air_temperature_c': -999 °C is outside -80 .. 70 °C"},
        {header + "2026-06-01T05:55:00Z,14.2,1012.3,100.5\n",
         f + ":2: column 'relative_humidity_pct': 100.5 % is outside 0 .. 100 %"},
        {header + "2026-06-01T05:55:00Z,14.2,1012.3,78\n2026-06-01T07:55:00+02:00,14.2,1012.3,78\n",
         f + ":3: time_utc '2026-06-01T07:55:00+02:00' is not UTC"},
        {header + "2026-06-01T05:55:00,14.2,1012.3,78\n",
         f + ":2: time_utc '2026-06-01T05:55:00' is not UTC"},
        {header + "01.06.2026 05:55,14.2,1012.3,78\n",
         f + ":2: time_utc '01.06.2026 05:55' is not an ISO 8601 UTC time"},
        {header + "2026-02-30T05:55:00Z,14.2,1012.3,78\n", f + ":2: time_utc: "},
        {header + ",14.2,1012.3,78\n", f + ":2: column 'time_utc': empty value"},
        {"# header only\n" + header, f + ":2: no rows after the header"},
        {"", f + ": no header line"},
        {"# nothing but\n# comments\n", f + ": no header line"},
    };
    for (const auto& c : cases) {
        const std::string e = error_of(c.text);
        EXPECT_EQ(e.substr(0, c.expected.size()), c.expected) << "text:\n" << c.text;
    }
}

TEST(MeteoCsv, NearestRowWithinTheMaximumOffset) {
    const auto rows = parse_meteo_csv(
        "time_utc,air_temperature_c,pressure_hpa,relative_humidity_pct\n"
        "2026-06-01T05:55:00Z,14.0,1012.0,70.0\n"
        "2026-06-01T06:01:00Z,16.0,1011.0,71.0\n"
        "2026-06-01T05:59:00Z,15.0,1011.5,72.0\n",
        kFile);
    // 06:00:00 lies 60 s from 05:59 and from 06:01: the earlier row wins the tie.
    EXPECT_EQ(nearest_meteo_row(rows, k0600, 300, kFile).line, 4u);
    EXPECT_EQ(nearest_meteo_row(rows, k0600 + 1, 300, kFile).line, 3u);
    EXPECT_EQ(nearest_meteo_row(rows, k0555 - 300, 300, kFile).line, 2u);
    try {
        nearest_meteo_row(rows, k0600 + 361, 300, kFile);
        ADD_FAILURE() << "no error";
    } catch (const FormatError& e) {
        EXPECT_EQ(std::string(e.what()),
                  kFile.string() +
                      ":3: the nearest row (2026-06-01T06:01:00Z) is 301 s from the acquisition "
                      "time 2026-06-01T06:06:01Z, more than the 300 s allowed "
                      "(meteo.max_time_offset_seconds)");
    }
}

TEST(MeteoCsv, SidecarNamesAndTheSidecarOfAScan) {
    EXPECT_TRUE(is_meteo_sidecar_name("pier_20260601T060000Z.meteo.csv"));
    EXPECT_FALSE(is_meteo_sidecar_name(".pier.meteo.csv"));
    EXPECT_FALSE(is_meteo_sidecar_name(".meteo.csv"));
    EXPECT_FALSE(is_meteo_sidecar_name("pier.meteo.csv.part"));
    EXPECT_FALSE(is_meteo_sidecar_name("pier.csv"));
    EXPECT_EQ(meteo_sidecar_of("/srv/ingest/pier_20260601T060000Z.ptx"),
              std::filesystem::path("/srv/ingest/pier_20260601T060000Z.meteo.csv"));
    EXPECT_EQ(meteo_sidecar_of("a.b.e57"), std::filesystem::path("a.b.meteo.csv"));
}

}  // namespace
}  // namespace tlsmon
