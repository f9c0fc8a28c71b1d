// The reference-epoch cache: a product derived from the reference is built once, reused from
// memory and, after a restart, from the database; rebuilt when its entry is corrupt or its
// parameters change; never taken from another reference.
#include <gtest/gtest.h>

#include "core/payload.hpp"
#include "formats/scan_file.hpp"
#include "pipeline_site.hpp"

namespace tlsmon::test {
namespace {

// A product whose value shows which reference and parameter it was built from.
struct SumOfHeights {
    double value = 0;
    std::string encode() const {
        PayloadWriter w;
        w.put(value);
        return w.take();
    }
    static SumOfHeights decode(std::string_view payload) {
        PayloadReader r(payload);
        SumOfHeights s{r.get<double>()};
        r.finish();
        return s;
    }
};

SumOfHeights sum_of_heights(const std::vector<Scan>& scans, double scale) {
    SumOfHeights s;
    for (const auto& scan : scans) {
        for (const auto& p : scan.xyz) s.value += scale * p.z();
    }
    return s;
}

ReferenceEpoch reference_of(const Epoch& e) {
    return ReferenceEpoch(
        e, [e] { return std::make_shared<const std::vector<Scan>>(read_scans(e.file_path)); });
}

double product(ReferenceCache& cache, ReferenceEpoch& reference, double scale) {
    return cache
        .get<SumOfHeights>(
            reference, ProductKey{"test.sum", "scale=" + std::to_string(scale), 1},
            [&](const std::vector<Scan>& scans) { return sum_of_heights(scans, scale); })
        ->value;
}

TEST(PipelineReferenceCache, BuiltOnceReusedFromMemoryAndAfterARestartFromTheDatabase) {
    PipelineSite site;
    const Epoch e = site.add_epoch("a.xyz", 1000, 2.0);  // 441 points at z = 2
    {
        ReferenceCache cache(*site.db);
        ReferenceEpoch ref = reference_of(e);
        EXPECT_DOUBLE_EQ(product(cache, ref, 1.0), 882.0);
        EXPECT_DOUBLE_EQ(product(cache, ref, 1.0), 882.0);
        EXPECT_EQ(cache.counters().built, 1);
        EXPECT_EQ(cache.counters().from_memory, 1);
    }
    site.restart();
    ReferenceCache cache(*site.db);
    // After the restart the scan is not even readable: the product must come from the cache.
    ReferenceEpoch ref(e, []() -> ReferenceEpoch::Scans { throw Error("scan must not be read"); });
    EXPECT_DOUBLE_EQ(product(cache, ref, 1.0), 882.0);
    EXPECT_EQ(cache.counters().from_database, 1);
    EXPECT_EQ(cache.counters().built, 0);
}

TEST(PipelineReferenceCache, RebuiltWhenAParameterChanges) {
    PipelineSite site;
    const Epoch e = site.add_epoch("a.xyz", 1000, 2.0);
    ReferenceCache first(*site.db);
    ReferenceEpoch ref = reference_of(e);
    EXPECT_DOUBLE_EQ(product(first, ref, 1.0), 882.0);
    site.restart();
    ReferenceCache cache(*site.db);
    ReferenceEpoch again = reference_of(e);
    EXPECT_DOUBLE_EQ(product(cache, again, 0.5), 441.0);  // stale entry: built anew
    EXPECT_EQ(cache.counters().built, 1);
    EXPECT_EQ(cache.counters().from_database, 0);
    EXPECT_DOUBLE_EQ(product(cache, again, 1.0), 882.0);  // and back: built again
    EXPECT_EQ(cache.counters().built, 2);
}

TEST(PipelineReferenceCache, RebuiltWhenTheStoredEntryIsCorrupt) {
    PipelineSite site;
    const Epoch e = site.add_epoch("a.xyz", 1000, 2.0);
    {
        ReferenceCache cache(*site.db);
        ReferenceEpoch ref = reference_of(e);
        product(cache, ref, 1.0);
    }
    site.db.reset();
    // Flip the stored payload behind the daemon's back, as a disk fault would.
    const fs::path db_file = site.dir / "tlsmon.sqlite";
    const std::string sql = "UPDATE reference_cache SET payload = X'000000000000F03F'";
    ASSERT_EQ(std::system(("sqlite3 '" + db_file.string() + "' \"" + sql + "\"").c_str()), 0);
    site.db.emplace(site.open());
    ReferenceCache cache(*site.db);
    ReferenceEpoch ref = reference_of(e);
    EXPECT_DOUBLE_EQ(product(cache, ref, 1.0), 882.0);  // not 1.0 from the altered bytes
    EXPECT_EQ(cache.counters().built, 1);
    EXPECT_EQ(cache.counters().from_database, 0);
}

TEST(PipelineReferenceCache, NeverMixedBetweenTwoReferences) {
    PipelineSite site;
    const Epoch a = site.add_epoch("a.xyz", 1000, 2.0);
    const Epoch b = site.add_epoch("b.xyz", 2000, 3.0);
    ReferenceCache cache(*site.db);
    ReferenceEpoch ref_a = reference_of(a);
    ReferenceEpoch ref_b = reference_of(b);
    EXPECT_DOUBLE_EQ(product(cache, ref_a, 1.0), 882.0);
    EXPECT_DOUBLE_EQ(product(cache, ref_b, 1.0), 1323.0);
    site.restart();
    ReferenceCache after(*site.db);
    ReferenceEpoch again_a = reference_of(a);
    EXPECT_DOUBLE_EQ(product(after, again_a, 1.0), 882.0);  // b's entry replaced a's: rebuilt
    EXPECT_EQ(after.counters().built, 1);
}

}  // namespace
}  // namespace tlsmon::test
