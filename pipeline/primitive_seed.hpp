#pragma once
// The coarse step of the primitives' extraction (docs/primitives.md): RANSAC over a thinned
// sample with normals, by the Point Cloud Library's sample consensus (SACSegmentation with
// normals: SACMODEL_NORMAL_PLANE, SACMODEL_CYLINDER, SACMODEL_NORMAL_SPHERE; Fischler &
// Bolles 1981). Its headers stay in pipeline/pcl_primitives.cpp; PCL's generator has a fixed
// seed, so the same sample gives the same primitive. The fine step is
// algorithms/primitives/primitive_fit.hpp on every point.
#include <cstddef>
#include <optional>

#include "algorithms/primitives/primitive.hpp"
#include "pipeline/pcl_adapter.hpp"

namespace tlsmon {

struct PrimitiveSeedParams {
    double threshold = 0.02;     // m, a point within this of the model counts for it
    int iterations = 2000;       // RANSAC samples
    double normal_weight = 0.1;  // weight of the normals' angular distance in the consensus
    double min_radius = 0.05;    // m, cylinder and sphere
    double max_radius = 20.0;    // m
};

struct PrimitiveSeed {
    primitives::Primitive primitive;
    std::size_t inliers = 0;  // of the sample
};

// The primitive of `kind` with the largest consensus in `sample`; nullopt when there is none
// (fewer than the model's minimal sample, or no model found).
std::optional<PrimitiveSeed> ransac_primitive(primitives::Kind kind, const SurfaceSample& sample,
                                              const PrimitiveSeedParams& params);

}  // namespace tlsmon
