#include "pipeline/reference_cache.hpp"

#include <spdlog/spdlog.h>

#include "pipeline/sha256.hpp"

namespace tlsmon {

namespace {

ReferenceCacheKey store_key(const ReferenceEpoch& reference, const ProductKey& key) {
    return ReferenceCacheKey{key.stage, reference.epoch().sha256, sha256_text(key.parameters),
                             key.format_version};
}

}  // namespace

std::string ReferenceCache::identity(const ReferenceEpoch& reference, const ProductKey& key) {
    return reference.epoch().sha256 + "|" + std::to_string(key.format_version) + "|" +
           key.parameters;
}

std::optional<std::string> ReferenceCache::load(const ReferenceEpoch& reference,
                                                const ProductKey& key) {
    if (!db_) return std::nullopt;
    CachedPayload cached = db_->reference_cache().load(store_key(reference, key));
    if (cached.status == CacheLookup::hit) return std::move(cached.payload);
    log_rebuild(reference, key, cached.reason);
    return std::nullopt;
}

void ReferenceCache::store(const ReferenceEpoch& reference, const ProductKey& key,
                           const std::string& payload) {
    db_->reference_cache().store(store_key(reference, key), payload);
}

void ReferenceCache::log_rebuild(const ReferenceEpoch& reference, const ProductKey& key,
                                 const std::string& why) const {
    spdlog::info("reference cache: building '{}' from reference epoch {} ({}): {}", key.stage,
                 reference.epoch().id, reference.epoch().sha256.substr(0, 12), why);
}

}  // namespace tlsmon
