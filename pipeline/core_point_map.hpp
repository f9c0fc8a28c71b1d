#pragma once
// One epoch's M3C2 map as stored: the m3c2 stage's reference product (core points, normals,
// zones; the reference cache) with the epoch's float32 core point arrays (distance, LoD95,
// n1, n2). Read by `tlsmon query corepoints` and the dashboard's epoch view.
#include "pipeline/m3c2_reference.hpp"
#include "storage/epoch_database.hpp"

namespace tlsmon {

struct CorePointMap {
    M3c2Reference reference;
    std::vector<float> distance, lod95, n1, n2;  // one per core point; distance NaN: none
};

// There is no map to read: no such epoch, or no M3C2 result in it.
class NoCorePointMap : public Error {
  public:
    using Error::Error;
};

// NoCorePointMap when there is none; Error naming the epoch and what is wrong when the
// stored map cannot be put together: arrays of another length, no or an unreadable
// reference product, one measured with other parameters.
CorePointMap read_core_point_map(const EpochDatabase& db, EpochId epoch);

}  // namespace tlsmon
