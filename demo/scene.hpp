#pragma once
// What `tlsmon demo` writes into its working folder before anything runs: the simulator's
// scene file (a preset with the demo's events) and the daemon's configuration (the site
// the simulator describes, merged with the demo's daemon settings). Plain text, so a
// newcomer can read them, and rerun either half by hand.
#include <array>
#include <string>

namespace tlsmon {

// The scene: `preset` with a knocked target at epochs/4 and a step of one band of the
// pier's south face at epochs/2 (docs/simulator.md, "Events"). For `small` the grid is
// refined to 0.05°, the targets are five spheres, which the registration finds at that
// resolution, and a detail scan of a strip of the south face at 0.012° serves the keypoint
// method; `pier` and `hochmosel` keep their own grids, detail scans and targets.
struct DemoScene {
    std::string preset = "small";
    int epochs = 96;
    int knocked_epoch = 24;
    int step_epoch = 48;
    std::string knocked_target;  // "T2" (small, pier) or "H2" (hochmosel)
};
DemoScene demo_scene(const std::string& preset, int epochs);
std::string scene_file_text(const DemoScene& scene);

// The band of the south face that the step moves, and the demo's daemon settings.
struct DemoSite {
    std::string site_toml;             // what `tlsmon simulate` writes (site_configuration)
    std::array<double, 3> step_min{};  // the step band as a box around the south face
    std::array<double, 3> step_max{};
    std::string west_zone = "pier_west_face";  // a zone the step does not move
    std::string check_zone_toml;               // a no-change check zone's [[zone]] table, or ""
    int modbus_port = 1502;
    int http_port = 8080;  // the dashboard on 127.0.0.1; 0: none
};
// The names the configuration gives the step band and its rules.
inline constexpr const char* kStepZone = "pier_south_top";
inline constexpr const char* kStepRule = "south_top_step";
inline constexpr const char* kWestRule = "west_face_watch";

// The daemon's configuration: the site, a fresh database and ingest folder beside the file,
// short ingest timings, no waiting for meteo (the sidecar is written before its scan), Modbus
// and the dashboard on 127.0.0.1, the step band as a zone and alarm rules on it and on the west
// face.
std::string demo_daemon_config(const DemoSite& site);

}  // namespace tlsmon
