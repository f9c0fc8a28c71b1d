// ISO-8601 UTC text <-> seconds (the subset of ISO 8601 / RFC 3339 that people type).
#include "core/utc_time.hpp"

#include <array>
#include <cctype>
#include <chrono>
#include <cstdio>

namespace tlsmon {

namespace {

[[noreturn]] void bad_time(std::string_view text, const std::string& why) {
    throw Error("time '" + std::string(text) + "': " + why +
                " (expected e.g. 2026-03-01T12:15:00Z)");
}

// Reads exactly `digits` digits at `pos`.
int read_digits(std::string_view text, std::size_t& pos, int digits) {
    int value = 0;
    for (int i = 0; i < digits; ++i, ++pos) {
        if (pos >= text.size() || !std::isdigit(static_cast<unsigned char>(text[pos]))) {
            bad_time(text, "expected a digit at character " + std::to_string(pos + 1));
        }
        value = value * 10 + (text[pos] - '0');
    }
    return value;
}

void expect(std::string_view text, std::size_t& pos, char c) {
    if (pos >= text.size() || text[pos] != c) {
        bad_time(text, std::string("expected '") + c + "' at character " + std::to_string(pos + 1));
    }
    ++pos;
}

}  // namespace

namespace {
// The UTC instants (seconds since 1970) from which GPS - UTC equals index + 1.
constexpr std::array<double, 18> kLeapSecondUtc{
    362793600, 394329600,  425865600,  489024000,  567993600,  631152000,
    662688000, 709948800,  741484800,  773020800,  820454400,  867715200,
    915148800, 1136073600, 1230768000, 1341100800, 1435708800, 1483228800};
constexpr double kGpsEpochUtc = 315964800.0;  // 1980-01-06T00:00:00Z
}  // namespace

double gps_to_utc(double gps_seconds) {
    const double gps_on_utc_scale = gps_seconds + kGpsEpochUtc;
    int leap = 0;
    for (std::size_t k = 0; k < kLeapSecondUtc.size(); ++k) {
        if (gps_on_utc_scale >= kLeapSecondUtc[k] + static_cast<double>(k + 1)) leap = int(k) + 1;
    }
    return gps_on_utc_scale - leap;
}

double utc_to_gps(double utc_seconds) {
    int leap = 0;
    for (std::size_t k = 0; k < kLeapSecondUtc.size(); ++k) {
        if (utc_seconds >= kLeapSecondUtc[k]) leap = int(k) + 1;
    }
    return utc_seconds - kGpsEpochUtc + leap;
}

UtcSeconds now_utc() {
    return std::chrono::duration_cast<std::chrono::seconds>(
               std::chrono::system_clock::now().time_since_epoch())
        .count();
}

std::string format_utc(UtcSeconds t) {
    using namespace std::chrono;
    const sys_seconds tp{seconds{t}};
    const auto day = floor<days>(tp);
    const year_month_day ymd{day};
    const hh_mm_ss hms{tp - day};
    const int y = static_cast<int>(ymd.year());
    if (y < 0 || y > 9999) {  // outside ISO 8601's four digits: the rare, slow way
        char buf[48];
        std::snprintf(
            buf, sizeof buf, "%d-%02u-%02uT%02d:%02d:%02dZ", y, static_cast<unsigned>(ymd.month()),
            static_cast<unsigned>(ymd.day()), static_cast<int>(hms.hours().count()),
            static_cast<int>(hms.minutes().count()), static_cast<int>(hms.seconds().count()));
        return buf;
    }
    // Digit by digit: a year of series is 35,040 of these, and snprintf was most of its print.
    std::string out = "0000-00-00T00:00:00Z";
    const auto put = [&](std::size_t at, int value, int digits) {
        for (int i = digits - 1; i >= 0; --i, value /= 10) out[at + i] = char('0' + value % 10);
    };
    put(0, y, 4);
    put(5, static_cast<int>(static_cast<unsigned>(ymd.month())), 2);
    put(8, static_cast<int>(static_cast<unsigned>(ymd.day())), 2);
    put(11, static_cast<int>(hms.hours().count()), 2);
    put(14, static_cast<int>(hms.minutes().count()), 2);
    put(17, static_cast<int>(hms.seconds().count()), 2);
    return out;
}

UtcSeconds parse_utc(std::string_view text) {
    using namespace std::chrono;
    std::size_t pos = 0;
    const int y = read_digits(text, pos, 4);
    expect(text, pos, '-');
    const int mo = read_digits(text, pos, 2);
    expect(text, pos, '-');
    const int d = read_digits(text, pos, 2);
    const year_month_day ymd{year{y}, month{static_cast<unsigned>(mo)},
                             day{static_cast<unsigned>(d)}};
    if (!ymd.ok()) bad_time(text, "no such date");
    int h = 0, mi = 0, s = 0;
    if (pos < text.size() && (text[pos] == 'T' || text[pos] == 't' || text[pos] == ' ')) {
        ++pos;
        h = read_digits(text, pos, 2);
        expect(text, pos, ':');
        mi = read_digits(text, pos, 2);
        if (pos < text.size() && text[pos] == ':') {
            ++pos;
            s = read_digits(text, pos, 2);
        }
        if (h > 23 || mi > 59 || s > 59) bad_time(text, "no such time of day");
    }
    int offset_s = 0;
    if (pos < text.size()) {
        if (text[pos] == 'Z' || text[pos] == 'z') {
            ++pos;
        } else if (text[pos] == '+' || text[pos] == '-') {
            const int sign = text[pos] == '-' ? -1 : 1;
            ++pos;
            const int oh = read_digits(text, pos, 2);
            expect(text, pos, ':');
            const int om = read_digits(text, pos, 2);
            if (oh > 23 || om > 59) bad_time(text, "no such UTC offset");
            offset_s = sign * (oh * 3600 + om * 60);
        }
    }
    if (pos != text.size()) {
        bad_time(text, "unexpected text at character " + std::to_string(pos + 1));
    }
    const auto local =
        sys_days{ymd}.time_since_epoch().count() * 86400LL + h * 3600LL + mi * 60LL + s;
    return local - offset_s;  // 12:00+02:00 is 10:00Z
}

}  // namespace tlsmon
