#pragma once
// The registration stage's rows (storage/epoch_results.hpp): the registration row with its
// quality, each target's observation, the exclusions, the registration's σ per zone and the
// matched planes.
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

// The row of an epoch that no registration could take to the reference's frame: the
// reference itself is its own datum (identity, accepted); any other epoch stays in the
// scanner's frame, `unregistered`, and its values raise no alarm (docs/registration.md).
RegistrationRow datum_without_registration(bool is_reference);

}  // namespace tlsmon
