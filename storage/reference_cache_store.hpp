#pragma once
// The reference-epoch cache on disk: per pipeline stage ONE entry holding what that stage
// derived from the reference epoch (search structure, core points, normals, images,
// keypoints, ...), as an opaque payload the stage encodes itself. An entry is valid only for
// the reference it was computed from, the parameters it depends on and the payload's format;
// anything else is `stale` and the stage rebuilds it. The payload's SHA-256 is stored beside
// it and checked on every load, so a payload altered on disk is `corrupt`, never a hit.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/utc_time.hpp"
#include "storage/ids.hpp"

namespace tlsmon {

struct ReferenceCacheKey {
    std::string stage;             // the stage's name, e.g. "reference_bounds"
    std::string reference_sha256;  // the reference epoch's sha256
    std::string params_hash;       // the stage's hash of the parameters the payload depends on
    int format_version = 1;        // the stage's payload encoding
};

enum class CacheLookup {
    hit,
    missing,  // no entry for this stage
    stale,    // an entry for this stage exists with another reference/params/version
    corrupt,  // the entry matches the key but its payload fails its checksum
};
std::string_view to_string(CacheLookup lookup);

struct CachedPayload {
    CacheLookup status = CacheLookup::missing;
    std::string payload;  // only for a hit
    std::string reason;   // why missing/stale/corrupt, for a log line ("" for a hit)
};

// One entry as listed for tests and status (without its payload).
struct ReferenceCacheEntry {
    std::string stage;
    std::string reference_sha256;
    std::string params_hash;
    int format_version = 0;
    std::int64_t payload_bytes = 0;
    UtcSeconds created = 0;
};

class ReferenceCacheStore {
  public:
    explicit ReferenceCacheStore(Connection& connection) : c_(&connection) {}

    CachedPayload load(const ReferenceCacheKey& key) const;
    // Replaces the stage's entry (whatever its key was) in one transaction, durable like an
    // epoch commit (synchronous=FULL).
    void store(const ReferenceCacheKey& key, std::string_view payload);
    // Removes the stage's entry, if any.
    void clear(const std::string& stage);
    std::vector<ReferenceCacheEntry> entries() const;  // by stage name

  private:
    Connection* c_;
};

}  // namespace tlsmon
