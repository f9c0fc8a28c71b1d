#pragma once
// What the registration on planes measured in one epoch (pipeline/registration_on_planes.hpp),
// as the registration row and the plane rows record it.
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/registration/plane_registration.hpp"

namespace tlsmon {

// One reference plane matched in the epoch, under the accepted transformation.
struct PlaneObservation {
    std::size_t plane = 0;  // the reference plane's index: its identity while the reference stays
    std::string zone;       // the zone its reference centroid lies in; "" outside every zone
    // "datum": in the adjustment; "moved": left out by the congruence test; "monitored":
    // inside a zone, so never in the datum (the structure is what is measured).
    std::string role;
    registration::FittedPlane reference;  // reference frame
    registration::FittedPlane epoch;      // epoch frame, ranges corrected
    // w = (tilt towards the reference plane's long axis u, towards v = n × u, shift along n),
    // its cofactor (σ0 = 1) and T = wᵀ·Q⁻¹·w (plane_registration.hpp).
    registration::PlaneMisclosure misclosure;
    double critical = 0.0;  // χ²(3, 1 − plane_alpha)
    bool significant() const { return misclosure.test_statistic > critical; }
};

// The approximate transformation (the last accepted one, or the targets') matched too few
// planes, and the matching without a prior (plane_matching_without_prior.hpp) found the
// scanner elsewhere: a station change.
struct StationChange {
    double shift_m = 0.0;     // |t − t_prior|
    double turn_deg = 0.0;    // the angle of R·R_priorᵀ
    std::size_t support = 0;  // reference planes the prior-free hypothesis explained
};

struct PlaneMeasurement {
    std::string role;     // "alone": the epoch's datum; "joint": combined with the targets'
    bool used = false;    // entered the epoch's transformation
    std::string refused;  // why it did not ("" when used)
    std::size_t reference_planes = 0, epoch_planes = 0;
    std::vector<PlaneObservation> matched;  // by reference index
    std::size_t in_datum = 0, moved = 0, monitored = 0;
    // The congruence test: Ω and χ²(r, 1 − α) of the first round (every candidate plane) and
    // of the last (the planes that stayed).
    double first_omega = 0, first_limit = 0, last_omega = 0, last_limit = 0;
    bool congruent = false;
    // Joint: χ² of the difference to the targets' transformation (6 degrees of freedom).
    std::optional<double> agreement;
    double detection_ms = 0, adjustment_ms = 0;
    // The targets' verdict the planes replaced (method targets+planes, targets refused).
    std::string targets_status;
    std::optional<registration::RigidTransform> transform;  // the planes' own estimate
    std::optional<StationChange> station_change;
    // Each zone's plane: the largest reference plane whose centroid lies in it, by index.
    // Its change is the zone's plane series (registration_rows.hpp), when it was matched.
    std::map<std::string, std::size_t> zone_plane;
};

}  // namespace tlsmon
