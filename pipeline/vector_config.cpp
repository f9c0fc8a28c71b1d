#include "pipeline/vector_config.hpp"

#include "core/error.hpp"

namespace tlsmon {

void validate(const VectorConfig& c) {
    vectors::validate(static_cast<const vectors::Parameters&>(c));
    if (!(c.window > 0 && c.window <= 10)) throw Error("vectors: window must lie in (0, 10] m");
    if (!(c.search_depth > 0 && c.search_depth <= 10))
        throw Error("vectors: search_depth must lie in (0, 10] m");
    if (!(c.max_incidence_deg > 0 && c.max_incidence_deg <= 90))
        throw Error("vectors: max_incidence_deg must lie in (0, 90]°");
}

std::vector<SectionKey<VectorConfig>> vector_keys() {
    using K = Keys<VectorConfig>;
    return {
        K::flag(&VectorConfig::enabled, "enabled",
                "Run the 3-D vectors (docs/vectors.md) for every epoch: each patch of the "
                "reference inside a zone (the supervoxels of the registration on stable areas, "
                "`registration.stable_voxel`, `stable_seed`) registered on its own to the epoch "
                "by matching its heights and intensities, a displacement vector with its "
                "covariance per patch and per zone."),
        K::number(&VectorConfig::window, "window", 0.05, 10, "m",
                  "The side of the square measured about each patch's centroid, in its plane: "
                  "the area that moves as one body."),
        K::number(&VectorConfig::search_depth, "search_depth", 0.001, 10, "m",
                  "A point belongs to an area when it lies within this of the patch's plane: "
                  "the largest movement along the normal measured."),
        K::number(&VectorConfig::search_radius, "search_radius", 0, 1, "m",
                  "The largest movement along the surface the coarse step looks for (the "
                  "normalised cross-correlation of the intensities over whole pixels)."),
        K::number(&VectorConfig::block, "block", 0.001, 100, "m",
                  "The side of the blocks over which the covariance is estimated (cluster-"
                  "robust): larger than the distance over which neighbouring points' errors "
                  "are correlated."),
        K::integer(&VectorConfig::min_points, "min_points", 10, 100000000, "",
                   "Points the reference and the epoch each need in an area for a vector."),
        K::integer(&VectorConfig::min_blocks, "min_blocks", 2, 1000000, "",
                   "Blocks with points an area needs for its covariance."),
        K::number(&VectorConfig::clip, "clip", 1, 100, "",
                  "Residuals beyond this many robust standard deviations of their group "
                  "(heights, intensities) are left out."),
        K::number(&VectorConfig::max_sigma, "max_sigma", 0.00001, 1, "m",
                  "An area whose σ along the surface (in its worst direction) exceeds this gives "
                  "no vector: its texture does not observe the movement there."),
        K::number(&VectorConfig::max_spacing, "max_spacing", 0.0001, 1, "m",
                  "An area the scan samples coarser than this (the mean spacing of its points on "
                  "the surface) gives no vector: its intensity image is aliased and the match "
                  "follows the scan's lattice as the scanner drifts. The scanner's footprint at "
                  "the structure, as keypoints.max_sample_spacing."),
        K::integer(&VectorConfig::max_iterations, "max_iterations", 1, 1000, "",
                   "Gauss–Newton iterations of each area's registration at most."),
        K::number(&VectorConfig::max_incidence_deg, "max_incidence_deg", 1, 90, "°",
                  "A patch seen at a larger angle between its normal and the line of sight is "
                  "left out: its intensity texture is smeared along the beam's footprint."),
        K::integer(&VectorConfig::threads, "threads", 0, 256, "",
                   "Threads of the stage; 0: every core."),
    };
}

}  // namespace tlsmon
