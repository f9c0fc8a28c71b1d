#pragma once
// Stage "coverage": does the epoch cover the part of the site the reference epoch covers?
// A scanner turned off its aim, a scan cut short or a file of another station gives points
// that mostly lie outside the reference's extent. The share inside is stored with every
// epoch; with `min_inside_share` set, an epoch below it is rejected before any analysis.
// The reference's extent is the first product of the reference cache.
#include <string>
#include <string_view>

#include "algorithms/extent.hpp"
#include "pipeline/reference_cache.hpp"
#include "pipeline/stage.hpp"

namespace tlsmon {

struct CoverageConfig {
    double margin = 1.0;            // m: the reference's bounding box grown on every side
    double min_inside_share = 0.0;  // 0..1: a smaller share inside -> rejected (0 = never)
};

// The reference's extent, as kept in the reference cache.
struct ReferenceExtent {
    BoundingBox box;
    std::uint64_t points = 0;

    std::string encode() const;
    static ReferenceExtent decode(std::string_view payload);
};

struct CoverageResult {
    double inside_share = 0;  // of the epoch's points, inside the grown reference box
};

StageVerdict check_coverage(const CoverageConfig& config, const EpochInput& input,
                            ReferenceEpoch& reference, ReferenceCache& cache,
                            CoverageResult& result);

}  // namespace tlsmon
