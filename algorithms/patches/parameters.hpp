#pragma once
// The parameters of patch-based M3C2 (docs/pbm3c2.md; after the thesis on rigid patches in
// TLS point clouds, §5.1): which points of an epoch belong to a reference patch, and when a
// patch gives a distance. The patches themselves are the reference's supervoxels
// ([registration] stable_voxel, stable_seed), shared with the registration on stable areas.
namespace tlsmon::patches {

struct Parameters {
    // m: a point belongs to a patch when it projects into the patch's footprint and lies
    // within this of the reference plane along its normal — the largest change measured.
    double search_depth = 0.10;
    int min_points = 30;  // per patch and epoch for a plane, else no distance
    // m: a reference patch whose points lie farther than this (RMS) from their plane is not
    // a plane (an edge, a corner, clutter): no distance there.
    double max_roughness = 0.01;
    // °: a patch seen at a larger angle between its normal and the line of sight is left out:
    // there the points' places along the normal rest on the beam's angle and footprint more
    // than on its range (as the keypoints' max_incidence_deg; docs/pbm3c2.md).
    double max_incidence_deg = 80.0;
    int threads = 0;  // 0: every core
};

// Throws Error naming the parameter when a value cannot give a meaningful result.
void validate(const Parameters& p);

}  // namespace tlsmon::patches
