// `tlsmon query stable-areas --as-zones`: the built binary on stable-area masks written through
// the storage API. A settling slope unstable in the last two epochs becomes a [[zone]] with its
// normal, a heap of patches facing every way one without, and what is not an area (a lone
// patch, patches inside a zone, patches unstable in one epoch only) none; the printed tables,
// added to the configuration, load as zones that hold the area's patches.
#include <gtest/gtest.h>

#include <cmath>

#include "config/config.hpp"
#include "storage/epoch_database.hpp"
#include "tests/support/run_tlsmon.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/text_file.hpp"

namespace tlsmon {
namespace {

constexpr UtcSeconds kT0 = 1772366400;  // 2026-03-01T12:00:00Z
constexpr std::uint8_t kStable = 0, kUnstable = 1;

const char* kConfig = R"([station]
name = "p3"
[paths]
ingest = "ingest"
archive = "archive"
quarantine = "quarantine"
database = "tlsmon.sqlite"
[registration]
method = "stable_areas"
stable_seed = 1.0
stable_persistent_epochs = 2
[[zone]]
name = "pier"
min = [-5.0, -5.0, 0.0]
max = [5.0, 5.0, 20.0]
normal = [0.0, -1.0, 0.0]
)";

struct Patch {
    Eigen::Vector3d centroid, normal;
    std::uint8_t last, before;  // the state in the newest epoch and in the one before
};

// A slope of 3 × 3 patches 1 m apart (normal up and south), settling; a heap of four facing
// every way, there since the epoch before; a lone unstable patch; four unstable inside the
// zone; three on the ground unstable in the newest epoch only; stable ground around.
std::vector<Patch> scene() {
    std::vector<Patch> p;
    const Eigen::Vector3d slope_normal = Eigen::Vector3d(0, -1, 2).normalized();
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            p.push_back({Eigen::Vector3d(20.0 + i, 30.0 + j, 4.0 + 0.5 * j), slope_normal,
                         kUnstable, kUnstable});
        }
    }
    const Eigen::Vector3d heap_normals[] = {{1, 0, 0}, {-1, 0, 0}, {0, 0, 1}, {0, 1, 0}};
    for (int k = 0; k < 4; ++k) {
        p.push_back(
            {Eigen::Vector3d(40.0 + 0.8 * k, -10.0, 1.0), heap_normals[k], kUnstable, kUnstable});
    }
    p.push_back({Eigen::Vector3d(-30, -30, 0), Eigen::Vector3d::UnitZ(), kUnstable, kUnstable});
    for (int k = 0; k < 4; ++k) {
        p.push_back(
            {Eigen::Vector3d(k, -4.9, 10.0), Eigen::Vector3d(0, -1, 0), kUnstable, kUnstable});
    }
    for (int k = 0; k < 3; ++k) {
        p.push_back(
            {Eigen::Vector3d(-20.0 + k, 10, 0), Eigen::Vector3d::UnitZ(), kUnstable, kStable});
    }
    for (int k = 0; k < 20; ++k) {
        p.push_back(
            {Eigen::Vector3d(-15.0 + k, -20, 0), Eigen::Vector3d::UnitZ(), kStable, kStable});
    }
    return p;
}

StableAreaMask mask_of(const std::vector<Patch>& patches, bool newest) {
    StableAreaMask m;
    m.reference_epoch = 1;
    m.segmentation = "voxel 0.1 seed 1";
    for (const auto& p : patches) {
        const std::uint8_t state = newest ? p.last : p.before;
        SupervoxelRow row;
        for (int i = 0; i < 3; ++i) {
            row.centroid[i] = p.centroid[i];
            row.normal[i] = p.normal[i];
        }
        row.voxels = 40;
        m.supervoxels.push_back(row);
        m.states.push_back(state);
        m.changes.push_back(state == kUnstable ? -0.0021f : 0.0001f);
        m.lods.push_back(0.0008f);
        (state == kUnstable ? m.unstable : m.stable) += 1;
    }
    return m;
}

class StableAreasAsZones : public ::testing::Test {
  protected:
    void SetUp() override {
        config_ = dir_ / "site.toml";
        test::write_text(config_, kConfig);
        auto db = EpochDatabase::open(dir_ / "tlsmon.sqlite", EpochDatabase::Mode::read_write);
        const auto patches = scene();
        for (int i = 0; i < 3; ++i) {
            std::string sha(64, 'a');
            sha.back() = static_cast<char>('0' + i);
            const auto id =
                db.epochs()
                    .insert({sha, kT0 + 900 * i, "/ingest/s" + std::to_string(i) + ".ptx", 1000,
                             std::nullopt})
                    .id;
            db.epochs().claim(id);
            EpochResults r;
            if (i > 0) r.stable_areas = mask_of(patches, i == 2);
            db.results().commit(id, r);
        }
        db.epochs().set_reference(1);
    }
    test::TempDir dir_;
    std::filesystem::path config_;
};

TEST_F(StableAreasAsZones, TheSlopeAndTheHeapBecomeZones) {
    const auto r = test::run_tlsmon(
        "query stable-areas --epoch 3 --as-zones --config " + config_.string(), false);
    ASSERT_EQ(r.status, 0) << r.out;
    // The printed tables, added to the configuration, load: two zones more.
    const Config with =
        parse_config(std::string(kConfig) + r.out, "site.toml + output", dir_.path());
    ASSERT_EQ(with.zones.size(), 3u) << r.out;
    const auto& slope = with.zones[1];
    const auto& heap = with.zones[2];
    EXPECT_EQ(slope.name, "unstable area 3.1");
    EXPECT_EQ(heap.name, "unstable area 3.2");
    // Each box holds its patches with half a seed around them, and none of the others.
    const auto holds = [](const ZoneConfig& z, const Eigen::Vector3d& p) {
        return zone_shape(z).contains(p);
    };
    int in_slope = 0, in_heap = 0;
    for (const auto& p : scene()) {
        in_slope += holds(slope, p.centroid);
        in_heap += holds(heap, p.centroid);
    }
    EXPECT_EQ(in_slope, 9);
    EXPECT_EQ(in_heap, 4);
    EXPECT_NEAR(slope.min[0], 19.5, 1e-9);
    EXPECT_NEAR(slope.max[2], 5.5, 1e-9);
    // The slope faces one way: its normal; the heap does not: none, and the output says why.
    ASSERT_TRUE(slope.normal);
    EXPECT_NEAR(Eigen::Vector3d(slope.normal->data()).dot(Eigen::Vector3d(0, -1, 2).normalized()),
                1.0, 1e-4);
    EXPECT_FALSE(heap.normal);
    EXPECT_NE(r.out.find("no normal: its supervoxels' normals lie up to 66 deg from their mean"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("9 supervoxels about [21.0, 31.0, 4.5] m"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("change -2.10 to -2.10 mm (LoD95 up to 0.80 mm)"), std::string::npos)
        << r.out;
}

TEST_F(StableAreasAsZones, NoAreaBeforeThePersistenceAndNoneWithoutTheConfiguration) {
    // Epoch 2 is the first with a mask: nothing has been unstable two epochs in a row yet.
    const auto first = test::run_tlsmon(
        "query stable-areas --epoch 2 --as-zones --config " + config_.string(), false);
    ASSERT_EQ(first.status, 0) << first.out;
    EXPECT_EQ(parse_config(std::string(kConfig) + first.out, "out", dir_.path()).zones.size(), 1u);
    EXPECT_EQ(first.out.find("[[zone]]"), std::string::npos) << first.out;
    // The configured zones and persistence are needed: --db alone is refused, saying why.
    const auto bare = test::run_tlsmon("query stable-areas --epoch 3 --as-zones --db " +
                                       (dir_ / "tlsmon.sqlite").string());
    EXPECT_EQ(bare.status, 1);
    EXPECT_NE(bare.out.find("--as-zones needs --config FILE"), std::string::npos) << bare.out;
    // --state and --as-zones exclude each other.
    const auto both = test::run_tlsmon(
        "query stable-areas --epoch 3 --as-zones --state stable "
        "--config " +
        config_.string());
    EXPECT_NE(both.status, 0);
}

}  // namespace
}  // namespace tlsmon
