// `tlsmon export`: the built binary on a database the pipeline filled with a plate lifted
// 4 mm far from the origin (UTM-sized coordinates, as a site's project frame may be). The LAS
// file is read back by tlsmon's own reader and by an independent one (copc.js), and every
// coordinate and attribute is compared with what the database stores; the CSV holds the same.
#include <SQLiteCpp/SQLiteCpp.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <regex>

#include "config/site_definition.hpp"
#include "core/utc_time.hpp"
#include "formats/las_reader.hpp"
#include "pipeline/core_point_map.hpp"
#include "tests/pipeline/pipeline_site.hpp"
#include "tests/support/csv_cells.hpp"
#include "tests/support/independent_las.hpp"
#include "tests/support/run_tlsmon.hpp"

namespace tlsmon::test {
namespace {

const Eigen::Vector3d kFarAway(512345.0, 5432109.0, 250.0);

// What the database stores for the epoch, column by column as the export names them.
struct Stored {
    std::vector<Eigen::Vector3d> xyz;
    std::map<std::string, std::vector<double>> columns;
};

Stored stored_map(const std::filesystem::path& db_path, EpochId epoch) {
    const auto db = EpochDatabase::open(db_path, EpochDatabase::Mode::read_only);
    const CorePointMap m = read_core_point_map(db, epoch);
    Stored s;
    const auto& ref = m.reference.reference;
    for (std::size_t k = 0; k < ref.size(); ++k) {
        s.xyz.push_back(ref.core_points()[k]);
        const Eigen::Vector3d n = ref.normals()[k];
        s.columns["m3c2_distance_m"].push_back(m.distance[k]);
        s.columns["m3c2_lod95_m"].push_back(m.lod95[k]);
        s.columns["significant"].push_back(std::abs(m.distance[k]) > m.lod95[k] ? 1 : 0);
        s.columns["normal_x"].push_back(static_cast<float>(n.x()));
        s.columns["normal_y"].push_back(static_cast<float>(n.y()));
        s.columns["normal_z"].push_back(static_cast<float>(n.z()));
        s.columns["m3c2_n1"].push_back(m.n1[k]);
        s.columns["m3c2_n2"].push_back(m.n2[k]);
        s.columns["spread1_m"].push_back(static_cast<float>(ref.reference_side[k].spread));
        s.columns["normal_radius_m"].push_back(static_cast<float>(ref.normal_radius[k]));
    }
    return s;
}

// M3C2 on the plate of PipelineSite::add_epoch (10 m × 10 m, 0.5 m grid) at kFarAway: a core
// point every 2 m, normals up.
void measure_the_plate(PipelineSite& site) {
    M3c2Config& c = site.config.m3c2;
    c = plate_m3c2_config();
    c.zones = {box_zone("plate", kFarAway + Eigen::Vector3d(-0.1, -0.1, -1.0),
                        kFarAway + Eigen::Vector3d(10.1, 10.1, 1.0))};
    for (const auto& z : c.zones) site.db->site().upsert_zone(z.name, "{}");
}

// `count` epochs of the plate 15 minutes apart, epoch i lifted by i · `lift`, processed.
std::vector<Epoch> lifted_plates(PipelineSite& site, int count, double lift) {
    std::vector<Epoch> epochs;
    for (int i = 0; i < count; ++i) {
        epochs.push_back(site.add_epoch("e" + std::to_string(i) + ".xyz", 1'780'000'000 + 900 * i,
                                        lift * i, kFarAway));
    }
    ReferenceCache cache(*site.db);
    for (const auto& e : epochs) EXPECT_EQ(site.process(e, cache), EpochOutcome::done) << e.id;
    return epochs;
}

TEST(ExportCommand, M3c2MapAsLasWithExtraBytesReadsBackInTwoReadersAndAsCsv) {
    PipelineSite site;
    measure_the_plate(site);
    const Epoch e1 = lifted_plates(site, 2, 0.004)[1];
    const auto db = site.dir / "tlsmon.sqlite";
    const auto las = site.dir / "e1.las";
    const auto csv = site.dir / "e1.csv";
    const std::string args = " --db " + db.string() + " --epoch " + std::to_string(e1.id);
    const CommandRun r = run_tlsmon("export" + args + " --out " + las.string());
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_NE(r.out.find("wrote 36 points with 10 attributes"), std::string::npos) << r.out;
    ASSERT_EQ(run_tlsmon("export" + args + " --map m3c2 --out " + csv.string()).status, 0);

    const Stored s = stored_map(db, e1.id);
    ASSERT_EQ(s.xyz.size(), 36u);
    // Every stored core point lifted by 4 mm: the values compared below are not all zero.
    for (double d : s.columns.at("m3c2_distance_m")) ASSERT_NEAR(d, 0.004, 1e-6);

    // tlsmon's reader: coordinates to the file's 1 µm step, attributes exactly (float32 as
    // stored), the epoch's acquisition as every point's GPS time.
    const LasPoints own = read_las_points(las);
    ASSERT_EQ(own.xyz.size(), s.xyz.size());
    for (std::size_t k = 0; k < s.xyz.size(); ++k)
        EXPECT_LE((own.xyz[k] - s.xyz[k]).cwiseAbs().maxCoeff(), 0.5e-6 + 1e-9) << k;
    ASSERT_EQ(own.attributes.size(), s.columns.size());
    for (const auto& a : own.attributes) {
        SCOPED_TRACE(a.name);
        ASSERT_TRUE(s.columns.count(a.name));
        EXPECT_LE(a.description.size(), 32u);
        EXPECT_FALSE(a.description.empty());
        const auto& expected = s.columns.at(a.name);
        ASSERT_EQ(a.values.size(), expected.size());
        for (std::size_t k = 0; k < expected.size(); ++k) EXPECT_EQ(a.values[k], expected[k]) << k;
    }
    ASSERT_TRUE(own.acquired_utc.has_value());
    EXPECT_NEAR(*own.acquired_utc, double(e1.acquired), 1e-3);
    EXPECT_TRUE(own.wkt.empty());

    // copc.js: LAS 1.4, point format 6, the WKT bit required for formats 6–10 and the GPS
    // time bit; µm scale; the same values by name.
    const nlohmann::json other = read_las_independently(las);
    EXPECT_EQ(other.at("version"), "1.4");
    EXPECT_EQ(other.at("format"), 6);
    EXPECT_EQ(other.at("pointCount"), 36);
    EXPECT_EQ(other.at("globalEncoding").get<int>(), 0x11);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(other.at("scale")[k].get<double>(), 1e-6);
    const auto& points = other.at("points");
    for (std::size_t k = 0; k < s.xyz.size(); ++k) {
        for (int a = 0; a < 3; ++a) {
            EXPECT_NEAR(points.at(std::string(1, "XYZ"[a]))[k].get<double>(), s.xyz[k][a],
                        0.5e-6 + 1e-9);
        }
        EXPECT_EQ(points.at("ReturnNumber")[k], 1);
        EXPECT_EQ(points.at("NumberOfReturns")[k], 1);
    }
    ASSERT_EQ(other.at("extraBytes").size(), s.columns.size());
    for (const auto& [name, expected] : s.columns) {
        SCOPED_TRACE(name);
        ASSERT_TRUE(points.contains(name));
        for (std::size_t k = 0; k < expected.size(); ++k)
            EXPECT_EQ(las_number(points.at(name)[k]), expected[k]) << k;
    }
    // Adjusted Standard GPS time: GPS seconds − 1e9 (18 leap seconds ahead of UTC since 2017).
    const double gps = double(e1.acquired) - 315964800.0 + 18.0 - 1e9;
    EXPECT_NEAR(points.at("GpsTime")[0].get<double>(), gps, 1e-3);

    // The CSV: the same columns, the coordinates at full precision.
    const auto rows = csv_cells(read_file(csv));
    ASSERT_EQ(rows.size(), s.xyz.size() + 1);
    ASSERT_EQ(rows[0].size(), 3 + s.columns.size());
    EXPECT_EQ(rows[0][0], "x_m");
    for (std::size_t k = 0; k < s.xyz.size(); ++k) {
        for (int a = 0; a < 3; ++a) EXPECT_EQ(std::stod(rows[k + 1][std::size_t(a)]), s.xyz[k][a]);
        for (std::size_t col = 3; col < rows[0].size(); ++col) {
            EXPECT_EQ(std::stod(rows[k + 1][col]), s.columns.at(rows[0][col])[k]) << rows[0][col];
        }
    }
}

// The site's [station] crs (or --crs) becomes the LAS file's OGC WKT record, as PROJ writes
// the system; the CSV has no place for it.
TEST(ExportCommand, TheSitesCoordinateSystemIsTheLasFilesWkt) {
    PipelineSite site;
    measure_the_plate(site);
    const Epoch e0 = lifted_plates(site, 1, 0.0)[0];
    const auto config = site.dir / "site.toml";
    write_file(config, "[station]\ncrs = \"EPSG:25832\"\n[paths]\ndatabase = \"" +
                           (site.dir / "tlsmon.sqlite").string() + "\"\n");
    const auto las = site.dir / "e0.las";
    const std::string epoch = " --epoch " + std::to_string(e0.id) + " --out " + las.string();
    const CommandRun r = run_tlsmon("export --config " + config.string() + epoch);
    ASSERT_EQ(r.status, 0) << r.out;
    const std::string utm32 = "PROJCS[\"ETRS89 / UTM zone 32N\",GEOGCS[\"ETRS89\"";
    EXPECT_EQ(read_las_points(las).wkt.rfind(utm32, 0), 0u) << read_las_points(las).wkt;
    const nlohmann::json other = read_las_independently(las);
    EXPECT_EQ(other.at("wkt").get<std::string>().rfind(utm32, 0), 0u) << other.at("wkt");
    EXPECT_EQ(other.at("vlrs")[1].at("user"), "LASF_Projection");
    EXPECT_EQ(other.at("vlrs")[1].at("record"), 2112);
    EXPECT_NE(other.at("wkt").get<std::string>().find("AUTHORITY[\"EPSG\",\"25832\"]"),
              std::string::npos);
    // --crs names another system for this file.
    ASSERT_EQ(run_tlsmon("export --config " + config.string() + epoch + " --crs EPSG:31467").status,
              0);
    EXPECT_EQ(read_las_points(las).wkt.rfind("PROJCS[\"DHDN / 3-degree Gauss-Kruger zone 3\"", 0),
              0u);
    const CommandRun bad =
        run_tlsmon("export --config " + config.string() + epoch + " --crs bogus");
    EXPECT_NE(bad.status, 0);
    EXPECT_NE(bad.out.find("'bogus' is not a coordinate reference system PROJ knows"),
              std::string::npos)
        << bad.out;
}

// GDAL/OGR as the independent reader of GeoJSON: `ogr2ogr` turns a file into CSV with the
// geometry as WKT (GDAL 3.6's ogrinfo has no JSON output yet); `ogrinfo -so` its summary.
std::vector<std::vector<std::string>> read_geojson_with_ogr(const fs::path& file) {
    const CommandRun r = run_tlsmon_at(
        "ogr2ogr", "-f CSV /vsistdout/ " + file.string() + " -lco GEOMETRY=AS_WKT", false);
    EXPECT_EQ(r.status, 0) << r.out;
    return csv_cells(r.out);
}

std::size_t column(const std::vector<std::string>& header, const std::string& name) {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name;
    return static_cast<std::size_t>(it - header.begin());
}

// The numbers of a WKT geometry's text, in order.
std::vector<double> wkt_numbers(const std::string& wkt) {
    std::vector<double> out;
    const std::regex number(R"([-+]?[0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)");
    for (auto it = std::sregex_iterator(wkt.begin(), wkt.end(), number);
         it != std::sregex_iterator(); ++it)
        out.push_back(std::stod(it->str()));
    return out;
}

// An epoch's zones (a box and a prism, as the configuration stores them) and its M3C2 map
// as GeoJSON, read back by GDAL/OGR: the site's system named, each zone's footprint and
// every value equal to the database's; the points' coordinates and attributes likewise.
TEST(ExportCommand, ZonesAndPointsAsGeoJsonReadByOgr) {
    PipelineSite site;
    measure_the_plate(site);
    // Stored as the daemon stores the configuration's zones (config/site_definition.cpp).
    const Eigen::Vector3d o = kFarAway;
    ZoneConfig plate;
    plate.name = "plate";
    plate.min = {o.x() - 0.1, o.y() - 0.1, o.z() - 1};
    plate.max = {o.x() + 10.1, o.y() + 10.1, o.z() + 1};
    ZoneConfig west = plate;
    west.name = "plate west triangle";
    west.polygon = {
        {o.x() - 0.1, o.y() - 0.1}, {o.x() + 5, o.y() - 0.1}, {o.x() - 0.1, o.y() + 10.1}};
    west.max[0] = o.x() + 5;
    site.config.m3c2.zones.clear();
    for (const ZoneConfig& z : {plate, west}) {
        site.config.m3c2.zones.push_back(zone_shape(z));
        site.db->site().upsert_zone(z.name, zone_json(z));
    }
    const auto box = site.config.m3c2.zones[0].box;
    const auto& tri = site.config.m3c2.zones[1];
    const std::vector<Epoch> epochs = lifted_plates(site, 2, 0.004);
    const Epoch e1 = epochs[1];
    const auto db = site.dir / "tlsmon.sqlite";
    const auto config = site.dir / "site.toml";
    write_file(config,
               "[station]\ncrs = \"EPSG:25832\"\n[paths]\ndatabase = \"" + db.string() + "\"\n");
    const std::string args = " --config " + config.string() + " --epoch " + std::to_string(e1.id);
    const auto zones = site.dir / "zones.geojson";
    CommandRun r = run_tlsmon("export" + args + " --map zones --out " + zones.string());
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_NE(r.out.find("wrote 2 zones"), std::string::npos) << r.out;

    const CommandRun summary = run_tlsmon_at("ogrinfo", "-ro -so -al " + zones.string(), false);
    ASSERT_EQ(summary.status, 0) << summary.out;
    EXPECT_NE(summary.out.find("Geometry: Polygon"), std::string::npos) << summary.out;
    EXPECT_NE(summary.out.find("Feature Count: 2"), std::string::npos) << summary.out;
    EXPECT_NE(summary.out.find("ETRS89 / UTM zone 32N"), std::string::npos) << summary.out;

    // Every value as the database has it, read back through OGR.
    const auto rows = read_geojson_with_ogr(zones);
    ASSERT_EQ(rows.size(), 3u);
    const auto& header = rows[0];
    std::vector<EpochZoneValue> stored;
    {
        const auto reader = EpochDatabase::open(db, EpochDatabase::Mode::read_only);
        stored = reader.series().epoch_zone_values(e1.id);
    }
    ASSERT_GE(stored.size(), 4u);
    std::size_t checked = 0;
    for (std::size_t i = 1; i < rows.size(); ++i) {
        const auto& row = rows[i];
        const std::string name = row[column(header, "zone")];
        SCOPED_TRACE(name);
        EXPECT_EQ(row[column(header, "epoch")], std::to_string(e1.id));
        EXPECT_EQ(row[column(header, "acquired")], "2026/05/28 20:41:40+00");  // OGR's DateTime
        for (const auto& v : stored) {
            if (v.zone != name) continue;
            EXPECT_NEAR(std::stod(row[column(header, v.quantity)]), v.value,
                        1e-12 + 1e-12 * std::abs(v.value))
                << v.quantity;
            const std::string u = row[column(header, v.quantity + "_uncertainty")];
            if (v.uncertainty) {
                EXPECT_NEAR(std::stod(u), *v.uncertainty, 1e-12 + 1e-12 * *v.uncertainty);
            } else {
                EXPECT_EQ(u, "") << v.quantity;  // null
            }
            EXPECT_EQ(row[column(header, v.quantity + "_n")], std::to_string(v.n));
            EXPECT_EQ(row[column(header, v.quantity + "_significant")],
                      v.significant ? "1" : "0");  // OGR's Boolean subtype
            ++checked;
        }
        // The footprint: the box's rectangle, the prism's triangle (closed, counter-clockwise).
        const auto xy = wkt_numbers(row[column(header, "WKT")]);
        if (name == "plate") {
            ASSERT_EQ(xy.size(), 10u);
            const double expected[] = {box.min().x(), box.min().y(), box.max().x(), box.min().y(),
                                       box.max().x(), box.max().y(), box.min().x(), box.max().y()};
            for (int k = 0; k < 8; ++k) EXPECT_NEAR(xy[std::size_t(k)], expected[k], 1e-9) << k;
        } else {
            ASSERT_EQ(xy.size(), 8u);
            for (int k = 0; k < 3; ++k) {
                EXPECT_NEAR(xy[2 * std::size_t(k)], tri.polygon[std::size_t(k)].x(), 1e-9);
                EXPECT_NEAR(xy[2 * std::size_t(k) + 1], tri.polygon[std::size_t(k)].y(), 1e-9);
            }
        }
        EXPECT_NEAR(std::stod(row[column(header, "z_min_m")]), box.min().z(), 1e-9);
    }
    EXPECT_EQ(checked, stored.size());
    for (const auto& v : stored) {
        if (v.quantity == "m3c2_median_m") {
            EXPECT_NEAR(v.value, 0.004, 1e-5) << v.zone;
        }
    }

    // The zones as CSV: the same values.
    const auto zones_csv = site.dir / "zones.csv";
    ASSERT_EQ(run_tlsmon("export" + args + " --map zones --out " + zones_csv.string()).status, 0);
    const auto csv_rows = csv_cells(read_file(zones_csv));
    ASSERT_EQ(csv_rows.size(), 3u);
    EXPECT_EQ(csv_rows[1][column(csv_rows[0], "zone")], "plate");

    // The M3C2 map as Point features with every attribute.
    const auto points = site.dir / "m3c2.geojson";
    r = run_tlsmon("export" + args + " --map m3c2 --out " + points.string());
    ASSERT_EQ(r.status, 0) << r.out;
    const Stored s = stored_map(db, e1.id);
    const auto prows = read_geojson_with_ogr(points);
    ASSERT_EQ(prows.size(), s.xyz.size() + 1);
    for (std::size_t k = 0; k < s.xyz.size(); ++k) {
        const auto& row = prows[k + 1];
        const auto xyz = wkt_numbers(row[column(prows[0], "WKT")]);
        ASSERT_EQ(xyz.size(), 3u);
        for (int a = 0; a < 3; ++a) EXPECT_NEAR(xyz[std::size_t(a)], s.xyz[k][a], 1e-8);
        for (const auto& [name, expected] : s.columns) {
            const double v = expected[k];
            EXPECT_NEAR(std::stod(row[column(prows[0], name)]), v, 1e-12 + 1e-12 * std::abs(v))
                << name << " " << k;
        }
    }

    // Without a site system the file says the frame is local, not WGS 84 degrees.
    const auto local = site.dir / "local.geojson";
    ASSERT_EQ(run_tlsmon("export --db " + db.string() + " --epoch " + std::to_string(e1.id) +
                         " --out " + local.string())
                  .status,
              0);
    const CommandRun frame = run_tlsmon_at("ogrinfo", "-ro -so -al " + local.string(), false);
    EXPECT_NE(frame.out.find("ENGCRS[\"tlsmon project frame\""), std::string::npos) << frame.out;
    EXPECT_EQ(frame.out.find("WGS 84"), std::string::npos) << frame.out;
}

// A window as a bundle: the extract holds the window's epochs and the reference, nothing
// dangling; a LAS map per analysed epoch equal to the source's; the series of the window;
// every file's checksum checked by coreutils' sha256sum.
TEST(ExportCommand, AWindowAsABundleOfExtractMapsSeriesAndChecksums) {
    PipelineSite site;
    measure_the_plate(site);
    const std::vector<Epoch> epochs = lifted_plates(site, 4, 0.002);
    site.db->events().record({1'780'000'000 + 100, "info", "before", "outside", std::nullopt});
    site.db->events().record(
        {1'780'000'000 + 1000, "info", "inside", "in the window", std::nullopt});
    const auto db = site.dir / "tlsmon.sqlite";
    const auto bundle = site.dir / "bundle";
    const std::string window =
        " --from " + format_utc(epochs[1].acquired) + " --to " + format_utc(epochs[2].acquired);
    CommandRun r =
        run_tlsmon("export --db " + db.string() + " --bundle " + bundle.string() + window);
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_NE(r.out.find("3 epochs, 0 campaigns, 2 map files"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(bundle.string() + ".part"));

    // Every file's checksum, the manifest's too.
    r = run_tlsmon_at("cd " + bundle.string() + " && sha256sum", "-c SHA256SUMS");
    EXPECT_EQ(r.status, 0) << r.out;
    EXPECT_NE(r.out.find("maps/epoch-000003-m3c2.las: OK"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("manifest.json: OK"), std::string::npos) << r.out;
    const auto manifest = nlohmann::json::parse(read_file(bundle / "manifest.json"));
    EXPECT_EQ(manifest.at("epochs"), 3);
    EXPECT_EQ(manifest.at("window").at("from"), format_utc(epochs[1].acquired));
    EXPECT_EQ(manifest.at("files").size(), 4u);             // database, two maps, series
    EXPECT_EQ(manifest.at("maps_not_written").size(), 4u);  // no PB-M3C2, no vectors
    EXPECT_NE(manifest.at("maps_not_written")[0].at("reason").get<std::string>().find("has no"),
              std::string::npos);

    // The extract: the window's epochs and the reference, every reference resolved, read by
    // tlsmon's reading commands.
    {
        SQLite::Database extract((bundle / "tlsmon.sqlite").string(), SQLite::OPEN_READONLY);
        EXPECT_EQ(extract.execAndGet("PRAGMA integrity_check").getString(), "ok");
        SQLite::Statement fk(extract, "PRAGMA foreign_key_check");
        EXPECT_FALSE(fk.executeStep());
        SQLite::Statement ids(extract, "SELECT id FROM epochs ORDER BY id");
        std::vector<std::int64_t> kept;
        while (ids.executeStep()) kept.push_back(ids.getColumn(0).getInt64());
        EXPECT_EQ(kept, (std::vector<std::int64_t>{epochs[0].id, epochs[1].id, epochs[2].id}));
        EXPECT_EQ(extract
                      .execAndGet("SELECT group_concat(kind) FROM system_events WHERE kind IN"
                                  " ('before', 'inside')")
                      .getString(),
                  "inside");
        EXPECT_EQ(extract
                      .execAndGet("SELECT count(*) FROM zone_results WHERE epoch_id = " +
                                  std::to_string(epochs[3].id))
                      .getInt(),
                  0);
    }
    r = run_tlsmon("query epochs --db " + (bundle / "tlsmon.sqlite").string() + " --format csv",
                   false);
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_EQ(csv_cells(r.out).size(), 4u);  // header and three epochs

    // The maps equal the source's stored values.
    for (int i : {1, 2}) {
        const Stored s = stored_map(db, epochs[std::size_t(i)].id);
        const LasPoints own =
            read_las_points(bundle / ("maps/epoch-00000" +
                                      std::to_string(epochs[std::size_t(i)].id) + "-m3c2.las"));
        ASSERT_EQ(own.xyz.size(), s.xyz.size());
        for (const auto& a : own.attributes) {
            for (std::size_t k = 0; k < a.values.size(); ++k) {
                const double expected = s.columns.at(a.name)[k];
                if (std::isnan(expected)) continue;
                EXPECT_EQ(a.values[k], expected) << a.name << " " << k;
            }
        }
        EXPECT_NEAR(s.columns.at("m3c2_distance_m")[0], 0.002 * i, 1e-5);
    }
    // The series: the window's two analysed epochs only.
    const auto rows = csv_cells(read_file(bundle / "series.csv"));
    ASSERT_GT(rows.size(), 1u);
    const std::size_t epoch_column = column(rows[0], "epoch");
    for (std::size_t i = 1; i < rows.size(); ++i) {
        EXPECT_TRUE(rows[i][epoch_column] == std::to_string(epochs[1].id) ||
                    rows[i][epoch_column] == std::to_string(epochs[2].id))
            << rows[i][epoch_column];
    }

    // Never over an existing folder; a window on a single-file export is refused.
    r = run_tlsmon("export --db " + db.string() + " --bundle " + bundle.string());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("exists already"), std::string::npos) << r.out;
    r = run_tlsmon("export --db " + db.string() + " --epoch 2 --out " +
                   (site.dir / "x.las").string() + window);
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.out.find("--from/--to choose the epochs of a --bundle"), std::string::npos)
        << r.out;
    r = run_tlsmon("export --db " + db.string() + " --bundle " + (site.dir / "b2").string() +
                   " --from " + format_utc(epochs[2].acquired) + " --to " +
                   format_utc(epochs[1].acquired));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.out.find("is after --to"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(site.dir / "b2"));
    EXPECT_FALSE(fs::exists(site.dir / "b2.part"));
}

TEST(ExportCommand, WhatCannotBeExportedIsAClearErrorAndWritesNothing) {
    PipelineSite site;
    const Epoch e0 = site.add_epoch("e0.xyz", 1'780'000'000);
    {
        ReferenceCache cache(*site.db);
        ASSERT_EQ(site.process(e0, cache), EpochOutcome::done);
    }
    const std::string db = " --db " + (site.dir / "tlsmon.sqlite").string();
    const auto out = site.dir / "out.las";
    const auto refused = [&](const std::string& args, const std::string& says) {
        const CommandRun r = run_tlsmon("export" + db + " " + args);
        EXPECT_NE(r.status, 0) << args;
        EXPECT_NE(r.out.find(says), std::string::npos) << args << ": " << r.out;
        EXPECT_FALSE(fs::exists(out)) << args;
        EXPECT_FALSE(fs::exists(out.string() + ".part")) << args;
    };
    refused("--epoch 99 --out " + out.string(), "no epoch 99");
    refused("--epoch " + std::to_string(e0.id) + " --map vectors --out " + out.string(),
            "has no 3-D vectors");
    refused("--epoch " + std::to_string(e0.id) + " --map pbm3c2 --out " + out.string(),
            "has no PB-M3C2 patches");
    refused("--epoch " + std::to_string(e0.id) + " --out " + (site.dir / "out.txt").string(),
            "name a .las, .csv or .geojson file");
    refused("--epoch " + std::to_string(e0.id) + " --map zones --out " + out.string(),
            "--map zones: zones are areas, not points; write a .geojson or .csv file");
    refused("--campaign 3 --out " + out.string(), "no campaign 3");
    refused("--out " + out.string(), "give --epoch or --campaign");
    refused("--epoch 1 --campaign 1 --out " + out.string(), "excludes");
}

}  // namespace
}  // namespace tlsmon::test
