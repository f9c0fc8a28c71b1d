#pragma once
// What the primitives stage (pipeline/primitive_stage.hpp) keeps of the reference epoch in
// the reference cache: per zone naming a primitive, the reference's fit — its frame, which
// every epoch's fit shares, its parameters and their covariance — or why there is none.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "algorithms/primitives/primitive_fit.hpp"

namespace tlsmon {

struct PrimitiveReference {
    static constexpr int kFormatVersion = 1;
    static constexpr const char* kStage = "primitives";

    struct Entry {
        std::string zone;
        primitives::Fit fit;             // status other than fitted: the zone is not measured
        std::string refused;             // why there is no primitive ("" when fitted)
        std::uint64_t seed_inliers = 0;  // of RANSAC's sample
        // Cylinder: the axial distance from the frame's origin to the zone's far end along
        // the axis (the "top" whose displacement the stage reports), m.
        double far_end = 0.0;
    };
    std::vector<Entry> entries;  // in the configuration's order of the zones
    Eigen::Vector3d scanner = Eigen::Vector3d::Zero();

    std::string encode() const;
    static PrimitiveReference decode(std::string_view payload);  // throws Error when malformed
};

}  // namespace tlsmon
