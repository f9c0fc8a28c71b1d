// `tlsmon query corepoints`: the built binary on a database the pipeline filled with a plate
// lifted 4 mm (tests/pipeline/test_m3c2_stage.cpp's construction): one CSV row per core
// point with its position, normal, distance, LoD and zones; clear errors otherwise.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "tests/pipeline/pipeline_site.hpp"
#include "tests/support/run_tlsmon.hpp"

namespace tlsmon::test {
namespace {

std::vector<std::string> fields(const std::string& line) {
    std::vector<std::string> out;
    std::istringstream in(line);
    for (std::string f; std::getline(in, f, ',');) out.push_back(f);
    return out;
}

TEST(QueryCorePoints, WritesOneRowPerCorePointOfTheEpoch) {
    PipelineSite site;
    M3c2Config& c = site.config.m3c2;
    c = plate_m3c2_config();
    c.zones = {box_zone("plate", {-0.1, -0.1, -1.0}, {10.1, 10.1, 1.0}),
               prism_zone("triangle", {{0, 0}, {10, 0}, {0, 10}}, -1.0, 1.0)};
    for (const auto& z : c.zones) site.db->site().upsert_zone(z.name, "{}");
    const Epoch e0 = site.add_epoch("e0.xyz", 1000);
    const Epoch e1 = site.add_epoch("e1.xyz", 2000, 0.004);
    {
        ReferenceCache cache(*site.db);
        ASSERT_EQ(site.process(e0, cache), EpochOutcome::done);
        ASSERT_EQ(site.process(e1, cache), EpochOutcome::done);
    }
    const auto db = site.dir / "tlsmon.sqlite";
    const auto out = site.dir / "e1.csv";
    const CommandRun r = run_tlsmon("query corepoints --db " + db.string() + " --epoch " +
                                    std::to_string(e1.id) + " --out " + out.string());
    ASSERT_EQ(r.status, 0) << r.out;
    std::ifstream in(out);
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line,
              "core,x,y,z,nx,ny,nz,normal_radius,spread1,distance,lod95,n1,n2,significant,zones");
    int rows = 0, in_triangle = 0;
    while (std::getline(in, line)) {
        const auto f = fields(line);
        ASSERT_EQ(f.size(), 15u) << line;
        ++rows;
        const double x = std::stod(f[1]), y = std::stod(f[2]);
        EXPECT_NEAR(std::stod(f[6]), 1.0, 1e-9) << line;  // nz
        EXPECT_EQ(std::stod(f[7]), 1.5) << line;
        EXPECT_NEAR(std::stod(f[8]), 0.0, 1e-9) << line;  // a flat plate: no spread
        EXPECT_NEAR(std::stod(f[9]), 0.004, 1e-6) << line;
        EXPECT_NEAR(std::stod(f[10]), 1.96e-3, 1e-6) << line;
        EXPECT_EQ(f[13], "true") << line;
        const bool triangle = x + y <= 10.0;
        in_triangle += triangle;
        EXPECT_EQ(f[14], triangle ? "plate;triangle" : "plate") << line;
    }
    EXPECT_EQ(rows, 36);
    EXPECT_EQ(in_triangle, 15);

    const CommandRun none = run_tlsmon("query corepoints --db " + db.string() + " --epoch 99");
    EXPECT_EQ(none.status, 1);
    EXPECT_NE(none.out.find("no epoch 99"), std::string::npos) << none.out;
}

}  // namespace
}  // namespace tlsmon::test
