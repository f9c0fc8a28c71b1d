#pragma once
// One epoch of a preset rendered as the pipeline tests need it, in a fraction of a full
// epoch's time: each target's window at the preset's step (what the registration measures)
// and the window of the pier's south and west faces at `face_step_deg`, or the preset's
// detail scans — the same geometry, beam, noise, scanner drift and air as a full epoch.
#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <vector>

#include "core/scan.hpp"
#include "pipeline/registration_stage.hpp"
#include "pipeline/stage.hpp"
#include "simulator/epoch_conditions.hpp"
#include "simulator/render.hpp"
#include "tests/simulator/narrow_window.hpp"

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

inline WindowedEpoch render_windows(const sim::Site& site, int epoch, double hours,
                                    double face_step_deg) {
    WindowedEpoch e = render_target_windows(site, epoch, hours);
    sim::Site faces = site;
    auto& s = faces.scanner;
    s.azimuth_min_deg = 68.0;
    s.azimuth_max_deg = 89.0;
    s.elevation_min_deg = -3.0;
    s.elevation_max_deg = 42.0;
    s.azimuth_step_deg = s.elevation_step_deg = face_step_deg;
    e.pier.push_back(sim::render_epoch(faces, e.conditions, 2).scan);
    return e;
}

// Epoch `ei` registered on its targets' windows against the reference's, as the stage
// outputs the analyses take (the range scales are the truth's air, as a site takes them from
// its weather station); nullopt, and a test failure, when the registration refuses it.
inline std::optional<StageOutputs> registered_outputs(const RegistrationConfig& targets,
                                                      const ReferenceTargets& reference,
                                                      const WindowedEpoch& e0,
                                                      const WindowedEpoch& ei, int epoch) {
    const double k_r = e0.conditions.atmosphere.range_scale;
    const double k_e = ei.conditions.atmosphere.range_scale;
    const RegistrationResult r = register_epoch(targets, reference, ei.targets, {}, {k_e, k_r});
    EXPECT_TRUE(r.accepted()) << "epoch " << epoch << ": " << r.tested.reason << " " << r.gate;
    if (!r.accepted()) return std::nullopt;
    StageOutputs o;
    o.to_reference = r.tested.transform;
    o.range_scale = k_e;
    o.scanner = ei.pier.front().scanner_position();
    o.reference_range_scale = k_r;
    return o;
}

}  // namespace tlsmon::test
