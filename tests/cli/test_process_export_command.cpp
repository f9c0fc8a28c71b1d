// `tlsmon export`: the built binary on a database the pipeline filled with a plate lifted
// 4 mm far from the origin (UTM-sized coordinates, as a site's project frame may be). The LAS
// file is read back by tlsmon's own reader and by an independent one (copc.js), and every
// coordinate and attribute is compared with what the database stores; the CSV holds the same.
#include <gtest/gtest.h>

#include <cmath>

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

TEST(ExportCommand, M3c2MapAsLasWithExtraBytesReadsBackInTwoReadersAndAsCsv) {
    PipelineSite site;
    measure_the_plate(site);
    const Epoch e0 = site.add_epoch("e0.xyz", 1'780'000'000, 0.0, kFarAway);
    const Epoch e1 = site.add_epoch("e1.xyz", 1'780'000'900, 0.004, kFarAway);
    {
        ReferenceCache cache(*site.db);
        ASSERT_EQ(site.process(e0, cache), EpochOutcome::done);
        ASSERT_EQ(site.process(e1, cache), EpochOutcome::done);
    }
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
    const Epoch e0 = site.add_epoch("e0.xyz", 1'780'000'000, 0.0, kFarAway);
    {
        ReferenceCache cache(*site.db);
        ASSERT_EQ(site.process(e0, cache), EpochOutcome::done);
    }
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
            "name a .las or a .csv file");
    refused("--campaign 3 --out " + out.string(), "no campaign 3");
    refused("--out " + out.string(), "give --epoch or --campaign");
    refused("--epoch 1 --campaign 1 --out " + out.string(), "excludes");
}

}  // namespace
}  // namespace tlsmon::test
