#pragma once
// Stage "registration": each configured target is found in the epoch through the grid's
// angular window about its reference centre and fitted (sphere: known-radius fit;
// checkerboard: plane + intensity pattern), its covariance given a floor; the reference
// centres are measured once in the reference epoch (a product of the reference cache) or
// taken from a survey; the weighted rigid transformation epoch -> reference with its tests
// (algorithms/registration/target_tests.hpp) excludes a moved target, and the quality gate
// of the configuration decides whether the epoch can be analysed. The accepted
// transformation is handed to the later stages (StageOutputs).
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "algorithms/registration/target_tests.hpp"
#include "pipeline/icp_measurement.hpp"
#include "pipeline/plane_measurement.hpp"
#include "pipeline/reference_cache.hpp"
#include "pipeline/registration_config.hpp"
#include "pipeline/stable_area_measurement.hpp"
#include "pipeline/stage.hpp"

namespace tlsmon {

// The short names stored and printed (`used`, `excluded_outlier`; `too_few_targets`, ...).
const char* name_of(registration::TargetUse use);
const char* name_of(registration::RegistrationStatus status);

// One target as measured in one epoch.
struct TargetMeasurement {
    std::string name;
    TargetKind kind = TargetKind::sphere;
    std::string status = "not_found";                  // found | not_found | bad_fit | excluded
    std::string reason;                                // why, when not found
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // project frame of the epoch
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();  // m², with the floor
    std::size_t points = 0;                                    // points in the search window
    Eigen::Vector3d viewpoint = Eigen::Vector3d::Zero();       // the scanner, project frame
    bool found() const { return status == "found"; }
};

// The reference centres: measured in the reference epoch, or surveyed.
struct ReferenceTargets {
    // Its reference-cache entry's format. 3: a checkerboard's plane weighted by colour
    // (algorithms/registration/checkerboard_centre.hpp, step 1). 4: a sphere's fit leaves out
    // the cap where its mount meets it (sphere_fit.hpp). An older entry's centres are measured
    // again, as the epochs' are.
    static constexpr int kFormatVersion = 4;
    std::vector<TargetMeasurement> targets;  // in the configuration's order

    std::string encode() const;
    static ReferenceTargets decode(std::string_view payload);
};

// Finds and fits one target in the scans near `predicted` (project frame). Where several
// scans hold it (an overview and a target's detail scan), the fit on the most points wins:
// the finest sampling.
TargetMeasurement measure_target(const TargetConfig& target, const std::vector<Scan>& scans,
                                 const Eigen::Vector3d& predicted,
                                 const RegistrationConfig& config);

ReferenceTargets measure_reference_targets(const RegistrationConfig& config,
                                           const std::vector<Scan>& scans);

// The σ of the registration at a zone: the largest √tr(Σ_p) over the box's corners (Σ_p is
// a convex quadratic in p, so its largest value over a box lies at a corner).
struct ZoneRegistrationSigma {
    std::string zone;
    double max_sigma_3d = 0;  // m
};
std::vector<ZoneRegistrationSigma> zone_sigmas(const RegistrationConfig& config,
                                               const registration::RigidTransform& T);

// The σ part of the quality gate (registration.max_sigma_*) on a transformation: why it
// refuses, "" when it passes.
std::string sigma_gate(const RegistrationConfig& config, const registration::RigidTransform& T);

struct RegistrationResult {
    std::vector<TargetMeasurement> measured;  // this epoch, in the configuration's order
    std::vector<TargetMeasurement> reference;
    registration::TestedRegistration tested;
    std::string gate;  // why the quality gate refused, "" if it passed
    double rms = 0;    // m, RMS residual length of the used targets
    double max_residual = 0;
    int used = 0;
    std::vector<ZoneRegistrationSigma> zones;
    // Targets that failed their outlier test in this epoch and are left out of its adjustment:
    // excluded as moved (until re-surveyed), or not yet, having failed in fewer than
    // `confirm_exclusion_epochs` consecutive epochs (RegistrationStage::measure).
    std::vector<std::string> newly_excluded, outliers;
    // Range scales n_true/n_setting applied (1/scale about the scanner) from the meteo of
    // the epoch and of the reference; absent: not corrected.
    std::optional<double> epoch_range_scale, reference_range_scale;
    std::string atmosphere;  // what was done about the air, in words
    // The ICP on stable regions, when it ran (pipeline/icp_registration.hpp).
    std::optional<IcpMeasurement> icp;
    // The registration on planes, when it ran (pipeline/registration_on_planes.hpp).
    std::optional<PlaneMeasurement> planes;
    // The registration on stable areas, when it ran (pipeline/stable_area_registration.hpp).
    std::optional<StableAreaMeasurement> stable_areas;
    bool accepted() const { return tested.accepted() && gate.empty(); }
};

// A second, independent estimate `other` of an accepted epoch's transformation joined to it:
// when the two agree (χ² of their difference against the sum of their covariances below
// χ²(6, 1 − 0.001)) the transformation becomes their combination by weights and the σ gate is
// evaluated again; otherwise the accepted one is kept. Returns "" when joined, else why not
// (naming `kept`, the method the accepted one came from); `agreement` receives the χ².
std::string join_estimate(const RegistrationConfig& config, RegistrationResult& result,
                          const registration::RigidTransform& other, const std::string& kept,
                          std::optional<double>& agreement);

// An estimate that stands in for a refused registration (`before`: that verdict, "" when
// there was none; `refused`: why the estimate cannot, "" when it was made): when it passes the
// σ gate it becomes the epoch's transformation, accepted
// with `accepted_reason`; otherwise the epoch is refused with `status` and `refused`. Returns
// whether it was taken.
bool stand_in(const RegistrationConfig& config, RegistrationResult& result,
              const std::optional<registration::RigidTransform>& estimate, std::string& refused,
              const std::string& accepted_reason, registration::RegistrationStatus status,
              const std::string& before);

// n_true/n_setting for the measured air of `meteo` (IAG 1999, core/group_refractivity.hpp);
// absent without meteo values or with the correction off.
std::optional<double> measured_range_scale(const RegistrationConfig& config,
                                           const std::optional<MeteoSidecar>& meteo);

// The scales of the epoch and of the reference epoch (absent: not corrected).
struct RangeScales {
    std::optional<double> epoch, reference;
};

// Registers one epoch against the reference centres; `excluded`: targets excluded until an
// operator re-surveys them. Pure apart from reading the scans.
RegistrationResult register_epoch(const RegistrationConfig& config,
                                  const ReferenceTargets& reference, const std::vector<Scan>& scans,
                                  const std::set<std::string>& excluded,
                                  const RangeScales& scales = {});

// register_epoch's outliers (`newly_excluded`) kept there when they have failed their test in
// `confirm` consecutive epochs, this one included (`runs`: the epochs before,
// StageHistory::outlier_runs); the others moved to `outliers`, left out of this epoch only.
// One test at α0 per target and epoch fails by chance about once in 1/α0 epochs; a moved
// target fails again (docs/registration.md, "Confirmed exclusions").
void confirm_exclusions(RegistrationResult& result, const std::map<std::string, int>& runs,
                        int confirm);

// The stage: every epoch states its datum. With targets or the ICP fallback: the reference
// centres from the cache (`registration.targets`), register_epoch, the ICP; the verdict
// rejects an epoch that fails a test or the gate; the registration row, the targets' rows
// and the exclusions written; the accepted map handed on (StageOutputs). Without: the
// reference's own frame (never an ICP of the reference onto itself, which a sampled surface
// need not return as the identity), or `unregistered` for every other epoch.
class RegistrationStage final : public Stage {
  public:
    explicit RegistrationStage(RegistrationConfig config) : config_(std::move(config)) {}
    const char* name() const override { return "registration"; }
    StageVerdict run(StageContext& ctx) const override;
    // The measurement alone, into `result` (the one-shot `tlsmon register` and the stage).
    StageVerdict measure(StageContext& ctx, RegistrationResult& result) const;
    // What an accepted registration hands to the later stages.
    static StageOutputs outputs_of(const RegistrationResult& result, const EpochInput& input);

  private:
    RegistrationConfig config_;
};

}  // namespace tlsmon
