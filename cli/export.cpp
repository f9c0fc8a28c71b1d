// `tlsmon export (--epoch N [--map m3c2|pbm3c2|vectors] | --campaign N) --out FILE`: one
// stored map's per-point results as LAS 1.4 (point format 6, every attribute as extra bytes)
// or CSV, by the file's extension (docs/export.md); the LAS file names the site's coordinate
// system when it has one.
#include <fstream>
#include <iostream>

#include "cli/commands.hpp"
#include "cli/query_output.hpp"
#include "config/config.hpp"
#include "core/csv.hpp"
#include "formats/coordinate_system.hpp"
#include "formats/las_writer.hpp"
#include "pipeline/result_points.hpp"

namespace tlsmon {

namespace {

bool ends_with(const std::string& s, std::string_view suffix) {
    return s.size() >= suffix.size() &&
           std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(),
                      [](char a, char b) { return std::tolower(a) == std::tolower(b); });
}

// The same columns as the LAS file's: x, y, z, then the attributes in their order.
void write_csv(const std::filesystem::path& path, const LasPoints& p) {
    std::vector<std::string> fields = {"x_m", "y_m", "z_m"};
    for (const auto& a : p.attributes) fields.push_back(a.name);
    std::string text = csv_line(fields);
    for (std::size_t i = 0; i < p.xyz.size(); ++i) {
        fields.clear();
        for (int k = 0; k < 3; ++k) fields.push_back(csv_number(p.xyz[i][k]));
        for (const auto& a : p.attributes) fields.push_back(csv_number(a.values[i]));
        append_csv_line(text, fields);
    }
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) throw Error("cannot write " + path.string());
}

}  // namespace

int run_export(const ExportOptions& o) {
    return run_reporting_errors("export", [&] {
        const bool las = ends_with(o.out, ".las");
        if (!las && !ends_with(o.out, ".csv")) {
            throw Error("--out " + o.out + ": name a .las or a .csv file");
        }
        // The coordinate system: --crs, or the site's [station] crs.
        std::string crs = o.crs;
        if (crs.empty() && !o.read.config.empty()) crs = load_config(o.read.config).station.crs;
        const std::string wkt = crs.empty() ? "" : coordinate_system_wkt(crs);
        const auto db = open_for_reading(o.read);
        LasPoints points = o.campaign > 0
                               ? campaign_result_points(db, o.campaign)
                               : epoch_result_points(db, o.epoch, parse_result_map(o.map));
        points.wkt = wkt;
        if (las) {
            write_las(o.out, points);
        } else {
            write_csv(o.out, points);
        }
        std::cout << "wrote " << points.xyz.size() << " points with " << points.attributes.size()
                  << " attributes to " << o.out << "\n";
    });
}

}  // namespace tlsmon
