#pragma once
// A zone's displacement that stands for the whole zone, not for where its keypoints happen
// to match (docs/keypoints.md, "Zones that bend"). Over a pier face that bends, the
// displacement grows from the foot to the top, while the matches crowd where the texture is
// resolved best (near the foot: a shorter range, a finer sampling): their plain mean leans
// towards the foot's small values. So the zone is cut into strata, the bands of the vertical
// angle the outlier filters already judge by (the case study's segments), neighbouring bands
// joined until each stratum holds `min_stratum_matches` kept matches, and each stratum's
// mean is weighted by its share of the zone's wall area, the weights of a stratified sample
// (Cochran 1977, "Sampling techniques", §5.2):
//
//     d̄ = Σ_s w_s·d̂_s,   SE(d̄)² = Σ_s w_s²·(v_s/n_s + (Ē_s − ē_s)²·Var(b_s)),
//     w_s = A_s / Σ A_s,   d̂_s = d̄_s + b_s·(Ē_s − ē_s),
//
// A_s the wall area of the zone in the stratum's bands, counted in cells of the wall plane
// that hold reference points (a face seen through a gap or cut by the scan's edge counts what
// was seen; a band where nothing matched counts with the stratum it joined). Within a stratum
// the mean is moved along the kept matches' line on the vertical angle from their mean angle
// ē_s to the stratum's cells' Ē_s (the separate regression estimator, Cochran 1977 §7.10;
// b_s the slope, zone_strata.cpp): the matches crowd where the texture is resolved best, not
// where the stratum's area is. v_s = n_s·SE_s² the stratum's variance per kept match about its
// line, SE_s its kept mean's standard error as a trimmed mean's (segment_displacement.hpp),
// but never below the one pooled within all strata (a stratum of a few matches says little
// about its own spread).
#include <Eigen/Core>
#include <cstddef>
#include <span>
#include <vector>

#include "algorithms/keypoints/segment_displacement.hpp"

namespace tlsmon::keypoints {

// The centres of the wall cells (squares of `cell` metres in the wall's plane, along h and
// v) that hold at least one of `points`: the zone's area as the reference saw it. Empty when
// the wall is undefined.
std::vector<Eigen::Vector3d> wall_cell_centres(std::span<const Eigen::Vector3d> points,
                                               const WallFrame& wall, double cell = 0.25);
// Their vertical angles seen from `scanner` (rad), the key of their band.
std::vector<float> vertical_angles(std::span<const Eigen::Vector3d> centres,
                                   const Eigen::Vector3d& scanner);

struct StratifiedParameters {
    SegmentParameters segment;             // min_matches: of the whole zone
    std::size_t min_stratum_matches = 10;  // bands are joined until a stratum holds this many
    double band_width = 0;                 // rad, the strata's height in vertical angle
    // The reference scanner's position (project frame), whence the cells' vertical angles
    // were taken: the matches' are taken alike for the strata's regression (zone_strata.cpp).
    Eigen::Vector3d scanner = Eigen::Vector3d::Zero();
};

// The zone's displacement from `matches` whose `segment` is their band of the vertical angle
// (vertical_angle_band at `band_width`), every one of them in the zone: counts, spread and
// wall as segment_displacement over all kept matches; mean, along and their standard errors
// stratified as above; `covered_area_share`, the area share of the bands with a kept match.
// Without wall cells, or with an undefined wall (its frame then fitted to the kept matches),
// it is the plain mean of segment_displacement.
SegmentDisplacement stratified_displacement(std::span<const KeypointMatch> matches,
                                            std::span<const OutlierFilter> removed_by,
                                            const WallFrame& wall,
                                            std::span<const float> cell_elevations,
                                            const StratifiedParameters& parameters);

}  // namespace tlsmon::keypoints
