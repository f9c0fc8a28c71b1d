#pragma once
// What M3C2 derives once from the reference epoch: its core points, their normals (and the
// radius each was taken at) and the reference's side of every cylinder. The reference's own
// search structure is not part of it: nothing after preparation needs it. A new epoch costs
// only its own side (cylinder_sides over its points) and the distances.
//
// encode()/decode() give the reference cache's payload (pipeline/reference_cache.hpp); the
// cylinders' index is rebuilt from the stored core points and normals on decode.
#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "algorithms/m3c2/cylinder.hpp"
#include "algorithms/m3c2/distance.hpp"
#include "algorithms/m3c2/normals.hpp"
#include "algorithms/m3c2/parameters.hpp"

namespace tlsmon::m3c2 {

struct Reference {
    // 2: stray_distance, the sides' roughness. 3: where in each cylinder its points lie.
    static constexpr int kFormatVersion = 3;

    Cylinders cylinders;  // core points (centres), normals (axes), index
    // Per core point: the radius its normal was taken at; 0 where the normal was given
    // (a zone's design normal); NaN where it is undefined.
    std::vector<double> normal_radius;
    std::vector<CylinderSide> reference_side;

    std::size_t size() const { return cylinders.centres.size(); }
    const std::vector<Eigen::Vector3d>& core_points() const { return cylinders.centres; }
    const std::vector<Eigen::Vector3d>& normals() const { return cylinders.axes; }

    std::string encode() const;
    static Reference decode(std::string_view payload);  // throws Error when malformed
};

// Normals at the core points, the cylinders and the reference's side of them.
// `given_normals`: empty, or one per core point; a finite one is that core point's normal
// (normalised and oriented like an estimated one) instead of the estimate — the design
// normal of a planar face, which near an edge or at grazing incidence is closer to the truth
// than any neighbourhood's (docs/m3c2.md, "Edges and grazing faces"). `left_out`: the
// reference's points neither normals nor cylinders take, as for cylinder_sides.
Reference prepare_reference(const std::vector<Eigen::Vector3d>& reference,
                            std::vector<Eigen::Vector3d> core_points,
                            const NormalParameters& normals, const CylinderParameters& cylinders,
                            unsigned threads = 0,
                            std::span<const Eigen::Vector3d> given_normals = {},
                            std::span<const std::uint8_t> left_out = {});

// One compared epoch: its side of every cylinder, then the distance at every core point.
std::vector<Distance> distances(const Reference& reference,
                                const std::vector<CylinderSide>& compared_side,
                                const DistanceParameters& parameters);

}  // namespace tlsmon::m3c2
