#pragma once
// The simulated site as plain structs with defaults: a bridge pier on a ground plane, an
// optional deck, reference targets on stable ground, and a terrestrial laser scanner on a
// tripod that exports one structured scan per epoch.
//
// Project frame: x east, y north, z up, metres; the ground is the plane z = 0.
// Scanner frame: levelled scanner, z up; azimuth φ counted counter-clockwise from the
// scanner's +x axis, elevation e from the horizontal; beam direction
// (cos e cos φ, cos e sin φ, sin e).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace tlsmon::sim {

// The pier: an axis-aligned box standing on the ground (x0..x1, y0..y1, 0..height), or, with
// a diameter, a round pier: a vertical cylinder of that diameter about the box's centre (the
// box still places the foundation and the deck).
struct Pier {
    double x0 = 2.0, x1 = 17.0;   // 15 m wall, seen almost head-on from the south
    double y0 = 45.0, y1 = 52.0;  // 7 m wall, seen at a grazing angle from the west
    double height = 40.0;
    double diameter = 0.0;  // m; > 0: a round pier

    bool round() const { return diameter > 0.0; }
    Eigen::Vector2d centre() const { return {0.5 * (x0 + x1), 0.5 * (y0 + y1)}; }
    // The section's depth across x and across y (thermal bending's b).
    Eigen::Vector2d section_depth() const {
        return round() ? Eigen::Vector2d(diameter, diameter) : Eigen::Vector2d(x1 - x0, y1 - y0);
    }
};

// An optional deck on top of the pier (box), not deformed: the superstructure sits on
// bearings and its own movement is not modelled.
struct Deck {
    bool enabled = false;
    double overhang = 1.0;      // beyond the pier in x on each side, m
    double half_length = 30.0;  // along y, each side of the pier centre, m
    double thickness = 3.0;     // m
};

// A reference target on stable ground. Spheres: centre and radius. Checkerboards: a square
// 2x2 black/white pattern whose centre is the common corner; facing the scanner.
struct Target {
    enum class Kind { sphere, checkerboard };
    // What holds the target up (simulator/target_layout.hpp): a mast (vertical pole), a
    // stand (pole and three legs), a short mast on a stable block (abutment/foundation), or
    // nothing modelled. Masts and stands are scene geometry: rays hit them.
    enum class Mount { none, mast, stand, abutment };
    std::string name;
    Kind kind = Kind::sphere;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    double radius = 0.0725;  // sphere, m (standard 145 mm sphere)
    double size = 0.40;      // checkerboard side, m
    Mount mount = Mount::none;
    double base_z = 0.0;  // z of the support's foot (ground or block top), m
};

// A detail scan: the station scanning a smaller window at a finer step right after its
// overview (what a scanner's region or fine scan is), exported into the same file as a
// further scan with its own grid. Far walls need it for the keypoint method: the sample
// spacing (range × step) must stay below the texture the footprint resolves
// (docs/keypoints.md, "Sampling").
struct DetailScan {
    std::string name = "detail";
    double azimuth_min_deg = 0.0, azimuth_max_deg = 0.0;
    double elevation_min_deg = 0.0, elevation_max_deg = 0.0;
    double step_deg = 0.005;  // horizontal and vertical
};

struct Scanner {
    std::string station = "S1";
    Eigen::Vector3d position{0.0, 0.0, 1.5};  // tripod ~1.5 m above the ground
    double heading_deg = 0.0;  // rotation of the scanner's x axis about z from project +x
    // Angular window of the structured scan (scanner frame) and its steps.
    double azimuth_min_deg = 55.0, azimuth_max_deg = 105.0;
    double elevation_min_deg = -10.0, elevation_max_deg = 50.0;
    double azimuth_step_deg = 0.12, elevation_step_deg = 0.12;
    double max_range = 300.0;         // no return beyond, m
    double min_return = 0.005;        // weaker returns (dark, far, grazing) give no point
    std::vector<DetailScan> details;  // after the overview, in this order
    // Where this window's first column and row lie in the lattice of the scan it was cut
    // from (tests/simulator/narrow_window.hpp): the noise is drawn per cell of that lattice,
    // so a window cut out of a scan carries the scan's noise, and two windows of one shape
    // do not carry the same noise field. 0 for a whole scan.
    std::uint32_t first_column = 0, first_row = 0;
};

// The laser beam: a Gaussian beam whose 1/e² diameter grows linearly from the exit
// aperture, D(r) = exit_diameter + divergence · r (far-field approximation). Defaults of a
// phase-based scanner of the Z+F IMAGER 5016 class: ≈ 3.5 mm at exit, ≈ 0.3 mrad (full
// angle), i.e. 6.5 mm at 10 m and 18.5 mm at 50 m (see simulator/footprint.hpp).
struct Beam {
    bool footprint = true;          // false: one infinitely thin ray per cell (exact geometry)
    double exit_diameter = 0.0035;  // m, 1/e² diameter at the exit aperture
    double divergence_mrad = 0.3;   // full angle, 1/e²
};

// Measurement model. Range σ per return (see simulator/range_noise.hpp): `constant`
// σ = a + b·range, or `signal` σ = a_s + b_s·range/√(ρ·|cos α|) from the returned signal;
// angular noise on the beam direction; additive intensity noise. All Gaussian, seeded per
// epoch and column of the scan's lattice.
struct Noise {
    enum class Model { constant, signal };
    bool enabled = true;
    Model model = Model::signal;
    double range_a = 0.001;     // m, constant model
    double range_b_ppm = 10.0;  // ppm of range, constant model
    // Signal model, calibrated to ≈ 0.25 mm at 10 m on white (ρ 0.8) and ≈ 0.8 mm at 50 m
    // on black (ρ 0.14), head-on (docs/simulator.md).
    double signal_a = 0.0002;   // m, floor
    double signal_b_ppm = 4.5;  // ppm of range at ρ·|cos α| = 1
    double angular_arcsec = 3.0;
    double intensity_sigma = 0.01;
    std::uint64_t seed = 1;
};

// Scanner instability per epoch (what registration must remove): rotation about the
// standing axis drifting smoothly plus jitter, a small tilt, a small translation.
struct Drift {
    bool enabled = true;
    double yaw_amplitude_arcsec = 30.0;  // smooth part: A·sin(2π t / period)
    double yaw_period_hours = 24.0;
    double yaw_jitter_arcsec = 2.0;
    double tilt_amplitude_arcsec = 5.0;
    double tilt_jitter_arcsec = 1.0;
    double translation_sigma = 0.0005;  // m, per axis per epoch
};

// Thermal bending of the pier, driven by the weather (see simulator/deformation.hpp for the
// equations): the temperature difference across the section in x and in y, lagged, gives
// a constant curvature κ = α_T·ΔT/b; the mean section temperature a vertical extension.
struct Deformation {
    bool enabled = true;
    double expansion_coefficient = 1.0e-5;  // α_T, 1/K (concrete, EN 1992-1-1 §3.1.3)
    double time_constant_hours = 3.0;       // thermal lag of the section behind its faces
    double exponent = 2.0;                  // height profile (z/H)^p; 2 = constant curvature
    double reference_temperature_c = 15.0;  // uniform temperature of the undeformed box
};

// Events: a step of one part of the pier, a knocked target, a knocked scanner, missing scans,
// a scan cut short.
struct Events {
    int step_epoch = -1;  // from this epoch on; -1 = none
    double step_z_min = 30.0, step_z_max = 40.0;
    Eigen::Vector3d step_displacement{0.0, -0.010, 0.0};
    // The whole pier tilting as a rigid body about its foot's centre from this epoch on (a
    // foundation settling on one side): its axis leans `tilt_arcsec` towards +x and +y.
    int tilt_epoch = -1;
    Eigen::Vector2d tilt_arcsec{20.0, 0.0};
    // A bearing that seizes, a crack that opens: from this epoch on the thermal bending (the
    // horizontal part of the thermal field) is scaled by `bending_factor`; the vertical
    // expansion stays. The structure's thermal behaviour changes, not its position.
    int bending_change_epoch = -1;
    double bending_factor = 0.5;
    int knocked_target = -1;  // index into targets; -1 = none
    int knocked_epoch = -1;
    Eigen::Vector3d knocked_displacement{0.010, 0.0, 0.0};
    // The scanner knocked or set up anew: from this epoch on it stands `station_shift` (m,
    // scanner frame) away and turned by `station_turn_deg` about its standing axis, while the
    // header keeps the nominal pose.
    int station_change_epoch = -1;
    Eigen::Vector3d station_shift{0.2, 0.0, 0.0};
    double station_turn_deg = 5.0;
    std::vector<int> missing_epochs;
    int cut_short_epoch = -1;
    double cut_short_fraction = 0.5;  // fraction of the file's bytes written (at a line end)
};

// ---- Weather, atmosphere and the site's weather station (simulator/weather.hpp,
// simulator/atmosphere.hpp, simulator/meteo_station.hpp) ----

// The site's air and sun: a daily temperature cycle in local solar time (minimum at
// sunrise, maximum at `max_hour_solar`), day-to-day variation of the mid-range temperature,
// the cloudiness and the pressure as seeded AR(1) sequences, and solar heating of the
// pier's faces. Defaults: early summer at the Hochmoselbrücke (49.97° N, 7.07° E).
struct Weather {
    std::uint64_t seed = 11;
    double latitude_deg = 49.97;
    double longitude_deg = 7.07;       // east positive; local solar time = UTC + λ/15° h + EoT
    double mean_temperature_c = 16.0;  // mid-range temperature of an average day
    double day_sigma_c = 3.0;          // day-to-day σ of the mid-range temperature
    double day_correlation = 0.7;      // AR(1) coefficient from one day to the next
    double daily_range_c = 11.0;       // clear-sky daily range (max − min)
    double max_hour_solar = 15.0;      // local solar time of the daily maximum
    double cloudiness_mean = 0.45;     // 0 clear .. 1 overcast
    double cloudiness_sigma = 0.3;
    double pressure_hpa = 1013.25;             // mean station pressure
    double pressure_sigma_hpa = 6.0;           // day-to-day σ (synoptic)
    double pressure_tide_hpa = 0.5;            // semidiurnal atmospheric tide amplitude
    double absorptance = 0.65;                 // solar absorptance of the concrete faces
    double surface_coefficient = 17.0;         // W/(m²·K), outer surface heat transfer h_o
    double surface_time_constant_hours = 1.0;  // lag of a face behind its sol-air temperature
};

// The scanner's atmospheric setting (fixed, as entered on site) and its laser's wavelength;
// the true group index follows the scene's air, so ranges carry n_true / n_setting.
struct Atmosphere {
    bool enabled = true;
    double wavelength_nm = 1500.0;  // Z+F IMAGER 5016 class
    double scanner_temperature_c = 20.0;
    double scanner_pressure_hpa = 1013.25;
    double scanner_humidity_pct = 60.0;
};

// The site's weather station: one reading a minute, written beside each scan as
// `<stem>.meteo.csv` (docs/formats.md), from `span_minutes` before the acquisition to it.
struct MeteoStation {
    bool enabled = true;
    int span_minutes = 5;
    double temperature_sigma_c = 0.1;
    double pressure_sigma_hpa = 0.1;
    double humidity_sigma_pct = 0.1;
};

// ---- end of weather ----

struct Texture {
    std::uint64_t seed = 7;
    double albedo = 0.45;      // mean concrete reflectance
    double panel_width = 2.5;  // formwork panel, m
    double panel_height = 1.25;
    double joint_width = 0.02;         // m
    double tie_hole_radius = 0.015;    // m
    double range_attenuation = 400.0;  // intensity ∝ exp(−range / this)
};

// ---- Scene: terrain, stable blocks and occluders (simulator/terrain.hpp, occluders.hpp) ----

// The valley: a cross-section z = h(y) across the valley (the bridge runs along y), piecewise
// linear through (profile_y[k], profile_z[k]) and level beyond the ends, extruded along x.
// The default is the flat plane z = 0. Stable blocks (foundation, abutment) are boxes on it.
// A rigid motion of a block from an epoch on (a foundation block settling, a wall pushed by
// the slope): what the congruence test of the registration on planes has to find. Applied
// about the block's centre: rotation first, then the translation.
struct BlockMotion {
    int from_epoch = -1;                                        // below 0: the block never moves
    Eigen::Vector3d translation = Eigen::Vector3d::Zero();      // m
    Eigen::Vector3d rotation_arcsec = Eigen::Vector3d::Zero();  // about x, y, z
};

struct Block {
    // wall: a retaining wall or a building face, a planar surface of the site set at an angle.
    enum class Kind { foundation, abutment, wall };
    std::string name;
    Kind kind = Kind::foundation;
    // The box (m) before its yaw: lo and hi of its own axes about its centre.
    Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi = Eigen::Vector3d::Zero();
    double yaw_deg = 0.0;  // turned about the vertical through its centre, counter-clockwise
    double albedo = 0.40;  // mean reflectance (concrete texture)
    BlockMotion motion;

    Eigen::Vector3d centre() const { return 0.5 * (lo + hi); }
    // Its own frame (origin at the centre, axes of lo/hi) into the site's at `epoch`.
    Eigen::Isometry3d pose(int epoch) const;
    // The motion at `epoch` (identity before motion.from_epoch), about the centre.
    Eigen::Isometry3d displacement(int epoch) const;
};
const char* kind_name(Block::Kind kind);

// A patch of ground that creeps (a slope sliding, a fill settling): the terrain inside the
// circle of `radius` about `centre` (x, y) moves as a slab by `rate` per epoch from
// `from_epoch` on (its texture with it; a step opens at its rim). What the registration on
// stable areas must leave out of its datum once significant, and report.
struct Creep {
    int from_epoch = -1;  // below 0: nothing creeps
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    double radius = 5.0;                                       // m
    Eigen::Vector3d rate = Eigen::Vector3d(0.0, 0.0, -0.001);  // m per epoch
    // rate·(epoch − from_epoch + 1) from from_epoch on, else zero.
    Eigen::Vector3d displacement(int epoch) const;
    bool holds(double x, double y) const {  // (x, y) of the unmoved ground inside the circle
        return (Eigen::Vector2d(x, y) - centre).squaredNorm() <= radius * radius;
    }
};

struct Terrain {
    std::vector<double> profile_y{0.0};  // m, increasing
    std::vector<double> profile_z{0.0};  // m, ground height at profile_y
    double albedo = 0.20;                // mean ground reflectance (soil, grass, gravel)
    // Roughness: clods, stones and tufts as a height along the ground's normal, value noise
    // within ±roughness (m) on a lattice of roughness_wavelength (m); it moves with the ground
    // (a creeping slab carries it). 0: the smooth profile.
    double roughness = 0.0;
    double roughness_wavelength = 0.25;
    std::vector<Block> blocks;
    Creep creep;
};

// Occluders: a vehicle (box) or a person (cylinder) standing somewhere on a path between
// the scanner and the pier at random epochs; seeded per epoch.
struct Occluder {
    enum class Kind { vehicle, person };
    std::string name;
    Kind kind = Kind::person;
    double probability = 0.1;  // of being present at an epoch
    Eigen::Vector2d path_start = Eigen::Vector2d::Zero(), path_end = Eigen::Vector2d::Zero();
    double length = 0.5, width = 0.5, height = 1.75;  // m; a person: diameter = width
    double albedo = 0.30;
};

// A vegetation patch (a bush): an ellipsoid on the ground filled with leaves, one possible
// leaf per voxel of `leaf_spacing`, present with probability `density`; the leaves move by
// up to `sway` between epochs (wind), so its points differ from epoch to epoch.
struct Vegetation {
    std::string name;
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();        // m, on the ground
    Eigen::Vector3d radii = Eigen::Vector3d(1.5, 1.0, 1.0);  // m, ellipsoid half-axes
    double leaf_spacing = 0.08;                              // m, voxel side
    double leaf_radius = 0.025;                              // m
    double density = 0.15;                                   // fraction of voxels holding a leaf
    double sway = 0.01;    // m, largest leaf movement between epochs
    double albedo = 0.30;  // leaves at 1.5 µm
};

struct Occlusion {
    std::uint64_t seed = 11;
    std::vector<Occluder> occluders;
    std::vector<Vegetation> vegetation;
};

// ---- end of terrain and occluders ----

struct Site {
    Pier pier;
    Deck deck;
    std::vector<Target> targets;
    Scanner scanner;
    Beam beam;
    Noise noise;
    Drift drift;
    Deformation deformation;
    Events events;
    Texture texture;
    Weather weather;
    Atmosphere atmosphere;
    MeteoStation meteo;
    double cadence_seconds = 900.0;
    // Terrain, stable blocks and occluders.
    Terrain terrain;
    Occlusion occlusion;
};

// Presets. `small`: tests (179k cells); `pier`: benchmarks (10.5 M cells, ≈ 6.8 M points);
// `round`: `pier` with a round pier (4 m column, 50 m high); `hochmosel`: a 140 m pier at
// 100–180 m range as in the Hochmoselbrücke case study.
Site preset_small();
Site preset_pier();
Site preset_round();
Site preset_hochmosel();
// By name; throws tlsmon::Error naming the unknown preset.
Site preset(const std::string& name);
std::vector<std::string> preset_names();

}  // namespace tlsmon::sim
