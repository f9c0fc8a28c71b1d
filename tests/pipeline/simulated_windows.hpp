#pragma once
// One epoch of a preset rendered as the pipeline tests need it, in a fraction of a full
// epoch's time: each target's window at the preset's step (what the registration measures)
// and the window of the pier's south and west faces at `face_step_deg`, or the preset's
// detail scans — the same geometry, beam, noise, scanner drift and air as a full epoch.
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "core/scan.hpp"
#include "pipeline/registration_stage.hpp"
#include "pipeline/stage.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/render.hpp"
#include "tests/simulator/narrow_window.hpp"
#include "tests/support/simulated_targets.hpp"

namespace tlsmon::test {

struct WindowedEpoch {
    std::vector<Scan> targets;  // one window per target
    std::vector<Scan> pier;     // the faces' window
    sim::EpochConditions conditions;
};

// The targets' windows of an epoch, with its conditions.
inline WindowedEpoch render_target_windows(const sim::Site& site, int epoch, double hours) {
    WindowedEpoch e;
    e.conditions = sim::epoch_conditions(site, epoch, hours);
    for (const auto& t : site.targets) {
        sim::Site one = site;
        sim::test::narrow_window(one.scanner, t.centre, 0.9);
        e.targets.push_back(sim::render_epoch(one, e.conditions, 2).scan);
    }
    return e;
}

// The targets' windows and the site's detail scans: a detail scan named after a target (its
// fine scan) goes with the targets, the others with the pier.
inline WindowedEpoch render_detail_windows(const sim::Site& site, int epoch, double hours) {
    WindowedEpoch e = render_target_windows(site, epoch, hours);
    for (std::size_t d = 0; d < site.scanner.details.size(); ++d) {
        const bool target_scan =
            std::any_of(site.targets.begin(), site.targets.end(),
                        [&](const auto& t) { return t.name == site.scanner.details[d].name; });
        (target_scan ? e.targets : e.pier)
            .push_back(sim::render_detail(site, d, e.conditions, 2).scan);
    }
    return e;
}

// A window of the scanner's (azimuth × elevation, degrees).
struct Window {
    double azimuth_min, azimuth_max, elevation_min, elevation_max;
};

// The pier's south and west faces: the window the keypoint and patch tests render.
inline constexpr Window kPierFaces{68.0, 89.0, -3.0, 42.0};

// `window` of the site's scanner at `step_deg`, at its place in a whole scan's lattice at this
// step (tests/simulator/narrow_window.hpp): its noise is not the targets' windows' noise.
inline Scan render_window(const sim::Site& site, const sim::EpochConditions& conditions,
                          double step_deg, const Window& window = kPierFaces) {
    sim::Site cut = site;
    auto& s = cut.scanner;
    s.azimuth_min_deg = window.azimuth_min;
    s.azimuth_max_deg = window.azimuth_max;
    s.elevation_min_deg = window.elevation_min;
    s.elevation_max_deg = window.elevation_max;
    s.azimuth_step_deg = s.elevation_step_deg = step_deg;
    sim::test::place_in_lattice(s, site.scanner);
    return sim::render_epoch(cut, conditions, 2).scan;
}

// The targets' windows and `pier` (default: the pier's south and west faces) at `step_deg`.
inline WindowedEpoch render_windows(const sim::Site& site, int epoch, double hours, double step_deg,
                                    const Window& pier = kPierFaces) {
    WindowedEpoch e = render_target_windows(site, epoch, hours);
    e.pier.push_back(render_window(site, e.conditions, step_deg, pier));
    return e;
}

// Epoch `ei` registered on its targets' windows against the reference's, as the stage
// outputs the analyses take (the range scales are the truth's air, as a site takes them from
// its weather station); nullopt when the registration refuses it, `refused` then saying why.
inline std::optional<StageOutputs> registered_windows(const RegistrationConfig& targets,
                                                      const ReferenceTargets& reference,
                                                      const WindowedEpoch& e0,
                                                      const WindowedEpoch& ei,
                                                      std::string& refused) {
    auto o = simulated_outputs(targets, reference, ei.targets, ei.conditions.atmosphere.range_scale,
                               e0.conditions.atmosphere.range_scale, refused);
    // The pier's scanner: the same station as the targets' windows.
    if (o) o->scanner = ei.pier.front().scanner_position();
    return o;
}

}  // namespace tlsmon::test
