// `tlsmon export (--epoch N [--map m3c2|pbm3c2|vectors|zones] | --campaign N) --out FILE`: one
// stored map's per-point results as LAS 1.4 (point format 6, every attribute as extra bytes),
// CSV or GeoJSON, or an epoch's zones with their values as CSV or GeoJSON, by the file's
// extension (docs/export.md). LAS and GeoJSON files name the site's coordinate system when it
// has one.
#include <array>
#include <cctype>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/query_output.hpp"
#include "config/config.hpp"
#include "core/csv.hpp"
#include "core/utc_time.hpp"
#include "formats/coordinate_system.hpp"
#include "formats/geojson_writer.hpp"
#include "formats/las_writer.hpp"
#include "pipeline/result_points.hpp"

namespace tlsmon {

namespace {

enum class FileKind { las, csv, geojson };

FileKind file_kind(const std::string& out) {
    std::string ext = std::filesystem::path(out).extension().string();
    for (auto& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    if (ext == ".las") return FileKind::las;
    if (ext == ".csv") return FileKind::csv;
    if (ext == ".geojson") return FileKind::geojson;
    throw Error("--out " + out + ": name a .las, .csv or .geojson file");
}

void write_text(const std::filesystem::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
    out.close();
    if (!out) throw Error("cannot write " + path.string());
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
    write_text(path, text);
}

struct ZoneFeature {
    std::string geometry;  // GeoJSON text; "null" for a zone without a place in the frame
    GeoJsonProperties properties;
};

// A zone's footprint in x, y from its stored definition (config/site_definition.cpp): a
// box's rectangle or a prism's polygon, with its heights; none for the keypoint bands
// (slices of vertical angle, not of the project frame).
std::string zone_geometry(const nlohmann::json& d, GeoJsonProperties& properties) {
    if (!d.contains("min") || !d.contains("max")) return "null";
    const auto min = d.at("min").get<std::array<double, 3>>();
    const auto max = d.at("max").get<std::array<double, 3>>();
    properties.emplace_back("z_min_m", min[2]);
    properties.emplace_back("z_max_m", max[2]);
    std::vector<std::pair<double, double>> ring;
    if (d.contains("polygon")) {
        for (const auto& v : d.at("polygon")) ring.emplace_back(v.at(0), v.at(1));
    } else {
        ring = {{min[0], min[1]}, {max[0], min[1]}, {max[0], max[1]}, {min[0], max[1]}};
    }
    return geojson_polygon(ring);
}

// Every zone the epoch has values for: its footprint, and per quantity Q the properties Q,
// Q_uncertainty, Q_n and Q_significant.
std::vector<ZoneFeature> zone_features(const EpochDatabase& db, EpochId id) {
    const auto epoch = db.epochs().find(id);
    if (!epoch) throw Error("epoch " + std::to_string(id) + " does not exist");
    std::vector<ZoneFeature> features;
    std::string zone;
    for (const auto& v : db.series().epoch_zone_values(id)) {
        if (features.empty() || v.zone != zone) {
            zone = v.zone;
            ZoneFeature f;
            f.properties = {{"zone", v.zone},
                            {"epoch", static_cast<std::int64_t>(id)},
                            {"acquired", format_utc(epoch->acquired)}};
            f.geometry = zone_geometry(nlohmann::json::parse(v.definition), f.properties);
            features.push_back(std::move(f));
        }
        auto& p = features.back().properties;
        p.emplace_back(v.quantity, v.value);
        p.emplace_back(v.quantity + "_uncertainty",
                       v.uncertainty ? GeoJsonValue(*v.uncertainty) : GeoJsonValue());
        p.emplace_back(v.quantity + "_n", v.n);
        p.emplace_back(v.quantity + "_significant", v.significant);
    }
    if (features.empty()) throw Error("epoch " + std::to_string(id) + " has no zone values");
    return features;
}

std::string csv_text(const GeoJsonValue& v) {
    if (const auto* s = std::get_if<std::string>(&v)) return *s;
    if (const auto* d = std::get_if<double>(&v)) return csv_number(*d);
    if (const auto* i = std::get_if<std::int64_t>(&v)) return std::to_string(*i);
    if (const auto* b = std::get_if<bool>(&v)) return *b ? "1" : "0";
    return "";
}

// One row per zone; the columns are every property any zone has, in order of first
// appearance (zones measured by different stages have different quantities).
void write_zones_csv(const std::filesystem::path& path, const std::vector<ZoneFeature>& zones) {
    std::vector<std::string> columns;
    std::map<std::string, std::size_t> column_of;
    for (const auto& z : zones)
        for (const auto& [key, value] : z.properties)
            if (column_of.emplace(key, columns.size()).second) columns.push_back(key);
    std::string text = csv_line(columns);
    for (const auto& z : zones) {
        std::vector<std::string> fields(columns.size());
        for (const auto& [key, value] : z.properties) fields[column_of.at(key)] = csv_text(value);
        append_csv_line(text, fields);
    }
    write_text(path, text);
}

}  // namespace

int run_export(const ExportOptions& o) {
    return run_reporting_errors("export", [&] {
        const FileKind kind = file_kind(o.out);
        const bool zones = o.campaign <= 0 && o.map == "zones";
        if (zones && kind == FileKind::las) {
            throw Error("--map zones: zones are areas, not points; write a .geojson or .csv file");
        }
        // The coordinate system: --crs, or the site's [station] crs.
        std::string crs = o.crs;
        if (crs.empty() && !o.read.config.empty()) crs = load_config(o.read.config).station.crs;
        const CoordinateSystem system = crs.empty() ? CoordinateSystem{} : coordinate_system(crs);
        const auto db = open_for_reading(o.read);
        if (zones) {
            const auto features = zone_features(db, o.epoch);
            if (kind == FileKind::csv) {
                write_zones_csv(o.out, features);
            } else {
                GeoJsonWriter w(o.out, geojson_crs_name(system.urn, system.wkt));
                for (const auto& f : features) w.feature(f.geometry, f.properties);
                w.finish();
            }
            std::cout << "wrote " << features.size() << " zones to " << o.out << "\n";
            return;
        }
        LasPoints points = o.campaign > 0
                               ? campaign_result_points(db, o.campaign)
                               : epoch_result_points(db, o.epoch, parse_result_map(o.map));
        points.wkt = system.wkt;
        switch (kind) {
            case FileKind::las:
                write_las(o.out, points);
                break;
            case FileKind::csv:
                write_csv(o.out, points);
                break;
            case FileKind::geojson:
                write_geojson_points(o.out, points, geojson_crs_name(system.urn, system.wkt));
                break;
        }
        std::cout << "wrote " << points.xyz.size() << " points with " << points.attributes.size()
                  << " attributes to " << o.out << "\n";
    });
}

}  // namespace tlsmon
