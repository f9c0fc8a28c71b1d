// Campaign comparison scored against the simulator's truth (reported, not asserted), 2 threads:
//  1. the `pier` scene's TLS reference scan (0.026° steps): the cloth simulation filter's
//     ground against the per-point surface labels, and the segments of what is left with the
//     surface most of their points lie on;
//  2. seeded personal-laser-scanner campaigns walked around the pier (simulator/pls.hpp),
//     each with SLAM drift (random walk) and without, compared with a drift-free survey of all
//     sides at TLS noise (2 mm): the ground filter on the campaign, each registered segment's
//     recovered parameters against its true transformation, the test of whether the segments
//     moved as one, and C2C on the pier's segments.
// A segment's true transformation: the rigid transformation that best maps its points as
// measured without range noise (the drift alone), after the global registration, onto the
// surface points their pulses hit, along the true surface normals there (campaign/paired_fit.hpp),
// in the segment's own parameters (about its centroid); TRUTH=point takes the point-to-point best
// fit instead (Umeyama 1991), which also counts the drift along the surfaces that no surface-based
// comparison can see. It is compared only in what the segment observes: the observed combinations'
// χ² (rank dof) and, per observed translation, |t̂ − t| ≤ 2σ. Usage: bench_campaign_truth
// [CAMPAIGNS=20] [FIRST_SEED=1] [PULSE_RATE=30000]
//                             [DRIFT=random-walk] [TRUTH=point|plane] [FRAME=scene|slam] [verbose]
// FRAME=slam writes each campaign in the SLAM's own frame (simulator/pls.hpp, slam_frame: its
// start, a heading drawn from the seed), so the comparison must find the frame first (the
// coarse step on planes); the frame found is scored against the one written.
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "algorithms/campaign/ground_filter.hpp"
#include "algorithms/campaign/paired_fit.hpp"
#include "bench/bench_support.hpp"
#include "core/statistics.hpp"
#include "pipeline/campaign_comparison.hpp"
#include "simulator/pls.hpp"
#include "simulator/ray_cast.hpp"
#include "simulator/render.hpp"

namespace {

using namespace tlsmon;
using Eigen::Vector3d;
using sim::Surface;

constexpr unsigned kThreads = 2;

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

bool is_structure(Surface s) {
    return s == Surface::pier || s == Surface::deck || s == Surface::foundation ||
           s == Surface::abutment || s == Surface::wall;
}

struct GroundScore {
    std::size_t ground = 0, ground_removed = 0, structure = 0, structure_removed = 0;
    void add(std::span<const std::uint8_t> surface, std::span<const std::uint8_t> flagged) {
        for (std::size_t i = 0; i < surface.size(); ++i) {
            const auto s = Surface(surface[i]);
            if (s == Surface::ground) {
                ++ground;
                ground_removed += flagged[i];
            } else if (is_structure(s)) {
                ++structure;
                structure_removed += flagged[i];
            }
        }
    }
    void print(const char* what) const {
        std::printf(
            "%s: ground removed %.2f %% of %zu ground points, structure removed %.2f %% of "
            "%zu\n",
            what, 100.0 * double(ground_removed) / double(std::max<std::size_t>(ground, 1)), ground,
            100.0 * double(structure_removed) / double(std::max<std::size_t>(structure, 1)),
            structure);
    }
};

// The surface most of a segment's points lie on, and its share.
std::pair<Surface, double> majority(std::span<const std::size_t> members,
                                    std::span<const std::uint8_t> surface) {
    std::array<std::size_t, sim::kSurfaceKinds> count{};
    for (const auto i : members) ++count[surface[i]];
    const auto best = std::max_element(count.begin(), count.end());
    return {Surface(best - count.begin()),
            double(*best) / double(std::max<std::size_t>(members.size(), 1))};
}

std::vector<std::vector<std::size_t>> members_of(const campaign::Segmentation& s) {
    std::vector<std::vector<std::size_t>> m(s.segments.size());
    for (std::size_t i = 0; i < s.segment.size(); ++i)
        if (s.segment[i] >= 0) m[std::size_t(s.segment[i])].push_back(i);
    return m;
}

void reference_segments(const sim::Site& site, const CampaignParameters& p) {
    sim::Site s = site;
    s.scanner.azimuth_step_deg = s.scanner.elevation_step_deg = 0.026;
    auto t0 = std::chrono::steady_clock::now();
    const sim::RenderedScan scan = sim::render_epoch(s, 0, 0.0, kThreads);
    std::printf("TLS reference (pier, 0.026°): %zu points, rendered in %.1f s\n",
                scan.scan.xyz.size(), seconds_since(t0));
    t0 = std::chrono::steady_clock::now();
    const auto ground = campaign::classify_ground(scan.scan.xyz, p.ground, kThreads);
    std::printf("cloth: %d × %d particles, settled after %d iterations, %.2f s\n", ground.rows,
                ground.columns, ground.iterations, seconds_since(t0));
    GroundScore score;
    score.add(scan.surface, ground.ground);
    score.print("TLS reference");
    std::array<std::size_t, sim::kSurfaceKinds> removed{}, all{};
    for (std::size_t i = 0; i < scan.surface.size(); ++i) {
        ++all[scan.surface[i]];
        removed[scan.surface[i]] += ground.ground[i];
    }
    for (int k = 0; k < sim::kSurfaceKinds; ++k)
        if (all[k])
            std::printf("  %-12s %9zu points, %8zu removed as ground\n",
                        sim::surface_name(Surface(k)), all[k], removed[k]);

    std::vector<Vector3d> kept;
    std::vector<std::uint8_t> label;
    for (std::size_t i = 0; i < scan.scan.xyz.size(); ++i)
        if (!ground.ground[i]) {
            kept.push_back(scan.scan.xyz[i]);
            label.push_back(scan.surface[i]);
        }
    std::vector<campaign::VerticalityClass> classes;
    for (const float v : campaign::verticality(kept, p.verticality, kThreads))
        classes.push_back(campaign::classify(v, p.verticality));
    const auto seg = campaign::segment_cloud(kept, classes, p.segmentation, kThreads);
    const auto members = members_of(seg);
    std::printf("segments of the reference (≥ %d points): %zu; the %d largest:\n",
                p.segmentation.min_points, seg.segments.size(), 16);
    for (std::size_t k = 0; k < std::min<std::size_t>(16, seg.segments.size()); ++k) {
        const auto [surface, share] = majority(members[k], label);
        std::printf("  %2zu %-10s %8zu points, %5.1f %% %s\n", k,
                    campaign::class_name(seg.segments[k].kind), seg.segments[k].points, 100 * share,
                    sim::surface_name(surface));
    }
}

struct Scoring {
    bool point_to_plane_truth = true;  // else the point-to-point best fit
    bool verbose = false;              // a line per segment
};

struct Tally {
    std::size_t segments = 0, chi2_within = 0, components = 0, components_within = 0,
                segments_all_within = 0;
    std::size_t campaigns = 0, rejected = 0;
    std::vector<double> offsets_mm, c2c_pier_mm;
    // Segments matched to a reference segment, and those whose majority surface is the
    // matched one's; the points of each, and of all segments.
    std::size_t matched = 0, matched_same = 0, unmatched = 0;
    std::size_t points_matched = 0, points_same = 0, points_all = 0;
    // The campaign's frame: found on planes, and the error of the frame found (the coarse
    // step's heading; the whole frame's rotation and its shift at the pier).
    std::size_t coarse_planes = 0;
    std::vector<double> coarse_heading_deg, frame_rotation_mrad, frame_shift_mm;
};

// The frame found (c.frame(), campaign → reference) against the one the campaign was written
// in (to_campaign: scene → campaign), at the pier's centre `at`.
void score_frame(const CampaignComparison& c, const Eigen::Matrix4d& to_campaign,
                 const Vector3d& at, Tally& tally) {
    if (c.coarse.used != CoarseRegistration::planes) return;
    ++tally.coarse_planes;
    const Eigen::Matrix4d coarse = c.coarse.matrix * to_campaign;
    tally.coarse_heading_deg.push_back(std::atan2(coarse(1, 0), coarse(0, 0)) * 180 /
                                       std::numbers::pi);
    const Eigen::Matrix4d E = c.frame() * to_campaign;  // the identity, but for the drift
    tally.frame_rotation_mrad.push_back(
        1e3 * Eigen::AngleAxisd(Eigen::Matrix3d(E.topLeftCorner<3, 3>())).angle());
    tally.frame_shift_mm.push_back(1e3 * ((E * at.homogeneous()).head<3>() - at).norm());
}

// Each campaign segment's match against the truth: is the reference segment it was matched to
// on the same surface (the majority of each)?
void score_matching(const sim::PlsCloud& cloud, const CampaignComparison& c,
                    const std::vector<std::vector<std::size_t>>& reference_members,
                    std::span<const std::uint8_t> reference_surface, Tally& tally) {
    const auto members = members_of(c.segmentation);
    for (std::size_t s = 0; s < c.segments.size(); ++s) {
        const std::size_t n = members[s].size();
        tally.points_all += n;
        const auto r = c.segments[s].reference.reference;
        if (r < 0) {
            ++tally.unmatched;
            continue;
        }
        const bool same = majority(members[s], cloud.surface).first ==
                          majority(reference_members[std::size_t(r)], reference_surface).first;
        ++tally.matched;
        tally.matched_same += same;
        tally.points_matched += n;
        tally.points_same += same ? n : 0;
    }
}

void score_campaign(const sim::PlsCampaign& campaign, const sim::PlsCloud& cloud,
                    const Eigen::Matrix4d& to_campaign, const CampaignComparison& c,
                    const Scoring& scoring, Tally& tally, const char* name) {
    const auto members = members_of(c.segmentation);
    const std::vector<Vector3d> measured = sim::noise_free_points(campaign, cloud);
    const Eigen::Matrix4d G = c.frame() * to_campaign;
    std::size_t registered = 0, within = 0;
    double largest = 0, smallest = 1e9;
    for (std::size_t s = 0; s < c.segments.size(); ++s) {
        const auto& t = c.segments[s].transform;
        if (!t.registered()) continue;
        ++registered;
        const std::size_t m = members[s].size();
        std::vector<Vector3d> from(m), to(m), normal(m);
        for (std::size_t k = 0; k < m; ++k) {
            const auto i = members[s][k];
            from[k] = (G * measured[i].homogeneous()).head<3>();
            to[k] = cloud.truth[i];
            normal[k] = cloud.normal[i].cast<double>();
        }
        const campaign::Vector6 truth =
            scoring.point_to_plane_truth
                ? campaign::fit_pairs_point_to_plane(from, to, normal, t.centroid)
                : campaign::parameters_of(
                      Eigen::umeyama(
                          Eigen::Map<const Eigen::Matrix3Xd>(from.data()->data(), 3, long(m)),
                          Eigen::Map<const Eigen::Matrix3Xd>(to.data()->data(), 3, long(m)), false),
                      t.centroid);
        const Eigen::VectorXd e = t.observed * (t.parameters - truth);
        const double chi2 = e.dot(t.observed_covariance.ldlt().solve(e));
        ++tally.segments;
        // χ²(rank) 95 % quantiles for rank 1–6.
        static constexpr double q95[7] = {0, 3.841, 5.991, 7.815, 9.488, 11.070, 12.592};
        tally.chi2_within += chi2 <= q95[t.rank()];
        bool all_within = true;
        for (int a = 0; a < 3; ++a) {
            if (!t.translation_observed(a)) continue;
            const double d = std::abs(t.parameters(3 + a) - truth(3 + a));
            const bool ok = d <= 2.0 * std::sqrt(t.covariance(3 + a, 3 + a));
            ++tally.components;
            tally.components_within += ok;
            all_within = all_within && ok;
            tally.offsets_mm.push_back(1e3 * std::abs(truth(3 + a)));
            largest = std::max(largest, std::abs(truth(3 + a)));
            smallest = std::min(smallest, std::abs(truth(3 + a)));
        }
        tally.segments_all_within += all_within;
        if (scoring.verbose) {
            const auto [surface, share] = majority(members[s], cloud.surface);
            std::printf("    seg %2zu %-8s %7zu pts %3zu cells rank %d χ² %7.1f  t̂-t (mm)", s,
                        sim::surface_name(surface), members[s].size(), t.clusters, t.rank(), chi2);
            for (int a = 0; a < 3; ++a)
                if (t.translation_observed(a))
                    std::printf(" %6.2f±%4.2f(t %6.2f)", 1e3 * (t.parameters(3 + a) - truth(3 + a)),
                                1e3 * std::sqrt(t.covariance(3 + a, 3 + a)), 1e3 * truth(3 + a));
                else
                    std::printf("        -                 ");
            // How much of the segment lies within 0.1 m above the ground cut.
            std::size_t edge = 0;
            for (const auto i : members[s]) {
                const Vector3d& x = c.registered[i];
                const campaign::GroundFilterParameters g;  // the defaults compare_campaign ran
                edge += x.z() - c.ground.cloth_height(x.x(), x.y(), g.cloth_resolution) <
                        g.class_threshold + 0.1;
            }
            std::printf("  %.0f %%, edge %.0f %%\n", 100 * share, 100.0 * double(edge) / double(m));
        }
        within += all_within;
        const auto [surface, share] = majority(members[s], cloud.surface);
        if (surface == Surface::pier && share > 0.9)
            tally.c2c_pier_mm.push_back(1e3 * c.segments[s].c2c.mean);
    }
    ++tally.campaigns;
    tally.rejected += c.consistency.differ;
    std::printf(
        "  spacing %.1f mm, %-11s %zu segments registered, %zu with every observed translation "
        "within 2σ; "
        "true |t| %.1f–%.1f mm; T = %.1f (dof %d, p %.3g)%s\n",
        1e3 * c.segmentation.spacing, name, registered, within, 1e3 * (registered ? smallest : 0),
        1e3 * largest, c.consistency.statistic, c.consistency.dof, c.consistency.p_value,
        c.consistency.differ ? " differ" : "");
}

void print_tally(const char* what, const Tally& t) {
    std::printf(
        "%s: %zu campaigns, the test says the segments differ in %zu; %zu registered "
        "segments: %.1f %% with every observed translation within 2σ, %.1f %% of %zu observed "
        "translations within 2σ, %.1f %% within the χ²(rank) 95 %% region\n",
        what, t.campaigns, t.rejected, t.segments,
        100.0 * double(t.segments_all_within) / double(std::max<std::size_t>(t.segments, 1)),
        100.0 * double(t.components_within) / double(std::max<std::size_t>(t.components, 1)),
        t.components, 100.0 * double(t.chi2_within) / double(std::max<std::size_t>(t.segments, 1)));
    std::printf(
        "  matched to a reference segment: %zu of %zu segments (%.1f %% of their points), on the "
        "same surface %zu (%.1f %% of the matched points)\n",
        t.matched, t.matched + t.unmatched,
        100.0 * double(t.points_matched) / double(std::max<std::size_t>(t.points_all, 1)),
        t.matched_same,
        100.0 * double(t.points_same) / double(std::max<std::size_t>(t.points_matched, 1)));
    if (!t.offsets_mm.empty()) {
        auto o = t.offsets_mm;
        std::sort(o.begin(), o.end());
        std::printf(
            "  true observed translations: median %.1f mm, 90 %% %.1f mm, largest %.1f mm\n",
            o[o.size() / 2], o[o.size() * 9 / 10], o.back());
    }
    if (!t.coarse_heading_deg.empty()) {
        const auto largest = [](std::vector<double> v) {
            double m = 0;
            for (const double x : v) m = std::max(m, std::abs(x));
            return m;
        };
        std::printf(
            "  frame found on planes in %zu of %zu campaigns: coarse heading error up to %.3f°; "
            "the whole frame's rotation error up to %.3f mrad, shift at the pier up to %.1f mm\n",
            t.coarse_planes, t.campaigns, largest(t.coarse_heading_deg),
            largest(t.frame_rotation_mrad), largest(t.frame_shift_mm));
    }
    if (!t.c2c_pier_mm.empty()) {
        double sum = 0;
        for (const double v : t.c2c_pier_mm) sum += v;
        std::printf("  C2C mean |d| on %zu pier segments: %.2f mm on average, largest %.2f mm\n",
                    t.c2c_pier_mm.size(), sum / double(t.c2c_pier_mm.size()),
                    *std::max_element(t.c2c_pier_mm.begin(), t.c2c_pier_mm.end()));
    }
}

}  // namespace

int main(int argc, char** argv) {
    const int campaigns = argc > 1 ? std::atoi(argv[1]) : 20;
    const int first_seed = argc > 2 ? std::atoi(argv[2]) : 1;
    const double pulse_rate = argc > 3 ? std::atof(argv[3]) : 30000.0;
    const sim::SlamDriftModel drift = sim::drift_model(argc > 4 ? argv[4] : "random-walk");

    sim::Site site = sim::preset_pier();
    site.occlusion.occluders.clear();  // nobody parked or walking about during the campaign
    const bool slam_frame = argc > 6 && std::string(argv[6]) == "slam";
    CampaignParameters p;
    p.threads = kThreads;
    p.coarse = slam_frame ? CoarseRegistration::planes : CoarseRegistration::automatic;
    reference_segments(site, p);

    sim::PlsCampaign survey;
    survey.trajectory = sim::walk_around_pier(site);
    survey.scanner.pulse_rate = 2.0 * pulse_rate;
    survey.scanner.range_sigma = 0.002;
    survey.scanner.seed = 1000003;
    auto t0 = std::chrono::steady_clock::now();
    const sim::PlsCloud reference = sim::render_pls(site, 0, survey, kThreads);
    std::printf(
        "\nreference survey of all sides (drift-free, 2 mm): %zu points in %.1f s, walk "
        "%.0f s\n",
        reference.points.size(), seconds_since(t0), reference.duration);

    t0 = std::chrono::steady_clock::now();
    const CampaignReference prepared(reference.points, p);
    std::printf("its local planes and segments: %.1f s (segments %.1f s)\n", seconds_since(t0),
                prepared.seconds);
    const auto reference_members = members_of(prepared.segmentation);

    Tally drifted, still;
    Scoring scoring;
    scoring.point_to_plane_truth = !(argc > 5 && std::string(argv[5]) == "point");
    scoring.verbose = argc > 7;
    const Vector3d pier_centre(site.pier.centre().x(), site.pier.centre().y(), 5.0);
    GroundScore ground;
    double compare_seconds = 0;
    for (int k = 0; k < campaigns; ++k) {
        const auto seed = std::uint64_t(first_seed + k);
        std::printf("campaign seed %llu\n", static_cast<unsigned long long>(seed));
        for (const auto model : {drift, sim::SlamDriftModel::none}) {
            sim::PlsCampaign c;
            c.trajectory = survey.trajectory;
            c.scanner.pulse_rate = pulse_rate;
            c.scanner.seed = seed;
            c.drift.model = model;
            c.drift.seed = seed;
            const sim::PlsCloud cloud = sim::render_pls(site, 0, c, kThreads);
            // The heading the scanner pointed at the start, drawn from the seed.
            std::mt19937_64 rng(seed);
            const double heading =
                std::uniform_real_distribution<double>(-std::numbers::pi, std::numbers::pi)(rng);
            const Eigen::Matrix4d to_campaign =
                slam_frame ? Eigen::Matrix4d(sim::slam_frame(c.trajectory, heading).inverse())
                           : Eigen::Matrix4d::Identity();
            std::vector<Vector3d> points(cloud.points.size());
            for (std::size_t i = 0; i < points.size(); ++i)
                points[i] = (to_campaign * cloud.points[i].homogeneous()).head<3>();
            t0 = std::chrono::steady_clock::now();
            const CampaignComparison result = compare_campaign(prepared, points, p);
            compare_seconds += seconds_since(t0);
            score_frame(result, to_campaign, pier_centre,
                        model == sim::SlamDriftModel::none ? still : drifted);
            if (model == sim::SlamDriftModel::none) ground.add(cloud.surface, result.ground.ground);
            score_matching(cloud, result, reference_members, reference.surface,
                           model == sim::SlamDriftModel::none ? still : drifted);
            score_campaign(c, cloud, to_campaign, result, scoring,
                           model == sim::SlamDriftModel::none ? still : drifted,
                           sim::drift_model_name(model));
        }
    }
    std::printf("\n");
    ground.print("campaigns (drift-free)");
    print_tally(sim::drift_model_name(drift), drifted);
    print_tally("no drift", still);
    std::printf("comparison: %.1f s per campaign on average (wall, 2 threads)\n",
                compare_seconds / std::max(1, 2 * campaigns));
    return 0;
}
