#pragma once
// What the registration stage needs of the site: its reference targets and the limits of its
// quality gate (docs/configuration.md, [registration] and [[target]]).
#include <Eigen/Core>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "algorithms/registration/rigid_transform.hpp"
#include "algorithms/zones/zone_shape.hpp"
#include "core/config_key.hpp"
#include "pipeline/icp_config.hpp"
#include "pipeline/plane_config.hpp"
#include "pipeline/stable_area_config.hpp"

namespace tlsmon {

enum class TargetKind { sphere, checkerboard };
const char* to_string(TargetKind kind);

struct TargetConfig {
    std::string name;
    TargetKind kind = TargetKind::sphere;
    double radius = 0.0725;                                 // sphere, m
    double size = 0.40;                                     // checkerboard side, m
    Eigen::Vector3d approximate = Eigen::Vector3d::Zero();  // project frame, within a few cm
    // A surveyed centre (project frame) replaces the one measured in the reference epoch.
    std::optional<Eigen::Vector3d> surveyed;
    double surveyed_sigma = 0.0005;  // m, per coordinate, of a surveyed centre
    // A sphere's mount: the unit direction from its centre to where it is held (project frame;
    // zero: not held), and the half-angle of the cap about it left out of the fit
    // (algorithms/registration/sphere_fit.hpp).
    Eigen::Vector3d mount = -Eigen::Vector3d::UnitZ();
    double mount_cap_deg = 30.0;
};

// What the datum rests on: the targets; the scene's own planes (the congruence test keeps the
// planes that stayed); the stable areas found in the scene itself (supervoxels whose change is
// not significant); or several, their estimates combined by their covariances. Bit flags.
enum class RegistrationMethod {
    targets = 1,
    planes = 2,
    targets_planes = 3,
    stable_areas = 4,
    targets_stable_areas = 5,
    planes_stable_areas = 6,
    targets_planes_stable_areas = 7,
};
const char* to_string(RegistrationMethod method);
// The method of that name ("targets", "planes", "targets+planes"); absent for another name.
std::optional<RegistrationMethod> registration_method_named(std::string_view name);

// The scaling of that name ("larger_of", "a_priori", "a_posteriori"); absent for another name.
std::optional<registration::CovarianceScaling> covariance_scaling_named(std::string_view name);
const char* to_string(registration::CovarianceScaling scaling);

// What to do with the epoch's meteo values (EpochInput::meteo).
enum class AtmosphereCorrection { measured_air, off };

// The most epochs `confirm_exclusion_epochs` may ask for (and the history the daemon reads).
constexpr int kMaxConfirmExclusionEpochs = 10;

struct RegistrationConfig {
    RegistrationMethod method = RegistrationMethod::targets;
    std::vector<TargetConfig> targets;  // none: no registration on targets
    double search_radius = 0.30;        // m about the predicted centre
    // Added (as σ² per coordinate) to every fitted centre's covariance: what a site's centres
    // scatter beyond their fits' σ. 0 on the simulator, whose fits' σ is what the centres
    // repeat to (docs/registration.md, "Centre σ floor").
    double centre_sigma_floor = 0.0;  // m
    // σ0² of the targets' adjustment (algorithms/registration/rigid_transform.hpp).
    registration::CovarianceScaling covariance_scaling = registration::CovarianceScaling::a_priori;
    int min_targets = 3;
    double max_rms = 0.002;                // m, RMS of the used targets' residual lengths
    double max_sigma_angle_arcsec = 10.0;  // each of ω, φ, κ
    double max_sigma_translation = 0.002;  // m, each of tx, ty, tz
    double global_alpha = 0.05;
    // Ω between χ²(r, 1 − global_alpha) and χ²(r, 1 − global_reject_alpha), no target to
    // blame: accepted with the covariance scaled by s0² (`accepted_scaled`); beyond: rejected.
    double global_reject_alpha = 0.001;
    double target_alpha = 0.001;
    // A target that fails its outlier test is left out of that epoch's adjustment; it is
    // excluded as moved (until re-surveyed) once it has failed in this many consecutive
    // registered epochs. At most kMaxConfirmExclusionEpochs.
    int confirm_exclusion_epochs = 2;
    AtmosphereCorrection atmosphere = AtmosphereCorrection::measured_air;
    // The scanner's atmospheric setting: the air its ranges were converted with.
    double scanner_wavelength_nm = 1500.0;
    double scanner_temperature_c = 20.0;
    double scanner_pressure_hpa = 1013.25;
    double scanner_humidity_pct = 60.0;
    // The site's zones; the registration's σ is propagated to each one's bounding box.
    std::vector<ZoneShape> zones;
    // ICP on the stable regions: refinement and fallback (pipeline/icp_registration.hpp).
    IcpConfig icp;
    // The registration on planes (pipeline/registration_on_planes.hpp).
    PlaneConfig planes;
    // The registration on stable areas (pipeline/stable_area_registration.hpp).
    StableAreaConfig stable_areas;
    bool uses(RegistrationMethod m) const {
        return (static_cast<int>(method) & static_cast<int>(m)) != 0;
    }
    bool uses_targets() const { return uses(RegistrationMethod::targets); }
    bool uses_planes() const { return uses(RegistrationMethod::planes); }
    bool uses_stable_areas() const { return uses(RegistrationMethod::stable_areas); }
};

// Whether an epoch can be registered at all: on targets, on planes, or by the ICP fallback
// on the stable regions (which also runs where no target is configured).
inline bool can_register(const RegistrationConfig& c) {
    return (c.uses_targets() && !c.targets.empty()) || c.uses_planes() || c.uses_stable_areas() ||
           (c.icp.falls_back() && !c.icp.regions.empty());
}

// What a site that cannot register says (check-config, and the log and events at start).
inline constexpr const char* kNoRegistrationWarning =
    "no registration can run: no [[target]] tables, registration.method is not on planes, and "
    "no ICP fallback on [[stable_region]] tables (registration.icp = \"fallback\" or "
    "\"both\"); every epoch but the reference "
    "is stored `unregistered` and its values raise no alarm";

// The registration on stable areas as the only datum is not yet safe on every site: where the
// stable areas hold a direction weakly and a block that holds it moves, the datum follows the
// block by a fraction of a millimetre while its σ says less (docs/registration.md,
// "Registration on stable areas"). Said by check-config and as an event at start.
inline bool stable_areas_alone(const RegistrationConfig& c) {
    return c.method == RegistrationMethod::stable_areas;
}
inline constexpr const char* kStableAreasAloneWarning =
    "registration.method = \"stable_areas\" alone: not yet validated as a site's only datum (a "
    "moved block that holds a weak direction pulls the datum by a few tenths of a millimetre, "
    "not always within its σ; docs/registration.md); combine it with targets or planes "
    "(\"targets+stable_areas\") where they exist";

// The keys of [registration]: its own, then the ICP's (`icp`, `icp_*`; core/config_key.hpp).
std::vector<SectionKey<RegistrationConfig>> registration_keys();
std::vector<SectionKey<IcpConfig>> icp_keys();
std::vector<SectionKey<PlaneConfig>> plane_keys();
std::vector<SectionKey<StableAreaConfig>> stable_area_keys();

}  // namespace tlsmon
