#include "pipeline/registration_config.hpp"

#include <array>

namespace tlsmon {

const char* to_string(TargetKind kind) {
    return kind == TargetKind::sphere ? "sphere" : "checkerboard";
}

namespace {

constexpr std::array<Named<RegistrationMethod>, 7> kMethods{{
    {RegistrationMethod::targets, "targets"},
    {RegistrationMethod::planes, "planes"},
    {RegistrationMethod::targets_planes, "targets+planes"},
    {RegistrationMethod::stable_areas, "stable_areas"},
    {RegistrationMethod::targets_stable_areas, "targets+stable_areas"},
    {RegistrationMethod::planes_stable_areas, "planes+stable_areas"},
    {RegistrationMethod::targets_planes_stable_areas, "targets+planes+stable_areas"},
}};

constexpr std::array<Named<registration::CovarianceScaling>, 3> kCovarianceScalings{{
    {registration::CovarianceScaling::a_priori, "a_priori"},
    {registration::CovarianceScaling::larger_of, "larger_of"},
    {registration::CovarianceScaling::a_posteriori, "a_posteriori"},
}};

constexpr std::array<Named<AtmosphereCorrection>, 2> kAtmosphereCorrections{{
    {AtmosphereCorrection::measured_air, "measured_air"},
    {AtmosphereCorrection::off, "off"},
}};
constexpr std::array<Named<IcpMode>, 4> kIcpModes{{
    {IcpMode::off, "off"},
    {IcpMode::refine, "refine"},
    {IcpMode::fallback, "fallback"},
    {IcpMode::both, "both"},
}};

}  // namespace

const char* to_string(RegistrationMethod method) {
    for (const auto& m : kMethods) {
        if (m.value == method) return m.name.data();
    }
    return "targets";
}

std::optional<RegistrationMethod> registration_method_named(std::string_view name) {
    for (const auto& m : kMethods) {
        if (m.name == name) return m.value;
    }
    return std::nullopt;
}

const char* to_string(registration::CovarianceScaling scaling) {
    for (const auto& s : kCovarianceScalings) {
        if (s.value == scaling) return s.name.data();
    }
    return "a_priori";
}

std::optional<registration::CovarianceScaling> covariance_scaling_named(std::string_view name) {
    for (const auto& s : kCovarianceScalings) {
        if (s.name == name) return s.value;
    }
    return std::nullopt;
}

std::vector<SectionKey<RegistrationConfig>> registration_keys() {
    using K = Keys<RegistrationConfig>;
    return {
        K::choice(&RegistrationConfig::method, "method", kMethods,
                  "What the datum rests on. `targets`: the [[target]] tables. `planes`: the "
                  "planes of the scene itself, detected in each scan's grid, matched to the "
                  "reference's and adjusted; the congruence test leaves out the planes that "
                  "moved, and planes inside a [[zone]] never enter the datum "
                  "(docs/registration.md, \"Registration on planes\"). `targets+planes`: both, "
                  "their estimates combined by their covariances when they agree; planes alone "
                  "when the targets are too few. `stable_areas`: targetless, on the supervoxels "
                  "of the reference whose change is not significant, found while registering "
                  "(docs/registration.md, \"Registration on stable areas\"); with `targets+` or "
                  "`planes+` it starts from their transformation and is combined with it when "
                  "the two agree, and stands alone when they are refused."),
        K::number(&RegistrationConfig::search_radius, "search_radius", 0.05, 5, "m",
                  "A target's points are taken within this of its predicted centre (its centre in "
                  "the reference epoch), through the scan grid's angular window."),
        K::number(&RegistrationConfig::centre_sigma_floor, "centre_sigma_floor", 0, 0.01, "m",
                  "Added as σ² per coordinate to every fitted centre's covariance. 0: the fits' "
                  "own σ, which on the simulator covers what the centres repeat to. A site "
                  "whose targets' centres scatter more than their fits say (the `no-change` "
                  "check of `tlsmon calibration` on its targets) sets the part the fits miss "
                  "(docs/registration.md, \"Centre σ floor\")."),
        K::choice(&RegistrationConfig::covariance_scaling, "covariance_scaling",
                  kCovarianceScalings,
                  "The variance factor σ0² of the targets' adjustment, Σ = σ0²·Q_xx, that every "
                  "LoD downstream inherits. `a_priori`: 1, the centres' covariances as they are "
                  "(they cover at the nominal rates over independent series). `larger_of`: "
                  "max(1, s0²), never more optimistic than the residuals, which pads the σ in "
                  "the epochs with s0² > 1. `a_posteriori`: s0² (t-expanded). An epoch that "
                  "fails the global test is scaled by s0² whatever this says "
                  "(docs/registration.md, \"Rigid transformation\"; docs/calibration.md)."),
        K::integer(&RegistrationConfig::min_targets, "min_targets", 3, 100, "",
                   "Usable targets that must remain after outliers are excluded; fewer: rejected."),
        K::number(&RegistrationConfig::max_rms, "max_rms", 0, 1, "m",
                  "Quality gate: RMS of the used targets' residual lengths."),
        K::number(&RegistrationConfig::max_sigma_angle_arcsec, "max_sigma_angle_arcsec", 0, 3600,
                  "″", "Quality gate: σ of each of ω, φ, κ."),
        K::number(&RegistrationConfig::max_sigma_translation, "max_sigma_translation", 0, 1, "m",
                  "Quality gate: σ of each of tx, ty, tz."),
        K::number(&RegistrationConfig::global_alpha, "global_alpha", 1e-6, 0.5, "",
                  "Significance level of the global test of the variance factor. An epoch that "
                  "fails it while every target passes its outlier test is accepted with the "
                  "covariance scaled by s0² (`accepted_scaled`), unless the hard limit below is "
                  "exceeded (docs/registration.md, \"Global test policy\")."),
        K::number(&RegistrationConfig::global_reject_alpha, "global_reject_alpha", 1e-9, 0.5, "",
                  "The variance factor's hard limit χ²(r, 1 − this)/r: above it an epoch that "
                  "fails the global test is rejected; at most `global_alpha` (equal: every failed "
                  "global test is rejected)."),
        K::number(&RegistrationConfig::target_alpha, "target_alpha", 1e-9, 0.5, "",
                  "Significance level of each target's outlier test (Baarda's α0)."),
        K::integer(&RegistrationConfig::confirm_exclusion_epochs, "confirm_exclusion_epochs", 1,
                   kMaxConfirmExclusionEpochs, "",
                   "A target that fails its outlier test is left out of that epoch's adjustment "
                   "(`target_outlier` event); it is excluded as moved until re-surveyed once it "
                   "has failed in this many consecutive registered epochs (`target_excluded`). "
                   "1: at the first failure, which at `target_alpha` = 0.001 and five stable "
                   "targets every 15 minutes loses one about every two days."),
        K::choice(&RegistrationConfig::atmosphere, "atmosphere", kAtmosphereCorrections,
                  "`measured_air`: when the epoch has meteo values, every range (target centres, "
                  "and the points handed to later stages) is corrected from the scanner's "
                  "setting below to the measured air, IAG 1999 group refractivity "
                  "(core/group_refractivity.hpp); the reference epoch with its own meteo. "
                  "Without meteo for the epoch or the reference, nothing is corrected and the "
                  "registration row says so. `off`: never corrected."),
        K::number(&RegistrationConfig::scanner_wavelength_nm, "scanner_wavelength_nm", 300, 2000,
                  "nm", "The scanner's carrier wavelength."),
        K::number(&RegistrationConfig::scanner_temperature_c, "scanner_temperature_c", -60, 60,
                  "°C", "Air temperature of the scanner's atmospheric setting."),
        K::number(&RegistrationConfig::scanner_pressure_hpa, "scanner_pressure_hpa", 300, 1200,
                  "hPa", "Air pressure of the scanner's atmospheric setting."),
        K::number(&RegistrationConfig::scanner_humidity_pct, "scanner_humidity_pct", 0, 100, "%",
                  "Relative humidity of the scanner's atmospheric setting."),
    };
}

std::vector<SectionKey<IcpConfig>> icp_keys() {
    using K = Keys<IcpConfig>;
    return {
        K::choice(&IcpConfig::mode, "icp", kIcpModes,
                  "Point-to-plane ICP on the `[[stable_region]]` tables only, never on the "
                  "structure (docs/registration.md). `refine`: after an accepted target "
                  "registration, combined with it by weights when the two agree. `fallback`: in "
                  "place of the targets when fewer than `min_targets` are usable (or they lie on a "
                  "line), from the identity, the epoch accepted if the ICP passes the `icp_*` "
                  "limits and the σ limits above. `both`: either. `off`: targets only. The row's "
                  "`method` says which was used."),
        K::number(&IcpConfig::max_correspondence_distance, "icp_max_correspondence_distance", 0.001,
                  1, "m", "ICP pairs an epoch point with the nearest reference point within this."),
        K::integer(&IcpConfig::max_iterations, "icp_max_iterations", 1, 1000, "",
                   "ICP iterations at most; not converged by then: refused."),
        K::number(&IcpConfig::voxel_size, "icp_voxel_size", 0.01, 2, "m",
                  "Both clouds are thinned to the mean of the points in each voxel of this side "
                  "(each pair weighs its voxel's number of points); the reference's normals come "
                  "from its means within three voxels."),
        K::number(&IcpConfig::min_overlap, "icp_min_overlap", 0, 1, "",
                  "Quality gate: share of the epoch's thinned stable points that found a pair "
                  "(the fitness)."),
        K::integer(&IcpConfig::min_points, "icp_min_points", 7, 10000000, "",
                   "Quality gate: pairs at least."),
        K::number(&IcpConfig::max_rms, "icp_max_rms", 0, 0.1, "m",
                  "Quality gate: RMS of the point-to-plane distances."),
        K::number(&IcpConfig::cluster_size, "icp_cluster_size", 0.1, 100, "m",
                  "The ICP's covariance lets the residuals within cells of this side err together "
                  "(an error common to each cell, its variance estimated from the epoch's own "
                  "residuals, and cluster-robust; docs/registration.md)."),
        K::number(&IcpConfig::sigma_factor, "icp_sigma_factor", 1, 10, "",
                  "The ICP's σ is multiplied by this. 1: as the epoch's residuals give it (honest "
                  "on the simulator without a factor, docs/registration.md); above 1 pads it."),
    };
}

std::vector<SectionKey<PlaneConfig>> plane_keys() {
    using K = Keys<PlaneConfig>;
    return {
        K::number(&PlaneConfig::flatness, "plane_flatness", 0, 0.05, "m",
                  "A real surface's own departure from a plane (formwork, joints), added to the "
                  "model's σ."),
        K::integer(&PlaneConfig::min_points, "plane_min_points", 10, 10000000, "",
                   "Fewer points in a block of the grid: no plane."),
        K::number(&PlaneConfig::max_normal_sigma_arcsec, "plane_max_normal_sigma_arcsec", 1, 36000,
                  "″", "A plane whose normal's σ is larger is not significant and is not kept."),
        K::number(&PlaneConfig::max_angle_deg, "plane_max_angle_deg", 0.01, 30, "°",
                  "Matching: an epoch plane's normal, mapped by the approximate transformation, "
                  "within this of the reference plane's."),
        K::number(&PlaneConfig::max_offset, "plane_max_offset", 0.001, 5, "m",
                  "Matching: the mapped epoch centroid within this of the reference plane."),
        K::number(&PlaneConfig::alpha, "plane_alpha", 1e-6, 0.5, "",
                  "The congruence test's level: the global test of \"no plane moved\"; while it "
                  "fails, the plane with the largest test statistic leaves the datum."),
        K::integer(&PlaneConfig::min_planes, "plane_min_planes", 3, 100000, "",
                   "Planes that must stay in the datum; fewer: the epoch is not registered on "
                   "planes."),
    };
}

std::vector<SectionKey<StableAreaConfig>> stable_area_keys() {
    using K = Keys<StableAreaConfig>;
    return {
        K::number(&StableAreaConfig::voxel, "stable_voxel", 0.01, 2, "m",
                  "The reference is voxelised at this before its supervoxels (VCCS) are grown, "
                  "and each epoch thinned to one centroid per voxel of this side."),
        K::number(&StableAreaConfig::seed, "stable_seed", 0.05, 20, "m",
                  "The supervoxels' seed resolution: their size, the unit that is stable or not."),
        K::integer(&StableAreaConfig::min_samples, "stable_min_samples", 4, 1000000, "",
                   "A supervoxel with fewer voxels (in the reference, or in the epoch) has no "
                   "change and stays out of the datum."),
        K::number(&StableAreaConfig::max_roughness, "stable_max_roughness", 0, 1, "m",
                  "A supervoxel whose voxels' RMS distance from its plane is larger is no patch "
                  "of plane (leaves, edges, corners, a wall with the ground at its foot) and "
                  "never enters the datum."),
        K::number(&StableAreaConfig::max_correspondence_distance,
                  "stable_max_correspondence_distance", 0.001, 1, "m",
                  "An epoch voxel pairs with the supervoxel of the nearest reference voxel within "
                  "this; beyond, it is new (a passer-by) and left out."),
        K::number(&StableAreaConfig::alpha, "stable_alpha", 1e-6, 0.5, "",
                  "A supervoxel whose change exceeds its LoD at this level leaves the stable set "
                  "(and returns when it no longer does)."),
        K::integer(&StableAreaConfig::max_iterations, "stable_max_iterations", 1, 100, "",
                   "Rounds of register, test, drop at most; the set not settled by then: the "
                   "last round's registration, and the row says so."),
        K::number(&StableAreaConfig::cluster_size, "stable_cluster_size", 1e-3, 1000, "m",
                  "The covariance of the registration on stable areas lets the residuals of all "
                  "supervoxels whose centroids share a cell of this side be correlated "
                  "(cluster-robust, docs/registration.md); no factor is applied."),
        K::number(&StableAreaConfig::min_share, "stable_min_share", 0, 1, "",
                  "Guard: the stable supervoxels' share of the voxels with a change; fewer: "
                  "the epoch is rejected, never analysed on a weak datum."),
        K::number(&StableAreaConfig::min_conditioning, "stable_min_conditioning", 0, 1, "",
                  "Guard: the smallest eigenvalue of the adjustment's normal matrix over its "
                  "largest, rotations as the movement at the stable set's RMS radius; below it "
                  "the stable set does not hold all six parameters (all in one plane, or planes "
                  "in only two directions) and the epoch is rejected."),
        K::integer(&StableAreaConfig::min_supervoxels, "stable_min_supervoxels", 3, 1000000, "",
                   "Guard: stable supervoxels at least."),
        K::integer(&StableAreaConfig::persistent_epochs, "stable_persistent_epochs", 1, 10000, "",
                   "A supervoxel outside the zones unstable in this many consecutive epochs is "
                   "reported as an unstable area (a creeping slope, a settling fill, a parked "
                   "vehicle): one `unstable_area` event when it first gets there."),
    };
}

}  // namespace tlsmon
