#pragma once
// The simulator's truth files (`<stem>.truth.json`, docs/simulator.md) as the report reads
// them: what an analysis of a simulated series is scored against. Only the truth's own
// numbers are used — the scanner's pose error, the pier's displacement field and the events —
// never anything tlsmon computed.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace tlsmon::report {

struct PierBox {
    double x0 = 0, x1 = 0, y0 = 0, y1 = 0, height = 0;
};

struct StepEvent {
    int since_epoch = 0;
    double z_min = 0, z_max = 0;
    Eigen::Vector3d displacement = Eigen::Vector3d::Zero();
};

struct KnockedTarget {
    int since_epoch = 0;
    std::string target;
    Eigen::Vector3d displacement = Eigen::Vector3d::Zero();
};

struct TruthSample {
    std::string name;
    Eigen::Vector3d point = Eigen::Vector3d::Zero();         // undeformed, project frame
    Eigen::Vector3d displacement = Eigen::Vector3d::Zero();  // as the truth states it
};

// One epoch's truth.
struct TruthEpoch {
    std::filesystem::path file;
    int epoch = 0;
    std::int64_t time_unix = 0;
    bool missing = false;  // the scanner delivered nothing at this epoch
    // p_true = header_to_true · p_header (absent for a missing scan).
    std::optional<Eigen::Affine3d> header_to_true;
    Eigen::Vector3d scanner_position = Eigen::Vector3d::Zero();
    PierBox pier;
    bool deformation_enabled = false;
    double exponent = 2.0;
    Eigen::Vector3d top_displacement = Eigen::Vector3d::Zero();
    std::optional<StepEvent> step;
    std::optional<KnockedTarget> knocked;
    std::vector<TruthSample> samples;
};

// Every `*.truth.json` of `folder`, by epoch. Throws Error naming the file and the key for a
// file that is not a simulator truth file, and when the folder holds none.
std::vector<TruthEpoch> read_truth_folder(const std::filesystem::path& folder);
// One file (throws Error naming the file and key).
TruthEpoch read_truth_file(const std::filesystem::path& file);

// The pier's displacement at the undeformed point `p` in this epoch, from the truth's own
// description of its field (docs/simulator.md, "Deformation"): u_h(z) = top_h · (z/H)^p,
// u_z(z) = top_z · z/H, plus the step vector for z in [z_min, z_max] once stepped.
Eigen::Vector3d true_displacement(const TruthEpoch& truth, const Eigen::Vector3d& p);
// Its thermal part alone (the field without the events): what thermal compensation removes.
Eigen::Vector3d thermal_displacement(const TruthEpoch& truth, const Eigen::Vector3d& p);

// A zone given as an axis-aligned box (the `box` zones of the configuration).
struct ZoneBox {
    Eigen::Vector3d min = Eigen::Vector3d::Zero(), max = Eigen::Vector3d::Zero();
    bool contains(const Eigen::Vector3d& p) const {
        return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
    }
};

// The pier face a zone box lies on: its name, outward unit normal (towards a scanner that
// sees it, the M3C2 sign convention `orient = scanner`) and the face's part inside the box.
struct ZoneFace {
    std::string face;  // "south", "north", "west", "east"
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    double z_min = 0, z_max = 0;  // heights of the face inside the box
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
};
// The face of the pier the box is a slab across: the box's thinner horizontal side gives the
// normal's axis, and the one face on that axis whose plane crosses the box over some area is
// the zone's face; nullopt when there is none (or a box thick enough to hold both).
std::optional<ZoneFace> zone_face(const PierBox& pier, const ZoneBox& box);

// The true change of a zone between the reference epoch and epoch i: the displacement
// difference u_i − u_ref over the zone's face, sampled uniformly over its height (the field
// does not vary along a face's width), as the mean and the median of its component along
// the face's normal, and the mean vector; and the median along the normal of the thermal part
// alone (the field without its events): what a thermal compensation should remove.
struct ZoneTruth {
    double normal_mean = 0;
    double normal_median = 0;
    double thermal_normal_median = 0;
    Eigen::Vector3d mean_vector = Eigen::Vector3d::Zero();
};
ZoneTruth zone_truth(const TruthEpoch& reference, const TruthEpoch& epoch, const ZoneFace& face);

}  // namespace tlsmon::report
