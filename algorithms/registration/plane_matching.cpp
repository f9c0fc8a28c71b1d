#include "algorithms/registration/plane_matching.hpp"

#include <algorithm>
#include <cmath>

#include "algorithms/registration/plane_registration.hpp"

namespace tlsmon::registration {

std::vector<PlaneMatch> match_planes(std::span<const FittedPlane> reference,
                                     std::span<const FittedPlane> epoch,
                                     const RigidTransform& approximate,
                                     const PlaneMatchingParams& params) {
    const double cos_max = std::cos(params.max_angle_deg * 3.141592653589793 / 180.0);
    const Eigen::Matrix3d& R = approximate.rotation;
    const Eigen::Vector3d& t = approximate.translation;
    std::vector<PlaneMatch> candidates;
    for (std::size_t j = 0; j < epoch.size(); ++j) {
        const Eigen::Vector3d n = R * epoch[j].normal;
        const Eigen::Vector3d c = R * epoch[j].centroid + t;
        for (std::size_t i = 0; i < reference.size(); ++i) {
            const FittedPlane& ref = reference[i];
            // Both normals face their scanner; the same station sees a plane from one side.
            if (n.dot(ref.normal) < cos_max) continue;
            const Eigen::Vector3d d = c - ref.centroid;
            const double offset = ref.normal.dot(d);
            if (std::fabs(offset) > params.max_offset) continue;
            const Eigen::Vector3d in_plane = d - offset * ref.normal;
            const double reach =
                params.overlap_factor * (std::hypot(ref.extent_long, ref.extent_short) +
                                         std::hypot(epoch[j].extent_long, epoch[j].extent_short));
            if (in_plane.norm() > reach) continue;
            candidates.push_back({i, j, plane_misclosure({ref, epoch[j]}, R, t).test_statistic});
        }
    }
    std::sort(candidates.begin(), candidates.end(),
              [](const PlaneMatch& a, const PlaneMatch& b) { return a.statistic < b.statistic; });
    std::vector<bool> reference_taken(reference.size()), epoch_taken(epoch.size());
    std::vector<PlaneMatch> out;
    for (const PlaneMatch& m : candidates) {
        if (reference_taken[m.reference] || epoch_taken[m.epoch]) continue;
        reference_taken[m.reference] = epoch_taken[m.epoch] = true;
        out.push_back(m);
    }
    std::sort(out.begin(), out.end(),
              [](const PlaneMatch& a, const PlaneMatch& b) { return a.reference < b.reference; });
    return out;
}

}  // namespace tlsmon::registration
