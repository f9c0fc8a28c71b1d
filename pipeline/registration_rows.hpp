#pragma once
// The registration stage's rows (storage/epoch_results.hpp): the registration row with its
// quality, each target's observation, the exclusions, the registration's σ per zone, the
// matched planes and each zone's plane series.
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "pipeline/registration_stage.hpp"
#include "pipeline/stage.hpp"
#include "storage/epoch_results.hpp"

namespace tlsmon {

// What the registration measured, as the commit stores it; `verdict`: the stage's.
void record_registration(const RegistrationResult& r, const StageVerdict& verdict, EpochId epoch,
                         EpochResults& results);

// The planes the registration on planes matched, with their change under the accepted
// transformation (whichever method made it); none when the epoch was not accepted.
std::vector<PlaneRow> plane_rows(const RegistrationResult& r);

// The zone's plane series: for each zone, the change of its plane (the largest reference
// plane in it) when it was matched, as three quantities — the tilt of its normal towards the
// reference plane's long axis u and towards v = n × u (″), its shift along the normal (m,
// positive towards the scanner) — each with its LoD95 = 1.96·σ (the σ includes the
// registration's) and significant when beyond it (kPlaneQuantities, plane_config.hpp).
std::vector<ZoneResult> plane_zone_results(const std::map<std::string, std::size_t>& zone_plane,
                                           const std::vector<PlaneRow>& rows);

// The row of an epoch that no registration could take to the reference's frame: the
// reference itself is its own datum (identity, accepted); any other epoch stays in the
// scanner's frame, `unregistered`, and its values raise no alarm (docs/registration.md).
RegistrationRow datum_without_registration(bool is_reference);

}  // namespace tlsmon
