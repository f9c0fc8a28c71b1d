// The reference-epoch cache store: one entry per stage, a hit only for the same reference,
// parameters and format, and never for a payload altered on disk.
#include <SQLiteCpp/SQLiteCpp.h>
#include <gtest/gtest.h>

#include "fake_sha256.hpp"
#include "storage/epoch_database.hpp"
#include "tests/support/temp_dir.hpp"

namespace tlsmon {
namespace {

using Mode = EpochDatabase::Mode;

// Binary bytes with a NUL inside: the payload is a BLOB, not text.
constexpr char kBoundsBytes[] = "bbox\0\x01\x02\xff min=-1.5 max=2.25";
const std::string kBounds(kBoundsBytes, sizeof kBoundsBytes - 1);  // 26 bytes, NUL included

ReferenceCacheKey bounds_key(int reference = 1, std::string params = "p1", int version = 1) {
    return {"reference_bounds", test::fake_sha256(reference), std::move(params), version};
}

TEST(ReferenceCache, HitAfterReopen) {
    test::TempDir dir;
    const auto path = dir / "e.sqlite";
    const auto before = now_utc();
    {
        auto db = EpochDatabase::open(path, Mode::read_write);
        EXPECT_EQ(db.reference_cache().load(bounds_key()).status, CacheLookup::missing);
        db.reference_cache().store(bounds_key(), kBounds);
    }
    for (auto mode : {Mode::read_write, Mode::read_only}) {
        const auto db = EpochDatabase::open(path, mode);
        const auto got = db.reference_cache().load(bounds_key());
        EXPECT_EQ(got.status, CacheLookup::hit) << got.reason;
        EXPECT_EQ(got.payload, kBounds);
        EXPECT_EQ(got.reason, "");
        const auto entries = db.reference_cache().entries();
        ASSERT_EQ(entries.size(), 1u);
        EXPECT_EQ(entries[0].stage, "reference_bounds");
        EXPECT_EQ(entries[0].reference_sha256, test::fake_sha256(1));
        EXPECT_EQ(entries[0].params_hash, "p1");
        EXPECT_EQ(entries[0].format_version, 1);
        EXPECT_EQ(entries[0].payload_bytes, 26);
        EXPECT_GE(entries[0].created, before);
        EXPECT_LE(entries[0].created, now_utc());
    }
}

TEST(ReferenceCache, MissingNamesTheStage) {
    test::TempDir dir;
    auto db = EpochDatabase::open(dir / "e.sqlite", Mode::read_write);
    db.reference_cache().store(bounds_key(), kBounds);
    ReferenceCacheKey other = bounds_key();
    other.stage = "core_points";
    const auto got = db.reference_cache().load(other);
    EXPECT_EQ(got.status, CacheLookup::missing);
    EXPECT_EQ(got.payload, "");
    EXPECT_NE(got.reason.find("'core_points'"), std::string::npos) << got.reason;
}

TEST(ReferenceCache, StaleOnOtherParamsReferenceOrVersion) {
    test::TempDir dir;
    auto db = EpochDatabase::open(dir / "e.sqlite", Mode::read_write);
    db.reference_cache().store(bounds_key(1, "p1", 1), kBounds);
    struct Case {
        ReferenceCacheKey key;
        std::string says;
    };
    for (const auto& c :
         {Case{bounds_key(1, "p2", 1), "params hash 'p1' (wanted 'p2')"},
          Case{bounds_key(2, "p1", 1), "reference sha256 " + test::fake_sha256(1) + " (wanted " +
                                           test::fake_sha256(2) + ")"},
          Case{bounds_key(1, "p1", 2), "format version 1 (wanted 2)"}}) {
        const auto got = db.reference_cache().load(c.key);
        EXPECT_EQ(got.status, CacheLookup::stale) << c.says;
        EXPECT_EQ(got.payload, "") << c.says;
        EXPECT_EQ(got.reason, "cached for " + c.says);
    }
    // The stale lookups changed nothing: the entry is still a hit for its own key.
    EXPECT_EQ(db.reference_cache().load(bounds_key(1, "p1", 1)).payload, kBounds);
}

TEST(ReferenceCache, StoreReplacesTheStagesEntry) {
    test::TempDir dir;
    auto db = EpochDatabase::open(dir / "e.sqlite", Mode::read_write);
    db.reference_cache().store(bounds_key(1, "p1"), kBounds);
    db.reference_cache().store(bounds_key(1, "p2"), "rebuilt");
    const auto entries = db.reference_cache().entries();
    ASSERT_EQ(entries.size(), 1u);
    EXPECT_EQ(entries[0].params_hash, "p2");
    EXPECT_EQ(entries[0].payload_bytes, 7);
    EXPECT_EQ(db.reference_cache().load(bounds_key(1, "p1")).status, CacheLookup::stale);
    EXPECT_EQ(db.reference_cache().load(bounds_key(1, "p2")).payload, "rebuilt");
}

TEST(ReferenceCache, EmptyPayloadIsAHit) {
    test::TempDir dir;
    auto db = EpochDatabase::open(dir / "e.sqlite", Mode::read_write);
    db.reference_cache().store(bounds_key(), "");
    const auto got = db.reference_cache().load(bounds_key());
    EXPECT_EQ(got.status, CacheLookup::hit) << got.reason;
    EXPECT_EQ(got.payload, "");
}

TEST(ReferenceCache, ClearRemovesOnlyThatStage) {
    test::TempDir dir;
    auto db = EpochDatabase::open(dir / "e.sqlite", Mode::read_write);
    ReferenceCacheKey normals = bounds_key();
    normals.stage = "normals";
    db.reference_cache().store(bounds_key(), kBounds);
    db.reference_cache().store(normals, "n");
    db.reference_cache().clear("reference_bounds");
    EXPECT_EQ(db.reference_cache().load(bounds_key()).status, CacheLookup::missing);
    EXPECT_EQ(db.reference_cache().load(normals).payload, "n");
    ASSERT_EQ(db.reference_cache().entries().size(), 1u);
    EXPECT_EQ(db.reference_cache().entries()[0].stage, "normals");
}

TEST(ReferenceCache, PayloadAlteredOnDiskIsCorruptNeverAHit) {
    test::TempDir dir;
    const auto path = dir / "e.sqlite";
    auto db = EpochDatabase::open(path, Mode::read_write);
    db.reference_cache().store(bounds_key(), kBounds);
    std::string altered = kBounds;
    altered[10] ^= 0x10;  // one bit, the size unchanged
    for (const std::string& bytes : {altered, kBounds.substr(0, kBounds.size() - 1)}) {
        {  // behind the store's back, as a disk or a hand with the sqlite3 CLI would
            SQLite::Database raw(path.string(), SQLite::OPEN_READWRITE);
            SQLite::Statement s(raw, "UPDATE reference_cache SET payload = ? WHERE stage = ?");
            s.bind(1, bytes.data(), static_cast<int>(bytes.size()));
            s.bind(2, "reference_bounds");
            ASSERT_EQ(s.exec(), 1);
        }
        const auto got = db.reference_cache().load(bounds_key());
        EXPECT_EQ(got.status, CacheLookup::corrupt);
        EXPECT_EQ(got.payload, "");
        EXPECT_NE(got.reason.find("payload of " + std::to_string(bytes.size()) + " bytes"),
                  std::string::npos)
            << got.reason;
    }
    // Rebuilt: a store makes it a hit again.
    db.reference_cache().store(bounds_key(), kBounds);
    EXPECT_EQ(db.reference_cache().load(bounds_key()).status, CacheLookup::hit);
}

TEST(ReferenceCache, TwoReferencesAreNeverMixed) {
    test::TempDir dir;
    auto db = EpochDatabase::open(dir / "e.sqlite", Mode::read_write);
    db.reference_cache().store(bounds_key(1), "bounds of reference 1");
    const auto for_2 = db.reference_cache().load(bounds_key(2));
    EXPECT_EQ(for_2.status, CacheLookup::stale);
    EXPECT_EQ(for_2.payload, "");
    db.reference_cache().store(bounds_key(2), "bounds of reference 2");
    EXPECT_EQ(db.reference_cache().load(bounds_key(1)).status, CacheLookup::stale);
    EXPECT_EQ(db.reference_cache().load(bounds_key(2)).payload, "bounds of reference 2");
    // Stages are separate entries: one stage of reference 1 beside one of reference 2.
    ReferenceCacheKey normals = bounds_key(1);
    normals.stage = "normals";
    db.reference_cache().store(normals, "normals of reference 1");
    EXPECT_EQ(db.reference_cache().load(normals).payload, "normals of reference 1");
    EXPECT_EQ(db.reference_cache().load(bounds_key(2)).payload, "bounds of reference 2");
}

TEST(ReferenceCache, ReaderCannotStore) {
    test::TempDir dir;
    const auto path = dir / "e.sqlite";
    EpochDatabase::open(path, Mode::read_write);
    auto reader = EpochDatabase::open(path, Mode::read_only);
    EXPECT_THROW(reader.reference_cache().store(bounds_key(), kBounds), StorageError);
    EXPECT_EQ(reader.reference_cache().load(bounds_key()).status, CacheLookup::missing);
}

}  // namespace
}  // namespace tlsmon
