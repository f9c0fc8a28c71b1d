// The central database at fleet size (docs/central.md): how fast sites forward their outbox,
// and how fast the fleet's two common questions are answered on a loaded database.
//
//   bench_central_forward URL OWNER_PASSWORD_FILE [SITES [DAYS [ZONES [FORWARDED]]]]
//
// URL is an empty PostgreSQL database (its owner's login). Defaults: 100 sites, 365 days of
// 15-minute epochs, 20 zones, 2 of the sites forwarded through tlsmon.forward() (each by its
// own thread and connection, as its own role, in batches of 500 entries as a daemon sends
// them: an epoch, its registration and one M3C2 median per zone); the others loaded directly
// with INSERT ... SELECT, so the database holds the whole fleet. Then, each timed 20 times:
//   - the newest value of every zone of every site (`tlsmon fleet status`),
//   - one zone's year (`tlsmon fleet query series`).
#include "central/central_forward.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "bench/bench_support.hpp"
#include "central/central_schema.hpp"
#include "central/central_sites.hpp"
#include "central/fleet_queries.hpp"
#include "core/utc_time.hpp"

namespace tlsmon::bench {
namespace {

constexpr UtcSeconds kStart = 1767225600;  // 2026-01-01T00:00:00Z
constexpr int kCadence = 900;
constexpr int kBatch = 500;

std::string site_name(int k) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "s%03d", k);
    return buf;
}

std::string sha_of(int site, std::int64_t epoch) {
    char buf[65];
    std::snprintf(buf, sizeof buf, "%032llx%032llx", static_cast<unsigned long long>(site),
                  static_cast<unsigned long long>(epoch) * 2654435761ULL);
    return buf;
}

// One site's outbox as its daemon would write it, in batches, sent as the site.
struct ForwardResult {
    std::int64_t entries = 0;
    double cpu = 0;
};

ForwardResult forward_site(const std::string& url, const std::filesystem::path& password_file,
                           int site, int days, int zones) {
    CentralTarget t;
    const std::string role = site_role(site_name(site));
    // The site's own login: the URL's user replaced.
    t.url = "postgresql://" + role + url.substr(url.find('@'));
    t.password_file = password_file;
    t.application_name = "bench " + role;
    PgConnection c = PgConnection::open(t);
    const double cpu0 = thread_cpu_seconds();
    ForwardResult r;
    std::vector<OutboxEntry> batch;
    std::int64_t seq = 0;
    auto flush = [&] {
        if (batch.empty()) return;
        forward_batch(c, "bench", batch);
        r.entries += static_cast<std::int64_t>(batch.size());
        batch.clear();
    };
    const std::int64_t epochs = static_cast<std::int64_t>(days) * 86400 / kCadence;
    char buf[512];
    for (std::int64_t e = 0; e < epochs; ++e) {
        const UtcSeconds acquired = kStart + e * kCadence;
        const std::string sha = sha_of(site, e);
        std::snprintf(buf, sizeof buf,
                      R"({"sha256":"%s","acquired":%lld,"status":"done","reason":"","file":)"
                      R"("/srv/tlsmon/archive/%s.ptx","file_size":123456789,"points":4000000,)"
                      R"("total_ms":5400.0})",
                      sha.c_str(), static_cast<long long>(acquired), sha.c_str());
        batch.push_back({++seq, acquired, "epoch", buf});
        std::snprintf(buf, sizeof buf,
                      R"({"sha256":"%s","acquired":%lld,"method":"targets+atmosphere",)"
                      R"("accepted":1,"status":"accepted","reason":"","target_count":5,)"
                      R"("rms_m":0.00071,"max_residual_m":0.0011,"sigma0":0.93,"parameters":)"
                      R"([1e-6,2e-6,3e-6,0.001,0.002,0.003],"sigmas":null,)"
                      R"("variance_factor":0.87,"redundancy":9})",
                      sha.c_str(), static_cast<long long>(acquired));
        batch.push_back({++seq, acquired, "registration", buf});
        for (int z = 0; z < zones; ++z) {
            std::snprintf(buf, sizeof buf,
                          R"({"sha256":"%s","acquired":%lld,"zone":"zone%02d","quantity":)"
                          R"("m3c2_median_m","value":%.17g,"uncertainty":0.0011,"n":800,)"
                          R"("significant":0})",
                          sha.c_str(), static_cast<long long>(acquired), z,
                          0.001 * std::sin(0.01 * static_cast<double>(e + z)));
            batch.push_back({++seq, acquired, "zone_result", buf});
        }
        if (batch.size() >= kBatch) flush();
    }
    flush();
    r.cpu = thread_cpu_seconds() - cpu0;
    return r;
}

double median_ms(const std::function<void()>& f) {
    std::vector<double> ms;
    for (int k = 0; k < 20; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        f();
        ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count());
    }
    std::sort(ms.begin(), ms.end());
    return ms[ms.size() / 2];
}

}  // namespace
}  // namespace tlsmon::bench

int main(int argc, char** argv) {
    using namespace tlsmon;
    using namespace tlsmon::bench;
    if (argc < 3) {
        std::fprintf(stderr,
                     "usage: %s URL OWNER_PASSWORD_FILE [SITES [DAYS [ZONES [FORWARDED]]]]\n",
                     argv[0]);
        return 2;
    }
    const std::string url = argv[1];
    const int sites = argc > 3 ? std::stoi(argv[3]) : 100;
    const int days = argc > 4 ? std::stoi(argv[4]) : 365;
    const int zones = argc > 5 ? std::stoi(argv[5]) : 20;
    const int forwarded = argc > 6 ? std::stoi(argv[6]) : 2;
    CentralTarget owner;
    owner.url = url;
    owner.password_file = argv[2];
    owner.statement_timeout_s = 3600;
    PgConnection c = PgConnection::open(owner);
    migrate_central(c);
    for (int k = 0; k < sites; ++k) {
        if (c.exec("SELECT 1 FROM tlsmon.sites WHERE name = $1", {site_name(k)}).rows.empty())
            add_site(c, site_name(k), "bench", "bench-" + site_name(k));
    }
    std::printf("fleet: %d sites x %d days of 15-minute epochs x %d zones = %lld zone results\n",
                sites, days, zones, static_cast<long long>(sites) * days * 96 * zones);

    // Forwarded: one thread and connection per site, at once.
    {
        const BenchDir dir;
        for (int k = 0; k < forwarded; ++k)
            std::ofstream(dir / (site_name(k) + ".pw")) << "bench-" << site_name(k) << "\n";
        const auto t0 = std::chrono::steady_clock::now();
        std::vector<ForwardResult> results(forwarded);
        std::vector<std::thread> threads;
        for (int k = 0; k < forwarded; ++k)
            threads.emplace_back([&, k] {
                results[k] = forward_site(url, dir / (site_name(k) + ".pw"), k, days, zones);
            });
        for (auto& t : threads) t.join();
        const double wall =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::int64_t entries = 0;
        double cpu = 0;
        for (const auto& r : results) entries += r.entries, cpu += r.cpu;
        std::printf(
            "forwarded: %d sites, %lld entries in %.1f s wall: %.0f entries/s "
            "(site side %.2f CPU s; the rest is the server's)\n",
            forwarded, static_cast<long long>(entries), wall, entries / wall, cpu);
    }

    // The rest of the fleet loaded directly, month by month partitions first.
    {
        const auto t0 = std::chrono::steady_clock::now();
        c.exec(
            "SELECT tlsmon.ensure_month(m) FROM generate_series(to_timestamp($1),"
            " to_timestamp($1) + make_interval(days => $2), interval '1 month') m",
            {std::to_string(kStart), std::to_string(days)});
        for (int k = forwarded; k < sites; ++k) {
            const std::vector<PgParam> p{site_name(k), std::to_string(kStart),
                                         std::to_string(days * 96), std::to_string(zones)};
            c.exec(
                "INSERT INTO tlsmon.epochs SELECT s.id, md5(s.name || e) || md5(e::text),"
                " to_timestamp($2::bigint + 900 * e), 'done', '', 'x.ptx', 1, 1, 1, e"
                " FROM tlsmon.sites s, generate_series(0, $3::int - 1) e WHERE s.name = $1",
                {p[0], p[1], p[2]});
            c.exec(
                "INSERT INTO tlsmon.zone_results SELECT s.id, 'zone' || lpad(z::text, 2, '0'),"
                " 'm3c2_median_m', to_timestamp($2::bigint + 900 * e),"
                " md5(s.name || e) || md5(e::text), 0.001 * sin(0.01 * (e + z)), 0.0011, 800,"
                " false FROM tlsmon.sites s, generate_series(0, $3::int - 1) e,"
                " generate_series(0, $4::int - 1) z WHERE s.name = $1",
                p);
            c.exec(
                "INSERT INTO tlsmon.zone_latest SELECT DISTINCT ON (zone) site_id, zone,"
                " quantity, acquired, sha256, value, uncertainty, n, significant FROM"
                " tlsmon.zone_results WHERE site_id = (SELECT id FROM tlsmon.sites WHERE name"
                " = $1) AND acquired > to_timestamp($2::bigint + 900 * ($3::int - 2))"
                " ORDER BY zone, acquired DESC",
                {p[0], p[1], p[2]});
        }
        // What autovacuum does to an insert-only table (autovacuum_vacuum_insert_threshold):
        // the visibility map that lets the series be read from the index alone.
        c.exec("VACUUM (ANALYZE) tlsmon.zone_results");
        c.exec("ANALYZE");
        std::printf("loaded directly: %d sites in %.0f s\n", sites - forwarded,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    const auto size = c.exec(
        "SELECT pg_size_pretty(pg_database_size(current_database())),"
        " (SELECT count(*) FROM tlsmon.zone_latest)");
    std::printf("database: %s, %s zone quantities\n", size.rows[0][0]->c_str(),
                size.rows[0][1]->c_str());

    std::size_t rows = 0;
    const double latest = median_ms([&] { rows = fleet_latest(c, {}).rows.size(); });
    std::printf("newest value of every zone of every site: %zu rows, median %.1f ms\n", rows,
                latest);
    const double year = median_ms([&] {
        rows = fleet_series(c, site_name(sites / 2), "zone07", "m3c2_median_m", std::nullopt,
                            std::nullopt)
                   .rows.size();
    });
    std::printf("one zone's %d days: %zu rows, median %.1f ms\n", days, rows, year);
    const double forwarded_year = median_ms([&] {
        rows = fleet_series(c, site_name(0), "zone07", "m3c2_median_m", std::nullopt, std::nullopt)
                   .rows.size();
    });
    std::printf("one zone's %d days of a forwarded site: %zu rows, median %.1f ms\n", days, rows,
                forwarded_year);
    return 0;
}
