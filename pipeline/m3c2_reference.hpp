#pragma once
// What the M3C2 stage (pipeline/m3c2_stage.hpp) keeps of the reference epoch in the reference
// cache, and its encoding; `tlsmon query corepoints` reads it back without the stage.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "algorithms/m3c2/reference.hpp"

namespace tlsmon {

// What the M3C2 stage keeps of the reference epoch.
struct M3c2Reference {
    // 2: the reference's points at a depth discontinuity left out (m3c2_stage.hpp, m3c2_cloud).
    // 3: the kernel's format 3, where in each cylinder its points lie (m3c2::Reference). An
    // older product is rebuilt.
    static constexpr int kFormatVersion = 3;
    static constexpr const char* kStage = "m3c2";

    m3c2::Reference reference;
    Eigen::Vector3d scanner = Eigen::Vector3d::Zero();   // the reference scan's position
    std::vector<std::string> zone_names;                 // in the configuration's order
    std::vector<std::vector<std::uint32_t>> zone_cores;  // per zone, its core points (ascending)

    std::string encode() const;
    static M3c2Reference decode(std::string_view payload);
};

}  // namespace tlsmon
