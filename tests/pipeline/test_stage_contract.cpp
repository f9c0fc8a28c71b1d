// The stage contract (pipeline/stage.hpp) carries a new analysis without touching the
// pipeline: a stage written here — the points per zone — joins the site's list, prepares its
// reference product once (cached), measures each epoch and its rows are committed with the
// epoch's, in the order of the list.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "core/payload.hpp"
#include "pipeline/site_stages.hpp"
#include "pipeline_site.hpp"

namespace tlsmon::test {
namespace {

// The reference's points per zone (the product) and the epoch's (the rows).
struct ZonePointCounts {
    static constexpr const char* kStage = "zone_point_count";
    static constexpr int kFormatVersion = 1;
    std::vector<std::uint64_t> counts;  // per zone, in the configuration's order

    std::string encode() const {
        PayloadWriter w;
        w.put_array(counts);
        return w.take();
    }
    static ZonePointCounts decode(std::string_view payload) {
        PayloadReader r(payload);
        ZonePointCounts c{r.get_array<std::uint64_t>()};
        r.finish();
        return c;
    }
};

std::vector<std::uint64_t> count_in_zones(const std::vector<Scan>& scans,
                                          const std::vector<ZoneShape>& zones) {
    std::vector<std::uint64_t> counts(zones.size(), 0);
    for (const auto& s : scans)
        for (const auto& p : s.xyz)
            for (std::size_t z = 0; z < zones.size(); ++z) counts[z] += zones[z].contains(p);
    return counts;
}

class ZonePointCountStage final : public ReferenceStage<ZonePointCounts> {
  public:
    explicit ZonePointCountStage(std::vector<ZoneShape> zones) : zones_(std::move(zones)) {}
    const char* name() const override { return "zone_point_count"; }
    std::string reference_parameters() const override {
        std::string names;
        for (const auto& z : zones_) names += z.name + ";";
        return names;
    }
    ZonePointCounts prepare_reference(const std::vector<Scan>& scans) const override {
        return {count_in_zones(scans, zones_)};
    }
    StageVerdict measure(StageContext& ctx, const ZonePointCounts& reference) const override {
        const auto counts = count_in_zones(*ctx.input.scans, zones_);
        for (std::size_t z = 0; z < zones_.size(); ++z) {
            ZoneResult r;
            r.zone = zones_[z].name;
            r.quantity = "point_count_change";
            r.value = double(counts[z]) - double(reference.counts[z]);
            r.n = static_cast<std::int64_t>(counts[z]);
            ctx.results.zone_results.push_back(r);
        }
        return StageVerdict{"", std::to_string(zones_.size()) + " zones counted"};
    }

  private:
    std::vector<ZoneShape> zones_;
};

TEST(StageContract, AStageOfItsOwnJoinsTheListAndItsRowsAreCommitted) {
    PipelineSite site;
    // Columns x = 0, 0.5, 1, 1.5 of the 21 x 21 grid: 84 points of the reference.
    site.config.zones = {box_zone("west_strip", {-0.1, -0.1, -1.0}, {1.9, 10.1, 1.0})};
    for (const auto& z : site.config.zones) site.db->site().upsert_zone(z.name, "{}");
    site.config.stages = site_stages(site.config);
    site.config.stages.push_back(std::make_shared<ZonePointCountStage>(site.config.zones));

    const Epoch e0 = site.add_epoch("e0.xyz", 1000);
    // Moved 0.6 m east: columns x = 0.6, 1.1, 1.6 inside, 63 points.
    const Epoch e1 = site.add_epoch("e1.xyz", 2000, 0.0, {0.6, 0.0, 0.0});
    ReferenceCache cache(*site.db);
    ASSERT_EQ(site.process(e0, cache), EpochOutcome::done);
    ASSERT_EQ(site.process(e1, cache), EpochOutcome::done);

    const auto points = site.db->series().points("west_strip", "point_count_change", {});
    ASSERT_EQ(points.size(), 2u);
    EXPECT_EQ(points[0].value, 0.0);
    EXPECT_EQ(points[0].n, 84);
    EXPECT_EQ(points[1].value, 63.0 - 84.0);
    EXPECT_EQ(points[1].n, 63);
    // The product was prepared once and then reused, beside the coverage extent.
    EXPECT_EQ(cache.counters().built, 2);
    EXPECT_EQ(cache.counters().from_memory, 2);
    // Listed after the site's stages, with its note.
    const auto stages = site.db->series().stages(e1.id);
    ASSERT_EQ(stages.size(), 3u);
    EXPECT_EQ(stages[2].stage, "zone_point_count");
    EXPECT_EQ(stages[2].note, "1 zones counted");
}

TEST(StageContract, TheSiteListFollowsTheConfiguration) {
    PipelineConfig config;
    const auto names = [](const StageList& list) {
        std::vector<std::string> out;
        for (const auto& s : list) out.emplace_back(s->name());
        return out;
    };
    // No zones: M3C2 and the zone keypoints have nothing to measure.
    EXPECT_EQ(names(site_stages(config)), (std::vector<std::string>{"coverage", "registration"}));
    config.m3c2.zones = {box_zone("z", {0, 0, 0}, {1, 1, 1})};
    config.keypoints.zones = config.m3c2.zones;
    EXPECT_EQ(names(site_stages(config)),
              (std::vector<std::string>{"coverage", "registration", "m3c2", "keypoints"}));
    // Patch-based M3C2 when enabled, with zones (off by default).
    config.pbm3c2.enabled = true;
    EXPECT_EQ(names(site_stages(config)),
              (std::vector<std::string>{"coverage", "registration", "m3c2", "keypoints"}));
    config.pbm3c2.zones = config.m3c2.zones;
    EXPECT_EQ(
        names(site_stages(config)),
        (std::vector<std::string>{"coverage", "registration", "m3c2", "pbm3c2", "keypoints"}));
    // The primitives when a zone names one (enabled by default).
    config.primitives.zones = {{config.m3c2.zones[0], primitives::Kind::cylinder}};
    EXPECT_EQ(names(site_stages(config)),
              (std::vector<std::string>{"coverage", "registration", "m3c2", "pbm3c2", "primitives",
                                        "keypoints"}));
    config.primitives.zones.clear();
    config.pbm3c2.enabled = false;
    config.m3c2.enabled = false;
    config.keypoints.zones.clear();
    config.keypoints.segments = KeypointSegments::bands;  // bands need no zone
    EXPECT_EQ(names(site_stages(config)),
              (std::vector<std::string>{"coverage", "registration", "keypoints"}));
}

TEST(StageContract, TheDocsTableListsTheSiteStagesInOrder) {
    std::ifstream in(std::string(TLSMON_SOURCE_DIR) + "/docs/pipeline.md");
    ASSERT_TRUE(in) << "docs/pipeline.md";
    std::vector<std::string> documented;
    bool table = false;
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("| stage | what it does | rejects when |", 0) == 0) table = true;
        if (!table || line.rfind("| `", 0) != 0) {
            if (table && !documented.empty() && line.empty()) break;
            continue;
        }
        documented.push_back(line.substr(3, line.find('`', 3) - 3));
    }
    PipelineConfig config;  // every stage configured
    config.m3c2.zones = {box_zone("z", {0, 0, 0}, {1, 1, 1})};
    config.pbm3c2.enabled = true;
    config.pbm3c2.zones = config.m3c2.zones;
    config.primitives.zones = {{config.m3c2.zones[0], primitives::Kind::cylinder}};
    config.vectors.enabled = true;
    config.vectors.zones = config.m3c2.zones;
    config.keypoints.zones = config.m3c2.zones;
    config.thermal.enabled = true;
    std::vector<std::string> listed;
    for (const auto& s : site_stages(config)) listed.emplace_back(s->name());
    EXPECT_EQ(documented, listed);
}

}  // namespace
}  // namespace tlsmon::test
