#pragma once
// The registration's records outside an epoch commit: which targets are excluded as moved
// (until an operator re-surveys them), and the rows `tlsmon query registrations` shows.
#include <set>
#include <string>
#include <vector>

#include "storage/epoch_results.hpp"
#include "storage/ids.hpp"

namespace tlsmon {

struct Connection;

class RegistrationStore {
  public:
    explicit RegistrationStore(Connection& connection) : c_(&connection) {}

    // Targets excluded as moved by an epoch and not re-surveyed since.
    std::set<std::string> excluded_targets() const;
    // An operator re-surveyed the target: it is offered to the registration again (its
    // reference centre is measured anew when the reference's parameters change).
    // Returns the number of exclusions cleared.
    int mark_resurveyed(const std::string& target, std::int64_t unix_time);

    std::optional<RegistrationRow> of_epoch(EpochId id) const;
    std::vector<TargetObservation> targets_of_epoch(EpochId id) const;
    std::vector<RegistrationZoneSigma> zone_sigmas_of_epoch(EpochId id) const;

  private:
    Connection* c_;
};

}  // namespace tlsmon
