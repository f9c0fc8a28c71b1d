#include "algorithms/patches/patch_distance.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"

namespace tlsmon::patches {

void validate(const Parameters& p) {
    if (!(p.search_depth > 0))
        throw Error("pbm3c2.search_depth must be > 0 m, not " + std::to_string(p.search_depth));
    if (p.min_points < 4)
        throw Error("pbm3c2.min_points must be at least 4, not " + std::to_string(p.min_points));
    if (!(p.max_incidence_deg > 0 && p.max_incidence_deg <= 90))
        throw Error("pbm3c2.max_incidence_deg must be in (0, 90], not " +
                    std::to_string(p.max_incidence_deg));
    if (!(p.max_roughness > 0))
        throw Error("pbm3c2.max_roughness must be > 0 m, not " + std::to_string(p.max_roughness));
}

PatchResult patch_distance(const PlaneFit& reference, const PlaneFit& epoch,
                           double registration_sigma, const Parameters& p) {
    PatchResult r;
    r.reference = reference;
    r.epoch = epoch;
    const auto min_points = static_cast<std::size_t>(p.min_points);
    if (!reference.valid || reference.count < min_points) {
        r.outcome = PatchOutcome::few_reference_points;
        return r;
    }
    if (!(reference.sigma <= p.max_roughness) || !(reference.slope.norm() <= kMaxPatchTilt)) {
        r.outcome = PatchOutcome::rough;
        return r;
    }
    if (!epoch.valid || epoch.count < min_points) {
        r.outcome = PatchOutcome::few_epoch_points;
        return r;
    }
    r.outcome = PatchOutcome::measured;
    const Eigen::Vector2d at = reference.centroid;
    auto& d = r.distance;
    d.distance = epoch.height_at(at) - reference.height;
    const double s1 = reference.sigma / std::sqrt(double(reference.count));
    const double s2 = epoch.height_sigma_at(at);
    d.sampling_sigma = std::sqrt(s1 * s1 + s2 * s2);
    d.sigma = std::hypot(d.sampling_sigma, registration_sigma);
    d.lod = 1.96 * d.sigma;
    d.significant = std::abs(d.distance) > d.lod;
    return r;
}

}  // namespace tlsmon::patches
