// `tlsmon export --bundle DIR [--from T] [--to T]`: a time window of the site's results as a
// folder an analyst takes away (docs/export.md, "Bundles"): the window's database extract,
// every epoch's and campaign's maps as LAS, the zone series as one CSV, a manifest and
// SHA256SUMS.
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/query_output.hpp"
#include "config/config.hpp"
#include "core/csv.hpp"
#include "core/utc_time.hpp"
#include "formats/coordinate_system.hpp"
#include "formats/las_writer.hpp"
#include "pipeline/result_points.hpp"
#include "pipeline/sha256.hpp"
#include "storage/window_extract.hpp"

namespace tlsmon {

namespace fs = std::filesystem;

namespace {

// Every zone quantity's points in the window, one row each (docs/export.md lists the columns).
std::int64_t write_series(const EpochDatabase& db, const TimeRange& window, const fs::path& path) {
    std::string text = csv_line(std::vector<std::string>{
        "zone", "quantity", "epoch", "campaign", "acquired", "value", "uncertainty", "n",
        "significant", "datum", "registration_accepted"});
    std::int64_t rows = 0;
    for (const auto& [zone, definition] : db.site().zones()) {
        for (const auto& q : db.series().quantities(zone)) {
            db.series().for_each_point(zone, q, window, [&](const SeriesPoint& p) {
                append_csv_line(
                    text, std::vector<std::string>{
                              zone, q, p.epoch > 0 ? std::to_string(p.epoch) : "",
                              p.campaign ? std::to_string(*p.campaign) : "", format_utc(p.acquired),
                              csv_number(p.value), p.uncertainty ? csv_number(*p.uncertainty) : "",
                              std::to_string(p.n), p.significant ? "1" : "0", p.datum,
                              p.registration_accepted ? "1" : "0"});
                ++rows;
            });
        }
    }
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) throw Error("cannot write " + path.string());
    return rows;
}

std::string zero_padded(std::int64_t id) {
    std::string s = std::to_string(id);
    return std::string(s.size() < 6 ? 6 - s.size() : 0, '0') + s;
}

}  // namespace

int run_export_bundle(const ExportOptions& o) {
    return run_reporting_errors("export", [&] {
        const TimeRange window = time_range(o.read);
        const fs::path source = database_path(o.read);
        std::string crs = o.crs;
        if (crs.empty() && !o.read.config.empty()) crs = load_config(o.read.config).station.crs;
        const std::string wkt = crs.empty() ? "" : coordinate_system(crs).wkt;

        const fs::path dir = o.bundle;
        std::error_code ec;
        if (fs::exists(dir, ec)) throw Error("--bundle " + dir.string() + ": exists already");
        // Built under DIR.part and renamed when complete: DIR is whole or absent.
        const fs::path part = dir.string() + ".part";
        fs::remove_all(part, ec);
        fs::create_directories(part / "maps");
        try {
            const WindowExtract extract = extract_window(source, part / "tlsmon.sqlite", window);
            const auto db = EpochDatabase::open(extract.path, EpochDatabase::Mode::read_only);
            nlohmann::json files = nlohmann::json::array();
            nlohmann::json skipped = nlohmann::json::array();
            const auto add_file = [&](const std::string& name, nlohmann::json about) {
                about["path"] = name;
                about["bytes"] = fs::file_size(part / name);
                about["sha256"] = sha256_file(part / name);
                files.push_back(std::move(about));
            };
            add_file("tlsmon.sqlite", {{"kind", "database"}});

            // The maps of every analysed epoch of the window (not the reference epoch's
            // state-only rows outside it), and of every campaign.
            for (const Epoch& e : db.series().epochs_in_range(window, EpochStatus::done)) {
                for (const ResultMap map :
                     {ResultMap::m3c2, ResultMap::pbm3c2, ResultMap::vectors}) {
                    const std::string name = "maps/epoch-" + zero_padded(e.id) + "-" +
                                             std::string(to_string(map)) + ".las";
                    try {
                        LasPoints points = epoch_result_points(db, e.id, map);
                        points.wkt = wkt;
                        write_las(part / name, points);
                        add_file(name, {{"kind", "map"},
                                        {"epoch", e.id},
                                        {"map", to_string(map)},
                                        {"acquired", format_utc(e.acquired)},
                                        {"points", points.xyz.size()}});
                    } catch (const Error& why) {  // this epoch has no such map: said, not hidden
                        skipped.push_back(
                            {{"epoch", e.id}, {"map", to_string(map)}, {"reason", why.what()}});
                    }
                }
            }
            for (const CampaignRow& c : db.campaigns().in_range(window)) {
                const std::string name = "maps/campaign-" + zero_padded(c.id) + ".las";
                LasPoints points = campaign_result_points(db, c.id);
                points.wkt = wkt;
                write_las(part / name, points);
                add_file(name, {{"kind", "campaign"},
                                {"campaign", c.id},
                                {"acquired", format_utc(c.acquired)},
                                {"points", points.xyz.size()}});
            }
            const std::int64_t rows = write_series(db, window, part / "series.csv");
            add_file("series.csv", {{"kind", "series"}, {"rows", rows}});

            const auto bound = [](const std::optional<UtcSeconds>& t) {
                return t ? nlohmann::json(format_utc(*t)) : nlohmann::json(nullptr);
            };
            const nlohmann::json manifest = {
                {"bundle", "tlsmon export bundle 1"},
                {"created", format_utc(now_utc())},
                {"source", fs::absolute(source).string()},
                {"window", {{"from", bound(window.from)}, {"to", bound(window.to)}}},
                {"schema_version", extract.schema_version},
                {"epochs", extract.epochs},
                {"campaigns", extract.campaigns},
                {"crs", crs},
                {"files", files},
                {"maps_not_written", skipped}};
            {
                std::ofstream m(part / "manifest.json", std::ios::binary | std::ios::trunc);
                m << manifest.dump(2) << "\n";
                if (!m) throw Error("cannot write " + (part / "manifest.json").string());
            }
            // `sha256sum -c SHA256SUMS` in the folder checks every file, the manifest too.
            std::string sums;
            for (const auto& f : files)
                sums += f.at("sha256").get<std::string>() + "  " + f.at("path").get<std::string>() +
                        "\n";
            sums += sha256_file(part / "manifest.json") + "  manifest.json\n";
            {
                std::ofstream m(part / "SHA256SUMS", std::ios::binary | std::ios::trunc);
                m << sums;
                if (!m) throw Error("cannot write " + (part / "SHA256SUMS").string());
            }
            fs::rename(part, dir);
            std::cout << "bundle " << dir.string() << ": " << extract.epochs << " epochs, "
                      << extract.campaigns << " campaigns, " << files.size() - 2 << " map files, "
                      << rows << " series rows, " << skipped.size()
                      << " maps not written (manifest.json says why)\n";
        } catch (...) {
            fs::remove_all(part, ec);
            throw;
        }
    });
}

}  // namespace tlsmon
