#pragma once
// What the 3-D vector stage (pipeline/vector_stage.hpp) keeps of the reference epoch in the
// reference cache: its areas (the measuring window about each patch of the reference inside a
// zone, in the patch's frame), the reference's samples in each, and the zones' areas.
#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "algorithms/patches/patch_plane.hpp"
#include "algorithms/vectors/area_registration.hpp"

namespace tlsmon {

struct VectorReference {
    static constexpr int kFormatVersion = 1;
    static constexpr const char* kStage = "vectors";

    std::vector<patches::PatchFrame> frames;  // per area: its patch's frame
    std::vector<std::uint32_t> supervoxel;    // per area: its supervoxel of the reference
    // The reference's samples of area k: samples[offsets[k] .. offsets[k + 1]).
    std::vector<std::uint64_t> offsets{0};
    std::vector<vectors::AreaSample> samples;
    Eigen::Vector3d scanner = Eigen::Vector3d::Zero();   // the reference scan's position
    std::vector<std::string> zone_names;                 // in the configuration's order
    std::vector<std::vector<std::uint32_t>> zone_areas;  // per zone, its areas (ascending)

    std::size_t areas() const { return frames.size(); }
    std::span<const vectors::AreaSample> area_samples(std::size_t k) const {
        return {samples.data() + offsets[k], samples.data() + offsets[k + 1]};
    }

    std::string encode() const;
    static VectorReference decode(std::string_view payload);  // throws Error when malformed
};

}  // namespace tlsmon
