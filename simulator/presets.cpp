// The named scenes. All share the layout: the pier's 15 m south wall seen almost
// head-on from the station, its west wall at a grazing angle, the bridge running north
// (along y) across a valley that runs east–west. Targets are set out as a surveyor would
// for the distance: spread in azimuth, height and range, on masts, stands and the stable
// blocks, left and right of the pier so it never hides them.
#include <cmath>

#include "core/error.hpp"
#include "simulator/scene.hpp"
#include "simulator/target_layout.hpp"

namespace tlsmon::sim {

namespace {

using K = Target::Kind;
using M = Target::Mount;

TargetPlacement sphere(std::string name, double distance, double azimuth_deg, double height,
                       M mount, double radius = 0.0725) {
    TargetPlacement p;
    p.name = std::move(name);
    p.kind = K::sphere;
    p.distance = distance;
    p.azimuth_deg = azimuth_deg;
    p.height = height;
    p.mount = mount;
    p.radius = radius;
    return p;
}

TargetPlacement board(std::string name, double distance, double azimuth_deg, double height, M mount,
                      double size = 0.40) {
    TargetPlacement p = sphere(std::move(name), distance, azimuth_deg, height, mount);
    p.kind = K::checkerboard;
    p.size = size;
    return p;
}

// A person walking from `from` to `to` (x, y), present with `probability` per epoch.
Occluder person(double probability, Eigen::Vector2d from, Eigen::Vector2d to) {
    Occluder o;
    o.name = "person";
    o.kind = Occluder::Kind::person;
    o.probability = probability;
    o.path_start = from;
    o.path_end = to;
    return o;
}

// A vehicle (length x width x height, m) somewhere on the track from `from` to `to`.
Occluder vehicle(std::string name, double probability, Eigen::Vector2d from, Eigen::Vector2d to,
                 Eigen::Vector3d size, double albedo) {
    Occluder o;
    o.name = std::move(name);
    o.kind = Occluder::Kind::vehicle;
    o.probability = probability;
    o.path_start = from;
    o.path_end = to;
    o.length = size.x();
    o.width = size.y();
    o.height = size.z();
    o.albedo = albedo;
    return o;
}

Vegetation bush(Eigen::Vector2d centre, Eigen::Vector3d radii) {
    Vegetation v;
    v.name = "bush";
    v.centre = centre;
    v.radii = radii;
    return v;
}

void place_all(Site& s, const std::vector<TargetPlacement>& placements) {
    s.targets.clear();
    for (const TargetPlacement& p : placements) s.targets.push_back(place_target(s, p));
}

Block block(std::string name, Block::Kind kind, Eigen::Vector3d lo, Eigen::Vector3d hi) {
    Block b;
    b.name = std::move(name);
    b.kind = kind;
    b.lo = lo;
    b.hi = hi;
    return b;
}

// A wall `length` long and `thickness` thick, from the ground at z0 to z1, centred at (x, y)
// and facing `facing_deg` (the direction of its front face's normal, counter-clockwise from
// +x): a retaining wall or a building's face, set at an angle to the grid.
Block wall(std::string name, double x, double y, double facing_deg, double length, double z0,
           double z1, double thickness = 0.4) {
    Block b;
    b.name = std::move(name);
    b.kind = Block::Kind::wall;
    b.lo = {x - 0.5 * length, y - 0.5 * thickness, z0};
    b.hi = {x + 0.5 * length, y + 0.5 * thickness, z1};
    b.yaw_deg = facing_deg + 90.0;  // the box's −y face turned to face `facing_deg`
    b.albedo = 0.35;
    return b;
}

// A surveyor's fine scan of a target: a window over the target's angular size and
// `margin_deg` more (the scanner's drift moves it by a few arc seconds), at `step_deg`.
DetailScan target_scan(const Site& s, const Target& t, double step_deg, double margin_deg = 0.1) {
    constexpr double deg = 180.0 / 3.14159265358979323846;
    const Eigen::Vector3d d = t.centre - s.scanner.position;
    const double azimuth = std::atan2(d.y(), d.x()) * deg - s.scanner.heading_deg;
    const double elevation = std::atan2(d.z(), std::hypot(d.x(), d.y())) * deg;
    const double extent = t.kind == Target::Kind::sphere ? t.radius : t.size / std::sqrt(2.0);
    const double half = std::atan2(extent, d.norm()) * deg + margin_deg;
    DetailScan scan;
    scan.name = t.name;
    scan.azimuth_min_deg = azimuth - half;
    scan.azimuth_max_deg = azimuth + half;
    scan.elevation_min_deg = elevation - half;
    scan.elevation_max_deg = elevation + half;
    scan.step_deg = step_deg;
    return scan;
}

// `small` and `pier`: the station on the valley floor 45 m south of the pier; the floor is
// level to 60 m, then the valley's north side rises 25 m over 70 m (20°), seen beyond the
// pier at 60–150 m. The pier stands on a foundation (pile cap) showing 0.4 m above the
// floor, 1.5 m wider than the pier all round; an abutment block at the foot of the north
// side, east of the pier.
//
// Two low retaining walls set at an angle, either side of the pier: their faces (normals
// (0.6, −0.8) and (−0.7, −0.7)) hold the registration on planes across the line of sight,
// which the blocks' faces, square to the grid, hardly do. Their tops stay below the lines of
// sight to the far targets (T5 beyond the west wall, T4 beyond the east one).
void valley_near(Site& s) {
    s.terrain.profile_y = {60.0, 130.0};
    s.terrain.profile_z = {0.0, 25.0};
    s.terrain.blocks = {
        block("P-foundation", Block::Kind::foundation, {s.pier.x0 - 1.5, s.pier.y0 - 1.5, -1.0},
              {s.pier.x1 + 1.5, s.pier.y1 + 1.5, 0.4}),
        block("A-north", Block::Kind::abutment, {22.0, 56.0, -1.0}, {30.0, 62.0, 2.5}),
        wall("W-west", -2.5, 52.0, -53.13, 6.0, -0.5, 1.2),
        wall("W-east", 21.5, 40.5, -135.0, 5.0, -0.5, 1.0)};
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
    valley_near(s);
    // Four targets a 0.1° grid still resolves: two spheres on masts 20–22 m out, a board on
    // a stand, and a 0.6 m board on the pier's foundation at 44 m.
    place_all(s, {sphere("T1", 20.0, 92.0, 1.0, M::mast), board("T2", 26.0, 68.0, 1.2, M::stand),
                  sphere("T3", 22.0, 65.0, 1.6, M::mast),
                  board("T4", 44.2, 89.0, 0.6, M::abutment, 0.60)});
    return s;
}

Site preset_pier() {
    Site s = preset_small();
    s.scanner.station = "pier";
    // 2539 columns x 4154 rows = 10.5 M cells at 0.013° (2.3 mm at 10 m).
    s.scanner.azimuth_step_deg = 0.013;
    s.scanner.elevation_step_deg = 0.013;
    s.deck.enabled = true;
    // Six targets 18–85 m out over 64–93° of azimuth and 1.2–10.6 m of height, chosen as a
    // surveyor would for the distance: 145 mm spheres only near (their centres hold to
    // 0.15 mm there), large boards beyond, two of them on the stable blocks at the pier's foot
    // and the valley side, and a far board up the north side to hold the rotation.
    place_all(
        s, {sphere("T1", 18.0, 91.0, 1.6, M::mast), board("T2", 27.0, 64.0, 1.4, M::stand),
            board("T3", 44.2, 88.8, 0.6, M::abutment, 0.60),
            board("T4", 64.1, 66.0, 1.0, M::abutment, 0.60),
            board("T5", 85.0, 93.0, 1.7, M::mast, 1.0), sphere("T6", 25.0, 72.0, 1.2, M::stand)});
    // A person crossing between the station and the pier about one scan in twelve, a
    // maintenance van parked on the track in front of the pier about one scan in twenty-five,
    // and a bush west of the pier.
    s.occlusion.occluders = {
        person(0.08, {-3.0, 28.0}, {20.0, 36.0}),
        vehicle("van", 0.04, {-4.0, 33.0}, {22.0, 33.0}, {5.0, 2.0, 2.3}, 0.6)};
    s.occlusion.vegetation = {bush({-3.0, 36.0}, {1.8, 1.2, 1.4})};
    return s;
}

// `round`: `pier` with a round pier instead of the wall, a column of 4 m diameter and 50 m
// height about the same centre, 47 m from the station (a 20″ lean moves its top 4.8 mm);
// the scan reaches 50° up to see its top under the deck.
Site preset_round() {
    Site s = preset_pier();
    s.scanner.station = "round";
    s.pier.diameter = 4.0;
    s.pier.height = 50.0;
    s.scanner.elevation_max_deg = 50.0;
    return s;
}

Site preset_hochmosel() {
    Site s;
    s.scanner.station = "hochmosel";
    s.pier = {2.0, 17.0, 100.0, 107.0, 140.0};
    // The station on the valley's south slope, 20 m above the floor: the slope falls 1:3 to
    // the floor at y = 60 m, the floor runs to 230 m, and the north side rises 45 m over
    // 90 m. From there the pier's foot at 100 m is seen 12° below the horizon, and the floor
    // behind it at 175 m at 7° (ρ·cos α ≈ 0.025 on 0.2 ground: well above min_return).
    s.terrain.profile_y = {-30.0, 0.0, 60.0, 230.0, 320.0};
    s.terrain.profile_z = {30.0, 20.0, 0.0, 0.0, 45.0};
    s.terrain.blocks = {
        block("P-foundation", Block::Kind::foundation, {0.0, 98.0, -2.0}, {19.0, 109.0, 2.0}),
        block("A-east", Block::Kind::abutment, {20.0, 60.0, -1.0}, {32.0, 66.0, 3.0}),
        // Retaining walls at an angle either side of the pier, below the lines of sight to
        // the far targets (valley_near's, larger for the distance).
        wall("W-west", -8.0, 110.0, -53.13, 8.0, -0.5, 4.0, 0.6),
        wall("W-east", 35.0, 115.0, -135.0, 7.0, -0.5, 5.0, 0.6)};
    s.scanner.position = {0.0, 0.0, 21.5};
    // Pier at 100–175 m range; 1334 columns x 2601 rows = 3.5 M cells at 0.03°.
    s.scanner.azimuth_min_deg = 64.0;
    s.scanner.azimuth_max_deg = 104.0;
    s.scanner.elevation_min_deg = -20.0;
    s.scanner.elevation_max_deg = 58.0;
    s.scanner.azimuth_step_deg = 0.03;
    s.scanner.elevation_step_deg = 0.03;
    s.scanner.max_range = 400.0;
    // A detail scan of a 3.5 m strip of the south face (x ≈ 4.4–7.9 m) over the pier's
    // whole height at 0.005° (9–14 mm at 100–155 m): 401 columns x 12501 rows = 5.0 M
    // cells, for the keypoint method (docs/keypoints.md, "Sampling").
    DetailScan strip;
    strip.name = "strip";
    strip.azimuth_min_deg = 85.5;
    strip.azimuth_max_deg = 87.5;
    strip.elevation_min_deg = -12.5;
    strip.elevation_max_deg = 50.0;
    strip.step_deg = 0.005;
    s.scanner.details = {strip};
    s.deck.enabled = true;
    s.deck.half_length = 60.0;
    s.deck.thickness = 6.0;
    // Far targets hold the rotation: two on the pier's foundation left and right of the pier
    // (98.5 m), one on the abutment (66 m) and a 1 m board on a mast on the floor at 170 m;
    // two near ones on the slope for the translation. Sizes grow with the distance so each
    // keeps tens of points at 0.03°.
    place_all(s, {sphere("H1", 25.0, 100.0, 1.8, M::mast, 0.10),
                  board("H2", 35.0, 72.0, 1.5, M::stand, 0.60),
                  sphere("H3", 98.5, 89.7, 0.6, M::abutment, 0.15),
                  board("H4", 99.9, 80.5, 0.8, M::abutment, 1.0),
                  sphere("H5", 66.3, 66.9, 0.5, M::abutment, 0.15),
                  board("H6", 170.0, 96.0, 2.0, M::mast, 1.0)});
    // Fine scans of the far targets at 0.005° (their overview gives 9–89 mm between points):
    // the registration's rotation rests on them, and at 150 m an arc second is 0.7 mm.
    for (const Target& t : s.targets) {
        if ((t.centre - s.scanner.position).norm() > 60.0)
            s.scanner.details.push_back(target_scan(s, t, 0.005));
    }
    s.events.step_z_min = 100.0;
    s.events.step_z_max = 140.0;
    s.occlusion.occluders = {
        vehicle("truck", 0.05, {-30.0, 80.0}, {40.0, 80.0}, {7.0, 2.5, 3.2}, 0.5),
        person(0.08, {-10.0, 70.0}, {25.0, 96.0})};
    s.occlusion.vegetation = {bush({-6.0, 92.0}, {2.5, 1.5, 2.0})};
    return s;
}

std::vector<std::string> preset_names() {
    return {"small", "pier", "round", "hochmosel"};
}

Site preset(const std::string& name) {
    if (name == "small") return preset_small();
    if (name == "pier") return preset_pier();
    if (name == "round") return preset_round();
    if (name == "hochmosel") return preset_hochmosel();
    throw Error("unknown simulator preset '" + name +
                "' (expected small, pier, round or hochmosel)");
}

}  // namespace tlsmon::sim
