#pragma once
// What the patch-based M3C2 stage (pipeline/pbm3c2_stage.hpp) keeps of the reference epoch in
// the reference cache: its patches (the supervoxels inside the zones, each with its frame and
// footprint), the reference points' plane moments on each (per block), and the zones' patches.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "algorithms/patches/like_with_like.hpp"
#include "algorithms/patches/patch_index.hpp"

namespace tlsmon {

struct PbM3c2Reference {
    // 2: a point on one surface goes to its patch by its place in the plane, no longer by its
    // height (algorithms/patches/patch_index.hpp). 3: the moments leave out the points at the
    // scan grid's depth discontinuities. 4: the moments per block of the patch plane
    // (algorithms/patches/like_with_like.hpp). An older product is rebuilt.
    static constexpr int kFormatVersion = 4;
    static constexpr const char* kStage = "pbm3c2";

    std::vector<patches::Patch> patches;
    std::vector<std::uint32_t> supervoxel;  // per patch: its supervoxel of the reference
    // Per patch: its plane's reference points' moments per block, and their total.
    std::vector<std::vector<patches::BlockMoments>> blocks;
    std::vector<double> block_side;  // m, per patch (patches::block_side)
    std::vector<patches::PlaneMoments> moments;
    Eigen::Vector3d scanner = Eigen::Vector3d::Zero();     // the reference scan's position
    std::vector<std::string> zone_names;                   // in the configuration's order
    std::vector<std::vector<std::uint32_t>> zone_patches;  // per zone, its patches (ascending)

    // Where patch k's distance is taken, (u, v, w) in its frame: over the centroid of the
    // reference fit `result` rests on (the part both epochs saw alike, when only part was);
    // without a result, or where that fit failed, over the whole reference plane's centroid;
    // the frame's origin when neither could be fitted.
    Eigen::Vector3d measured_in_frame(std::size_t k,
                                      const patches::PatchResult* result = nullptr) const;
    // The same place in the site's frame.
    Eigen::Vector3d measured_at(std::size_t k, const patches::PatchResult* result = nullptr) const;
    // (u, v, w) in patch k's frame, in the site's.
    Eigen::Vector3d from_frame(std::size_t k, const Eigen::Vector3d& uvw) const;

    std::string encode() const;
    static PbM3c2Reference decode(std::string_view payload);  // throws Error when malformed
};

}  // namespace tlsmon
