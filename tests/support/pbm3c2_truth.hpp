#pragma once
// The truth of a zone's pbm3c2_median_m, the median over the zone's area
// (algorithms/patches/zone_median.hpp): the median of the true change along each patch's
// normal at the centres of the footprint cells of the zone's measured patches, the cells the
// stage counts.
#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <vector>

#include "algorithms/patches/patch_index.hpp"
#include "core/statistics.hpp"
#include "pipeline/pbm3c2_stage.hpp"

namespace tlsmon::test {

// `change(x)`: the true displacement at x between the reference and the epoch, an
// Eigen::Vector3d (not an expression of temporaries).
template <class Change>
double areal_median_truth(const PbM3c2Reference& reference, const PbM3c2Epoch& epoch,
                          std::size_t zone, const Change& change) {
    std::vector<double> along;
    for (const auto k : reference.zone_patches[zone]) {
        if (!std::isfinite(epoch.results[k].distance.distance)) continue;
        const Eigen::Vector3d n = reference.patches[k].frame.normal;
        for (const auto& x : patches::cell_centres(reference.patches[k]))
            along.push_back(change(x).dot(n));
    }
    return along.empty() ? std::nan("") : median(std::move(along));
}

}  // namespace tlsmon::test
