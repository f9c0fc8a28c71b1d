#pragma once
// The registration's records outside an epoch commit: which targets are excluded as moved
// (until an operator re-surveys them), and the rows `tlsmon query registrations` shows.
#include <array>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/utc_time.hpp"
#include "storage/epoch_results.hpp"
#include "storage/ids.hpp"

namespace tlsmon {

struct TimeRange;

struct Connection;

// One exclusion of a target as moved: the epoch that excluded it (and when that epoch was
// acquired), and when an operator re-surveyed it (absent: still excluded).
struct TargetExclusion {
    std::string target;
    EpochId epoch = 0;
    std::int64_t excluded_acquired = 0;  // unix time of the excluding epoch's acquisition
    std::optional<std::int64_t> resurveyed;
};

class RegistrationStore {
  public:
    explicit RegistrationStore(Connection& connection) : c_(&connection) {}

    // Targets excluded as moved by an epoch and not re-surveyed since.
    std::set<std::string> excluded_targets() const;
    // Per target, in how many of the newest `limit` registered epochs acquired before
    // `before` (newest first, without a break) it failed its outlier test
    // (`excluded_outlier`); targets with none are absent.
    std::map<std::string, int> outlier_runs(std::int64_t before, int limit) const;
    // An operator re-surveyed the target: it is offered to the registration again (its
    // reference centre is measured anew when the reference's parameters change).
    // Returns the number of exclusions cleared.
    int mark_resurveyed(const std::string& target, std::int64_t unix_time);
    // The operator's re-survey: clears the target's open exclusions and records a
    // `target_resurveyed` system event naming `actor`, in one immediate transaction (safe
    // while the daemon commits epochs). Returns the exclusions cleared; 0 records nothing.
    int resurvey(const std::string& target, std::int64_t unix_time, const std::string& actor);
    // Every exclusion, oldest first.
    std::vector<TargetExclusion> exclusions() const;
    // The newest epoch with target observations, if any.
    std::optional<EpochId> last_epoch_with_targets() const;
    // The transformation of the newest accepted registration acquired before `acquired`
    // (4×4 row-major, as RegistrationRow::transform): a fixed station's prior for the next.
    std::optional<std::array<double, 16>> last_accepted_transform(UtcSeconds acquired) const;
    // The state bytes of the newest `count` stable-area masks of epochs acquired before
    // `acquired`, newest first, stopping at the first on another reference or segmentation.
    std::vector<std::vector<std::uint8_t>> recent_stable_area_states(
        UtcSeconds acquired, EpochId reference_epoch, const std::string& segmentation,
        int count) const;

    std::optional<RegistrationRow> of_epoch(EpochId id) const;
    std::vector<TargetObservation> targets_of_epoch(EpochId id) const;
    std::vector<RegistrationZoneSigma> zone_sigmas_of_epoch(EpochId id) const;
    // The same for every epoch acquired in `range`, in three queries (a year of epochs one
    // by one is 100,000 statements), by epoch id.
    struct EpochRegistrations {
        std::map<EpochId, RegistrationRow> registration;
        std::map<EpochId, std::vector<TargetObservation>> targets;
        std::map<EpochId, std::vector<RegistrationZoneSigma>> zone_sigmas;
    };
    EpochRegistrations in_range(const TimeRange& range) const;
    // The registration on planes' matched planes, by reference index.
    std::vector<PlaneRow> planes_of_epoch(EpochId id) const;
    // The epoch's stable-area mask with its reference's supervoxels (the registration on
    // stable areas); absent when it did not run.
    std::optional<StableAreaMask> stable_areas_of_epoch(EpochId id) const;

  private:
    Connection* c_;
};

}  // namespace tlsmon
