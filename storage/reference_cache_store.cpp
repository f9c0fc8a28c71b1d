// The reference-epoch cache: one entry per stage, checked against its key and its checksum
// on every load (reference_cache_store.hpp).
#include "storage/reference_cache_store.hpp"

#include <sqlite3.h>

#include "storage/connection.hpp"
#include "storage/payload_checksum.hpp"

namespace tlsmon {

std::string_view to_string(CacheLookup lookup) {
    switch (lookup) {
        case CacheLookup::hit:
            return "hit";
        case CacheLookup::missing:
            return "missing";
        case CacheLookup::stale:
            return "stale";
        case CacheLookup::corrupt:
            return "corrupt";
    }
    return "?";
}

namespace {

// What differs between the stored key and the wanted one, e.g. "params hash 'a' (wanted
// 'b'), format version 1 (wanted 2)".
std::string differences(const ReferenceCacheKey& stored, const ReferenceCacheKey& wanted) {
    std::string out;
    auto add = [&](const std::string& what, const std::string& have, const std::string& want) {
        if (have == want) return;
        if (!out.empty()) out += ", ";
        out += what + " " + have + " (wanted " + want + ")";
    };
    add("reference sha256", stored.reference_sha256, wanted.reference_sha256);
    add("params hash", "'" + stored.params_hash + "'", "'" + wanted.params_hash + "'");
    add("format version", std::to_string(stored.format_version),
        std::to_string(wanted.format_version));
    return out;
}

}  // namespace

CachedPayload ReferenceCacheStore::load(const ReferenceCacheKey& key) const {
    const std::string context = "loading the reference cache of stage '" + key.stage + "'";
    return guarded(*c_, context.c_str(), [&]() -> CachedPayload {
        // The payload is read only when the key matches: a stale entry may be large.
        SQLite::Statement s(c_->db,
                            "SELECT reference_sha256, params_hash, format_version,"
                            " CASE WHEN reference_sha256 = ?2 AND params_hash = ?3"
                            " AND format_version = ?4 THEN payload END, payload_sha256"
                            " FROM reference_cache WHERE stage = ?1");
        s.bind(1, key.stage);
        s.bind(2, key.reference_sha256);
        s.bind(3, key.params_hash);
        s.bind(4, key.format_version);
        if (!s.executeStep()) {
            return {CacheLookup::missing, {}, "no cached entry for stage '" + key.stage + "'"};
        }
        const ReferenceCacheKey stored{key.stage, s.getColumn(0).getString(),
                                       s.getColumn(1).getString(), s.getColumn(2).getInt()};
        if (stored.reference_sha256 != key.reference_sha256 ||
            stored.params_hash != key.params_hash || stored.format_version != key.format_version) {
            return {CacheLookup::stale, {}, "cached for " + differences(stored, key)};
        }
        const auto payload = s.getColumn(3);
        std::string bytes;
        if (payload.getBytes() > 0) {
            bytes.assign(static_cast<const char*>(payload.getBlob()),
                         static_cast<std::size_t>(payload.getBytes()));
        }
        const std::string stored_sum = s.getColumn(4).getString();
        const std::string sum = payload_sha256(bytes);
        if (sum != stored_sum) {
            return {CacheLookup::corrupt,
                    {},
                    "payload of " + std::to_string(bytes.size()) + " bytes has sha256 " + sum +
                        ", stored " + stored_sum};
        }
        return {CacheLookup::hit, std::move(bytes), {}};
    });
}

void ReferenceCacheStore::store(const ReferenceCacheKey& key, std::string_view payload) {
    if (key.stage.empty()) throw_storage(*c_, "a reference cache entry needs a stage name");
    const std::string context = "storing the reference cache of stage '" + key.stage + "'";
    // SQLite refuses a value above SQLITE_LIMIT_LENGTH (1e9 bytes by default) with "string or
    // blob too big"; say which stage and how large instead.
    const auto limit = sqlite3_limit(c_->db.getHandle(), SQLITE_LIMIT_LENGTH, -1);
    if (payload.size() > static_cast<std::size_t>(limit)) {
        throw_storage(*c_, context + ": payload of " + std::to_string(payload.size()) +
                               " bytes exceeds SQLite's limit of " + std::to_string(limit));
    }
    const std::string sum = payload_sha256(payload);
    guarded(*c_, context.c_str(), [&] {
        // One IMMEDIATE transaction on the connection's synchronous=FULL (set at open for
        // read_write), like an epoch commit: after a crash the old entry or the new one.
        SQLite::Transaction tx(c_->db, SQLite::TransactionBehavior::IMMEDIATE);
        SQLite::Statement s(c_->db,
                            "INSERT INTO reference_cache (stage, reference_sha256, params_hash,"
                            " format_version, created, payload, payload_sha256)"
                            " VALUES (?,?,?,?,?,?,?) ON CONFLICT (stage) DO UPDATE SET"
                            " reference_sha256 = excluded.reference_sha256,"
                            " params_hash = excluded.params_hash,"
                            " format_version = excluded.format_version,"
                            " created = excluded.created, payload = excluded.payload,"
                            " payload_sha256 = excluded.payload_sha256");
        s.bind(1, key.stage);
        s.bind(2, key.reference_sha256);
        s.bind(3, key.params_hash);
        s.bind(4, key.format_version);
        s.bind(5, static_cast<std::int64_t>(now_utc()));
        // bindNoCopy: `payload` outlives exec(). SQLite binds NULL for a null pointer, so an
        // empty payload gets a valid one.
        static const char kEmpty = 0;
        s.bindNoCopy(6, payload.empty() ? &kEmpty : payload.data(),
                     static_cast<int>(payload.size()));
        s.bind(7, sum);
        s.exec();
        tx.commit();
    });
}

void ReferenceCacheStore::clear(const std::string& stage) {
    guarded(*c_, "clearing a reference cache entry", [&] {
        SQLite::Statement s(c_->db, "DELETE FROM reference_cache WHERE stage = ?");
        s.bind(1, stage);
        s.exec();
    });
}

std::vector<ReferenceCacheEntry> ReferenceCacheStore::entries() const {
    return guarded(*c_, "listing the reference cache", [&] {
        // length() of a BLOB comes from its header, without reading the payload.
        SQLite::Statement s(c_->db,
                            "SELECT stage, reference_sha256, params_hash, format_version,"
                            " length(payload), created FROM reference_cache ORDER BY stage");
        std::vector<ReferenceCacheEntry> out;
        while (s.executeStep()) {
            out.push_back({s.getColumn(0).getString(), s.getColumn(1).getString(),
                           s.getColumn(2).getString(), s.getColumn(3).getInt(),
                           s.getColumn(4).getInt64(), s.getColumn(5).getInt64()});
        }
        return out;
    });
}

}  // namespace tlsmon
