// A campaign's zone values ([campaign] zone_series, pipeline/campaign_zones.hpp) scored against
// the simulator's truth (reported, not asserted), 2 threads. The `pier` scene's pier is tiled
// into zones of TILE × TILE m on each of its four faces (design normal outward), from the
// foundation up to 12 m; seeded personal-laser-scanner campaigns walk around it (as
// bench_campaign_truth: a drift-free survey of all sides at 2 mm is the reference), each with
// SLAM drift and without, and in each campaign one tile drawn from the seed bulges BULGE m
// outward (every campaign point on it moved along the face's normal). The truth of a zone is
// the bulge on the bulged tile and 0 elsewhere: what the segment's registration takes of the
// bulge (it fits the segment with the bulge in it) is the method's error. Per mode: each
// figure's error against its LoD95 and σ = LoD95/1.96 (coverage with its Wilson interval),
// bias, RMS and largest error; the bulged tiles apart. Nothing here was fitted: the LoD is
// the formula of campaign_zones.hpp.
// Usage: bench_campaign_zone_truth [CAMPAIGNS=20] [FIRST_SEED=1] [PULSE_RATE=30000]
//                                  [DRIFT=random-walk] [BULGE=0.02] [TILE=2]
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "pipeline/campaign_comparison.hpp"
#include "pipeline/campaign_epoch.hpp"
#include "pipeline/campaign_zones.hpp"
#include "report/calibration.hpp"
#include "simulator/pls.hpp"
#include "simulator/ray_cast.hpp"

namespace {

using namespace tlsmon;
using namespace tlsmon::report;
using Eigen::Vector3d;

constexpr unsigned kThreads = 2;

// A tile of a face: its zone and the face it lies on (outward normal).
struct Tile {
    ZoneShape zone;
    int face = 0;  // 0 south (−y), 1 north (+y), 2 west (−x), 3 east (+x)
};

const Vector3d kFaceNormal[4] = {{0, -1, 0}, {0, 1, 0}, {-1, 0, 0}, {1, 0, 0}};

int face_of(const Eigen::Vector3f& n) {
    for (int f = 0; f < 4; ++f)
        if (n.cast<double>().dot(kFaceNormal[f]) > 0.95) return f;
    return -1;
}

// The pier's faces tiled from z_low (the foundation's top, seen in the survey) up 12 m,
// 0.3 m clear of the corners (mixed returns on the edges are no face).
std::vector<Tile> tiles(const sim::Pier& pier, double z_low, double size) {
    std::vector<Tile> out;
    const double margin = 0.3;
    for (int f = 0; f < 4; ++f) {
        const bool along_x = f < 2;  // the south and north faces run along x
        const double a0 = (along_x ? pier.x0 : pier.y0) + margin;
        const double a1 = (along_x ? pier.x1 : pier.y1) - margin;
        const double plane = f == 0 ? pier.y0 : f == 1 ? pier.y1 : f == 2 ? pier.x0 : pier.x1;
        for (double a = a0; a + size <= a1 + 1e-9; a += size) {
            for (double z = z_low; z + size <= z_low + 12.0 + 1e-9; z += size) {
                Vector3d lo, hi;
                if (along_x) {
                    lo = {a, plane - 0.5, z};
                    hi = {a + size, plane + 0.5, z + size};
                } else {
                    lo = {plane - 0.5, a, z};
                    hi = {plane + 0.5, a + size, z + size};
                }
                ZoneShape zone =
                    box_zone("f" + std::to_string(f) + "_" + std::to_string(out.size()), lo, hi);
                zone.normal = kFaceNormal[f];
                out.push_back({zone, f});
            }
        }
    }
    return out;
}

struct Score {
    std::size_t n = 0, within95 = 0, within68 = 0;
    double sum = 0, sum2 = 0, largest = 0;
    std::vector<double> lod95;
    void add(double error, double lod) {
        ++n;
        within95 += std::abs(error) <= lod;
        within68 += std::abs(error) <= lod / kLod95Factor;
        sum += error;
        sum2 += error * error;
        largest = std::max(largest, std::abs(error));
        lod95.push_back(lod);
    }
    void print(const char* what) const {
        if (n == 0) {
            std::printf("  %s: no figures\n", what);
            return;
        }
        const auto w95 = wilson_interval(within95, n), w68 = wilson_interval(within68, n);
        auto l = lod95;
        std::sort(l.begin(), l.end());
        std::printf(
            "  %s: %zu figures; within LoD95 %.1f %% (Wilson %.1f–%.1f, %s), within σ %.1f %% "
            "(%.1f–%.1f, %s); bias %+.2f mm, RMS %.2f mm, largest %.2f mm; LoD95 median %.2f "
            "mm\n",
            what, n, 100.0 * double(within95) / double(n), 100 * w95.lower, 100 * w95.upper,
            to_string(sigma_verdict(within95, n, 0.95)), 100.0 * double(within68) / double(n),
            100 * w68.lower, 100 * w68.upper, to_string(sigma_verdict(within68, n, 0.6827)),
            1e3 * sum / double(n), 1e3 * std::sqrt(sum2 / double(n)), 1e3 * largest,
            1e3 * l[l.size() / 2]);
    }
};

}  // namespace

int main(int argc, char** argv) {
    const int campaigns = argc > 1 ? std::atoi(argv[1]) : 20;
    const int first_seed = argc > 2 ? std::atoi(argv[2]) : 1;
    const double pulse_rate = argc > 3 ? std::atof(argv[3]) : 30000.0;
    const sim::SlamDriftModel drift = sim::drift_model(argc > 4 ? argv[4] : "random-walk");
    const double bulge = argc > 5 ? std::atof(argv[5]) : 0.02;
    const double tile_size = argc > 6 ? std::atof(argv[6]) : 2.0;

    sim::Site site = sim::preset_pier();
    site.occlusion.occluders.clear();
    CampaignParameters p;
    p.threads = kThreads;
    sim::PlsCampaign survey;
    survey.trajectory = sim::walk_around_pier(site);
    survey.scanner.pulse_rate = 2.0 * pulse_rate;
    survey.scanner.range_sigma = 0.002;
    survey.scanner.seed = 1000003;
    const sim::PlsCloud reference = sim::render_pls(site, 0, survey, kThreads);
    const CampaignReference prepared(reference.points, p);
    std::vector<double> pier_z;
    for (std::size_t i = 0; i < reference.points.size(); ++i)
        if (reference.surface[i] == std::uint8_t(sim::Surface::pier) &&
            face_of(reference.normal[i]) >= 0)
            pier_z.push_back(reference.truth[i].z());
    std::sort(pier_z.begin(), pier_z.end());
    const double z_low = pier_z[pier_z.size() / 100] + 0.3;
    const std::vector<Tile> all = tiles(site.pier, z_low, tile_size);
    std::vector<ZoneShape> zones;
    for (const auto& t : all) zones.push_back(t.zone);
    std::printf("pier faces from z = %.2f m: %zu tiles of %.1f m; bulge %.1f mm\n", z_low,
                all.size(), tile_size, 1e3 * bulge);

    Score still[2], bulged[2];
    std::size_t zones_seen[2] = {0, 0};
    for (int k = 0; k < campaigns; ++k) {
        const auto seed = std::uint64_t(first_seed + k);
        std::mt19937_64 rng(seed * 7919);
        const std::size_t chosen =
            std::uniform_int_distribution<std::size_t>(0, all.size() - 1)(rng);
        const Tile& tile = all[chosen];
        for (int m = 0; m < 2; ++m) {
            sim::PlsCampaign c;
            c.trajectory = survey.trajectory;
            c.scanner.pulse_rate = pulse_rate;
            c.scanner.seed = seed;
            c.drift.model = m == 0 ? drift : sim::SlamDriftModel::none;
            c.drift.seed = seed;
            sim::PlsCloud cloud = sim::render_pls(site, 0, c, kThreads);
            for (std::size_t i = 0; i < cloud.points.size(); ++i) {
                if (cloud.surface[i] != std::uint8_t(sim::Surface::pier) ||
                    face_of(cloud.normal[i]) != tile.face || !tile.zone.contains(cloud.truth[i]))
                    continue;
                cloud.points[i] += bulge * kFaceNormal[tile.face];
            }
            const CampaignComparison result = compare_campaign(prepared, cloud.points, p);
            const auto rows = campaign_zone_results(stored_points(result, 0.05, kThreads),
                                                    segment_rows(result), zones, 30);
            zones_seen[m] += rows.size();
            double bulge_value = std::nan("");
            for (const auto& r : rows) {
                const bool is_bulged = r.zone == tile.zone.name;
                (is_bulged ? bulged : still)[m].add(r.value - (is_bulged ? bulge : 0.0),
                                                    *r.uncertainty);
                if (is_bulged) bulge_value = r.value;
            }
            std::printf("seed %llu %-11s: %zu zones with a value; bulged tile %s: %.2f mm\n",
                        static_cast<unsigned long long>(seed), sim::drift_model_name(c.drift.model),
                        rows.size(), tile.zone.name.c_str(), 1e3 * bulge_value);
        }
    }
    for (int m = 0; m < 2; ++m) {
        std::printf("\n%s (%zu zone values in %d campaigns):\n",
                    sim::drift_model_name(m == 0 ? drift : sim::SlamDriftModel::none),
                    zones_seen[m], campaigns);
        still[m].print("unchanged tiles (truth 0)");
        bulged[m].print("bulged tiles (truth the bulge)");
    }
    return 0;
}
