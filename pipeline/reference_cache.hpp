#pragma once
// What the stages derive once from the reference epoch (epoch 0 of the analyses) — search
// structures, core points, normals, images, keypoints, target centres; for now its extent —
// computed once, kept in memory for every later epoch, and persisted in the database so a
// restart does not compute it again.
//
// A product is identified by its stage, the reference's sha256, the parameters it depends on
// (as canonical text, hashed) and the version of its payload layout. It is taken from memory,
// else from the database's reference cache when an intact entry with the same identity is
// there, else built from the reference scan and stored; a missing, stale or corrupt entry is
// rebuilt with a log line saying which.
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/scan.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

// The reference epoch of this database and how to get its scan when a product must be built.
class ReferenceEpoch {
  public:
    using Scans = std::shared_ptr<const std::vector<Scan>>;
    using ScanLoader = std::function<Scans()>;
    ReferenceEpoch(Epoch epoch, ScanLoader load)
        : epoch_(std::move(epoch)), load_(std::move(load)) {}

    const Epoch& epoch() const { return epoch_; }
    // Read (once) on the first build that needs it. Throws Error when the file is gone or is
    // not the reference's content any more.
    const std::vector<Scan>& scans() {
        if (!scans_) scans_ = load_();
        return *scans_;
    }

  private:
    Epoch epoch_;
    ScanLoader load_;
    Scans scans_;
};

struct ProductKey {
    std::string stage;       // one entry per stage
    std::string parameters;  // canonical text of every parameter the product depends on
    int format_version = 1;  // bump when the payload layout changes
};

// A product type T provides `std::string encode() const` and `static T decode(std::string_view)`
// (throwing Error on a malformed payload).
class ReferenceCache {
  public:
    explicit ReferenceCache(EpochDatabase& db) : db_(&db) {}
    // In memory only: a one-shot command's products, built for one run.
    ReferenceCache() = default;

    template <class T, class Build>
    std::shared_ptr<const T> get(ReferenceEpoch& reference, const ProductKey& key, Build&& build) {
        const std::string id = identity(reference, key);
        auto& slot = memory_[key.stage];
        if (slot.identity == id && slot.product) {
            ++counters_.from_memory;
            return std::static_pointer_cast<const T>(slot.product);
        }
        std::shared_ptr<const T> product;
        if (auto payload = load(reference, key)) {
            try {
                product = std::make_shared<const T>(T::decode(*payload));
                ++counters_.from_database;
            } catch (const Error& e) {
                log_rebuild(reference, key, std::string("corrupt: ") + e.what());
            }
        }
        if (!product) {
            product = std::make_shared<const T>(build(reference.scans()));
            ++counters_.built;
            if (db_) store(reference, key, product->encode());
        }
        slot = {id, product};
        return product;
    }

    struct Counters {
        int from_memory = 0, from_database = 0, built = 0;
    };
    const Counters& counters() const { return counters_; }

  private:
    struct Slot {
        std::string identity;
        std::shared_ptr<const void> product;
    };
    static std::string identity(const ReferenceEpoch& reference, const ProductKey& key);
    // The stored payload when it is intact and has this identity; otherwise logs why it
    // must be built and returns nullopt.
    std::optional<std::string> load(const ReferenceEpoch& reference, const ProductKey& key);
    void store(const ReferenceEpoch& reference, const ProductKey& key, const std::string& payload);
    void log_rebuild(const ReferenceEpoch& reference, const ProductKey& key,
                     const std::string& why) const;

    EpochDatabase* db_ = nullptr;  // none: memory only
    std::map<std::string, Slot> memory_;
    Counters counters_;
};

}  // namespace tlsmon
