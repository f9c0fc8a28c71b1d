#include "central/fleet_queries.hpp"

#include <charconv>

namespace tlsmon {

namespace {

PgParam optional_text(const std::optional<std::int64_t>& v) {
    return v ? PgParam(std::to_string(*v)) : std::nullopt;
}

// The shortest text that reads back to `v`.
PgParam number_text(double v) {
    char buf[32];
    const auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;
    return std::string(buf, end);
}

PgParam text_or_null(const std::string& s) {
    return s.empty() ? std::nullopt : PgParam(s);
}

// Times as ISO-8601 UTC text, as the site's `tlsmon query` prints them.
constexpr const char* kIso = "'YYYY-MM-DD\"T\"HH24:MI:SS\"Z\"'";

std::string iso(const std::string& column) {
    return "to_char(" + column + " AT TIME ZONE 'UTC', " + kIso + ")";
}

}  // namespace

PgResult fleet_sites(PgConnection& c) {
    return c.exec(
        "SELECT s.name AS site, s.location, (SELECT count(*) FROM tlsmon.epochs e"
        " WHERE e.site_id = s.id) AS epochs, " +
        iso("(SELECT max(acquired) FROM tlsmon.epochs e WHERE e.site_id = s.id)") +
        " AS newest_epoch, " +
        iso("(SELECT max(forwarded_at) FROM tlsmon.site_cursors k"
            " WHERE k.site_id = s.id)") +
        " AS forwarded, (SELECT sum(entries) FROM tlsmon.site_cursors k"
        " WHERE k.site_id = s.id) AS entries FROM tlsmon.sites s ORDER BY s.name");
}

PgResult fleet_latest(PgConnection& c, const LatestFilter& f) {
    return c.exec(
        "SELECT s.name AS site, l.zone, l.quantity, " + iso("l.acquired") +
            " AS acquired, l.value, l.uncertainty, l.n, l.significant"
            " FROM tlsmon.zone_latest l JOIN tlsmon.sites s ON s.id = l.site_id"
            " WHERE ($1::double precision IS NULL OR abs(l.value) >= $1)"
            " AND ($2::text IS NULL OR s.name = $2) AND ($3::text IS NULL OR l.quantity = $3)"
            " ORDER BY s.name, l.zone, l.quantity",
        {f.min_abs ? number_text(*f.min_abs) : std::nullopt, text_or_null(f.site),
         text_or_null(f.quantity)});
}

PgResult fleet_series(PgConnection& c, const std::string& site, const std::string& zone,
                      const std::string& quantity, std::optional<std::int64_t> from,
                      std::optional<std::int64_t> to) {
    return c.exec("SELECT substr(r.sha256, 1, 12) AS epoch, " + iso("r.acquired") +
                      " AS acquired, r.value, r.uncertainty, r.n, r.significant"
                      " FROM tlsmon.zone_results r"
                      " WHERE r.site_id = (SELECT id FROM tlsmon.sites WHERE name = $1)"
                      " AND r.zone = $2 AND r.quantity = $3"
                      " AND ($4::bigint IS NULL OR r.acquired >= to_timestamp($4))"
                      " AND ($5::bigint IS NULL OR r.acquired < to_timestamp($5))"
                      " ORDER BY r.acquired, r.sha256",
                  {site, zone, quantity, optional_text(from), optional_text(to)});
}

PgResult fleet_alarms(PgConnection& c, const std::string& site, std::optional<std::int64_t> from,
                      std::optional<std::int64_t> to) {
    return c.exec("SELECT s.name AS site, " + iso("a.time") +
                      " AS time, a.rule, a.zone, a.quantity, a.kind, a.level, a.value, a.actor,"
                      " a.message FROM tlsmon.alarm_events a JOIN tlsmon.sites s"
                      " ON s.id = a.site_id WHERE ($1::text IS NULL OR s.name = $1)"
                      " AND ($2::bigint IS NULL OR a.time >= to_timestamp($2))"
                      " AND ($3::bigint IS NULL OR a.time < to_timestamp($3))"
                      " ORDER BY a.time, s.name, a.site_event_id",
                  {text_or_null(site), optional_text(from), optional_text(to)});
}

}  // namespace tlsmon
