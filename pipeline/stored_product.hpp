#pragma once
// A stage's reference product as the database's reference cache holds it (whatever its
// parameters): what the readers of stored maps need for the positions their arrays belong to.
#include "core/error.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

// Error naming the database when there is none, or it cannot be read.
template <class Product>
Product stored_product(const EpochDatabase& db) {
    for (const auto& e : db.reference_cache().entries()) {
        if (e.stage != Product::kStage) continue;
        const CachedPayload cached = db.reference_cache().load(
            ReferenceCacheKey{e.stage, e.reference_sha256, e.params_hash, e.format_version});
        if (cached.status != CacheLookup::hit) {
            throw Error(std::string("the ") + Product::kStage + " reference product in " +
                        db.path().string() + " cannot be read: " + cached.reason);
        }
        return Product::decode(cached.payload);
    }
    throw Error(std::string("no ") + Product::kStage + " reference product in " +
                db.path().string() + " (has the " + Product::kStage + " stage run?)");
}

}  // namespace tlsmon
