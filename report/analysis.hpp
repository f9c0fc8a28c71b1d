#pragma once
// A finished run, scored against the simulator's truth when there is one: the registration's
// error at the pier, each zone quantity against the true change since the reference epoch,
// and the alarms against the true step event. Without a truth (a real site) the same report
// holds the run's own figures: the registration's residuals and σ, each zone's series with
// its LoD95, the alarm events. Pure: plain data in, plain data out.
#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "report/data.hpp"
#include "report/truth.hpp"

namespace tlsmon::report {

// Bias (mean), RMS and largest magnitude of a list of errors; n = 0 when there are none.
struct ErrorSummary {
    std::size_t n = 0;
    double bias = 0, rms = 0, max_abs = 0;
};
ErrorSummary summarise(const std::vector<double>& errors);

// One epoch's registration against the truth.
struct RegistrationCheck {
    EpochId id = 0;
    int truth_epoch = -1;  // -1: no truth file for this epoch
    std::int64_t acquired = 0;
    std::string status;  // epoch status (done, rejected, failed, pending)
    bool registered = false;
    bool accepted = false;
    bool is_reference = false;
    std::int64_t targets_used = 0;
    double target_rms_m = 0;  // RMS of the used targets' residuals (the registration's own)
    std::vector<std::string> excluded;  // targets excluded as moved (or flagged) this epoch
    std::string reason;
    // The transformation's error at the pier against the exact answer H₀⁻¹·Hᵢ
    // (docs/simulator.md, "Scanner instability"), at the truth's pier sample points:
    std::optional<Eigen::Vector3d> top_error;  // at the top centre, m
    std::optional<double> max_error;           // largest over the sample points, m
    std::optional<double> zone_sigma_m;        // the registration's own largest zone σ (3-D)
    // Each target's residual length as the registration stored it (found or excluded), m.
    std::vector<std::pair<std::string, double>> target_residuals;
    // The estimated parameters (ω, φ, κ rad, tx, ty, tz m) minus the exact transformation's,
    // and their σ as the registration stored them (docs/calibration.md).
    std::string method;
    std::optional<std::array<double, 6>> parameter_error, parameter_sigma;
};

struct ZoneQuantityCheck {
    std::string zone;
    std::string quantity;
    std::string truth_kind;     // what it is compared with, in words; "" = no truth for it
    bool displacement = false;  // a change of the surface the plots draw (M3C2, keypoints)
    struct Row {
        EpochId id = 0;
        int truth_epoch = -1;
        std::int64_t acquired = 0;
        double value = 0;
        std::optional<double> lod;
        std::optional<double> truth;
        bool significant = false;
    };
    std::vector<Row> rows;
    ErrorSummary error;  // value − truth over the rows with a truth
};

struct ZoneCheck {
    ZoneId id = 0;
    std::string zone;
    std::optional<ZoneFace> face;                  // absent: not on one pier face
    std::vector<ZoneQuantityCheck> quantities;     // stored ones, with their truth
    std::vector<std::pair<int, ZoneTruth>> truth;  // (truth epoch, true change) for plots
    bool step_zone = false;                        // the truth's step moves it along its normal
    // A check zone on ground known not to move: its displacement quantities' truth is 0.
    bool no_change = false;
};

struct AlarmCheck {
    AlarmRuleId id = 0;  // its Modbus slot is id − 1
    std::string rule, zone, quantity;
    bool step_zone = false;
    std::optional<int> step_epoch;         // truth: first epoch of the step
    std::optional<int> first_raise_epoch;  // truth epoch of the first raise at/after it
    std::optional<int> latency_epochs;     // first_raise_epoch − step_epoch
    int raises = 0;                        // every raise, at any level
    int false_alarms = 0;                  // scored: raises before the step, or where it is not
    bool evaluated = false;                // the rule's quantity has rows in its zone
    std::vector<std::string> events;       // "epoch 65: raise alarm (+11.20 mm)" (database ids)
};

// A statistic that follows χ²(dof) when the σ involved are honest: a check of the σ that
// needs no truth (report/calibration.hpp). "agreement:<estimate>": a joint registration's two
// independent estimates of one epoch's transformation (the targets' and the ICP's, the
// planes' or the stable areas'), their difference against the sum of their covariances, 6
// degrees of freedom. "no_change:targets": a used target against the transformation of the
// others, its outlier test's T_i, the drop of Ω when it is left out (Förstner 1983), 3.
struct ChiSquareTest {
    EpochId epoch = 0;
    std::string method;
    double chi2 = 0;
    int dof = 6;
};

struct RunReport {
    std::filesystem::path database;
    bool scored = false;               // a truth was given: the comparisons below are filled
    std::optional<EpochId> reference;  // the database's reference epoch
    std::filesystem::path truth_folder;
    std::optional<int> reference_truth_epoch;
    int truth_epochs = 0;
    std::optional<KnockedTarget> knocked;  // truth
    std::optional<StepEvent> step;         // truth
    std::map<int, EpochId> epoch_id;       // truth epoch -> the database's epoch id
    std::vector<RegistrationCheck> registration;
    ErrorSummary registration_top_error;        // |error| at the top centre, accepted epochs
    ErrorSummary registration_max_error;        // largest over the pier samples, accepted epochs
    std::vector<double> bias_vector_mm;         // mean error vector at the top centre, mm (x, y, z)
    std::vector<std::string> excluded_targets;  // ever excluded, in order of first exclusion
    std::optional<int> knocked_excluded_from;   // truth epoch the knocked target is first out
    std::vector<ZoneCheck> zones;
    std::vector<AlarmCheck> alarms;
    std::vector<ChiSquareTest> chi_square_tests;  // of the accepted epochs, truth or not
    std::size_t epochs_done = 0, epochs_rejected = 0, epochs_failed = 0, epochs_pending = 0;
    std::vector<CampaignRow> campaigns;  // as stored: nothing of them is scored
};

// `truth` empty: a run without a truth (nothing is scored).
RunReport analyse(const RunData& run, const std::vector<TruthEpoch>& truth,
                  const std::filesystem::path& truth_folder);

}  // namespace tlsmon::report
