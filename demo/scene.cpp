#include "demo/scene.hpp"

#include <fmt/format.h>

namespace tlsmon {

DemoScene demo_scene(const std::string& preset, int epochs) {
    DemoScene s;
    s.preset = preset;
    s.epochs = epochs;
    s.knocked_epoch = epochs / 4;
    s.step_epoch = epochs / 2;
    s.knocked_target = preset == "hochmosel" ? "H2" : "T2";
    return s;
}

std::string scene_file_text(const DemoScene& s) {
    std::string t = fmt::format(
        "# Scene of `tlsmon demo` (docs/simulator.md): the `{0}` preset, a day of 15-minute\n"
        "# epochs, with thermal bending, scanner drift and two events. Rerun by hand with\n"
        "#   tlsmon simulate --config scene.toml --out DIR --epochs {1} --start START\n"
        "preset = \"{0}\"\ncadence = \"15min\"\n",
        s.preset, s.epochs);
    if (s.preset == "small") {
        // At the preset's 0.1° a 145 mm sphere at 20 m holds ≈ 19 points and the boards are
        // not found; 0.05° gives each sphere 60-100 points at ≈ 1 s of CPU per epoch.
        t += "\n[scanner]\nazimuth_step_deg = 0.05\nelevation_step_deg = 0.05\n";
        // At 0.05° the pier's faces are sampled every 39–52 mm, coarser than the texture the
        // keypoint method follows (docs/keypoints.md, "Sampling"): a detail scan of a 2.5 m
        // strip of the south face (x ≈ 8.4–10.9 m) from 5 m up to its top at 0.012°
        // (9–13 mm), 251 x 2918 cells: the demo's default day stays within 5 minutes.
        t += R"(
[[scanner.detail]]
name = "strip"
azimuth_min_deg = 76.5
azimuth_max_deg = 79.5
elevation_min_deg = 5.0
elevation_max_deg = 40.0
step_deg = 0.012
)";
    }
    t += fmt::format(
        "\n[events]\n"
        "# A target knocked 10 mm sideways: the registration must exclude it.\n"
        "knocked_target = \"{}\"\nknocked_epoch = {}\nknocked_displacement = [0.010, 0.0, 0.0]\n"
        "# The top band of the pier moves 25 mm towards the scanner (south): more than the\n"
        "# day's thermal bending of that band (up to ≈ 15 mm, north) plus the alarm's 5 mm, so\n"
        "# the alarm must see it whenever in the day it comes.\n"
        "step_epoch = {}\nstep_displacement = [0.0, -0.025, 0.0]\n",
        s.knocked_target, s.knocked_epoch, s.step_epoch);
    if (s.preset == "small") {
        // Spheres left and right of the pier, 20–44 m out, 1–2.5 m up; the far one on the
        // pier's foundation. T2 (on a stand) is the one knocked.
        t += R"(
[[target]]
name = "T1"
kind = "sphere"
distance = 20.0
azimuth_deg = 92.0
height = 1.0
mount = "mast"

[[target]]
name = "T2"
kind = "sphere"
distance = 26.0
azimuth_deg = 68.0
height = 1.2
mount = "stand"
radius = 0.1

[[target]]
name = "T3"
kind = "sphere"
distance = 22.0
azimuth_deg = 65.0
height = 1.6
mount = "mast"

[[target]]
name = "T4"
kind = "sphere"
distance = 44.2
azimuth_deg = 89.0
height = 0.6
mount = "abutment"
radius = 0.15

[[target]]
name = "T5"
kind = "sphere"
distance = 30.0
azimuth_deg = 78.0
height = 2.5
mount = "mast"
radius = 0.1
)";
    }
    return t;
}

std::string demo_daemon_config(const DemoSite& s) {
    const auto v = [](const std::array<double, 3>& a) {
        return fmt::format("[{:g}, {:g}, {:g}]", a[0], a[1], a[2]);
    };
    std::string t =
        "# Configuration of `tlsmon demo` (docs/configuration.md): the site as the simulator\n"
        "# describes it (its site.toml, first), then the demo's daemon settings.\n\n";
    t += s.site_toml;
    t += fmt::format(
        R"(
# ---- the demo's daemon settings ----
[paths]
ingest = "ingest"
archive = "archive"
quarantine = "quarantine"
database = "tlsmon.sqlite"

[ingest]
# Scans appear by rename, complete at once; a short wait keeps the demo brisk.
stable_seconds = "500ms"
rescan_interval = 1
# The demo replays a simulated day faster than real time: its scans are dated up to a day
# ahead of the clock (a real site keeps the default of an hour).
max_clock_ahead = "2d"

[meteo]
# The simulator writes each meteo sidecar before its scan.
wait_seconds = 0

[logging]
level = "info"

[modbus]
enabled = true
address = "127.0.0.1"
port = {}
# The demo's acquisition times follow a simulated day, not the wall clock.
stale_seconds = "2d"

[http]
enabled = {}
address = "127.0.0.1"
port = {}

# The band of the south face the simulator's step event moves.
[[zone]]
name = "{}"
min = {}
max = {}
normal = [0, -1, 0]

# The step moves the band towards the scanner (+ in M3C2); the thermal bending moves it
# away in the afternoon: a high limit only, two epochs in a row, beyond the LoD.
[[alarm.rule]]
name = "{}"
zone = "{}"
quantity = "m3c2_median_m"
alarm = {{ high = 0.005, deadband = 0.001 }}
on_delay = 1
significant_only = true
latching = true

# A zone the step does not move: any alarm here is a false alarm.
[[alarm.rule]]
name = "{}"
zone = "{}"
quantity = "m3c2_median_m"
alarm = {{ high = 0.005, low = -0.005, deadband = 0.001 }}
on_delay = 1
significant_only = true
)",
        s.modbus_port, s.http_port > 0 ? "true" : "false", s.http_port > 0 ? s.http_port : 8080,
        kStepZone, v(s.step_min), v(s.step_max), kStepRule, kStepZone, kWestRule, s.west_zone);
    return t + s.check_zone_toml;
}

}  // namespace tlsmon
