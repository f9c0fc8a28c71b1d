// The three named scenes. All share the layout: scanner at the origin on a 1.5 m tripod,
// the pier's 15 m south wall seen almost head-on, its west wall at a grazing angle, and
// four targets (two spheres, two checkerboards) on stable ground 20–40 m away, left and
// right of the pier so it never hides them.
#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "simulator/scene.hpp"

namespace tlsmon::sim {

namespace {

// A target at horizontal distance `distance` and scanner azimuth `azimuth_deg` (heading 0),
// `height` above the ground.
Target place(std::string name, Target::Kind kind, double distance, double azimuth_deg,
             double height) {
    Target t;
    t.name = std::move(name);
    t.kind = kind;
    const double a = azimuth_deg * std::numbers::pi / 180.0;
    t.centre = {distance * std::cos(a), distance * std::sin(a), height};
    return t;
}

std::vector<Target> four_targets(double near, double far, double left_deg, double right_deg) {
    using K = Target::Kind;
    // Spheres sit on 1.0 m masts, checkerboards on 1.2 m stands (masts not modelled).
    return {place("T1", K::sphere, near, right_deg, 1.0),
            place("T2", K::checkerboard, far, right_deg + 3.0, 1.2),
            place("T3", K::sphere, near + 2.0, left_deg, 1.0),
            place("T4", K::checkerboard, far - 4.0, left_deg - 3.0, 1.2)};
}

}  // namespace

Site preset_small() {
    Site s;
    s.scanner.station = "small";
    // 331 columns x 541 rows = 179k cells at 0.1°.
    s.scanner.azimuth_min_deg = 62.0;
    s.scanner.azimuth_max_deg = 95.0;
    s.scanner.elevation_min_deg = -8.0;
    s.scanner.elevation_max_deg = 46.0;
    s.scanner.azimuth_step_deg = 0.1;
    s.scanner.elevation_step_deg = 0.1;
    s.targets = four_targets(20.0, 26.0, 92.0, 65.0);
    return s;
}

Site preset_pier() {
    Site s = preset_small();
    s.scanner.station = "pier";
    // 2539 columns x 4154 rows = 10.5 M cells at 0.013° (2.3 mm at 10 m): ≈ 6.8 M points.
    s.scanner.azimuth_step_deg = 0.013;
    s.scanner.elevation_step_deg = 0.013;
    s.targets = four_targets(22.0, 36.0, 92.0, 65.0);
    s.deck.enabled = true;
    return s;
}

Site preset_hochmosel() {
    Site s;
    s.scanner.station = "hochmosel";
    s.pier = {2.0, 17.0, 100.0, 107.0, 140.0};
    // Pier at 100–175 m range; 1134 columns x 2101 rows = 2.4 M cells at 0.03°.
    s.scanner.azimuth_min_deg = 68.0;
    s.scanner.azimuth_max_deg = 102.0;
    s.scanner.elevation_min_deg = -5.0;
    s.scanner.elevation_max_deg = 58.0;
    s.scanner.azimuth_step_deg = 0.03;
    s.scanner.elevation_step_deg = 0.03;
    s.scanner.max_range = 400.0;
    s.deck.enabled = true;
    s.deck.half_length = 60.0;
    s.deck.thickness = 6.0;
    s.targets = four_targets(25.0, 38.0, 96.0, 73.0);
    s.events.step_z_min = 100.0;
    s.events.step_z_max = 140.0;
    return s;
}

std::vector<std::string> preset_names() {
    return {"small", "pier", "hochmosel"};
}

Site preset(const std::string& name) {
    if (name == "small") return preset_small();
    if (name == "pier") return preset_pier();
    if (name == "hochmosel") return preset_hochmosel();
    throw Error("unknown simulator preset '" + name + "' (expected small, pier or hochmosel)");
}

}  // namespace tlsmon::sim
