#pragma once
// The `small` scene at 0.1° seen to 30° elevation (about 60 k points an epoch), with four
// 0.3 m spheres 20–26 m out that the registration finds at that step; weather and noise from
// `seed`. A scene file for `tlsmon simulate --config`.
#include <string>

namespace tlsmon::test {

inline std::string small_scene_text(int seed) {
    const std::string s = std::to_string(seed);
    std::string t =
        "preset = \"small\"\n[scanner]\nelevation_max_deg = 30.0\n[weather]\nseed = " + s +
        "\n[noise]\nseed = " + s + "\n";
    const struct {
        const char* name;
        double distance, azimuth, height;
        const char* mount;
    } spheres[] = {{"T1", 20.0, 92.0, 1.0, "mast"},
                   {"T2", 26.0, 68.0, 1.2, "stand"},
                   {"T3", 22.0, 65.0, 1.6, "mast"},
                   {"T5", 24.0, 80.0, 2.5, "mast"}};
    for (const auto& sphere : spheres) {
        t += std::string("[[target]]\nname = \"") + sphere.name +
             "\"\nkind = \"sphere\"\ndistance = " + std::to_string(sphere.distance) +
             "\nazimuth_deg = " + std::to_string(sphere.azimuth) +
             "\nheight = " + std::to_string(sphere.height) + "\nradius = 0.15\nmount = \"" +
             sphere.mount + "\"\n";
    }
    return t;
}

}  // namespace tlsmon::test
