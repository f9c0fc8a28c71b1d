#pragma once
// The registration configuration a site engineer would write for a simulated site: each
// target of the scene with its kind and size, its approximate position a few centimetres
// off the true centre (as a site's approximate positions are). Shared by the pipeline tests
// and the benches that register simulated epochs.
#include <Eigen/Core>

#include "pipeline/registration_config.hpp"
#include "simulator/scene.hpp"

namespace tlsmon::test {

inline RegistrationConfig simulated_targets(const sim::Site& site) {
    RegistrationConfig c;
    for (const auto& t : site.targets) {
        TargetConfig g;
        g.name = t.name;
        g.kind =
            t.kind == sim::Target::Kind::sphere ? TargetKind::sphere : TargetKind::checkerboard;
        g.radius = t.radius;
        g.size = t.size;
        g.approximate = t.centre + Eigen::Vector3d(0.02, -0.015, 0.01);
        c.targets.push_back(g);
    }
    return c;
}

}  // namespace tlsmon::test
