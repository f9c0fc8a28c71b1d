// The registration stage against the simulator's truth, on scans rendered once by
// `tlsmon simulate` (docs/simulator.md): `bench_registration_truth SITE.toml E0.ptx E1.ptx ...
// [--truth-air]`, each scan with its `<name>.truth.json` beside it. Prints
//   - per epoch and target: how it was found and its centre's error against the truth's
//     centre (header_to_true · measured − truth), along the line of sight, across it
//     horizontally and across it vertically, each with the σ the fit gives;
//   - per later epoch: the registration onto the first (its status, s0², targets used) and
//     its error at the pier against the exact answer H₀⁻¹·Hᵢ (RMS over the pier's faces
//     every 2.5 m, and at the top corner with the predicted 3-D σ there).
// `--truth-air` scales every range back by the truth's own range scale, as exact meteo
// would, to tell the atmosphere's share from the fits'. `--method planes|targets+planes`
// registers on the scene's planes (alone or with the targets) in place of the site's
// registration.method; then per epoch the planes' roles, and the congruence test scored
// against the truth's blocks: the planes on a block that moved (found: flagged moved or
// significant) and the planes flagged on blocks that did not (false). The simulated deck does
// not move with the pier; a real one would, so it is put in a zone here (never in the datum).
// As in the daemon, each epoch's planes are matched from the last accepted pose; a station
// change (matched without a prior) is printed and counted.
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "algorithms/registration/point_to_plane.hpp"
#include "algorithms/registration/registration_error.hpp"
#include "bench/line_of_sight.hpp"
#include "config/config.hpp"
#include "formats/scan_file.hpp"
#include "pipeline/registration_on_planes.hpp"
#include "pipeline/registration_stage.hpp"
#include "pipeline/sha256.hpp"
#include "pipeline/stable_area_registration.hpp"

namespace {

using namespace tlsmon;

// A block of the truth: its box in its own frame at epoch 0, and whether it has moved.
struct TruthBlock {
    std::string name;
    Eigen::Vector3d half;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // own frame -> site, unmoved
    bool moved = false;
    // Whether a point (true frame) lies on the block, within `margin`.
    bool holds(const Eigen::Vector3d& p, double margin = 0.05) const {
        const Eigen::Vector3d q = pose.inverse() * p;
        return (q.cwiseAbs().array() <= half.array() + margin).all();
    }
};

struct Truth {
    Eigen::Affine3d header_to_true = Eigen::Affine3d::Identity();
    std::map<std::string, Eigen::Vector3d> centres;
    Eigen::Vector3d pier_min, pier_max;
    double range_scale = 1.0;
    std::vector<TruthBlock> blocks;
    Eigen::AlignedBox3d deck;                            // empty without a deck
    Eigen::Vector3d pier_top = Eigen::Vector3d::Zero();  // thermal displacement at the top
    double exponent = 2.0;
    // The creeping ground: centre (x, y), radius and how far it has moved (zero without).
    Eigen::Vector2d creep_centre = Eigen::Vector2d::Zero();
    double creep_radius = 0;
    Eigen::Vector3d creep = Eigen::Vector3d::Zero();
    bool on_creep(const Eigen::Vector3d& p) const {
        return creep_radius > 0 && (p.head<2>() - creep_centre).norm() <= creep_radius;
    }
    // The bushes: centre and half-axes of their ellipsoids.
    std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> bushes;
    // The pier's thermal displacement at a point of its faces (simulator/deformation.cpp).
    Eigen::Vector3d pier_displacement(const Eigen::Vector3d& p) const {
        const double zeta = std::clamp(p.z() / pier_max.z(), 0.0, 1.0);
        const double profile = std::pow(zeta, exponent);
        return {pier_top.x() * profile, pier_top.y() * profile, pier_top.z() * zeta};
    }
    bool on_pier(const Eigen::Vector3d& p, double margin = 0.05) const {
        return (p.array() >= pier_min.array() - margin).all() &&
               (p.array() <= pier_max.array() + margin).all() && p.z() > 0.45;
    }
    bool in_bush(const Eigen::Vector3d& p) const {
        for (const auto& [c, r] : bushes) {
            if (((p - c).array() / (r.array() + 0.1)).matrix().squaredNorm() <= 1.0) return true;
        }
        return false;
    }
};

Eigen::Vector3d vector_of(const nlohmann::json& a) {
    return {a.at(0).get<double>(), a.at(1).get<double>(), a.at(2).get<double>()};
}

Truth read_truth(const std::string& ptx) {
    const std::string path = ptx.substr(0, ptx.size() - 4) + ".truth.json";
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot open " + path);
    const auto j = nlohmann::json::parse(in);
    Truth t;
    const auto& h = j.at("scanner").at("header_to_true");
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m(r, c) = h.at(r).at(c).get<double>();
    t.header_to_true.matrix() = m;
    for (const auto& tj : j.at("targets")) {
        const auto& c = tj.at("centre");
        t.centres[tj.at("name").get<std::string>()] =
            Eigen::Vector3d(c.at(0).get<double>(), c.at(1).get<double>(), c.at(2).get<double>());
    }
    const auto& p = j.at("pier");
    t.pier_min = Eigen::Vector3d(p.at("x0").get<double>(), p.at("y0").get<double>(), 0.0);
    t.pier_max = Eigen::Vector3d(p.at("x1").get<double>(), p.at("y1").get<double>(),
                                 p.at("height").get<double>());
    if (j.contains("atmosphere") && j.at("atmosphere").value("enabled", false))
        t.range_scale = j.at("atmosphere").at("range_scale").get<double>();
    if (j.contains("deformation") && j.at("deformation").value("enabled", false)) {
        t.pier_top = vector_of(j.at("deformation").at("top_displacement_m"));
        t.exponent = j.at("deformation").at("exponent").get<double>();
    }
    for (const auto& v : j.at("occlusion").at("vegetation"))
        t.bushes.emplace_back(vector_of(v.at("centre")), vector_of(v.at("radii")));
    for (const auto& b : j.at("terrain").at("blocks")) {
        TruthBlock k;
        k.name = b.at("name").get<std::string>();
        const Eigen::Vector3d lo = vector_of(b.at("lo")), hi = vector_of(b.at("hi"));
        k.half = 0.5 * (hi - lo);
        k.pose.linear() =
            Eigen::AngleAxisd(b.value("yaw_deg", 0.0) * M_PI / 180.0, Eigen::Vector3d::UnitZ())
                .toRotationMatrix();
        k.pose.translation() = 0.5 * (lo + hi);
        k.moved = b.value("moved", false);
        t.blocks.push_back(k);
    }
    if (const auto& tr = j.at("terrain"); tr.contains("creep")) {
        const auto& c = tr.at("creep");
        t.creep_centre = {c.at("centre").at(0).get<double>(), c.at("centre").at(1).get<double>()};
        t.creep_radius = c.at("radius").get<double>();
        t.creep = vector_of(c.at("displacement_m"));
    }
    if (j.contains("deck") && j.at("deck").value("enabled", false)) {
        const auto& d = j.at("deck");
        const double cy = 0.5 * (t.pier_min.y() + p.at("y1").get<double>());
        const double overhang = d.at("overhang").get<double>();
        const double half = d.at("half_length").get<double>();
        t.deck = Eigen::AlignedBox3d(
            Eigen::Vector3d(t.pier_min.x() - overhang, cy - half, t.pier_max.z() - 0.5),
            Eigen::Vector3d(t.pier_max.x() + overhang, cy + half,
                            t.pier_max.z() + d.at("thickness").get<double>() + 0.5));
    }
    return t;
}

// Error of a measured centre (header frame) against the truth, split along the line of sight
// from the scanner, across it horizontally and across it vertically; with the fit's σ in the
// same directions.
void print_centre(const TargetMeasurement& m, const Truth& truth, const Eigen::Vector3d& scanner) {
    if (!m.found()) {
        std::printf("    %-4s %-11s %6zu pts  %s\n", m.name.c_str(), m.status.c_str(), m.points,
                    m.reason.c_str());
        return;
    }
    const Eigen::Vector3d c_true = truth.centres.at(m.name);
    const Eigen::Vector3d e = truth.header_to_true * m.centre - c_true;
    const Eigen::Matrix3d axes = bench::sight_axes(c_true - scanner);
    const Eigen::Vector3d los = axes.row(0), h = axes.row(1), v = axes.row(2);
    const Eigen::Matrix3d R = truth.header_to_true.linear();
    const Eigen::Matrix3d S = R * m.covariance * R.transpose();
    const auto sig = [&](const Eigen::Vector3d& d) { return std::sqrt(d.dot(S * d)); };
    std::printf(
        "    %-4s %6.1f m %6zu pts  error los %+7.3f (σ %.3f)  across %+7.3f (σ %.3f)  vertical "
        "%+7.3f (σ %.3f) mm\n",
        m.name.c_str(), (c_true - scanner).norm(), m.points, 1e3 * e.dot(los), 1e3 * sig(los),
        1e3 * e.dot(h), 1e3 * sig(h), 1e3 * e.dot(v), 1e3 * sig(v));
}

std::vector<Eigen::Vector3d> pier_points(const Truth& t) {
    std::vector<Eigen::Vector3d> p;
    for (double z = 0.0; z <= t.pier_max.z(); z += 2.5) {
        for (double x = t.pier_min.x(); x <= t.pier_max.x(); x += 2.5)
            p.emplace_back(x, t.pier_min.y(), z);
        for (double y = t.pier_min.y(); y <= t.pier_max.y(); y += 2.5)
            p.emplace_back(t.pier_min.x(), y, z);
    }
    return p;
}

// The congruence test against the truth's blocks in one epoch: planes on a moved block
// (and how many of them were flagged) and planes flagged elsewhere.
struct PlaneScore {
    int on_moved = 0, found = 0, flagged_elsewhere = 0;
};

PlaneScore score_planes(const PlaneMeasurement& m, const Truth& t0, const Truth& t) {
    PlaneScore s;
    for (const auto& o : m.matched) {
        const Eigen::Vector3d p = t0.header_to_true * o.reference.centroid;
        bool moved = false;
        for (const auto& b : t.blocks) moved = moved || (b.moved && b.holds(p));
        const bool flagged = o.role == "moved" || (o.role == "monitored" && o.significant());
        if (moved) {
            ++s.on_moved;
            s.found += flagged;
        } else if (o.role == "moved") {
            ++s.flagged_elsewhere;
        }
    }
    return s;
}

void print_planes(const PlaneMeasurement& m, const Truth& t0) {
    std::printf(
        "  planes (%s): %s%s; %zu in the reference, %zu in the epoch, %zu matched, %zu in "
        "the datum, %zu moved, %zu in zones; Ω %.1f (limit %.1f), last %.1f (%.1f); "
        "detection %.0f ms, adjustment %.1f ms\n",
        m.role.c_str(), m.used ? "used" : "not used: ", m.refused.c_str(), m.reference_planes,
        m.epoch_planes, m.matched.size(), m.in_datum, m.moved, m.monitored, m.first_omega,
        m.first_limit, m.last_omega, m.last_limit, m.detection_ms, m.adjustment_ms);
    constexpr double arcsec = 180.0 * 3600.0 / M_PI;
    for (const auto& o : m.matched) {
        if (o.role == "datum" && !o.significant()) continue;
        const Eigen::Vector3d c = t0.header_to_true * o.reference.centroid;
        std::string block;
        for (const auto& b : t0.blocks)
            if (b.holds(c)) block = b.name;
        std::printf(
            "    plane %3zu %-9s %-16s at (%.1f %.1f %.1f) %7zu pts  tilt %+7.1f %+7.1f″ "
            "shift %+7.3f mm (σ %.3f)  T %.1f\n",
            o.plane, o.role.c_str(), (o.zone.empty() ? block : o.zone).c_str(), c.x(), c.y(), c.z(),
            o.reference.points, o.misclosure.w(0) * arcsec, o.misclosure.w(1) * arcsec,
            1e3 * o.misclosure.w(2), 1e3 * std::sqrt(o.misclosure.cofactor(2, 2)),
            o.misclosure.test_statistic);
    }
}

// The stable-area mask against the truth: a supervoxel on the pier whose true change along
// its normal exceeds 3·LoD must be unstable; one on ground or a block that did not move must
// be stable; none in a bush may be stable. Also how often the LoD covers the true change.
struct MaskScore {
    int moving = 0, moving_unstable = 0, still = 0, still_stable = 0, bush_stable = 0, bush = 0;
    int with_change = 0, change_covered = 0;
    int creeping = 0, creeping_unstable = 0;  // on the creeping ground, moved beyond 3·LoD
};

MaskScore score_mask(const StableAreaMeasurement& m, const ReferenceSupervoxels& ref,
                     const Truth& t0, const Truth& t) {
    MaskScore s;
    const Eigen::Matrix3d R0 = t0.header_to_true.linear();
    for (std::size_t k = 0; k < m.states.size(); ++k) {
        const SupervoxelState st = m.states[k];
        if (st != SupervoxelState::stable && st != SupervoxelState::unstable) continue;
        const Eigen::Vector3d P = t0.header_to_true * ref.patches[k].centroid;
        const Eigen::Vector3d n = R0 * ref.patches[k].normal;
        if (t0.in_bush(P)) {
            ++s.bush;
            s.bush_stable += st == SupervoxelState::stable;
            continue;
        }
        double truth = 0;
        bool moved_block = false;
        if (t0.on_pier(P)) {
            truth = n.dot(t.pier_displacement(P) - t0.pier_displacement(P));
        } else if (t0.on_creep(P)) {
            truth = n.dot(t.creep - t0.creep);
            if (std::fabs(truth) > 3 * m.lods[k]) {
                ++s.creeping;
                s.creeping_unstable += st == SupervoxelState::unstable;
            }
        } else {
            for (const auto& b : t.blocks) moved_block = moved_block || (b.moved && b.holds(P));
        }
        ++s.with_change;
        s.change_covered += std::fabs(m.changes[k] - truth) <= m.lods[k];
        if (std::fabs(truth) > 3 * m.lods[k]) {
            ++s.moving;
            s.moving_unstable += st == SupervoxelState::unstable;
        } else if (!t0.on_pier(P) && !moved_block && (t0.deck.isEmpty() || !t0.deck.contains(P))) {
            ++s.still;
            s.still_stable += st == SupervoxelState::stable;
        }
    }
    return s;
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> files;
    bool truth_air = false;
    std::string method;
    for (int i = 2; i < argc; ++i) {
        if (std::strcmp(argv[i], "--truth-air") == 0)
            truth_air = true;
        else if (std::strcmp(argv[i], "--method") == 0 && i + 1 < argc)
            method = argv[++i];
        else
            files.emplace_back(argv[i]);
    }
    if (argc < 3 || files.size() < 2) {
        std::fprintf(stderr,
                     "usage: bench_registration_truth SITE.toml E0.ptx E1.ptx ... [--truth-air] "
                     "[--method targets|planes|stable_areas|targets+planes|...]\n");
        return 2;
    }
    try {
        RegistrationConfig config = pipeline_config(load_config(argv[1])).registration;
        if (!method.empty()) {
            const auto m = registration_method_named(method);
            if (!m) throw std::runtime_error("--method " + method + ": not a method");
            config.method = *m;
        }
        RegistrationConfig targets_config = config;
        if (!config.uses_targets()) targets_config.targets.clear();
        std::vector<Truth> truths;
        ReferenceTargets reference;
        ReferencePlanes reference_planes;
        ReferenceSupervoxels supervoxels;
        MaskScore mask_total;
        std::vector<std::vector<std::uint8_t>>
            masks;  // each epoch's states as stored, newest first
        // Over the later epochs: the pier's RMS errors, the components within 2σ, the planes.
        std::vector<double> pier_rms;
        int components = 0, within_2sigma = 0, registered = 0;
        PlaneScore total;
        int epochs_with_moved = 0, epochs_all_found = 0, station_changes = 0;
        std::optional<registration::RigidTransform> prior;  // the last accepted pose
        for (std::size_t i = 0; i < files.size(); ++i) {
            const HashedBytes content = read_file_hashed(files[i]);
            const std::vector<Scan> scans = parse_scans(content.bytes, files[i]);
            truths.push_back(read_truth(files[i]));
            const Truth& t = truths.back();
            if (i == 0 && !t.deck.isEmpty()) config.zones.push_back({"deck", t.deck, {}, {}});
            const Eigen::Vector3d scanner = t.header_to_true * scans.front().scanner_position();
            std::printf("%s (range scale %+.2f ppm)\n", files[i].c_str(),
                        (t.range_scale - 1) * 1e6);
            RangeScales scales;
            if (truth_air) scales = {t.range_scale, truths.front().range_scale};
            if (i == 0) {
                reference = measure_reference_targets(targets_config, scans);
                for (auto& m : reference.targets) {
                    if (truth_air && m.found())
                        m.centre = m.viewpoint + (m.centre - m.viewpoint) / t.range_scale;
                    print_centre(m, t, scanner);
                    if (truth_air && m.found())  // back as measured: the stage corrects it
                        m.centre = m.viewpoint + (m.centre - m.viewpoint) * t.range_scale;
                }
                if (config.uses_planes())
                    reference_planes = detect_scan_planes(config.planes, scans);
                if (config.uses_stable_areas()) {
                    supervoxels = build_supervoxels(config.stable_areas, scans);
                    std::size_t planar = 0;
                    for (const auto& q : supervoxels.patches)
                        planar += is_planar(config.stable_areas, q, supervoxels.viewpoint);
                    std::printf("  supervoxels: %zu (%zu planar) of %zu voxels, %.1f s\n",
                                supervoxels.patches.size(), planar, supervoxels.samples.size(),
                                1e-3 * supervoxels.milliseconds);
                }
                continue;
            }
            RegistrationResult r = register_epoch(targets_config, reference, scans, {}, scales);
            // As the daemon: from the last accepted registration's pose.
            apply_planes(config, reference_planes, scans, scales, r, prior);
            apply_stable_areas(config, supervoxels, scans, scales, r, prior);
            if (config.uses_stable_areas() && std::getenv("STABLE_UNDER_TRUTH")) {
                // The changes under the exact transformation: what the LoD model alone does.
                const Eigen::Affine3d X =
                    truths.front().header_to_true.inverse() * t.header_to_true;
                const auto T = registration::rigid_transform_from(
                    X.linear(), X.translation(), registration::Covariance6::Zero());
                const StableAreaMeasurement m =
                    supervoxel_changes(config, supervoxels, scans, T, scales);
                const MaskScore ms = score_mask(m, supervoxels, truths.front(), t);
                std::printf("    under the truth: still %d/%d stable, change within LoD %d/%d\n",
                            ms.still_stable, ms.still, ms.change_covered, ms.with_change);
                std::vector<std::pair<double, std::size_t>> worst;
                for (std::size_t k = 0; k < m.states.size(); ++k)
                    if (m.states[k] == SupervoxelState::unstable &&
                        !truths.front().on_pier(truths.front().header_to_true *
                                                supervoxels.patches[k].centroid))
                        worst.emplace_back(std::fabs(m.changes[k]) / m.lods[k], k);
                std::sort(worst.rbegin(), worst.rend());
                for (std::size_t w = 0; w < std::min<std::size_t>(12, worst.size()); ++w) {
                    const auto& q = supervoxels.patches[worst[w].second];
                    const Eigen::Vector3d v = (q.centroid - supervoxels.viewpoint).normalized();
                    std::printf(
                        "      at (%.1f %.1f %.1f) n (%.2f %.2f %.2f) incidence %.0f° %zu voxels σ "
                        "%.2f mm: change %+.2f LoD %.2f mm\n",
                        q.centroid.x(), q.centroid.y(), q.centroid.z(), q.normal.x(), q.normal.y(),
                        q.normal.z(), std::acos(std::fabs(v.dot(q.normal))) * 180 / M_PI, q.samples,
                        1e3 * q.sigma, 1e3 * m.changes[worst[w].second],
                        1e3 * m.lods[worst[w].second]);
                }
            }
            if (const auto& m = r.stable_areas; m && std::getenv("STABLE_WHERE")) {
                std::map<std::string, std::array<int, 4>> where;
                for (std::size_t k = 0; k < m->states.size(); ++k) {
                    const Eigen::Vector3d P =
                        truths.front().header_to_true * supervoxels.patches[k].centroid;
                    std::string name = truths.front().on_pier(P) ? "pier" : "";
                    for (const auto& b : t.blocks)
                        if (name.empty() && b.holds(P)) name = b.name;
                    if (name.empty() && !truths.front().deck.isEmpty() &&
                        truths.front().deck.contains(P))
                        name = "deck";
                    if (name.empty())
                        name = P.z() < 0.3 ? "ground" : (P.y() > 60 ? "valley side" : "other");
                    ++where[name][static_cast<int>(m->states[k])];
                }
                for (const auto& [name, c] : where)
                    std::printf("      %-12s stable %5d unstable %5d unknown %5d not planar %5d\n",
                                name.c_str(), c[0], c[1], c[2], c[3]);
            }
            if (const auto& m = r.stable_areas; m && std::getenv("STABLE_X")) {
                for (std::size_t k = 0; k < m->states.size(); ++k) {
                    const auto& q = supervoxels.patches[k];
                    if (m->states[k] != SupervoxelState::stable || std::fabs(q.normal.x()) < 0.3)
                        continue;
                    const Eigen::Vector3d v = (q.centroid - supervoxels.viewpoint).normalized();
                    std::printf(
                        "      x-holder at (%.1f %.1f %.1f) n (%.2f %.2f %.2f) incidence %.0f° %zu "
                        "voxels σ %.2f mm: change %+.2f LoD %.2f mm\n",
                        q.centroid.x(), q.centroid.y(), q.centroid.z(), q.normal.x(), q.normal.y(),
                        q.normal.z(), std::acos(std::fabs(v.dot(q.normal))) * 180 / M_PI, q.samples,
                        1e3 * q.sigma, 1e3 * m->changes[k], 1e3 * m->lods[k]);
                }
            }
            if (const auto& m = r.stable_areas) {
                const MaskScore ms = score_mask(*m, supervoxels, truths.front(), t);
                std::printf(
                    "  stable areas (%s, from %s): %s%s; %zu stable, %zu unstable, %zu unknown, "
                    "%zu not planar; share %.2f; %d rounds%s; %zu pairs (%zu outliers), RMS %.3f "
                    "mm, conditioning %.2g, inflation %.2f; %.2f s\n"
                    "    mask: moving %d/%d unstable, still %d/%d stable, bush %d/%d stable; "
                    "change within LoD %d/%d\n",
                    m->role.c_str(), m->start.c_str(),
                    m->used ? "used" : "not used: ", m->refused.c_str(), m->stable, m->unstable,
                    m->unknown, m->not_planar, m->stable_share, m->iterations,
                    m->settled ? "" : " (not settled)", m->pairs, m->outliers, 1e3 * m->rms,
                    m->conditioning, m->inflation, 1e-3 * m->milliseconds, ms.moving_unstable,
                    ms.moving, ms.still_stable, ms.still, ms.bush_stable, ms.bush,
                    ms.change_covered, ms.with_change);
                if (ms.creeping > 0) {
                    std::printf("    creeping ground: %d/%d unstable\n", ms.creeping_unstable,
                                ms.creeping);
                }
                // The unstable areas the stage would report, over this run's own masks.
                StableAreaMeasurement with_patches = *m;
                with_patches.patches = supervoxels.patches;
                for (const auto& a : new_unstable_areas(config, with_patches, masks)) {
                    std::printf(
                        "    unstable area: %zu supervoxels about (%.1f %.1f %.1f) m, %.1f m "
                        "across; change %+.2f to %+.2f mm (LoD95 up to %.2f mm)%s\n",
                        a.supervoxels.size(), a.centre.x(), a.centre.y(), a.centre.z(),
                        2 * a.extent, 1e3 * a.min_change, 1e3 * a.max_change, 1e3 * a.max_lod,
                        truths.front().on_creep(truths.front().header_to_true * a.centre)
                            ? " (the creeping ground)"
                            : "");
                }
                std::vector<std::uint8_t> states(m->states.size());
                for (std::size_t k = 0; k < states.size(); ++k)
                    states[k] = static_cast<std::uint8_t>(m->states[k]);
                masks.insert(masks.begin(), std::move(states));
                mask_total.moving += ms.moving;
                mask_total.moving_unstable += ms.moving_unstable;
                mask_total.still += ms.still;
                mask_total.still_stable += ms.still_stable;
                mask_total.bush += ms.bush;
                mask_total.bush_stable += ms.bush_stable;
                mask_total.with_change += ms.with_change;
                mask_total.change_covered += ms.change_covered;
            }
            if (r.planes && r.planes->station_change) {
                ++station_changes;
                std::printf("  %s\n", describe(*r.planes->station_change).c_str());
            }
            for (auto m : r.measured) {
                if (truth_air && m.found())
                    m.centre = m.viewpoint + (m.centre - m.viewpoint) / t.range_scale;
                print_centre(m, t, scanner);
            }
            std::printf("  registration: %s%s%s, %d used, s0² %.2f, r %d\n",
                        name_of(r.tested.status), r.gate.empty() ? "" : ", gate: ", r.gate.c_str(),
                        r.used, r.tested.transform ? r.tested.transform->variance_factor : 0.0,
                        r.tested.transform ? r.tested.transform->redundancy : 0);
            for (std::size_t k = 0; k < r.tested.targets.size(); ++k) {
                const auto& v = r.tested.targets[k];
                if (v.use == registration::TargetUse::not_usable) continue;
                std::printf("    %-4s %-16s T %7.2f (crit %.2f)  residual %.3f mm\n",
                            config.targets[k].name.c_str(), name_of(v.use), v.statistic, v.critical,
                            1e3 * v.residual.norm());
            }
            if (r.planes) {
                print_planes(*r.planes, truths.front());
                const PlaneScore ps = score_planes(*r.planes, truths.front(), t);
                total.on_moved += ps.on_moved;
                total.found += ps.found;
                total.flagged_elsewhere += ps.flagged_elsewhere;
                if (ps.on_moved > 0) {
                    ++epochs_with_moved;
                    epochs_all_found += ps.found == ps.on_moved;
                }
            }
            if (!r.tested.transform || !r.accepted()) continue;
            ++registered;
            const auto& T = *r.tested.transform;
            prior = registration::RigidTransform{};
            prior->rotation = T.rotation;
            prior->translation = T.translation;
            const Eigen::Affine3d& H0 = truths.front().header_to_true;
            const Eigen::Affine3d& Hi = t.header_to_true;
            const auto pier = pier_points(t);
            double rms = 0;
            for (const auto& P : pier)
                rms += (T.apply(Hi.inverse() * P) - H0.inverse() * P).squaredNorm();
            rms = std::sqrt(rms / pier.size());
            pier_rms.push_back(rms);
            // The foot's and the top's corner: each component's error against its 2σ.
            for (const Eigen::Vector3d& P : {pier.front(), pier.back()}) {
                const Eigen::Vector3d x = Hi.inverse() * P;
                const Eigen::Vector3d e = T.apply(x) - H0.inverse() * P;
                const Eigen::Matrix3d S = registration::registration_covariance_at(T, x);
                for (int k = 0; k < 3; ++k) {
                    ++components;
                    within_2sigma += std::fabs(e(k)) <= 2 * std::sqrt(S(k, k));
                }
                std::printf(
                    "  pier at (%.1f %.1f %.1f): error %.3f mm (x %+.3f y %+.3f z %+.3f), σ %.3f "
                    "%.3f %.3f mm\n",
                    P.x(), P.y(), P.z(), 1e3 * e.norm(), 1e3 * e.x(), 1e3 * e.y(), 1e3 * e.z(),
                    1e3 * std::sqrt(S(0, 0)), 1e3 * std::sqrt(S(1, 1)), 1e3 * std::sqrt(S(2, 2)));
            }
            std::printf("  pier: RMS error %.3f mm over %zu points\n", 1e3 * rms, pier.size());
        }
        double sum = 0, worst = 0;
        for (const double e : pier_rms) {
            sum += e * e;
            worst = std::max(worst, e);
        }
        std::printf(
            "summary: %d of %zu epochs registered; pier RMS error %.3f mm (worst epoch %.3f mm); "
            "%d of %d components (foot and top corners) within 2σ (%.1f %%)\n",
            registered, files.size() - 1,
            pier_rms.empty() ? 0.0 : 1e3 * std::sqrt(sum / pier_rms.size()), 1e3 * worst,
            within_2sigma, components, components ? 100.0 * within_2sigma / components : 0.0);
        if (config.uses_stable_areas()) {
            const auto pct = [](int a, int b) { return b ? 100.0 * a / b : 0.0; };
            std::printf(
                "summary stable areas: moving supervoxels marked unstable %d/%d (%.1f %%); still "
                "ones marked stable %d/%d (%.1f %%); bush in the stable set %d/%d; change within "
                "its LoD95 %d/%d (%.1f %%)\n",
                mask_total.moving_unstable, mask_total.moving,
                pct(mask_total.moving_unstable, mask_total.moving), mask_total.still_stable,
                mask_total.still, pct(mask_total.still_stable, mask_total.still),
                mask_total.bush_stable, mask_total.bush, mask_total.change_covered,
                mask_total.with_change, pct(mask_total.change_covered, mask_total.with_change));
        }
        if (config.uses_planes()) {
            std::printf(
                "summary planes: %d epochs with a moved block: all its matched planes flagged in "
                "%d; %d of %d such planes flagged; %d planes flagged moved on unmoved ground; %d "
                "station changes\n",
                epochs_with_moved, epochs_all_found, total.found, total.on_moved,
                total.flagged_elsewhere, station_changes);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_registration_truth: %s\n", e.what());
        return 1;
    }
    return 0;
}
