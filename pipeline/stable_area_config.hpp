#pragma once
// What the targetless registration on stable areas needs of the site (docs/configuration.md,
// [registration] stable_* keys; docs/registration.md, "Registration on stable areas").
namespace tlsmon {

struct StableAreaConfig {
    // The reference's supervoxels (VCCS): voxel and seed resolution.
    double voxel = 0.10;  // m; the epoch is thinned to one centroid per voxel of this side too
    double seed = 1.0;    // m, the supervoxels' size
    // A supervoxel takes part when it is a patch of plane: at least this many voxels, and
    // their RMS distance from its plane at most `max_roughness` (leaves, edges and corners,
    // a wall with the ground at its foot are not).
    int min_samples = 12;
    double max_roughness = 0.005;  // m
    // An epoch voxel pairs with the supervoxel of the nearest reference voxel within this.
    double max_correspondence_distance = 0.05;  // m
    // A supervoxel's change is significant beyond its LoD at this level (two-sided).
    double alpha = 0.05;
    int max_iterations = 10;  // register, test, drop: at most this many rounds
    // Cells (by the supervoxels' centroids) whose residuals may be correlated in the
    // cluster-robust covariance of the adjustment.
    double cluster_size = 5.0;  // m
    // Guards: the stable supervoxels' share of the voxels with a change, and how well the
    // stable set holds its weakest direction: the smallest eigenvalue of the adjustment's
    // normal matrix over its largest, rotations taken as the movement at the set's RMS
    // radius (1: every direction held alike; 0: one free).
    double min_share = 0.10;
    double min_conditioning = 1.0e-4;
    int min_supervoxels = 20;
    // A supervoxel outside the zones that is unstable in this many consecutive epochs (with a
    // mask) is an unstable area of its own: a `unstable_area` event when it first gets there.
    int persistent_epochs = 4;
};

}  // namespace tlsmon
